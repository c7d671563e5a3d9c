# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Build 3-D tissues: beads on a body-centred cubic (BCC) lattice, whose Voronoi cells are
truncated octahedra (Kelvin's cells), inside a slab, block or cylinder; each bead's fresh
cell (its Voronoi cell clipped to the body), neighbours, volume, wall area and free
surface; a LAMMPS data file for ``dimension 3`` (doc/tissues.md, "3-D tissues").

Decisions (marked in doc/tissues.md):

* the lattice: BCC with cube edge ``a`` such that a cell (a^3 / 2) holds the volume of the
  material's sphere of diameter D, a = (pi D^3 / 3)^(1/3) (152.3 um for apple); the 14
  neighbours are 8 at sqrt(3) a / 2 (hexagonal faces) and 6 at a (square faces);
* the fill: the lattice points at least a/4 inside the body, the lattice centred in it (a
  slab T thick holds floor(2 T / a) layers a/2 apart, the outermost at least a/4
  inside); ``jitter`` moves each bead by up to ``jitter`` a in a random direction (below
  a/4, so every bead stays inside);
* a bead's cell: its Voronoi cell clipped to the body (exact for flat faces; a cylinder's
  side is a prism of ``SIDES`` faces), so the cells tile the body; fresh neighbours: beads
  whose clipped cells share a face of positive area; a surface cell has a face on the
  body's boundary;
* heterogeneous cells: as in 2-D, per-bead diameters (``cgms.tissue.cell_diameters``) in
  a ``Diameters`` section; ``jitter`` makes the cell volumes themselves heterogeneous.
