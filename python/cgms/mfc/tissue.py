# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Build fine-scale (MFC) tissues: one closed wall ring per cell around each CGMS bead.

Cell i of the MFC is bead i of the CGMS tissue: the cell centres are the bead positions of
a CGMS layout (:func:`cgms.tissue.rectangle`, ...) or data file, in the same order. Each cell
starts as a hexagon of the reference cell's area (side ``b_ref``) whose sides face the
lattice neighbours, so adjacent walls are parallel and one pectin layer (``x_ref - 2
apothem = d_p``) apart. ``per_side`` wall particles per side, vertices included, numbered
counter-clockwise with consecutive atom IDs; molecule ID = cell index + 1; atom type =
cell colour + 1 (three colours, no two adjacent cells alike, so pair coefficients tell
"own cell" from "neighbour cell").
"""

import math

import numpy as np
from scipy.spatial import cKDTree

from .. import folders

#: neighbours closer than this many lattice spacings are adjacent cells
ADJACENT = 1.2


def neighbour_angle(centres, spacing):
    """Direction (radians) of one lattice neighbour: of the closest pair of centres, or
    pi/2 (the CGMS default, rows along y) for a single cell."""
    c = np.asarray(centres, float)
    if len(c) < 2:
        return math.pi / 2
    dist, idx = cKDTree(c).query(c, k=2)
    i = int(np.argmin(dist[:, 1]))
    if dist[i, 1] > ADJACENT * spacing:
        return math.pi / 2
    d = c[idx[i, 1]] - c[i]
    return math.atan2(d[1], d[0])


def hexagon(centre, side, angle, per_side=16):
    """Wall particle positions (6 per_side, 2) of a hexagon of side ``side`` about
    ``centre`` whose sides face the directions ``angle + k 60 deg``, counter-clockwise,
    starting at the vertex at ``angle - 30 deg``."""
    k = np.arange(7)
    theta = angle - math.pi / 6 + k * math.pi / 3
    v = np.asarray(centre, float) + side * np.column_stack([np.cos(theta), np.sin(theta)])
    t = np.arange(per_side)[:, None] / per_side
    return np.concatenate([v[j] + t * (v[j + 1] - v[j]) for j in range(6)])


def colours(centres, spacing, angle):
    """Three-colouring of cells on a hexagonal lattice: lattice coordinates (q, r) along
    the neighbour directions ``angle`` and ``angle + 60 deg``, colour (q - r) mod 3 (the
    six neighbours differ by +-1 or +-2). ValueError when two adjacent cells share a
    colour (centres off the lattice)."""
    c = np.asarray(centres, float)
    e1 = spacing * np.array([math.cos(angle), math.sin(angle)])
    e2 = spacing * np.array([math.cos(angle + math.pi / 3), math.sin(angle + math.pi / 3)])
    qr = np.rint(np.linalg.solve(np.column_stack([e1, e2]), (c - c[0]).T).T).astype(int)
    col = (qr[:, 0] - qr[:, 1]) % 3
    pairs = cKDTree(c).query_pairs(ADJACENT * spacing, output_type="ndarray")
    same = pairs[col[pairs[:, 0]] == col[pairs[:, 1]]] if len(pairs) else pairs
    if len(same):
        i, j = same[0]
        raise ValueError(f"cells {i + 1} and {j + 1} are adjacent but share a colour: the "
                         "cell centres must lie on one hexagonal lattice")
    return col


def walls(centres, p):
    """Wall particles of every cell: positions (n_cells * n_wall, 2) in cell order, the
    cell (0-based) and colour of each particle, and the lattice angle."""
    c = np.asarray(centres, float)
    if c.ndim != 2 or c.shape[1] != 2 or len(c) == 0 or not np.all(np.isfinite(c)):
        raise ValueError(f"cell centres must be a non-empty finite (n, 2) array, got {c.shape}")
    if len(c) > 1:
        d = cKDTree(c).query(c, k=2)[0][:, 1].min()
        if d < 0.99 * p["x_ref"]:
            raise ValueError(f"two cell centres are {d:.4g} m apart, closer than the cell "
                             f"spacing x_ref = {p['x_ref']:.4g} m: their walls would overlap")
    angle = neighbour_angle(c, p["x_ref"])
    col = colours(c, p["x_ref"], angle)
    ring = [hexagon(ci, p["b_ref"], angle, int(p["per_side"])) for ci in c]
    n = p["n_wall"]
    return dict(xy=np.concatenate(ring), cell=np.repeat(np.arange(len(c)), n),
                colour=np.repeat(col, n), angle=angle)


def fluid_points(centre, p, angle=math.pi / 2):
    """SPH fluid particles of one cell: the square lattice of spacing ``fluid_spacing``
    offset by half a spacing from the centre, kept where every hexagon side line is at
    least ``fluid_margin`` away (656 points for the reference cell)."""
    h = p["fluid_spacing"]
    apothem = p["b_ref"] * math.sqrt(3) / 2
    m = int(math.ceil(p["b_ref"] / h)) + 1
    g = (np.arange(-m, m) + 0.5) * h
    pts = np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
    normals = np.array([[math.cos(angle + k * math.pi / 3), math.sin(angle + k * math.pi / 3)]
                        for k in range(6)])
    keep = np.all(pts @ normals.T <= apothem - p["fluid_margin"] + 1e-12 * h, axis=1)
    return np.asarray(centre, float) + pts[keep]


def lamella_bonds(xy, cell, p):
    """The bonded middle lamella: pairs (i, j) of wall particles of different cells, 0-based,
    within ``hypot(d_p, 1.05 l)`` of each other (``l`` the built wall particle spacing), and
    their kind: 2 for a particle and the one facing it across the pectin layer (closer than
    ``1.05 d_p``; at a built cell corner, the corners of the two other cells), 3 for the
    facing particle's neighbours along its wall (the diagonals of the truss, which resist
    the walls sliding along each other)."""
    xy, cell = np.asarray(xy, float), np.asarray(cell)
    spacing = p["b_ref"] / int(p["per_side"])
    reach = math.hypot(p["pectin"], 1.05 * spacing)
    pairs = cKDTree(xy).query_pairs(reach, output_type="ndarray")
    if not len(pairs):
        return np.zeros((0, 2), int), np.zeros(0, int)
    pairs = pairs[cell[pairs[:, 0]] != cell[pairs[:, 1]]]
    d = np.hypot(*(xy[pairs[:, 0]] - xy[pairs[:, 1]]).T)
    kind = np.where(d < 1.05 * p["pectin"], 2, 3)
    return pairs, kind


#: rest lengths of a lamella set in the fresh tissue are binned to this (m): one bond type
#: per bin (LAMMPS's harmonic bond has one rest length per type)
REST_BIN = 1e-8


def fresh_lamella(xy, cell, p):
    """The lamella set in a relaxed fresh tissue (wall positions ``xy``): the pairs of
    :func:`lamella_bonds` there, each at rest at its present length, binned to
    :data:`REST_BIN`. Returns the pairs (0-based), their bond types (2, 3, ...) and the rest
    length of each type (index 0 = type 2). Where the fresh cells rounded up and left a gap
    wider than the reach (at three-cell corners), no bond forms."""
    xy = np.asarray(xy, float)
    pairs, _ = lamella_bonds(xy, cell, p)
    d = np.hypot(*(xy[pairs[:, 0]] - xy[pairs[:, 1]]).T)
    bins = np.rint(d / REST_BIN).astype(int)
    used, index = np.unique(bins, return_inverse=True)
    return pairs, index + 2, used * REST_BIN


def write_data(path, centres, p, s=1.0, margin=None, title="MFC tissue", overwrite=False,
               xy=None, lamella=None):
    """LAMMPS data file of the wall rings (``atom_style angle``: ``id mol type x y z``),
    with the ring bonds (i -> next, counter-clockwise, type 1) and an angle at every wall
    particle (prev, i, next). Wall masses are those of dryness ``s``. The lamella bonds:
    ``lamella`` = (pairs, types) as from :func:`fresh_lamella`, else those of ``p``'s
    lamella at the built walls (types 2 and 3 for "bonded", 2 for "facing", none
    otherwise). ``xy``: wall positions other than the built ones (same cells, same
    order). Returns the :func:`walls` dict. An existing file is kept unless ``overwrite``."""
    from .model import level
    w = walls(centres, p)
    xy = w["xy"] if xy is None else np.asarray(xy, float)
    n, ncell = p["n_wall"], len(centres)
    if xy.shape != w["xy"].shape:
        raise ValueError(f"{len(xy)} wall positions for {len(w['xy'])} wall particles")
    margin = 3 * p["x_ref"] if margin is None else margin
    lo, hi = xy.min(axis=0) - margin, xy.max(axis=0) + margin
    ids = np.arange(1, len(xy) + 1)
    first = w["cell"] * n + 1
    nxt = first + (ids - first + 1) % n
    prv = first + (ids - first - 1) % n
    mass = level(p, s)["wall_mass"]
    ring = [(1, i, j) for i, j in zip(ids, nxt)]
    if lamella is None and p.get("lamella", "lj") in ("bonded", "facing"):
        pairs, kind = lamella_bonds(xy, w["cell"], p)
        if p["lamella"] == "facing":   # no diagonals: no shear stiffness to first order
            pairs, kind = pairs[kind == 2], kind[kind == 2]
        lamella = pairs, kind
    glue = [] if lamella is None else [(int(k), i + 1, j + 1) for (i, j), k in zip(*lamella)]
    bonds = ring + glue
    types = max([1] + [t for t, _, _ in glue])
    lines = [title, "", f"{len(xy)} atoms", f"{len(bonds)} bonds", f"{len(xy)} angles",
             "3 atom types", f"{types} bond types", "1 angle types", "",
             f"{lo[0]:.10e} {hi[0]:.10e} xlo xhi", f"{lo[1]:.10e} {hi[1]:.10e} ylo yhi",
             f"{-margin:.10e} {margin:.10e} zlo zhi", "", "Masses", ""]
    lines += [f"{t} {mass:.10e}" for t in (1, 2, 3)]
    lines += ["", "Atoms # angle", ""]
    lines += [f"{i} {c + 1} {k + 1} {x:.12e} {y:.12e} 0.0"
              for i, c, k, (x, y) in zip(ids, w["cell"], w["colour"], xy)]
    lines += ["", "Bonds", ""] + [f"{k + 1} {t} {i} {j}" for k, (t, i, j) in enumerate(bonds)]
    lines += ["", "Angles", ""] + [f"{i} 1 {a} {i} {b}" for i, a, b in zip(ids, prv, nxt)]
    folders.write_text(path, "\n".join(lines) + "\n", overwrite)
    assert ncell * n == len(xy)
    return w
