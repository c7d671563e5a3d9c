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


def per_bead(geo):
    """The fixed per-bead arrays of a built tissue (:func:`cgms.shaped_tensor.build`):
    dict with nb (n, NB) IDs, bondx, bondy (n, NB), wallx, wally (n, NW), nwall, area0,
    boundary."""
    n = geo["n"]
    x0 = geo["x0"]
    nbr = [np.flatnonzero(row) for row in geo["topo"]["neighbours"]]
    walls = [np.flatnonzero(geo["cell"] == i) for i in range(n)]
    NB = max(len(k) for k in nbr)
    NW = max(len(e) for e in walls)
    out = dict(nb=np.zeros((n, NB), dtype=np.int64), bondx=np.zeros((n, NB)),
               bondy=np.zeros((n, NB)), wallx=np.zeros((n, NW)), wally=np.zeros((n, NW)),
               nwall=np.array([len(e) for e in walls]),
               area0=np.asarray(geo["poly_area0"], float),
               boundary=np.asarray(geo["boundary"], dtype=int))
    for i in range(n):
        k, e = nbr[i], walls[i]
        out["nb"][i, :len(k)] = k + 1
        out["bondx"][i, :len(k)], out["bondy"][i, :len(k)] = (x0[k] - x0[i]).T
        out["wallx"][i, :len(e)], out["wally"][i, :len(e)] = geo["d0"][e].T
    return out


def per_bead_local(xy, spacing, cutoff=None):
    """:func:`per_bead` of the tissue built at ``xy`` (n, 2) without its (n, n) arrays:
    each bead's ring, walls and fresh polygon from :func:`cgms.shaped.topology` and
    :func:`cgms.shaped.junction_map` on the patch of the bead and its neighbours (its ring
    needs only their positions and which of them neighbour each other), so that a tissue
    of 10^4-10^5 beads fits in memory. The same numbers as :func:`per_bead` to rounding (a patch sums a junction's
    terms in another order)."""
    from scipy.spatial import cKDTree

    from . import shaped
    xy = np.asarray(xy, float)
    cutoff = shaped.CUTOFF if cutoff is None else cutoff
    tree = cKDTree(xy)
    rows = []
    for i in range(len(xy)):
        patch = np.array(sorted(tree.query_ball_point(xy[i], 1.01 * cutoff * spacing)))
        topo = shaped.topology(xy[patch], spacing, cutoff)
        M, cell, ja, jb, ghost = shaped.junction_map(topo, 1.0)
        me = int(np.flatnonzero(patch == i)[0])
        x = xy[patch]
        J = (M @ x.ravel()).reshape(-1, 2)
        e = np.flatnonzero(cell == me)
        a, b = J[ja[e]] - x[me], J[jb[e]] - x[me]
        k = np.flatnonzero(topo["neighbours"][me])
        rows.append(dict(nb=patch[k] + 1, bond=xy[patch[k]] - xy[i], wall=b - a,
                         area0=0.5 * np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]),
                         boundary=int(ghost[e].any())))
    n, NB = len(xy), max(len(r["nb"]) for r in rows)
    NW = max(len(r["wall"]) for r in rows)
    out = dict(nb=np.zeros((n, NB), dtype=np.int64), bondx=np.zeros((n, NB)),
               bondy=np.zeros((n, NB)), wallx=np.zeros((n, NW)), wally=np.zeros((n, NW)),
               nwall=np.array([len(r["wall"]) for r in rows]),
               area0=np.array([r["area0"] for r in rows]),
               boundary=np.array([r["boundary"] for r in rows]))
    for i, r in enumerate(rows):
        m, w = len(r["nb"]), len(r["wall"])
        out["nb"][i, :m] = r["nb"]
        out["bondx"][i, :m], out["bondy"][i, :m] = r["bond"].T
        out["wallx"][i, :w], out["wally"][i, :w] = r["wall"].T
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
