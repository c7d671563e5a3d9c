# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The fresh geometry of the 3-D shaped tensor model (doc/model.md, "The 3-D tensor model
(prototype)"): the lattice's Voronoi cell (faces with their fresh areas and normals, its
volume), tissues built on a lattice (blocks and slabs of BCC cells, whose Voronoi cells
are Kelvin's truncated octahedra; one-cell-thick layers of hexagonal prisms) and their
fresh neighbours, the Voronoi neighbours of the built tissue.

**Decision:** every cell's fresh polyhedron is the lattice's full Voronoi cell, a boundary
cell's too (the 3-D analogue of the 2-D ghost points, which give a boundary cell the same
regular hexagon as an interior one); a face whose neighbour is missing is a free wall.
"""

import math

import numpy as np
from scipy.spatial import HalfspaceIntersection, Voronoi

_TOL = 1e-9


def polyhedron(neighbours, caps=()):
    """The Voronoi cell of a lattice site at the origin: the intersection of the half
    spaces n . y <= |d| / 2 bisecting each ``neighbours`` vector d (m, 3), and of the
    ``caps``, (normal, offset) pairs n . y <= offset (faces without a neighbour: the held
    top and bottom of a layer of prisms). Returns a dict with per face (neighbour faces
    first, in the order given, then the caps) its vector area ``a0`` = S0 n0 (f, 3), its
    area ``S0`` and unit normal ``n0``, the polygon ``vertices`` (a list of (k, 3),
    counter-clockwise about n0), and the cell's ``volume`` V0."""
    d = np.asarray(neighbours, float).reshape(-1, 3)
    normals = [v / np.linalg.norm(v) for v in d] + [np.asarray(c[0], float) for c in caps]
    offsets = [0.5 * np.linalg.norm(v) for v in d] + [float(c[1]) for c in caps]
    normals, offsets = np.array(normals), np.array(offsets)
    with np.errstate(divide="ignore", invalid="ignore"):
        pts = HalfspaceIntersection(np.column_stack([normals, -offsets]),
                                    np.zeros(3)).intersections
    if not np.all(np.isfinite(pts)):
        raise ValueError("the lattice cell is not closed: its neighbour vectors (and caps) "
                         "leave it unbounded; give every direction a neighbour or a cap")
    scale = offsets.max()
    # one vertex per corner (qhull repeats a corner where more than three planes meet)
    uniq = []
    for p in pts:
        if not any(np.linalg.norm(p - q) <= _TOL * scale for q in uniq):
            uniq.append(p)
    pts = np.array(uniq)
    faces, a0 = [], []
    for nrm, off in zip(normals, offsets):
        on = pts[np.abs(pts @ nrm - off) <= 1e-7 * scale]
        if len(on) < 3:
            raise ValueError("a neighbour vector's plane does not bound the cell: "
                             "it is not a Voronoi neighbour of the lattice")
        c = on.mean(axis=0)
        e1 = on[0] - c
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(nrm, e1)
        order = np.argsort(np.arctan2((on - c) @ e2, (on - c) @ e1))
        poly = on[order]
        area = 0.5 * np.sum(np.cross(poly, np.roll(poly, -1, axis=0)), axis=0)
        faces.append(poly)
        a0.append(area)
    a0 = np.array(a0)
    S0 = np.linalg.norm(a0, axis=1)
    volume = float(np.sum(offsets * S0) / 3)      # pyramids from the site to each face
    return dict(a0=a0, S0=S0, n0=a0 / S0[:, None], vertices=faces, volume=volume,
                neighbours=d, n_caps=len(caps))


def bcc_vectors(spacing):
    """The 14 Voronoi neighbours of a BCC site whose nearest neighbours are ``spacing``
    apart: 8 at (+-1, +-1, +-1) a / 2 (the hexagonal faces) and 6 at +-a along the axes
    (the square faces), a = 2 spacing / sqrt(3) the cube's edge."""
    a = 2 * spacing / math.sqrt(3)
    eight = [(i, j, k) for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]
    six = [tuple(s * e) for e in np.eye(3) for s in (-1, 1)]
    return np.array([np.array(v) * a / 2 for v in eight] + [np.array(v) * a for v in six])


