# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Run a 3-D fine-scale (MFC) tissue in LAMMPS (doc/mfc.md, "3-D tissue"): its styles,
the drying levers of a level, minimisation to rest, and the measures of cells and tissue.

The styles: ``bond harmonic`` (wall edges and lamella), ``angle zero`` (the triangles
``fix mfc/pressure3d`` reads), ``dihedral harmonic`` (bending), and ``pair hybrid`` of two
``nm/cut``: the lamella's LJ between walls of different cells (different colours, atom
types), every pair counted (a lamella bond does not hide the LJ of its pair, as in 2-D),
and the wall's self-avoidance within one cell (one colour), sparing bonded pairs
(:data:`cgms.mfc.tissue3d.SELF_SPECIAL`). Every force has an energy, so steady
states are minima.
"""

import math

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from .model import level
from . import cell3d, tissue3d

DEFAULTS = dict(ftol=1e-10, chunk=2000, stage=0.05, max_iterations=20000, dmax=1e-7,
                kick=1e-7, seed=1)


def setup_commands(data, w, newton="on", processors=None):
    """LAMMPS commands that read a 3-D tissue data file
    (:func:`cgms.mfc.tissue3d.write_data`) and define its forces; the fluid and the wall
    rest lengths of a level follow with :func:`level_commands`."""
    rc = w["lamella_rc"]
    reach = w["spacing"]
    lines = ["units si", "dimension 3", "boundary s s s", f"newton {newton}",
             "atom_style molecular", "atom_modify map array"]
    if processors:
        lines.append(f"processors {processors}")
    lines += ["bond_style harmonic", "angle_style zero", "dihedral_style harmonic",
              f"read_data {data}", "angle_coeff *", *pair_commands(w),
              "neighbor 2e-6 bin", "neigh_modify delay 0 every 1 check yes",
              # a dihedral's far corner may be two wall edges from a rank's atoms
              f"comm_modify cutoff {max(3 * reach, rc + 2e-6):.6e}"]
    return lines


def pair_commands(w):
    """The pair forces of a 3-D tissue (after ``read_data``): the lamella's LJ between
    walls of different colours, the self-avoidance within a colour (a cell), each with its
    own weights of bonded pairs (``pair_modify special``). LAMMPS lets a sub-style set
    those only where the global ``special_bonds`` weight is neither 0 nor 1 (which change
    the neighbour list), so where the two differ the global weight is a placeholder, 0.5,
    that both replace; elsewhere it is 1 (LAMMPS then keeps no 1-3 and 1-4 lists, which
    the glued walls would make large)."""
    rc, r0 = w["lamella_rc"], w["self_r0"]
    spared = " ".join(f"{v:g}" for v in tissue3d.SELF_SPECIAL)
    placeholder = " ".join("1.0" if v == 1.0 else "0.5" for v in tissue3d.SELF_SPECIAL)
    lines = [f"special_bonds lj {placeholder} coul 1.0 1.0 1.0",
             f"pair_style hybrid nm/cut {rc:.10g} nm/cut {r0:.10g}", "pair_modify shift yes",
             f"pair_coeff * * nm/cut 1 {w['lamella_E0']:.10g} {w['pectin']:.10g} 8 4 "
             f"{rc:.10g}"]
    lines += [f"pair_coeff {t} {t} nm/cut 2 {w['self_E0']:.10g} {r0:.10g} 8 4 {r0:.10g}"
              for t in range(1, tissue3d.COLOURS + 1)]
    lines += ["pair_modify pair nm/cut 1 special lj 1.0 1.0 1.0",
              f"pair_modify pair nm/cut 2 special lj {spared}"]
    return lines


def level_commands(p, w, s, fix_id="cell"):
    """The drying levers at dryness ``s`` (:func:`cgms.mfc.model.level`): the fluid mass s
    times fresh (its rest volume ``s pi D^3 / 6``), turgor ``s P_T``, every wall bond's rest
    length times c(s). The lamella bonds keep their fresh rest lengths."""
    lv = level(p, s)
    lines = [f"bond_coeff {t} {w['k_bond'] / 2:.17e} {r * lv['contraction']:.17e}"
             for t, r in enumerate(w["rest_classes"], start=1)]
    lines += [f"fix {fix_id} all mfc/pressure3d modulus {p['K']:.10g} "
              f"turgor {lv['turgor']:.10g} volume {s * w['fluid_volume']:.15e}",
              f"fix_modify {fix_id} energy yes"]
    return lines


def minimize(lmp, ftol, iterations, dmax=DEFAULTS["dmax"]):
    """Conjugate gradients (quadratic line search) down to the largest force component
    ``ftol`` (N) or ``iterations``."""
    lmp.commands_list(["min_style cg", f"min_modify norm max dmax {dmax:.10g} line quadratic",
                       f"minimize 0.0 {ftol:.10g} {int(iterations)} {10 * int(iterations)}"])


def positions(lmp):
    """Wall particle positions (N, 3) ordered by atom ID (any number of ranks)."""
    n = lmp.get_natoms()
    return np.array(lmp.gather_atoms("x", 1, 3), dtype=float).reshape(n, 3)


def fmax(lmp):
    """Largest force component on any particle (N), after ``run 0``."""
    lmp.command("run 0")
    n = lmp.get_natoms()
    return float(np.abs(np.array(lmp.gather_atoms("f", 1, 3))).max()) if n else 0.0


def relax(lmp, p, w, s, ftol=DEFAULTS["ftol"], chunk=DEFAULTS["chunk"],
          max_iterations=DEFAULTS["max_iterations"], dmax=DEFAULTS["dmax"]):
    """Set the levers of ``s`` and minimise in chunks until the largest force is below
    ``ftol`` or ``max_iterations`` are spent. Returns iterations, largest force, energy,
    converged."""
    lmp.commands_list(["unfix cell"] if lmp.has_id("fix", "cell") else [])
    lmp.commands_list(level_commands(p, w, s))
    start = lmp.extract_global("ntimestep")
    while True:
        before = lmp.extract_global("ntimestep")
        minimize(lmp, ftol, min(chunk, max_iterations - (before - start)), dmax)
        done = lmp.extract_global("ntimestep") - start
        f = fmax(lmp)
        stalled = lmp.extract_global("ntimestep") == before
        if f < ftol or done >= max_iterations or stalled:
            break
    return dict(iterations=int(done), fmax=f, energy=float(lmp.get_thermo("pe")),
                converged=bool(f < ftol))


def kick(lmp, size, seed):
    """Move every wall particle at random by up to ``size`` (m): a contracted wall held in
    its symmetric shape is a saddle a minimiser started there never leaves (as 2-D)."""
    lmp.command(f"displace_atoms all random {size:.10g} {size:.10g} {size:.10g} "
                f"{int(seed)} units box")


def cells(x, w):
    """Per cell: volume centroid (n, 3), enclosed volume, wall area, from wall positions
    ``x`` (N, 3) in cell order."""
    m, tri = len(w["x"]), w["tri"]
    out = dict(centroid=[], volume=[], area=[])
    for c in range(len(x) // m):
        xc = x[c * m:(c + 1) * m]
        o = xc.mean(axis=0)
        y = xc - o
        a, b, d = y[tri[:, 0]], y[tri[:, 1]], y[tri[:, 2]]
        v6 = np.einsum("ij,ij->i", a, np.cross(b, d))        # 6 x tetrahedron volumes
        out["volume"].append(v6.sum() / 6)
        out["centroid"].append(o + (v6[:, None] * (a + b + d)).sum(axis=0) / (4 * v6.sum()))
        out["area"].append(cell3d.area(xc, tri))
    return {k: np.array(v) for k, v in out.items()}


def winding(points, x, tri):
    """Winding number of each point about the closed outward triangle mesh (x, tri): 1
    inside, 0 outside (the solid angles of its triangles over 4 pi, Van Oosterom and
    Strackee, IEEE Trans. Biomed. Eng. 30, 1983, 125)."""
    a = x[tri[:, 0]][None] - points[:, None]
    b = x[tri[:, 1]][None] - points[:, None]
    c = x[tri[:, 2]][None] - points[:, None]
    la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
    num = np.einsum("pti,pti->pt", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("pti,pti->pt", a, b) * lc
           + np.einsum("pti,pti->pt", b, c) * la + np.einsum("pti,pti->pt", c, a) * lb)
    return 2 * np.arctan2(num, den).sum(axis=1) / (4 * math.pi)


def intrusions(x, w):
    """Wall particles lying inside another cell's wall (walls that passed through each
    other): (particle, cell) pairs, 0-based. Empty when the lamella kept them apart."""
    m, tri = len(w["x"]), w["tri"]
    ncell = len(x) // m
    found = []
    for c in range(ncell):
        xc = x[c * m:(c + 1) * m]
        lo, hi = xc.min(axis=0), xc.max(axis=0)
        near = np.nonzero(np.all((x >= lo) & (x <= hi), axis=1))[0]
        near = near[near // m != c]
        if len(near):
            inside = near[winding(x[near], xc, tri) > 0.5]
            found += [(int(i), c) for i in inside]
    return found


def tissue(x, cell_measures):
    """The tissue's measures: volume and surface of the convex hull of all wall particles,
    the cells' summed volume, the extents along x, y, z (the block's axes); and those of
    the cell centroids (the 2-D reference's tissue measures are its centroids'): their
    hull's volume and surface and their extents."""
    hull = ConvexHull(x)
    c = cell_measures["centroid"]
    out = dict(volume=float(hull.volume), surface=float(hull.area),
               cell_volume=float(cell_measures["volume"].sum()),
               extents=[float(e) for e in x.max(axis=0) - x.min(axis=0)],
               centroid_extents=[float(e) for e in c.max(axis=0) - c.min(axis=0)])
    try:
        inner = ConvexHull(c)
        out.update(centroid_volume=float(inner.volume), centroid_surface=float(inner.area))
    except QhullError:                     # fewer than four cells, or all in one plane
        out.update(centroid_volume=0.0, centroid_surface=0.0)
    return out