"""

import math

import numpy as np
from scipy.spatial import ConvexHull, Delaunay, HalfspaceIntersection

from . import folders

#: faces of the prism that stands for a cylinder's curved side
SIDES = 128
#: the largest jitter (in cube edges): below a/4, the gap the fill rule leaves
MAX_JITTER = 0.24
#: a face shared by two cells counts when its area exceeds this share of a^2
FACE_TOL = 1e-9
#: LAMMPS reads data-file lines into 256 characters: this many neighbour IDs per line
MAX_NEIGHBOURS = 28


def cube_edge(diameter):
    """BCC cube edge a whose cell (a^3 / 2) has the volume of a sphere of ``diameter``."""
    return (math.pi * diameter ** 3 / 3) ** (1 / 3)


# --------------------------------------------------------------------------- bodies

def box(width, length, thickness, kind="block"):
    """A block (or slab: a slice ``thickness`` thick along z) centred at the origin, as
    half-spaces A x + b <= 0 (rows [A, b])."""
    h = np.array([width, length, thickness], float) / 2
    if not np.all(np.isfinite(h) & (h > 0)):
        raise ValueError(f"sizes must be positive, got {width!r}, {length!r}, {thickness!r}")
    rows = [np.r_[s * np.eye(3)[d], -h[d]] for d in range(3) for s in (1, -1)]
    return dict(kind=kind, size=(width, length, thickness), planes=np.array(rows),
                volume=float(np.prod(2 * h)), half=h)


def cylinder(radius, height, sides=SIDES):
    """A cylinder of ``radius`` and ``height``, axis along z, centred at the origin: its
    side a prism of ``sides`` faces (circumscribed polygon's inscribed circle = radius)."""
    if not (math.isfinite(radius) and radius > 0 and math.isfinite(height) and height > 0):
        raise ValueError(f"sizes must be positive, got {radius!r}, {height!r}")
    phi = 2 * math.pi * np.arange(sides) / sides
    rows = [np.r_[math.cos(p), math.sin(p), 0.0, -radius] for p in phi]
    rows += [np.r_[0, 0, 1.0, -height / 2], np.r_[0, 0, -1.0, -height / 2]]
    prism = sides * radius ** 2 * math.tan(math.pi / sides) * height
    return dict(kind="cylinder", size=(radius, height), planes=np.array(rows), volume=prism,
                half=np.array([radius, radius, height / 2]))


def inside(points, body, inset=0.0):
    """Which points lie at least ``inset`` inside the body."""
    p = body["planes"]
    return np.all(points @ p[:, :3].T + p[:, 3] <= -inset, axis=1)


# --------------------------------------------------------------------------- the lattice

def bcc(body, a, jitter=0.0, seed=0):
    """BCC lattice points (cube edge ``a``) at least a/4 inside ``body``, the lattice
    centred in the body's bounding box, optionally jittered. Returns (n, 3)."""
    if not (math.isfinite(a) and a > 0):
        raise ValueError(f"the cube edge must be positive, got {a!r}")
    if not 0 <= jitter <= MAX_JITTER:
        raise ValueError(f"jitter must be in 0..{MAX_JITTER} cube edges, got {jitter!r}")
    # layers a/2 apart along each axis, symmetric about the centre, as many as leave the
    # outermost at least a/4 inside the face
    axes = []
    for e in body["half"]:
        layers = int(math.floor(4 * e / a * (1 + 1e-9)))
        axes.append((np.arange(layers) - (layers - 1) / 2) * a / 2)
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    # a BCC point has all three half-layer indices of the same parity
    idx = np.rint(grid / (a / 2) + [(len(ax) - 1) / 2 for ax in axes]).astype(int)
    points = grid[(idx[:, 0] % 2 == idx[:, 1] % 2) & (idx[:, 1] % 2 == idx[:, 2] % 2)]
    points = points[inside(points, body, inset=a / 4 * (1 - 1e-9))]
    if jitter and len(points):
        rng = np.random.default_rng(seed)
        d = rng.normal(size=points.shape)
        d /= np.linalg.norm(d, axis=1)[:, None]
        points = points + jitter * a * rng.random(len(points))[:, None] ** (1 / 3) * d
    return points


# --------------------------------------------------------------------------- the cells

def _faces(hull, hs):
    """Area of the polytope ``hull`` on each half-space's plane of ``hs`` (rows [A, b],
    A x + b <= 0): its triangles matched to the plane they lie on."""
    unit = hs / np.linalg.norm(hs[:, :3], axis=1)[:, None]
    eq = hull.equations
    match = np.argmax(eq[:, :3] @ unit[:, :3].T, axis=1)
    tri = hull.points[hull.simplices]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return np.bincount(match, weights=area, minlength=len(hs))


def cells(points, body, a):
    """The fresh cells: per bead its clipped Voronoi cell's ``volume``, wall ``area``,
    ``free`` area on the body's boundary, ``surface`` flag and ``neighbours`` (lists of
    indices of beads sharing a face)."""
    points = np.asarray(points, float)
    n = len(points)
    if n < 2:
        raise ValueError(f"a tissue needs at least 2 beads, got {n}")
    if not np.all(inside(points, body)):
        raise ValueError("every bead must lie inside the body")
    tri = Delaunay(points)
    ptr, nbr = tri.vertex_neighbor_vertices
    planes = body["planes"]
    out = dict(volume=np.zeros(n), area=np.zeros(n), free=np.zeros(n),
               surface=np.zeros(n, bool), neighbours=[])
    for i in range(n):
        cand = nbr[ptr[i]:ptr[i + 1]]
        d = points[cand] - points[i]
        # bisector half-spaces d . x - d . (p_i + p_j) / 2 <= 0
        hs = np.c_[d, -np.einsum("ij,ij->i", d, (points[cand] + points[i]) / 2)]
        near = np.abs(points[i] @ planes[:, :3].T + planes[:, 3]) < 2 * a
        hs = np.r_[hs, planes[near]]
        verts = HalfspaceIntersection(hs, points[i]).intersections
        hull = ConvexHull(verts)
        out["volume"][i] = hull.volume
        out["area"][i] = hull.area
        faces = _faces(hull, hs)
        shared = [int(j) for j, f in zip(cand, faces[:len(cand)]) if f > FACE_TOL * a * a]
        out["neighbours"].append(sorted(shared))
        out["free"][i] = sum(faces[len(cand):])
        out["surface"][i] = out["free"][i] > FACE_TOL * a * a
    return out


def build(body, a, jitter=0.0, seed=0):
    """Beads and fresh cells of ``body`` (:func:`box`, :func:`cylinder`) on the BCC lattice
    of cube edge ``a``: a dict with ``x`` (n, 3) and the fields of :func:`cells`."""
    x = bcc(body, a, jitter, seed)
    if len(x) < 2:
        raise ValueError(f"the {body['kind']} holds {len(x)} bead(s) at cube edge "
                         f"{a * 1e6:.4g} um: it must be at least a/2 = {a * 5e5:.4g} um "
                         "thick, and larger to hold a tissue")
    if np.linalg.svd(x - x.mean(axis=0), compute_uv=False)[-1] < 1e-9 * a:
        raise ValueError(f"the {body['kind']} holds {len(x)} beads in one plane at cube edge "
                         f"{a * 1e6:.4g} um: a 3-D tissue needs two layers, a slab at least "
                         f"a = {a * 1e6:.4g} um thick (one layer is the 2-D model)")
    return dict(x=x, a=a, body=body, **cells(x, body, a))


# --------------------------------------------------------------------------- data file

def write_data(path, tissue, margin, title="CGMS 3-D tissue", diameters=None,
               overwrite=False):
    """A LAMMPS data file of ``atom_style cgms`` (``id type x y z``) for ``dimension 3``,
    with the fresh cells in two sections read by ``fix property/atom`` (doc/tissues.md,
    "3-D tissues"): ``Cells3d`` (``i_surface3d d_volume3d d_area3d d_free3d``) and
    ``Neighbours3d`` (``i2_nb3d NB``, neighbour IDs, 0 filling), and ``Diameters`` as in
    2-D. Returns NB."""
    x, n = tissue["x"], len(tissue["x"])
    nb = max(len(v) for v in tissue["neighbours"])
    if nb > MAX_NEIGHBOURS:
        raise ValueError(f"a cell has {nb} neighbours, more than the {MAX_NEIGHBOURS} a "
                         "data-file line holds: use a smaller jitter")
    lo, hi = x.min(axis=0) - margin, x.max(axis=0) + margin
    lines = [title, "", f"{n} atoms", "1 atom types", ""]
    lines += [f"{lo[d]:.10e} {hi[d]:.10e} {c}lo {c}hi" for d, c in enumerate("xyz")]
    lines += ["", "Atoms # cgms", ""]
    lines += [f"{i + 1} 1 {p[0]:.15e} {p[1]:.15e} {p[2]:.15e}" for i, p in enumerate(x)]
    lines += ["", "Cells3d", ""]
    lines += [f"{i + 1} {int(s)} {v:.15e} {ar:.15e} {f:.15e}" for i, (s, v, ar, f) in
              enumerate(zip(tissue["surface"], tissue["volume"], tissue["area"],
                            tissue["free"]))]
    lines += ["", "Neighbours3d", ""]
    for i, js in enumerate(tissue["neighbours"]):
        ids = [j + 1 for j in js] + [0] * (nb - len(js))
        lines.append(" ".join(str(v) for v in [i + 1] + ids))
    if diameters is not None:
        lines += ["", "Diameters", ""] + [f"{i + 1} {d:.17g}" for i, d in enumerate(diameters)]
    folders.write_text(path, "\n".join(lines) + "\n", overwrite)
    return nb


def read_commands(path, nb, diameters=False):
    """The LAMMPS commands that read a 3-D tissue file with its cell sections."""
    lines = ["dimension 3", "boundary f f f", "atom_style cgms",
             "fix cells3d all property/atom i_surface3d d_volume3d d_area3d d_free3d",
             f"fix nb3d all property/atom i2_nb3d {nb}"]
    tail = " fix cells3d NULL Cells3d fix nb3d NULL Neighbours3d"
    if diameters:
        lines.append("fix diam all property/atom d_diameter")
        tail += " fix diam NULL Diameters"
    return lines + [f"read_data {path}{tail}"]
