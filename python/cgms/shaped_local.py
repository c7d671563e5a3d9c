# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The fixed geometry of the shaped tensor model (:mod:`cgms.shaped_tensor`) without
(n, n) arrays, for tissues of 10^4-10^5 beads: the same rings, ghost points, walls and
fresh polygons as :func:`cgms.shaped.topology` and :func:`cgms.shaped.junction_map` (same
rules, same ring order), computed on every bead at once from a k-d tree's neighbour pairs.

``shaped.build`` holds the (n, n) distances (3 GB at 20 273 beads); this takes 0.1 s
there, and :func:`cgms.shaped_data.per_bead` turns it into LAMMPS's per-atom data (a
patch per bead, the way that replaced, took about 25 s). Only what the tensor model uses is built: per wall its cell and fresh
vector ``d0`` (ring order), per cell its fresh polygon area and whether it has a ghost
point (a free wall), and the fresh neighbour pairs (the bonds, i < k).
"""

import math

import numpy as np
from scipy.spatial import cKDTree

from . import shaped


def _rotate(v, angle):
    """Rotate the rows of ``v`` (m, 2) by the angles ``angle`` (m,)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])


def neighbour_pairs(xy, radius):
    """Pairs (i, k), i < k, of beads closer than ``radius``, sorted."""
    pairs = cKDTree(xy).query_pairs(radius, output_type="ndarray")
    pairs = np.sort(pairs, axis=1)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def pair_keys(pairs, n):
    """One integer per pair (i < k), sorted as the pairs are sorted."""
    return pairs[:, 0].astype(np.int64) * n + pairs[:, 1]


def rings(xy, spacing, cutoff=None):
    """Every bead's ring of neighbour and ghost points, as :func:`cgms.shaped.topology`
    builds it (neighbours within ``cutoff * spacing``, strictly; counter-clockwise from the
    smallest angle; round(gap / 60 deg) - 1 ghosts in a gap between two consecutive
    neighbours that are not neighbours of each other or are 180 degrees or more apart,
    placed by rotations of the gap's two sides blended linearly). Returns (bonds (i < k),
    ring owner (m,), ring point offsets from the owner (m, 2), ghost flags (m,)), the
    points of each owner contiguous and in ring order."""
    xy = np.asarray(xy, float)
    n = len(xy)
    cutoff = shaped.CUTOFF if cutoff is None else cutoff
    r = cutoff * spacing
    bonds = neighbour_pairs(xy, r)
    bonds = bonds[np.hypot(*(xy[bonds[:, 1]] - xy[bonds[:, 0]]).T) < r]
    keys = pair_keys(bonds, n)
    i = np.concatenate([bonds[:, 0], bonds[:, 1]])
    k = np.concatenate([bonds[:, 1], bonds[:, 0]])
    deg = np.bincount(i, minlength=n)
    if np.any(deg == 0):
        bead = int(np.flatnonzero(deg == 0)[0])
        raise ValueError(f"bead {bead + 1} has no neighbour within {cutoff} x spacing")
    d = xy[k] - xy[i]
    ang = np.arctan2(d[:, 1], d[:, 0])
    order = np.lexsort((ang, i))
    i, k, d, ang = i[order], k[order], d[order], ang[order]
    start = np.concatenate([[0], np.cumsum(deg)[:-1]])
    pos = np.arange(len(i)) - start[i]
    nxt = start[i] + (pos + 1) % deg[i]           # the next neighbour round the ring
    k2, d2 = k[nxt], d[nxt]
    gap = np.mod(ang[nxt] - ang, 2 * math.pi)
    gap[deg[i] == 1] = 2 * math.pi
    lo, hi = np.minimum(k, k2), np.maximum(k, k2)
    want = lo.astype(np.int64) * n + hi
    at = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
    closed = (keys[at] == want) & (gap < math.pi) & (deg[i] > 1)
    m = np.where(closed, 0, np.maximum(np.rint(gap / (math.pi / 3)).astype(int) - 1, 0))
    # ring points: each neighbour, then the ghosts of the gap after it
    count = 1 + m
    slot = np.repeat(np.arange(len(i)), count)
    g = np.arange(len(slot)) - np.repeat(np.cumsum(count) - count, count)   # 0: the real one
    ghost = g > 0
    offs = d[slot].copy()
    sg = slot[ghost]
    gg = g[ghost].astype(float)
    mm = m[sg].astype(float)
    phi = gap[sg] / (mm + 1)
    w = (mm + 1 - gg) / (mm + 1)
    offs[ghost] = (w[:, None] * _rotate(d[sg], gg * phi)
                   + (1 - w)[:, None] * _rotate(d2[sg], -(mm + 1 - gg) * phi))
    return bonds, i[slot], offs, ghost


def walls(owner, offs, n):
    """Per wall (one per ring point, facing it): its cell and its fresh vector from
    junction (j-1, j) to junction (j, j+1), the junctions being the centroids of the bead
    and two consecutive ring points; per cell the fresh polygon area (shoelace over the
    junctions relative to the bead)."""
    size = np.bincount(owner, minlength=n)
    start = np.concatenate([[0], np.cumsum(size)[:-1]])
    pos = np.arange(len(owner)) - start[owner]
    nxt = start[owner] + (pos + 1) % size[owner]
    prv = start[owner] + (pos - 1) % size[owner]
    J = (offs + offs[nxt]) / 3                      # junction (j, j+1)
    Jprev = J[prv]                                  # junction (j-1, j)
    cross = Jprev[:, 0] * J[:, 1] - Jprev[:, 1] * J[:, 0]
    return J - Jprev, 0.5 * np.bincount(owner, cross, minlength=n)


def base(xy0, mat, params=None, spacing=None):
    """What :func:`cgms.shaped_tensor.build` needs of the built tissue, as
    :func:`cgms.shaped.build` gives it but without (n, n) arrays: x0, n, mat, the wall
    parameters, per wall ``cell`` and ``d0``, per cell ``poly_area0`` and ``boundary``,
    the fresh ``bonds`` (i < k) and their sorted ``bond_keys``."""
    p = dict(shaped.DEFAULTS, **(params or {}))
    x0 = np.asarray(xy0, float)
    n = len(x0)
    spacing = mat["x_ref"] if spacing is None else spacing
    bonds, owner, offs, ghost = rings(x0, spacing)
    d0, area0 = walls(owner, offs, n)
    return dict(x0=x0, n=n, mat=mat, cell=owner, d0=d0, poly_area0=area0,
                boundary=np.bincount(owner, ghost, minlength=n) > 0, bonds=bonds,
                bond_keys=pair_keys(bonds, n), spacing=float(spacing),
                lamella=p["lamella"], wall_EA=p["wall_EA"], buckle=p["buckle"],
                soft=p["soft"], beta_a=p["beta_a"], beta_b=p["beta_b"])
