# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Bead positions in files: LAMMPS data files of ``atom_style cgms`` (written by
:func:`write_data`, read back by :func:`read_data`, the one parser of an Atoms section) and
plain centroid lists (``id x y`` per line, metres), e.g. digitised from a micrograph or the
reference centroids of a calibration. LAMMPS dumps are read by
:func:`cgms.morphology.read_dump`; :func:`read_any` takes any of the three."""

from pathlib import Path

import numpy as np

from . import folders


def _check_positive(name, value):
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def write_data(path, xy, margin, title="CGMS tissue", diameters=None, overwrite=False,
               ids=None):
    """Write positions ``xy`` (n, 2) in metres as a LAMMPS data file for atom_style cgms
    (Atoms columns: id type x y z). The box leaves ``margin`` metres around the tissue
    (z from -margin to margin). Returns the number of beads.

    ``diameters`` (n values, m): also write a ``Diameters`` section (lines ``id value``),
    read into a per-atom property by::

        fix diam all property/atom d_diameter            # before read_data
        read_data tissue.data fix diam NULL Diameters
        variable d atom d_diameter
        fix fluid all cgms/fluid diameter v_d ...

    ``ids``: the atom ids (default 1..n). An existing file is never replaced unless
    ``overwrite=True`` (FileExistsError)."""
    xy = np.asarray(xy, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2 or len(xy) == 0:
        raise ValueError(f"xy must be a non-empty (n, 2) array, got shape {xy.shape}")
    if not np.all(np.isfinite(xy)):
        raise ValueError("xy holds non-finite positions")
    margin = _check_positive("margin", margin)
    if diameters is not None:
        diameters = np.asarray(diameters, dtype=float).ravel()
        if len(diameters) != len(xy):
            raise ValueError(f"{len(diameters)} diameters for {len(xy)} beads")
        if not np.all(np.isfinite(diameters) & (diameters > 0)):
            raise ValueError("diameters must be positive finite numbers")
    ids = np.arange(1, len(xy) + 1) if ids is None else np.asarray(ids, dtype=np.int64).ravel()
    if len(ids) != len(xy) or len(np.unique(ids)) != len(ids) or ids.min() < 1:
        raise ValueError(f"ids must be {len(xy)} distinct positive integers")
    lo = xy.min(axis=0) - margin
    hi = xy.max(axis=0) + margin
    lines = [
        " ".join(str(title).split()) or "CGMS tissue",
        "",
        f"{len(xy)} atoms",
        "1 atom types",
        "",
        f"{lo[0]:.10e} {hi[0]:.10e} xlo xhi",
        f"{lo[1]:.10e} {hi[1]:.10e} ylo yhi",
        f"{-margin:.10e} {margin:.10e} zlo zhi",
        "",
        "Atoms # cgms",
        "",
    ]
    lines += [f"{i} 1 {x:.12e} {y:.12e} 0.0" for i, (x, y) in zip(ids, xy)]
    if diameters is not None:
        lines += ["", "Diameters", ""]
        lines += [f"{i} {d:.17g}" for i, d in zip(ids, diameters)]
    folders.write_text(path, "\n".join(lines) + "\n", overwrite)
    return len(xy)


def _sections(path, lines):
    """{section name: [(line number, words)]} of a data file's body (after the header)."""
    out, name = {}, None
    for lineno, raw in enumerate(lines, 1):
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) == 1 and words[0][0].isalpha():
            name = words[0]
            if name in out:
                raise ValueError(f"{path} line {lineno + 1}: a second {name} section")
            out[name] = []
        elif name is not None:
            out[name].append((lineno, words))
    return out


def _declared_atoms(lines):
    """The atom count of a data file's header ('N atoms', before the first section), or
    None."""
    for raw in lines:
        words = raw.split("#", 1)[0].split()
        if len(words) == 1 and words[0][0].isalpha():
            return None                      # the first section: the header is over
        if len(words) == 2 and words[1] == "atoms":
            try:
                return int(words[0])
            except ValueError:
                return None
    return None


def _atoms_style(lines):
    """The atom style a data file's Atoms line names (``Atoms # cgms``), or None."""
    for raw in lines[1:]:
        head, _, hint = raw.partition("#")
        if head.split() == ["Atoms"]:
            return hint.split()[0] if hint.split() else None
    return None


