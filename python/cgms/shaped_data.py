# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shaped coarse model's tissue as LAMMPS reads it (``pair_style cgms/shaped``,
doc/pair_cgms_shaped.rst): per bead its state F and the fixed data of the fresh tissue
(:func:`cgms.shaped_tensor.build`) as per-atom custom properties of ``fix property/atom``,
written into the data file so that read_data, write_data, restart files, migration and
sorting carry them. LAMMPS reads a data file's lines through a 256-character buffer, so
the properties are spread over six fixes (one data-file section each, named as the fix),
none with more than 9 numbers per bead:

- ``shaped_F``: ``d2_shaped_F`` 4, F11 F12 F21 F22, the state;
- ``shaped_nb``: ``i2_shaped_nb`` NB, the IDs of its fresh neighbours (0 fills the row),
  ``i_shaped_id`` its own ID (the pair refuses a tissue whose IDs were renumbered, e.g. by
  ``delete_atoms`` with ``compress yes``), ``i_shaped_nwall`` its number of walls, ``i_shaped_boundary`` 1 for a cell with a free
  wall (ghost points), ``d_shaped_area0`` its fresh polygon area (m^2);
- ``shaped_bx``, ``shaped_by``: ``d2_shaped_bondx``/``bondy`` NB, the fresh bond vectors
  x0_k - x0_i (m), in the order of the IDs;
- ``shaped_wx``, ``shaped_wy``: ``d2_shaped_wallx``/``wally`` NW, its fresh wall vectors
  d0_e (m), ring order (0 fills).

The rest lengths, fresh fluid areas and the fresh strain are not written: the pair derives
them from these and its own keywords (lamella, void, wall_EA), so they cannot disagree.
"""

import numpy as np

from . import folders

#: LAMMPS's read_data line buffer (read_data.cpp MAXLINE)
MAXLINE = 256

#: the pair style's keywords for the prototype's parameters (python name -> keyword)
KEYWORDS = dict(wall_EA="wall_EA", buckle="buckle", soft="soft", beta_a="beta_a",
                beta_b="beta_b", lamella="lamella", kg_ratio="kg_ratio", void="void",
                void_onset="void_onset", smooth="smooth", iso="iso", strip="strip")


def _slots(owner, n):
    """The place of each entry within its owner's row, for entries sorted by owner: 0, 1,
    ... per owner, and the row width."""
    counts = np.bincount(owner, minlength=n)
    first = np.cumsum(counts) - counts
    return np.arange(len(owner)) - first[owner], int(counts.max(initial=0))


def per_bead(geo):
    """The fixed per-bead arrays of a built tissue (:func:`cgms.shaped_tensor.build`, dense
    or ``local=True``): dict with nb (n, NB) IDs in increasing order, bondx, bondy (n, NB),
    wallx, wally (n, NW) in ring order, nwall, area0, boundary. Vectorised, so that the
    macroscale tissue's data take a fraction of a second."""
    n, x0 = geo["n"], geo["x0"]
    pairs = np.concatenate([geo["bonds"], geo["bonds"][:, ::-1]])
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    slot, NB = _slots(pairs[:, 0], n)
    walls = np.argsort(geo["cell"], kind="stable")     # ring order kept within a cell
    wslot, NW = _slots(geo["cell"][walls], n)
    out = dict(nb=np.zeros((n, NB), dtype=np.int64), bondx=np.zeros((n, NB)),
               bondy=np.zeros((n, NB)), wallx=np.zeros((n, NW)), wally=np.zeros((n, NW)),
               nwall=np.bincount(geo["cell"], minlength=n),
               area0=np.asarray(geo["poly_area0"], float),
               boundary=np.asarray(geo["boundary"], dtype=int))
    i, k = pairs[:, 0], pairs[:, 1]
    out["nb"][i, slot] = k + 1
    out["bondx"][i, slot], out["bondy"][i, slot] = (x0[k] - x0[i]).T
    owner = geo["cell"][walls]
    out["wallx"][owner, wslot], out["wally"][owner, wslot] = geo["d0"][walls].T
    return out


