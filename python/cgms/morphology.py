"""Tissue shape measures from bead centres (first version: convex outline)."""

import numpy as np
from scipy.spatial import ConvexHull


def hull_measures(xy):
    """Area and perimeter of the convex hull of the bead centres, and the elongation
    (extent along y / extent along x). The convex hull ignores inward bending of the
    edges; the ordered peripheral-bead outline of MODEL.md 9 replaces it later."""
    hull = ConvexHull(xy)
    extent = np.ptp(xy, axis=0)
    return dict(area=hull.volume, perimeter=hull.area, elongation=extent[1] / extent[0])
