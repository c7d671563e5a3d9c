# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A 3-D fine-scale (MFC) tissue: cells on a BCC lattice, each a closed triangulated wall
around its fluid, neighbouring walls glued by a lamella (doc/mfc.md, "3-D tissue").

Decisions (the 2-D tissue's, carried to 3-D; doc/mfc.md says why):

* a cell's wall is built as its own Voronoi polyhedron, Kelvin's truncated octahedron,
  scaled about the bead to the volume of the sphere of diameter D (as the 2-D hexagon
  holds the circle's area); each face is fanned from its centre and each fan triangle
  split into ``n`` x ``n`` (``36 n^2 + 2`` wall particles per cell; n = 5 by default, see
  :data:`TISSUE3D`). The faces are
  centrosymmetric, so two neighbours' facing walls carry the same nodes, each facing the
  other across the gap, as the 2-D hexagons' walls do (an icosphere would give facing walls
  whose nodes do not face each other, and spheres do not tile);
* the lattice: BCC of cube edge ``a + 2 d_p / sqrt(3)`` (``a`` from
  :func:`cgms.tissue3d.cube_edge`), so facing hexagonal walls are d_p = 8 um apart and
  facing square walls 2 d_p / sqrt(3) = 9.24 um (a scaled truncated octahedron keeps the
  ratio of its face distances);
* the wall (:func:`cgms.mfc.cell3d.wall`'s laws): harmonic bonds k = sqrt(3) E t / 2 along
  every edge; harmonic dihedrals on every edge (zero when flat); the fluid's rest volume
  pi D^3 / 6. The wall rests in the built polyhedron's shape, every edge at its built
  length times ``1 - stretch``, the pre-stress found so that the free fresh cell holds
  P_T (:func:`prestress`), as the 2-D ring's pre-stress makes the free cell a circle at
  P_T. (``rest="sphere"``: resting in the free cell's shape, the mesh on the sphere; its
  fresh block does not stay cubic, doc/results/mfc.md);
* between walls of different cells: the 2-D lamella's 8-4 LJ (r0 = d_p, cutoff 12 um)
  with E0 scaled by the wall area a 3-D node stands for over a 2-D node's
  (``spacing x H``); the lamella bonds, set at rest in the relaxed fresh tissue, with the
  LJ's stiffness at d_p (32 E0 / d_p^2, as 2-D);
* within a cell's wall, the self-avoidance: the 2-D one's repulsive 8-4 LJ (E0 scaled as
  the lamella's), of radius r0 = d_p, between particles not bonded to each other
  (:data:`SELF_SPECIAL`). A pair style cannot tell a cell's own pairs from a
  neighbour's, so the cells are coloured (:func:`colours`, atom types 1-4, no two
  neighbours alike) and a type's own pair is the self-avoidance (same-coloured cells are
  never neighbours).
"""

import functools
import math

import numpy as np
from scipy import optimize
from scipy.spatial import cKDTree

from .. import folders, tissue3d as coarse3d
from . import cell3d

#: the 3-D tissue's fixed values: face subdivision, the gap's reach for lamella bonds, the
#: wall's rest shape. Decision: n = 5 (902 particles per cell, edges 10.8 and 7.6 um): the
#: LJ acts between particles only, so a wall holds its neighbour's particles off only where
#: a triangle's centre lies well inside the LJ radius d_p of its corners (edge / sqrt(3)
#: below d_p). In the relaxed fresh 16-cell block, particles inside a neighbour's wall:
#: 1403 of 5216 at n = 3, 1486 of 9248 at n = 4, none of 14 432 at n = 5 (doc/mfc.md,
#: "Mesh").
TISSUE3D = dict(subdivision=5, reach=1.05, rest="polyhedron")
#: lamella rest lengths are binned to this (m), one bond type per bin (as 2-D)
REST_BIN = 1e-8
#: the wall's self-avoidance (doc/mfc.md, "3-D tissue", "Self-avoidance"): the weights of
#: its pairs 1, 2 and 3 bonds apart (``pair_modify special lj``). Decision: its radius is
#: d_p, and bonded pairs are spared. A particle repulsion stops a wall passing through
#: itself only if its radius exceeds the distance from the corners of one triangle to the
#: other's as they cross: hypot(l1, l2) / 2 for two edges crossing at their middles, at
#: most l_max / sqrt(2) = 7.6 um here (l_max = 10.8 um built, less as the wall dries), so
#: r0 = d_p = 8 um (the gap the lamella keeps between two walls, here between the layers
#: of a fold). That is above the shortest bond (7.6 um built, 5.5 um measured in a dried
#: fold), so bonded pairs are spared; the closest unbonded pair of the flat wall (a square
#: face's unbonded diagonal) is 10.8 um built, 8.6 um at the s = 0.3 rest lengths, so a
#: wall not folded or crushed is not touched. Pairs two bonds apart are not spared: they
#: include the far corners of a hinge, and spared, a hinge folds flat and through (a free cell
#: dried to s = 0.3 in one step crossed itself so, tests/mfc/test_mfc3d_crossing.py).
#: E0: the 2-D wall's (SELF_E0_FOLDS) scaled by area per node as the lamella's.
SELF_SPECIAL = (0.0, 1.0, 1.0)
#: atom types of the cell colours (:func:`colours`)
COLOURS = 4


def polyhedron(n):
    """The truncated octahedron of cube edge 1 (vertices the permutations of (0, +-1/4,
    +-1/2)), every face fanned from its centre and each fan triangle split n x n. Returns
    vertices (m, 3) and triangles (k, 3), counter-clockwise seen from outside."""
    if int(n) != n or not 1 <= n <= 12:
        raise ValueError(f"the face subdivision must be an integer 1..12, got {n!r}")
    n = int(n)
    corners = set()
    for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
        for sy in (1, -1):
            for sz in (1, -1):
                v = np.array([0, sy, 2 * sz])[list(perm)]
                corners.add(tuple(int(c) for c in v))
    corners = np.array(sorted(corners))                     # units of 1/4
    normals = [np.array(s) for s in np.ndindex(2, 2, 2)]
    normals = [2 * s - 1 for s in normals] + [e * sg for e in np.eye(3, dtype=int)
                                              for sg in (1, -1)]
    index, verts, tris = {}, [], []

    def node(p):                                            # p: integer, units of 1/(4n)
        key = tuple(int(c) for c in p)
        if key not in index:
            index[key] = len(verts)
            verts.append(key)
        return index[key]
    for nrm in normals:
        dist = corners @ nrm
        ring = corners[dist == dist.max()]
        centre = ring.mean(axis=0)
        # order the face's corners around its centre
        u = ring[0] - centre
        w = np.cross(nrm, u)
        order = np.argsort(np.arctan2((ring - centre) @ w, (ring - centre) @ u))
        ring = ring[order]
        c = np.rint(centre * n).astype(int)                 # centres are on the 1/4 grid
        assert np.allclose(centre * n, c)
        for k in range(len(ring)):
            a, b = ring[k] * n, ring[(k + 1) % len(ring)] * n
            # barycentric grid of the fan triangle (c, a, b): points (i c + j a + l b) / n
            grid = {}
            for i in range(n + 1):
                for j in range(n + 1 - i):
                    grid[i, j] = node((i * c + j * a + (n - i - j) * b) // n)
            for i in range(n):
                for j in range(n - i):
                    tris.append((grid[i, j], grid[i + 1, j], grid[i, j + 1]))
                    if i + j < n - 1:
                        tris.append((grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]))
    x = np.array(verts, float) / (4 * n)
    tri = np.array(tris, int)
    normal = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
    outward = np.einsum("ij,ij->i", normal, x[tri].mean(axis=1)) > 0
    tri[~outward] = tri[~outward][:, ::-1]
    return x, tri


def free_pressure(x, tri, edges, rest, k, modulus, turgor, fluid):
    """The fluid pressure of a free cell of bonds (stiffness ``k``, rest lengths ``rest``)
    and fluid (the Tait law of ``fix mfc/pressure3d``) at rest, minimised from ``x``
    (L-BFGS on the energy and its exact gradient; bending left out: it moves a fresh
    cell's pressure by about kappa / R^3, 4e-4 of P_T). Returns the pressure and the
    positions."""
    scale = float(np.linalg.norm(x, axis=1).max())
    unit = turgor * fluid            # energies in this unit, lengths in ``scale``

    def energy(y):
        z = y.reshape(-1, 3) * scale
        d = z[edges[:, 1]] - z[edges[:, 0]]
        length = np.linalg.norm(d, axis=1)
        stretch = length - rest
        v, dv = cell3d.volume(z, tri)
        q = fluid / v
        e = 0.5 * k * np.sum(stretch ** 2) + (modulus - turgor) * (v - fluid) \
            + modulus * fluid / 6 * (q ** 6 - 1)
        pressure = turgor + modulus * (q ** 7 - 1)
        g = -pressure * dv
        pull = (k * stretch / length)[:, None] * d
        np.add.at(g, edges[:, 1], pull)
        np.add.at(g, edges[:, 0], -pull)
        return e / unit, (g * scale / unit).ravel()
    res = optimize.minimize(energy, (x / scale).ravel(), jac=True, method="L-BFGS-B",
                            options=dict(maxiter=20000, maxcor=30, ftol=0, gtol=1e-12))
    z = res.x.reshape(-1, 3) * scale
    v = cell3d.volume(z, tri)[0]
    return turgor + modulus * ((fluid / v) ** 7 - 1), z


def prestress(x, tri, edges, length, k, modulus, turgor, fluid, first, tol=1e-5):
    """The pre-stress ``stretch`` that holds the turgor: with every edge resting at
    ``length (1 - stretch)``, the free cell (:func:`free_pressure`, from ``x``) is at
    rest with its fluid at ``turgor``, to ``tol`` (the relaxation's own precision is
    about 1e-6 of P_T). Secant steps from ``first``: a rule (Laplace's, the virial's)
    exact only for equilateral triangles that stay where they are; this mesh's are not
    all equilateral and its nodes slide as it relaxes."""
    s0 = first
    p0, y = free_pressure(x, tri, edges, length * (1 - s0), k, modulus, turgor, fluid)
    s1 = s0 * (1 + 1e-3)
    for _ in range(8):
        p1, y = free_pressure(y, tri, edges, length * (1 - s1), k, modulus, turgor, fluid)
        if abs(p1 / turgor - 1) < tol:
            return float(s1)
        if p1 == p0:
            break
        s0, p0, s1 = s1, p1, s1 + (turgor - p1) * (s1 - s0) / (p1 - p0)
    raise RuntimeError(f"the wall's pre-stress did not converge: P = {p1:.6g} Pa at "
                       f"stretch {s1:.6g}, turgor {turgor:.6g} Pa")


@functools.lru_cache(maxsize=8)
def _wall(values, n, rest):
    return _build_wall(dict(values), n, rest)


def wall(p, n=TISSUE3D["subdivision"], rest=None):
    """The fresh wall of one cell of MFC parameters ``p``: the mesh (centred on the bead),
    the wall's laws (:func:`cgms.mfc.cell3d.wall`), rest lengths, the fluid's rest volume,
    and the lamella's LJ and bond constants (cached: the pre-stress takes a few
    relaxations of a free cell)."""
    keys = ("diameter", "wall_Et", "wall_thickness", "bend_factor", "P_f", "K", "pectin",
            "b_ref", "per_side", "height", "lamella_E0", "lamella_rc", "self_E0")
    w = _wall(tuple((key, float(p[key])) for key in keys), int(n) if int(n) == n else n,
              rest or TISSUE3D["rest"])
    return {key: (v.copy() if isinstance(v, np.ndarray) else v) for key, v in w.items()}


def _build_wall(p, n, rest):
    """The fresh wall of one cell of MFC parameters ``p``: the mesh (centred on the bead),
    the wall's laws (:func:`cgms.mfc.cell3d.wall`), rest lengths, the fluid's rest volume,
    and the lamella's LJ and bond constants."""
    x, tri = polyhedron(n)
    # the 1-cube truncated octahedron has volume 1/2: scale it to pi D^3 / 6
    a = coarse3d.cube_edge(p["diameter"])
    x = x * a
    edges, hinges = cell3d.edges_and_hinges(tri)
    free = cell3d.wall(p, level=0)                          # the laws, not the mesh
    radius = p["diameter"] / 2
    built_area = cell3d.area(x, tri)
    fluid = math.pi * p["diameter"] ** 3 / 6
    # the free fresh cell: the mesh pushed out radially onto the sphere whose mesh holds
    # the fluid (where the pre-stress's relaxations start)
    sphere = x / np.linalg.norm(x, axis=1)[:, None]
    sphere *= (fluid / cell3d.volume(sphere, tri)[0]) ** (1 / 3)
    length = np.linalg.norm(x[edges[:, 1]] - x[edges[:, 0]], axis=1)
    if rest == "polyhedron":
        # rest shape: the built polyhedron, scaled to the sphere's area less the Laplace
        # pre-stress of the 3-D cell to start with
        shape = length
        first = 1 - math.sqrt(math.pi * p["diameter"] ** 2 / built_area) * (1 - free["stretch"])
    elif rest == "sphere":
        # rest shape: the mesh on the sphere; start from the virial of that sphere,
        # sum T l = k stretch sum l^2 = 3 P_T V_f
        shape = np.linalg.norm(sphere[edges[:, 1]] - sphere[edges[:, 0]], axis=1)
        first = 3 * p["P_f"] * fluid / (free["k_bond"] * np.sum(shape ** 2))
    else:
        raise ValueError(f"the wall's rest shape must be polyhedron or sphere, got {rest!r}")
    stretch = prestress(sphere, tri, edges, shape, free["k_bond"], p["K"], p["P_f"], fluid,
                        first)
    # one bond type per rest length (two for the polyhedron, a few dozen for the sphere)
    classes, kind = np.unique(np.round(shape / a, 9), return_inverse=True)
    classes = classes * a * (1 - stretch)
    node_area = built_area / len(x)
    # the 2-D lamella per node stood for spacing x H of wall: scale by the area per node
    area_2d = p["b_ref"] / int(p["per_side"]) * p["height"]
    per_node = node_area / area_2d
    e0 = p["lamella_E0"] * per_node
    return dict(x=x, tri=tri, edges=edges, hinges=hinges, radius=radius, cube=a,
                k_bond=free["k_bond"], stretch=stretch, k_dihedral=free["k_dihedral"],
                rest_classes=classes, bond_type=kind + 1, free_x=sphere,
                built_area=built_area, fluid_volume=fluid,
                mesh_volume=cell3d.volume(x, tri)[0], spacing=float(length.max()),
                node_area=node_area, lamella_E0=e0, lamella_k=32 * e0 / p["pectin"] ** 2,
                lamella_rc=p["lamella_rc"], pectin=p["pectin"], subdivision=n,
                self_E0=p["self_E0"] * per_node, self_r0=p["pectin"])


def lattice_edge(p):
    """BCC cube edge of the tissue: facing hexagonal walls d_p apart."""
    return coarse3d.cube_edge(p["diameter"]) + 2 * p["pectin"] / math.sqrt(3)


def block(p, cubes=2):
    """Bead positions of a block ``cubes`` cube edges on a side (BCC, the fill rule of
    :func:`cgms.tissue3d.bcc`): 16 cells for 2, 54 for 3."""
    if int(cubes) != cubes or not 1 <= cubes <= 6:
        raise ValueError(f"the block side must be 1..6 cube edges, got {cubes!r}")
    edge = lattice_edge(p)
    side = cubes * edge
    return coarse3d.bcc(coarse3d.box(side, side, side), edge)


def colours(centres, p):
    """Per cell a colour 0..3, no two neighbours alike, of cells on the BCC lattice of
    :func:`block`: in half cube edges the corner sublattice has even indices and the body
    centres odd ones, so the parity of the x index tells the sublattice (the 8 hexagonal
    neighbours are of the other), and the parity of the summed halved indices tells two
    square-face neighbours (2 apart along one axis) apart."""
    centres = np.atleast_2d(np.asarray(centres, float))
    idx = np.rint((centres - centres.min(axis=0)) / (lattice_edge(p) / 2)).astype(int)
    return 2 * (idx[:, 0] % 2) + (idx // 2).sum(axis=1) % 2


def walls(centres, p, n=TISSUE3D["subdivision"]):
    """Every cell's wall around its bead: positions (N, 3), cell index per particle, and
    the per-cell wall (:func:`wall`)."""
    w = wall(p, n)
    centres = np.atleast_2d(np.asarray(centres, float))
    if centres.ndim != 2 or centres.shape[1] != 3 or len(centres) < 1:
        raise ValueError(f"cell centres must be (n, 3) positions, got shape {centres.shape}")
    x = np.concatenate([w["x"] + c for c in centres])
    cell = np.repeat(np.arange(len(centres)), len(w["x"]))
    return x, cell, w


def lamella_pairs(x, cell, w, p):
    """Pairs (i, j) of wall particles of different cells (0-based) within the lamella's
    reach, ``hypot(1.05 x 2 d_p / sqrt(3), 1.05 x spacing)``: each node, the one facing it
    across the gap (d_p or 9.24 um in the built tissue) and that one's neighbours along its
    wall (the truss's diagonals, which resist the walls sliding along each other)."""
    reach = math.hypot(TISSUE3D["reach"] * 2 * p["pectin"] / math.sqrt(3),
                       TISSUE3D["reach"] * w["spacing"])
    pairs = cKDTree(x).query_pairs(reach, output_type="ndarray")
    if not len(pairs):
        return np.zeros((0, 2), int)
    return pairs[cell[pairs[:, 0]] != cell[pairs[:, 1]]]


def fresh_lamella(x, cell, w, p):
    """The lamella set in a relaxed fresh tissue (positions ``x``): pairs, their bond types
    (after the wall's), the rest length per lamella type (each bond at its present length,
    binned to :data:`REST_BIN`)."""
    pairs = lamella_pairs(x, cell, w, p)
    d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    used, index = np.unique(np.rint(d / REST_BIN).astype(int), return_inverse=True)
    return pairs, index + 1 + len(w["rest_classes"]), used * REST_BIN


def write_data(path, centres, p, n=TISSUE3D["subdivision"], x=None, lamella=None,
               margin=None, title="MFC 3-D tissue", overwrite=False):
    """LAMMPS data file (``atom_style molecular``: ``id mol type x y z``, molecule = cell)
    of the walls around ``centres`` (or at positions ``x``, e.g. a relaxed state), with
    wall bonds (types 1.. by rest-length class), triangles as angles (type 1), hinges as
    dihedrals (type 1) and the lamella bonds ``lamella`` = (pairs, types, rest) of
    :func:`fresh_lamella`; atom type = the cell's colour + 1 (:func:`colours`). Returns
    (positions, cell, wall)."""
    built, cell, w = walls(centres, p, n)
    colour = colours(centres, p)
    x = built if x is None else np.asarray(x, float)
    if x.shape != built.shape:
        raise ValueError(f"positions of shape {x.shape} do not fit {len(centres)} cells of "
                         f"{len(w['x'])} wall particles")
    ncell, m = len(np.atleast_2d(centres)), len(w["x"])
    pairs, types, rest = lamella if lamella is not None else (np.zeros((0, 2), int), [], [])
    alike = colour[cell[pairs[:, 0]]] == colour[cell[pairs[:, 1]]]
    if np.any(alike):
        i, j = pairs[np.argmax(alike)]
        raise ValueError(f"cells {cell[i] + 1} and {cell[j] + 1} are glued but have one "
                         "colour (their walls would avoid each other as a cell's own): the "
                         "cell centres must lie on the BCC lattice of cgms.mfc.tissue3d.block")
    margin = 2 * w["radius"] if margin is None else margin
    lo, hi = x.min(axis=0) - margin, x.max(axis=0) + margin
    mass = p["solid_ratio"] * p["rho0"] * w["fluid_volume"] / m
    nbond = len(w["edges"]) * ncell + len(pairs)
    lines = [title, "", f"{len(x)} atoms", f"{nbond} bonds", f"{len(w['tri']) * ncell} angles",
             f"{len(w['hinges']) * ncell} dihedrals", "", f"{COLOURS} atom types",
             f"{len(w['rest_classes']) + len(rest)} bond types", "1 angle types",
             "1 dihedral types", ""]
    lines += [f"{lo[d]:.10e} {hi[d]:.10e} {c}lo {c}hi" for d, c in enumerate("xyz")]
    lines += ["", "Masses", ""] + [f"{t} {mass:.10e}" for t in range(1, COLOURS + 1)]
    lines += ["", "Bond Coeffs # harmonic", ""]
    lines += [f"{t + 1} {w['k_bond'] / 2:.17e} {r:.17e}"
              for t, r in enumerate(w["rest_classes"])]
    lines += [f"{t} {w['lamella_k'] / 2:.17e} {r:.17e}"
              for t, r in enumerate(rest, start=len(w["rest_classes"]) + 1)]
    lines += ["", "Dihedral Coeffs # harmonic", "", f"1 {w['k_dihedral']:.12e} 1 1"]
    lines += ["", "Atoms # molecular", ""]
    lines += [f"{i + 1} {cell[i] + 1} {colour[cell[i]] + 1} {a:.15e} {b:.15e} {c:.15e}"
              for i, (a, b, c) in enumerate(x)]
    bonds = [(t, *(e + k * m + 1)) for k in range(ncell)
             for t, e in zip(w["bond_type"], w["edges"])]
    bonds += [(int(t), i + 1, j + 1) for (i, j), t in zip(pairs, types)]
    rows = {"Bonds": bonds,
            "Angles": [(1, *(t + k * m + 1)) for k in range(ncell) for t in w["tri"]],
            "Dihedrals": [(1, *(h + k * m + 1)) for k in range(ncell) for h in w["hinges"]]}
    for name, entries in rows.items():
        lines += ["", name, ""]
        lines += [" ".join(str(int(v)) for v in (k + 1, *e)) for k, e in enumerate(entries)]
    folders.write_text(path, "\n".join(lines) + "\n", overwrite=overwrite)
    return x, cell, w
