# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""LAMMPS text dumps (``dump custom``, optionally gzipped): :func:`read_dump` gives every
frame's timestep, box, bead ids, positions and the other columns by name, as NumPy arrays.
(:mod:`cgms.trajectory` reads long trajectories frame by frame with MDAnalysis.)"""

import gzip
import warnings

import numpy as np

#: coordinate column sets, in the order they are looked for
_COORDS = (("x", "y"), ("xu", "yu"), ("xs", "ys"), ("xsu", "ysu"))


def _open_text(path):
    path = str(path)
    if path.endswith(".gz"):
        return gzip.open(path, "rt")
    return open(path)


def _dump_frames(path):
    """Parse a LAMMPS text dump: list of dicts (timestep, box, box_flags, columns names,
    rows (n, ncol) str array, items: other ITEM names). A truncated last frame (dump
    still being written) is dropped with a warning; other malformed input raises."""
    frames = []
    with _open_text(path) as fh:
        lines = fh.read().splitlines()
    i, n_lines = 0, len(lines)

    def need(k, what):
        if i + k > n_lines:
            raise EOFError(what)

    frame, pending = None, {}
    try:
        while i < n_lines:
            line = lines[i].strip()
            if not line:
                i += 1
                continue
            if not line.startswith("ITEM:"):
                raise ValueError(f"{path}: line {i + 1}: expected 'ITEM: ...', got {line[:60]!r}")
            item = line[5:].strip()
            i += 1
            if item.startswith("TIMESTEP"):
                need(1, "TIMESTEP")
                frame = dict(timestep=int(lines[i].split()[0]), items=pending, natoms=None)
                frames.append(frame)
                pending = {}
                i += 1
                continue
            standard = item.startswith(("NUMBER OF ATOMS", "BOX BOUNDS", "ATOMS"))
            if not standard:  # ITEM: UNITS, ITEM: TIME (written before TIMESTEP), ...
                start = i
                while i < n_lines and not lines[i].startswith("ITEM:"):
                    i += 1
                key = item.split()[0] if item else item
                if frame is None or "columns" in frame:
                    pending[key] = lines[start:i]
                else:
                    frame["items"][key] = lines[start:i]
                continue
            if frame is None:
                raise ValueError(f"{path}: line {i}: '{line}' before the first ITEM: TIMESTEP")
            if item.startswith("NUMBER OF ATOMS"):
                need(1, "NUMBER OF ATOMS")
                frame["natoms"] = int(lines[i])
                i += 1
            elif item.startswith("BOX BOUNDS"):
                need(3, "BOX BOUNDS")
                frame["box_flags"] = item.split()[2:]
                frame["box"] = np.array([[float(w) for w in lines[i + k].split()]
                                         for k in range(3)])
                i += 3
            elif item.startswith("ATOMS"):
                if frame["natoms"] is None:
                    raise ValueError(f"{path}: line {i}: ITEM: ATOMS before ITEM: NUMBER OF ATOMS")
                cols = item.split()[1:]
                n = frame["natoms"]
                need(n, "ATOMS")
                rows = [lines[i + k].split() for k in range(n)]
                bad = [k for k, r in enumerate(rows) if len(r) != len(cols)]
                if bad:
                    if i + n >= n_lines and bad == [n - 1]:
                        raise EOFError("ATOMS")
                    raise ValueError(f"{path}: line {i + bad[0] + 1}: {len(rows[bad[0]])} values "
                                     f"for {len(cols)} columns {cols}")
                frame["columns"] = cols
                frame["rows"] = np.array(rows, dtype=str).reshape(n, len(cols))
                i += n
    except EOFError as exc:
        if frames and "columns" not in frames[-1]:
            last = frames.pop()["timestep"]
        else:
            last = "unknown"
        warnings.warn(f"{path}: the dump ends inside ITEM: {exc} (a frame still being "
                      f"written?); the incomplete last frame (timestep {last}) is left out",
                      UserWarning, stacklevel=3)
    for f in frames:
        if "columns" not in f:
            raise ValueError(f"{path}: frame at timestep {f['timestep']} has no ITEM: ATOMS")
        if "box" not in f:
            raise ValueError(f"{path}: frame at timestep {f['timestep']} has no ITEM: BOX BOUNDS")
    if not frames:
        raise ValueError(f"{path}: no complete frame (ITEM: TIMESTEP ... ITEM: ATOMS)")
    return frames


def _real_box(box, flags):
    """(lo (3,), lengths (3,), tilt (xy, xz, yz)) from the BOX BOUNDS lines."""
    if box.shape[1] == 3:  # triclinic: bounding box plus tilt factors
        xy, xz, yz = box[:, 2]
        lo = np.array([box[0, 0] - min(0.0, xy, xz, xy + xz), box[1, 0] - min(0.0, yz), box[2, 0]])
        hi = np.array([box[0, 1] - max(0.0, xy, xz, xy + xz), box[1, 1] - max(0.0, yz), box[2, 1]])
        return lo, hi - lo, (xy, xz, yz)
    return box[:, 0], box[:, 1] - box[:, 0], (0.0, 0.0, 0.0)


def _frame_xy(path, f):
    """Real x, y from whichever coordinate columns the frame has (unsorted)."""
    col = {c: k for k, c in enumerate(f["columns"])}
    for cx, cy in _COORDS:
        if cx in col and cy in col:
            x = f["rows"][:, col[cx]].astype(float)
            y = f["rows"][:, col[cy]].astype(float)
            if cx.startswith("xs"):
                lo, length, (txy, txz, tyz) = _real_box(f["box"], f["box_flags"])
                cz = "zs" if cx == "xs" else "zsu"
                z = f["rows"][:, col[cz]].astype(float) if cz in col else 0.0
                x, y = (lo[0] + x * length[0] + y * txy + z * txz,
                        lo[1] + y * length[1] + z * tyz)
            return np.column_stack([x, y]), (cx, cy)
    missing = [c for c in ("x", "y") if c not in col]
    raise ValueError(f"{path}: frame at timestep {f['timestep']}: no column "
                     f"{' and '.join(repr(c) for c in missing)} (nor xu yu, xs ys, xsu ysu) "
                     f"in ITEM: ATOMS {' '.join(f['columns'])}")


def read_dump(path, columns=None):
    """Frames of a LAMMPS ``dump custom`` (or ``dump atom``) text file (``.gz`` allowed).

    Returns a list with one dict per frame:

    - ``timestep`` (int), ``ids`` (n,) int sorted ascending,
    - ``xy`` (n, 2) float positions sorted by id, in the dump's length unit (SI for CGMS);
      scaled columns (xs ys, xsu ysu) are converted with the box, triclinic included,
    - ``box``: the three BOX BOUNDS lines as written, (3, 2) or (3, 3) for triclinic,
    - ``columns``: {name: (n,) array sorted by id} for the requested extra columns
      (``columns``: a name, a list of names, ``"all"`` for every column except id and the
      coordinates used, or None for none); numeric columns are float, others str,
    - ``time``: simulated time, when the dump has ``ITEM: TIME`` (dump_modify time yes).

    Read in float64 with a plain-text parser: any columns, any ITEM sections, a truncated
    last frame dropped with a warning. (A whole trajectory frame by frame, without loading
    it into memory, is :func:`cgms.trajectory.universe`, MDAnalysis.)

    Raises ValueError for a dump without ``id`` or coordinate columns, naming the missing
    column, or without a requested column.
    """
    frames = _dump_frames(path)
    if isinstance(columns, str) and columns != "all":
        columns = [columns]
    result = []
    for f in frames:
        col = {c: k for k, c in enumerate(f["columns"])}
        if "id" not in col:
            raise ValueError(f"{path}: frame at timestep {f['timestep']}: no column 'id' in "
                             f"ITEM: ATOMS {' '.join(f['columns'])}")
        ids = f["rows"][:, col["id"]].astype(np.int64)
        order = np.argsort(ids, kind="stable")
        ids = ids[order]
        if np.any(np.diff(ids) == 0):
            raise ValueError(f"{path}: frame at timestep {f['timestep']}: repeated atom id "
                             f"{int(ids[np.flatnonzero(np.diff(ids) == 0)[0]])}")
        xy, used = _frame_xy(path, f)
        if columns == "all":
            names = [c for c in f["columns"] if c != "id" and c not in used
                     and c not in ("z", "zu", "zs", "zsu")]
        else:
            names = list(columns or [])
        missing = [c for c in names if c not in col]
        if missing:
            raise ValueError(f"{path}: frame at timestep {f['timestep']}: no column "
                             f"{', '.join(repr(c) for c in missing)} in ITEM: ATOMS "
                             f"{' '.join(f['columns'])}")
        extra = {}
        for c in names:
            raw = f["rows"][order, col[c]]
            try:
                extra[c] = raw.astype(float)
            except ValueError:
                extra[c] = raw
        result.append(dict(timestep=f["timestep"], ids=ids, xy=xy[order], box=f["box"],
                           columns=extra))
        if f["items"].get("TIME"):
            result[-1]["time"] = float(f["items"]["TIME"][0])
    return result