def read_data(path):
    """The beads of a LAMMPS data file of ``atom_style cgms``: a dict with ``ids`` (sorted),
    ``xy`` (n, 2, ordered by id, metres) and ``diameters`` (ordered by id, or None without a
    ``Diameters`` section). ValueError names the file and line of anything malformed."""
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None
    sections = _sections(path, lines[1:])   # line 1 is the title
    # the header lines (counts, box) come before the first section
    if "Atoms" not in sections:
        raise ValueError(f"{path}: no Atoms section (not a LAMMPS data file?)")
    style = _atoms_style(lines)
    if style not in (None, "cgms", "atomic"):
        # another style's columns differ (angle: id mol type x y z): x would be read wrong
        raise ValueError(f"{path}: its Atoms section is of atom_style {style}; a tissue file "
                         "is of atom_style cgms or atomic ('id type x y z': cgms tissue, or "
                         "LAMMPS's write_data of a CGMS run)")
    rows = []
    for lineno, words in sections["Atoms"]:
        try:
            if len(words) < 5:
                raise ValueError
            rows.append((int(words[0]), float(words[2]), float(words[3])))
        except ValueError:
            raise ValueError(f"{path} line {lineno + 1}: expected 'id type x y z' in the Atoms "
                             "section") from None
    if not rows:
        raise ValueError(f"{path}: the Atoms section is empty")
    declared = _declared_atoms(lines[1:])
    if declared is not None and declared != len(rows):
        raise ValueError(f"{path}: its header declares {declared} atoms, its Atoms section "
                         f"holds {len(rows)} (a file cut short or edited by hand?)")
    rows.sort()
    ids = np.array([r[0] for r in rows], dtype=np.int64)
    if np.any(np.diff(ids) == 0):
        raise ValueError(f"{path}: atom id {ids[np.flatnonzero(np.diff(ids) == 0)[0]]} given "
                         "twice")
    xy = np.array([r[1:] for r in rows], dtype=float)
    diameters = None
    if "Diameters" in sections:
        found = {}
        for lineno, words in sections["Diameters"]:
            try:
                found[int(words[0])] = float(words[1])
            except (ValueError, IndexError):
                raise ValueError(f"{path} line {lineno + 1}: expected 'id diameter' in the "
                                 "Diameters section") from None
        missing = [int(i) for i in ids if int(i) not in found]
        if missing:
            raise ValueError(f"{path}: no diameter for atom id(s) {missing[:10]}")
        diameters = np.array([found[int(i)] for i in ids])
    return dict(ids=ids, xy=xy, diameters=diameters)


def read_centroids(path):
    """``(ids, xy)`` of a centroid list: one ``id x y`` line per cell (metres; ``#``
    comments, blank lines and a first header line such as ``id x y`` are skipped; commas
    count as spaces; further columns are ignored). A LAMMPS dump gives its last frame."""
    path = Path(path)
    text = path.read_text()
    first = next((line.strip() for line in text.splitlines() if line.strip()), "")
    if first.startswith("ITEM:"):
        from . import morphology
        frame = morphology.read_dump(path)[-1]
        return frame["ids"], frame["xy"]
    ids, xy, seen = [], [], False
    for lineno, raw in enumerate(text.splitlines(), 1):
        words = raw.split("#", 1)[0].replace(",", " ").split()
        if not words:
            continue
        if not seen and not _is_number(words[0]):
            seen = True   # a header line (id x y)
            continue
        seen = True
        if len(words) < 3:
            raise ValueError(f"{path} line {lineno}: expected 'id x y', got {raw.strip()!r}")
        try:
            ident = int(words[0])
            x, y = float(words[1]), float(words[2])
        except ValueError:
            raise ValueError(f"{path} line {lineno}: expected an integer id and two numbers, "
                             f"got {raw.strip()!r}") from None
        ids.append(ident)
        xy.append((x, y))
    if not ids:
        raise ValueError(f"{path}: no 'id x y' lines")
    return np.array(ids, dtype=np.int64), np.array(xy, dtype=float)


def _is_number(word):
    try:
        float(word)
        return True
    except ValueError:
        return False


def write_centroids(path, xy, ids=None, comment="", overwrite=False):
    """Write positions (metres) as an ``id x y`` centroid list (ids 1..n by default)."""
    xy = np.asarray(xy, float)
    ids = np.arange(1, len(xy) + 1) if ids is None else np.asarray(ids, int)
    lines = [f"# {line}" for line in comment.splitlines()] + ["# id x y (m)"]
    lines += [f"{i} {x!r} {y!r}" for i, (x, y) in zip(ids, xy)]
    return folders.write_text(path, "\n".join(lines) + "\n", overwrite)


def is_data_file(path):
    """Whether ``path`` is a LAMMPS data file (it has an Atoms section), rather than a
    centroid list or a dump."""
    try:
        with open(path) as fh:
            return any(line.split("#", 1)[0].strip() == "Atoms" for line in fh)
    except UnicodeDecodeError:
        return False


def read_vertices(path):
    """Polygon vertices from a text file: one ``x y`` pair (metres) per line; blank lines
    and ``#`` comments are ignored."""
    rows = []
    for lineno, raw in enumerate(Path(path).read_text().splitlines(), 1):
        words = raw.split("#", 1)[0].replace(",", " ").split()
        if not words:
            continue
        if len(words) != 2:
            raise ValueError(f"{path} line {lineno}: expected 'x y', got {raw.strip()!r}")
        try:
            rows.append([float(words[0]), float(words[1])])
        except ValueError:
            raise ValueError(f"{path} line {lineno}: not numbers: {raw.strip()!r}") from None
    return np.array(rows).reshape(-1, 2)
