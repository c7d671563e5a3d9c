# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Measures of fine-scale (MFC) cells and tissues from wall particle positions.

A cell is the closed polygon of its wall particles in ID order (counter-clockwise). Per
cell: area (shoelace), perimeter (sum of bond lengths), area centroid, roundness
4 pi A / P^2, elongation (major / minor axis of the second-moment ellipse) and
compactness sqrt(4 A / pi) / major axis. The tissue measures A, P, EL are those of the
CGMS beads (:func:`cgms.morphology.measures`) applied to the cell centroids, so the two
models are measured alike.

A ring that crosses itself (its walls passed through each other) or encloses no area has no
such measures: :class:`RingError` names the cell (its shoelace area would be silently wrong,
or its second moments not positive).
"""

import math

import numpy as np

from .. import morphology


class RingError(ValueError):
    """A cell's wall ring is not a simple polygon of positive area. ``cell`` is 1-based (the
    molecule ID of the wall data file); ``level``, when set, the dryness it was met at."""

    def __init__(self, cell, why):
        super().__init__(f"cell {cell}'s wall ring {why}")
        self.cell, self.why, self.level = cell, why, None


def crossing(q):
    """The first pair (i, j), i < j, of non-adjacent edges i -> i+1 and j -> j+1 of the
    closed polygon ``q`` (n, 2) that cross each other properly, or None."""
    a, b = q, np.roll(q, -1, axis=0)
    n = len(q)

    def side(p, r, t):   # sign of the turn p -> r -> t, for every pair (rows: i, columns: j)
        return np.sign((r[:, None, 0] - p[:, None, 0]) * (t[None, :, 1] - p[:, None, 1])
                       - (r[:, None, 1] - p[:, None, 1]) * (t[None, :, 0] - p[:, None, 0]))

    # edge j's ends on either side of edge i's line, and edge i's on either side of j's
    straddles = side(a, b, a) * side(a, b, b) < 0
    cross = straddles & straddles.T
    i, j = np.nonzero(np.triu(cross, 2))
    keep = ~((i == 0) & (j == n - 1))    # the closing edge touches the first one
    return (int(i[keep][0]), int(j[keep][0])) if keep.any() else None


def polygons(xy, n_wall):
    """Wall positions (n_cells * n_wall, 2), in ID order, as (n_cells, n_wall, 2)."""
    xy = np.asarray(xy, float)[:, :2]
    if len(xy) % n_wall:
        raise ValueError(f"{len(xy)} wall particles is not a multiple of {n_wall} per cell")
    return xy.reshape(-1, n_wall, 2)


def cells(xy, n_wall):
    """Per-cell measures as a dict of arrays: ``area``, ``perimeter``, ``centroid`` (n, 2),
    ``roundness``, ``elongation``, ``compactness``, ``major`` (axis length)."""
    poly = polygons(xy, n_wall)
    out = {k: np.empty(len(poly)) for k in ("area", "perimeter", "roundness", "elongation",
                                            "compactness", "major")}
    out["centroid"] = np.empty((len(poly), 2))
    for c, q in enumerate(poly):
        if not np.all(np.isfinite(q)):
            raise RingError(c + 1, "has a particle at a position that is not finite")
        pair = crossing(q)
        if pair is not None:
            i, j = (c * n_wall + k + 1 for k in pair)   # atom IDs: consecutive along a ring
            raise RingError(c + 1, f"crosses itself (its wall segment from particle {i} on "
                                   f"crosses the one from particle {j} on: the walls passed "
                                   "through each other)")
        try:
            area, centroid, (sxx, syy, sxy) = morphology._polygon_moments(q)
        except ValueError:
            raise RingError(c + 1, "encloses no positive area (collapsed or turned "
                                   "inside out)") from None
        lam = np.linalg.eigvalsh(np.array([[sxx, sxy], [sxy, syy]]))
        if not lam[0] > 0:
            raise RingError(c + 1, "is degenerate (no extent along one axis)")
        perimeter = float(np.sum(np.hypot(*(np.roll(q, -1, axis=0) - q).T)))
        # an ellipse of semi-axes a, b has area moment pi a^3 b / 4 = A a^2 / 4
        major = 4 * math.sqrt(lam[1] / area)
        out["area"][c] = area
        out["perimeter"][c] = perimeter
        out["centroid"][c] = centroid
        out["roundness"][c] = 4 * math.pi * area / perimeter ** 2
        out["elongation"][c] = math.sqrt(lam[1] / lam[0])
        out["compactness"][c] = math.sqrt(4 * area / math.pi) / major
        out["major"][c] = major
    return out


def tissue(centroids):
    """Tissue area, perimeter, elongation (and the rest of
    :func:`cgms.morphology.measures`) of the cell centroids, with the outline's longest
    edge ``FINE_EDGE_FACTOR`` (2.0) median spacings: the dried cells' centroids are
    irregular."""
    return morphology.measures(
        centroids, morphology.default_max_edge(centroids, morphology.FINE_EDGE_FACTOR))


def summary(xy, n_wall, fresh=None):
    """Cell and tissue measures of one state: a dict of cell means, tissue ``A``, ``P``,
    ``EL``, ``ELpca`` (second moments) and, given the ``fresh`` summary, ``A/A0``, ``P/P0``,
    ``EL/EL0``, ``ELpca/ELpca0`` and the relative change of the mean cell area and
    perimeter."""
    cell = cells(xy, n_wall)
    out = dict(cells=len(cell["area"]))
    if len(cell["area"]) >= 3:   # a tissue outline needs three cells
        t = tissue(cell["centroid"])
        out.update(A=t["area"], P=t["perimeter"], EL=t["elongation"],
                   ELpca=t["elongation_pca"])
    out.update(cell_area=float(cell["area"].mean()),
               cell_perimeter=float(cell["perimeter"].mean()),
               cell_roundness=float(cell["roundness"].mean()),
               cell_elongation=float(cell["elongation"].mean()),
               cell_compactness=float(cell["compactness"].mean()))
    if fresh is not None and "A" in out:
        # ELpca/ELpca0 too where the fresh record has ELpca (records before it lack it)
        out.update(morphology.normalise(
            dict(area=t["area"], perimeter=t["perimeter"], elongation=t["elongation"],
                 elongation_pca=t["elongation_pca"]),
            dict(area=fresh["A"], perimeter=fresh["P"], elongation=fresh["EL"],
                 **({"elongation_pca": fresh["ELpca"]} if "ELpca" in fresh else {}))))
    if fresh is not None:
        out["cell_area/A0"] = out["cell_area"] / fresh["cell_area"]
        out["cell_perimeter/P0"] = out["cell_perimeter"] / fresh["cell_perimeter"]
    return out, cell