def _fixes(b):
    """[(fix ID, property/atom arguments, [per-bead column arrays])]."""
    NB, NW = b["nb"].shape[1], b["wallx"].shape[1]
    return [("shaped_F", "d2_shaped_F 4", None),
            ("shaped_nb", f"i2_shaped_nb {NB} i_shaped_id i_shaped_nwall i_shaped_boundary "
             "d_shaped_area0", [b["nb"], np.arange(1, len(b["nb"]) + 1)[:, None],
                                b["nwall"][:, None], b["boundary"][:, None], b["area0"][:, None]]),
            ("shaped_bx", f"d2_shaped_bondx {NB}", [b["bondx"]]),
            ("shaped_by", f"d2_shaped_bondy {NB}", [b["bondy"]]),
            ("shaped_wx", f"d2_shaped_wallx {NW}", [b["wallx"]]),
            ("shaped_wy", f"d2_shaped_wally {NW}", [b["wally"]])]


def fix_command(geo):
    """The ``fix property/atom`` lines that define the properties (before read_data);
    ``geo`` a built tissue or its :func:`per_bead` arrays."""
    b = geo if "wallx" in geo else per_bead(geo)
    return "\n".join(f"fix {fid} all property/atom {args}" for fid, args, _ in _fixes(b))


def read_command(path):
    """The ``read_data`` line that reads the tissue and its sections."""
    fixes = _fixes(dict(nb=np.zeros((1, 1)), wallx=np.zeros((1, 1)), nwall=np.zeros(1),
                        boundary=np.zeros(1), area0=np.zeros(1), bondx=0, bondy=0, wally=0))
    return f"read_data {path} " + " ".join(f"fix {fid} NULL {fid}" for fid, _, _ in fixes)


def pair_style(s, params=None):
    """``pair_style cgms/shaped`` with dryness ``s`` and the prototype's ``params``."""
    words = [f"dryness {float(s)!r}"]
    for key, value in (params or {}).items():
        if key not in KEYWORDS:
            raise ValueError(f"pair_style cgms/shaped has no keyword for {key!r}")
        words.append(f"{KEYWORDS[key]} {value if isinstance(value, str) else repr(float(value))}")
    return "pair_style cgms/shaped " + " ".join(words)


def write_data(path, geo, z, margin=None, title="CGMS shaped tissue", overwrite=False):
    """Write the tissue ``geo`` (built, or its :func:`per_bead` arrays with "n") in state
    ``z`` (:mod:`cgms.shaped_tensor`'s [x, F]) as a
    LAMMPS data file for ``atom_style atomic`` with the ``shaped`` section (read it with
    :func:`fix_command` and :func:`read_command`). Every number is written so that it reads
    back to the same double. The box leaves ``margin`` (default 4 x the longest fresh bond)
    around the tissue. Returns the number of beads."""
    n = geo["n"] if "n" in geo else len(geo["nb"])
    z = np.asarray(z, float)
    if z.shape != (6 * n,):
        raise ValueError(f"z must hold 6 n = {6 * n} numbers, not {z.shape}")
    if not np.all(np.isfinite(z)):
        raise ValueError("z holds non-finite numbers")
    x, F = z[:2 * n].reshape(n, 2), z[2 * n:].reshape(n, 4)
    b = geo if "wallx" in geo else per_bead(geo)
    if margin is None:
        margin = 4 * max(np.abs(b["bondx"]).max(), np.abs(b["bondy"]).max())
    lo, hi = x.min(axis=0) - margin, x.max(axis=0) + margin
    lines = [" ".join(str(title).split()) or "CGMS shaped tissue", "", f"{n} atoms",
             "1 atom types", "", f"{lo[0]!r} {hi[0]!r} xlo xhi", f"{lo[1]!r} {hi[1]!r} ylo yhi",
             f"{-margin!r} {margin!r} zlo zhi", "", "Masses", "", "1 1.0", "", "Atoms # atomic",
             ""]
    lines += [f"{i + 1} 1 {x[i, 0]!r} {x[i, 1]!r} 0.0" for i in range(n)]
    for fid, args, columns in _fixes(b):
        columns = [F] if columns is None else columns
        lines += ["", f"{fid} # {args}", ""]
        for i in range(n):
            words = [str(i + 1)] + [repr(v) if isinstance(v, float) else str(v)
                                    for c in columns for v in c[i].tolist()]
            line = " ".join(words)
            if len(line) >= MAXLINE:
                raise ValueError(f"bead {i + 1}'s {fid} line has {len(line)} characters; LAMMPS "
                                 f"reads at most {MAXLINE - 1} (a cell with too many walls or "
                                 "neighbours for this format)")
            lines.append(line)
    folders.write_text(path, "\n".join(lines) + "\n", overwrite)
    return n
