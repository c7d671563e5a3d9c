# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Closed triangulated walls that pass through themselves or through each other: the 3-D
twin of :func:`cgms.mfc.metrics.crossing` (doc/mfc.md, "3-D tissue").

Two triangles that share no corner and intersect do so along a segment whose two ends are
where an edge of one pierces the other, so the test is: does any of the six edges cross
the other triangle (signed volumes, strict: a touch in a point or along a line, a set of
measure zero, is not counted). Candidate pairs are pruned by a k-d tree over the
triangles' centroids and their bounding spheres. Triangles sharing a corner (a wall's own
neighbours) are not tested: a wall that folds through itself also brings triangles that
share none into each other, so a crossing is found from those.

Between cells no corner is shared, so every intersecting pair of two cells' triangles is
two walls that passed through each other: the lamella's gap (d_p = 8 um) is gone there.
"""

import numpy as np
from scipy.spatial import cKDTree

#: candidate pairs tested per NumPy pass (memory: about 1 kB per pair)
CHUNK = 200_000


def _orient(a, b, c, d):
    """Sign of the volume of the tetrahedron a b c d (rows of (k, 3) arrays)."""
    return np.sign(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)))


def _edge_pierces(p, q, a, b, c):
    """Does the segment p q cross the triangle a b c (through its interior)?"""
    ends = _orient(p, a, b, c) * _orient(q, a, b, c) < 0
    s1, s2, s3 = _orient(p, q, a, b), _orient(p, q, b, c), _orient(p, q, c, a)
    return ends & (s1 != 0) & (s1 == s2) & (s2 == s3)


def _intersect(t, u):
    """Do the triangles t and u (each (k, 3, 3): pair, corner, xyz) intersect?"""
    hit = np.zeros(len(t), bool)
    for one, other in ((t, u), (u, t)):
        for e in range(3):
            hit |= _edge_pierces(one[:, e], one[:, (e + 1) % 3], other[:, 0], other[:, 1],
                                 other[:, 2])
    return hit


def intersecting_triangles(x, tri):
    """Pairs (i, j), i < j, of triangles of the mesh (positions ``x`` (N, 3), triangles
    ``tri`` (k, 3)) that share no corner and intersect, as a (m, 2) array sorted by i."""
    x = np.asarray(x, float)
    tri = np.asarray(tri, int)
    if not np.all(np.isfinite(x)):
        raise ValueError("wall positions that are not finite")
    corners = x[tri]                                           # (k, 3, 3)
    centre = corners.mean(axis=1)
    radius = np.linalg.norm(corners - centre[:, None], axis=2).max(axis=1)
    pairs = cKDTree(centre).query_pairs(2 * radius.max() * (1 + 1e-9), output_type="ndarray")
    if not len(pairs):
        return np.zeros((0, 2), int)
    i, j = pairs[:, 0], pairs[:, 1]
    near = np.linalg.norm(centre[i] - centre[j], axis=1) <= (radius[i] + radius[j]) * (1 + 1e-9)
    i, j = i[near], j[near]
    shared = (tri[i][:, :, None] == tri[j][:, None, :]).any(axis=(1, 2))
    i, j = i[~shared], j[~shared]
    hit = np.concatenate([_intersect(corners[i[k:k + CHUNK]], corners[j[k:k + CHUNK]])
                          for k in range(0, len(i), CHUNK)] or [np.zeros(0, bool)])
    out = np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1)[hit]
    return out[np.lexsort((out[:, 1], out[:, 0]))]


def tissue_crossings(x, tri, n_wall):
    """The crossings of a tissue of closed walls, every cell ``n_wall`` particles in ID
    order and triangulated alike (``tri``, 0-based within a cell). Returns a dict:
    ``self`` (cells' own triangle pairs that intersect: a wall through itself) and
    ``between`` (triangle pairs of two cells: two walls through each other), each a list
    of (cell_a, cell_b, particle_a, particle_b) with 1-based cell (molecule) and atom IDs,
    particle the first corner of each triangle; ``cells`` the 1-based cells involved."""
    x = np.asarray(x, float)
    if len(x) % n_wall:
        raise ValueError(f"{len(x)} wall particles is not a multiple of {n_wall} per cell")
    ncell = len(x) // n_wall
    tri = np.asarray(tri, int)
    every = np.concatenate([tri + c * n_wall for c in range(ncell)])
    owner = np.repeat(np.arange(ncell), len(tri))
    pairs = intersecting_triangles(x, every)
    out = dict(self=[], between=[])
    for a, b in pairs:
        ca, cb = int(owner[a]), int(owner[b])
        row = (ca + 1, cb + 1, int(every[a, 0]) + 1, int(every[b, 0]) + 1)
        out["self" if ca == cb else "between"].append(row)
    out["cells"] = sorted({r[k] for key in ("self", "between") for r in out[key] for k in (0, 1)})
    return out


def describe(found):
    """One clause naming what :func:`tissue_crossings` found, or '' when nothing."""
    parts = []
    own = sorted({r[0] for r in found["self"]})
    if own:
        r = found["self"][0]
        which = (f"cell {own[0]}'s wall crosses itself" if len(own) == 1 else
                 f"the walls of {len(own)} cells cross themselves (cells {_ids(own)})")
        parts.append(f"{which} ({len(found['self'])} intersecting triangle pairs; first: "
                     f"cell {r[0]}'s triangles at particles {r[2]} and {r[3]})")
    two = sorted({(r[0], r[1]) for r in found["between"]})
    if two:
        r = found["between"][0]
        parts.append(f"{len(two)} pair{'s' if len(two) > 1 else ''} of cells' walls pass "
                     f"through each other ({', '.join(f'{a}-{b}' for a, b in two[:8])}"
                     f"{' ...' if len(two) > 8 else ''}; {len(found['between'])} "
                     f"intersecting triangle pairs; first: the triangles at particles {r[2]} "
                     f"(cell {r[0]}) and {r[3]} (cell {r[1]}))")
    return "; ".join(parts)


def _ids(cells, most=8):
    return ", ".join(str(c) for c in cells[:most]) + (" ..." if len(cells) > most else "")