def hexagon_vectors(spacing, angle=0.0):
    """The six in-plane neighbours of a hexagonal lattice site (z = 0), the first at
    ``angle`` (rad) from the x axis."""
    t = angle + np.arange(6) * math.pi / 3
    return spacing * np.column_stack([np.cos(t), np.sin(t), np.zeros(6)])


def block(nx, ny, nz, spacing):
    """A block of BCC cells: the cube corners (nx, ny, nz of them along x, y, z) and the
    cube centres between them, nearest neighbours ``spacing`` apart. Returns the points
    (n, 3), centred on the origin, and the lattice's neighbour vectors."""
    for v in (nx, ny, nz):
        if int(v) != v or v < 1:
            raise ValueError(f"a block needs a whole number >= 1 of cells per side, not {v!r}")
    a = 2 * spacing / math.sqrt(3)
    grid = np.array(np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz),
                                indexing="ij")).reshape(3, -1).T
    centre = np.array(np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), np.arange(nz - 1),
                                  indexing="ij")).reshape(3, -1).T + 0.5
    pts = a * np.concatenate([grid, centre]).astype(float)
    return pts - pts.mean(axis=0), bcc_vectors(spacing)


def slab(width, depth, thickness, spacing):
    """A slab (a slice of a tissue) of BCC cells: the block whose cube corners span at
    most ``width`` x ``depth`` x ``thickness`` (m) along x, y, z."""
    a = 2 * spacing / math.sqrt(3)
    counts = [math.floor(v / a + 1e-9) + 1 for v in (width, depth, thickness)]
    return block(*counts, spacing)


def prism_layer(xy, spacing, height):
    """A one-cell-thick layer of hexagonal prisms of ``height`` on a hexagonal lattice
    ``xy`` (n, 2) (e.g. :func:`cgms.tissue.rectangle`): the points (n, 3) at z = 0, the
    six in-plane neighbour vectors and the caps (the top and bottom faces)."""
    xy = np.asarray(xy, float)
    pts = np.column_stack([xy, np.zeros(len(xy))])
    caps = [((0.0, 0.0, 1.0), height / 2), ((0.0, 0.0, -1.0), height / 2)]
    d = xy[1:] - xy[0]
    v = d[np.argmin(np.hypot(d[:, 0], d[:, 1]))]      # a nearest neighbour's direction
    return pts, hexagon_vectors(spacing, math.atan2(v[1], v[0])), caps


def fresh_neighbours(points, vectors):
    """The fresh neighbours of a built tissue: the pairs of points that share a ridge of
    its Voronoi diagram (scipy.spatial.Voronoi, in the dimensions the points span) and
    whose bond is one of the lattice cell's neighbour ``vectors``, so that the hull's long
    pairs (two surface points whose unbounded cells meet) are left out.

    Returns ``face`` (n, m): the index of cell i's neighbour across its face j, or -1 (a
    free wall), and the bonds (b, 2) with i < k."""
    points = np.asarray(points, float)
    n = len(points)
    span = np.ptp(points, axis=0) > _TOL * max(np.ptp(points), 1e-300)
    face = -np.ones((n, len(vectors)), int)
    if n < 2:
        return face, np.zeros((0, 2), int)
    if span.sum() >= 2 and n > span.sum() + 1:
        pairs = Voronoi(points[:, span]).ridge_points
    else:                       # a row or a handful of points: every pair is a candidate
        pairs = np.array([(i, k) for i in range(n) for k in range(i + 1, n)])
    scale = np.linalg.norm(vectors, axis=1).min()
    for i, k in pairs:
        dv = points[k] - points[i]
        hit = np.flatnonzero(np.linalg.norm(vectors - dv, axis=1) <= 1e-6 * scale)
        back = np.flatnonzero(np.linalg.norm(vectors + dv, axis=1) <= 1e-6 * scale)
        if len(hit) and len(back):
            face[i, hit[0]] = k
            face[k, back[0]] = i
    bonds = np.array(sorted({(min(i, k), max(i, k)) for i in range(n) for k in face[i]
                             if k >= 0}), int).reshape(-1, 2)
    return face, bonds
