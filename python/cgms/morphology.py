# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Tissue shape measures from bead (cell-centroid) positions (doc/model.md).

The tissue outline is the ordered closed polygon of the peripheral bead centres, found from
a Delaunay triangulation of the beads with the long (non-neighbour) triangles removed.
Tissue area ``A`` and perimeter ``P`` are those of that polygon; the elongation ``EL`` is
the length of the vertical centre line over that of the horizontal centre line (both
measured inside the outline). Values are normalised by the fresh state (``A/A0`` ...).

Functions (all on NumPy arrays of positions ``xy`` with shape (n, 2), in any length unit):

- :func:`outline`: indices of the peripheral beads, counter-clockwise.
- :func:`boundary_cycles`: every boundary cycle (outer outlines and holes), for diagnosis.
- :func:`measures`: area, perimeter, elongation, centroid of the outline polygon.
- :func:`elongation_pca`, :func:`polygon_elongation`: major/minor axis ratio from the area
  second moments (``ELpca``, reported beside the paper's EL; robust to notches).
- :func:`normalise`: ``A/A0``, ``P/P0``, ``EL/EL0`` relative to a fresh tissue.
- :func:`shrinkage`: per-bead local area shrinkage between a fresh and a later state.
- :func:`read_dump` (:mod:`cgms.dumps`): frames of a LAMMPS ``dump custom`` text file.
"""

import math
import warnings

import numpy as np
from scipy.spatial import Delaunay, cKDTree

from .dumps import read_dump  # noqa: F401 - the dump reader, kept here for callers

#: default ``max_edge`` as a multiple of the median nearest-neighbour distance; it lies
#: between the first (1) and second (sqrt 3 = 1.73) neighbour shells of a hexagonal lattice
MAX_EDGE_FACTOR = 1.5

#: ``max_edge`` factor for the fine model's cell centroids: its dried cells flatten (their
#: elongation 1.8-2.5 at s = 0.3), so their centroids are irregular and at 1.5 the outline
#: drops cells and counts holes from s = 0.4 on (the 86-cell tissue at s = 0.3: P/P0 1.155
#: at 1.5, 0.598 at 2.0); 2.0 bridges them, and also the outline's one-spacing notches
#: that 1.5 follows (the same tissue at s = 0.8: A/A0 0.7652 against 0.7672 at 1.5;
#: doc/results/validation.md)
FINE_EDGE_FACTOR = 2.0


# ---------------------------------------------------------------------------------------
# triangulation and outline


def _points(xy, name="xy"):
    """``xy`` as a float (n, 2) array; (n, 3) arrays lose their z column."""
    p = np.asarray(xy, dtype=float)
    if p.ndim != 2 or p.shape[1] not in (2, 3):
        raise ValueError(f"{name} must have shape (n, 2) (or (n, 3), z ignored), "
                         f"got {p.shape}")
    p = p[:, :2]
    if not np.all(np.isfinite(p)):
        bad = np.flatnonzero(~np.all(np.isfinite(p), axis=1))
        raise ValueError(f"{name} has non-finite positions at indices {bad[:10].tolist()}")
    return p


def _check_points(p):
    """Reject fewer than 3 beads, coincident beads and collinear beads; return the
    nearest-neighbour distances."""
    n = len(p)
    if n < 3:
        raise ValueError(f"an outline needs at least 3 beads, got {n}")
    dist, nbr = cKDTree(p).query(p, k=2)
    if np.any(dist[:, 1] == 0):
        i = int(np.flatnonzero(dist[:, 1] == 0)[0])
        raise ValueError(f"beads {i} and {int(nbr[i, 1])} coincide at {p[i].tolist()}")
    q = p - p.mean(axis=0)
    sv = np.linalg.svd(q, compute_uv=False)
    if sv[1] <= 1e-9 * sv[0]:
        raise ValueError(f"all {n} beads are collinear (a single row has no area); "
                         "an outline needs a two-dimensional tissue")
    return dist[:, 1]


def spacing(xy):
    """Median nearest-neighbour distance of the beads (at least 2)."""
    p = _points(xy)
    return float(np.median(cKDTree(p).query(p, k=2)[0][:, 1]))


def pieces(xy, gap=MAX_EDGE_FACTOR):
    """The beads grouped into the pieces of the tissue: an array of piece labels 0, 1, ...
    (piece 0 the largest), two beads lying in one piece when a chain of beads links them
    with no step longer than ``gap`` times the median nearest-neighbour distance. One
    label for an intact tissue; a tissue torn apart, or a bead flung out, has more."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    p = _points(xy)
    pairs = cKDTree(p).query_pairs(gap * spacing(p), output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(p),) * 2)
    _, label = connected_components(graph, directed=False)
    sizes = np.bincount(label)
    rank = np.empty_like(sizes)
    rank[np.argsort(-sizes, kind="stable")] = np.arange(len(sizes))
    return rank[label]


def default_max_edge(xy, factor=MAX_EDGE_FACTOR):
    """The longest triangle edge: ``factor`` (default ``MAX_EDGE_FACTOR``, 1.5) times the
    median nearest-neighbour distance of the beads."""
    p = _points(xy)
    return factor * float(np.median(_check_points(p)))


def _signed_areas(p, tri):
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def triangles(xy, max_edge=None):
    """Kept Delaunay triangles of the beads: (k, 3) bead indices, each counter-clockwise,
    no edge longer than ``max_edge`` (default :func:`default_max_edge`), no zero-area
    sliver. Raises ValueError for degenerate input or when no triangle is kept."""
    p = _points(xy)
    nn = _check_points(p)
    if max_edge is None:
        max_edge = MAX_EDGE_FACTOR * float(np.median(nn))
    elif not max_edge > 0:
        raise ValueError(f"max_edge must be > 0, got {max_edge}")
    q = p - p.mean(axis=0)
    try:
        tri = Delaunay(q).simplices.astype(np.int64)
    except Exception as exc:  # scipy.spatial.QhullError (name varies between versions)
        raise ValueError(f"Delaunay triangulation of {len(p)} beads failed: {exc}") from exc
    area = _signed_areas(q, tri)
    tri[area < 0] = tri[area < 0][:, ::-1]
    area = np.abs(area)
    e = np.stack([np.hypot(*(q[tri[:, (k + 1) % 3]] - q[tri[:, k]]).T) for k in range(3)],
                 axis=1)
    keep = np.all(e <= max_edge, axis=1) & (area > 1e-12 * max_edge**2)
    if not np.any(keep):
        raise ValueError(f"no Delaunay triangle has all edges <= max_edge = {max_edge:.6g} "
                         f"(median nearest-neighbour distance {np.median(nn):.6g}): "
                         "the beads do not form a connected tissue at that length")
    return tri[keep]


def _cycles_from_triangles(p, tri):
    """All boundary cycles of the union of the CCW triangles ``tri``: list of bead-index
    arrays (first bead not repeated), kept region on the left of each cycle, so outer
    outlines are counter-clockwise and holes clockwise.

    Boundary edges are the directed triangle edges whose reverse is not present. At a bead
    with several boundary edges (two parts of the tissue touching at one bead), the walk
    continues along the edge that bounds the same empty wedge as the edge it came in on,
    so each cycle is the full boundary of one connected empty region: the outer outline
    of a tissue pinched at a bead passes that bead twice instead of splitting."""
    n = len(p)
    a = np.concatenate([tri[:, 0], tri[:, 1], tri[:, 2]])
    b = np.concatenate([tri[:, 1], tri[:, 2], tri[:, 0]])
    code, rev = a * n + b, b * n + a
    bnd = ~np.isin(code, rev)
    a, b = a[bnd], b[bnd]
    out = {}
    for k, u in enumerate(a):
        out.setdefault(int(u), []).append(k)
    # successor of edge u->v: among the edges v->w, the first met turning counter-
    # clockwise from the direction v->u (that wedge is the empty side of u->v)
    succ = np.empty(len(a), dtype=np.int64)
    for k in range(len(a)):
        u, v = a[k], b[k]
        cand = out[int(v)]
        if len(cand) == 1:
            succ[k] = cand[0]
            continue
        r = math.atan2(p[u, 1] - p[v, 1], p[u, 0] - p[v, 0])
        ang = [(math.atan2(p[b[j], 1] - p[v, 1], p[b[j], 0] - p[v, 0]) - r) % (2 * math.pi)
               for j in cand]
        succ[k] = cand[int(np.argmin(ang))]
    seen = np.zeros(len(a), dtype=bool)
    cycles = []
    for k0 in range(len(a)):
        if seen[k0]:
            continue
        cyc, k = [], k0
        while not seen[k]:
            seen[k] = True
            cyc.append(int(a[k]))
            k = succ[k]
        if k != k0:  # cannot happen for a valid triangulation
            raise RuntimeError("outline walk did not close; please report this tissue")
        cyc = np.array(cyc, dtype=np.int64)
        start = int(np.argmin(cyc))  # deterministic start: the smallest bead index
        cycles.append(np.roll(cyc, -start))
    return cycles


def polygon_area(poly):
    """Signed (shoelace) area of the polygon with vertices ``poly`` (m, 2), implicitly
    closed; positive for counter-clockwise order."""
    q = np.asarray(poly, dtype=float)
    q = q - q.mean(axis=0)
    x, y = q[:, 0], q[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def boundary_cycles(xy, max_edge=None):
    """Every boundary cycle of the kept triangulation (see :func:`outline`), largest
    signed area first. Counter-clockwise cycles (area > 0) are outer outlines of
    separate tissue pieces; clockwise ones (area < 0) are holes (a kept-triangle gap
    inside the tissue, e.g. a locally stretched region). Returns a list of
    ``(indices, signed_area)``."""
    p = _points(xy)
    cycles = _cycles_from_triangles(p, triangles(p, max_edge))
    res = [(c, polygon_area(p[c])) for c in cycles]
    return sorted(res, key=lambda t: -t[1])


def outline(xy, max_edge=None):
    """Indices of the peripheral beads, as an ordered closed polygon, counter-clockwise.

    Method: Delaunay triangulation of the bead centres; triangles with any edge longer
    than ``max_edge`` (default 1.5 x the median nearest-neighbour distance, between the
    first and second neighbour shells of a hexagonal lattice) are dropped, so concave
    (inward-bent) edges of the tissue are followed bead by bead; the boundary edges
    (used by exactly one kept triangle) are walked into cycles.

    The polygon is closed implicitly: the last bead connects to the first, which is not
    repeated. It starts at the smallest bead index of the outline.

    Degenerate input (fewer than 3 beads, coincident beads, all beads collinear, no kept
    triangle) raises ValueError. If the boundary is not one cycle, the outer cycle of the
    largest tissue piece (largest area) is returned and a UserWarning says what was left
    out: holes inside the tissue (their area counts as tissue), other pieces not connected
    to it by triangles, and beads in no kept triangle (isolated beads or dangling chains).
    A bead where two parts of the tissue touch at a single point appears twice in the
    returned outline (the polygon is then only weakly simple; area and perimeter are still
    those of the whole piece). Use :func:`boundary_cycles` to inspect all cycles.
    """
    p = _points(xy)
    tri = triangles(p, max_edge)
    cycles = [(c, polygon_area(p[c])) for c in _cycles_from_triangles(p, tri)]
    cycles.sort(key=lambda t: -t[1])
    best, best_area = cycles[0]
    if best_area <= 0:  # cannot happen: every piece has a CCW outer cycle
        raise RuntimeError("no counter-clockwise outer outline found; please report this")
    notes = []
    pieces = [c for c, s in cycles if s > 0]
    holes = [c for c, s in cycles if s < 0]
    if len(pieces) > 1:
        other = np.setdiff1d(np.concatenate(pieces[1:]), best)
        notes.append(f"{len(pieces) - 1} other tissue piece(s) with {len(other)} outline "
                     f"bead(s) (areas {[round(s / best_area, 4) for c, s in cycles[1:] if s > 0]}"
                     " of the largest) are left out")
    if holes:
        notes.append(f"{len(holes)} hole(s) inside the tissue (total area "
                     f"{-sum(s for c, s in cycles if s < 0) / best_area:.4g} of the outline "
                     "area) count as tissue")
    loose = len(p) - len(np.unique(tri))
    if loose:
        notes.append(f"{loose} bead(s) belong to no triangle with edges <= max_edge "
                     "(isolated or on dangling chains) and are ignored")
    if len(np.unique(best)) < len(best):
        notes.append("the outline passes a bead twice (two parts touching at one bead)")
    if notes:
        warnings.warn("tissue outline: " + "; ".join(notes), UserWarning, stacklevel=2)
    return best


# ---------------------------------------------------------------------------------------
# measures


def _polygon_moments(poly):
    """Area, centroid and central second moments (Sxx, Syy, Sxy = integrals of dx^2,
    dy^2, dx dy over the polygon) of a CCW polygon."""
    q = np.asarray(poly, dtype=float)
    o = q.mean(axis=0)
    q = q - o
    x0, y0 = q[:, 0], q[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    c = x0 * y1 - x1 * y0
    area = 0.5 * c.sum()
    if not area > 0:
        raise ValueError("the outline polygon has no positive area")
    cx = ((x0 + x1) * c).sum() / (6 * area)
    cy = ((y0 + y1) * c).sum() / (6 * area)
    ixx = ((x0 * x0 + x0 * x1 + x1 * x1) * c).sum() / 12
    iyy = ((y0 * y0 + y0 * y1 + y1 * y1) * c).sum() / 12
    ixy = ((x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * c).sum() / 24
    return (area, np.array([cx, cy]) + o,
            (ixx - area * cx * cx, iyy - area * cy * cy, ixy - area * cx * cy))


def _axis_ratio(sxx, syy, sxy):
    lam = np.linalg.eigvalsh(np.array([[sxx, sxy], [sxy, syy]]))
    if not lam[0] > 0:
        raise ValueError("degenerate second moments (no extent along one axis)")
    return math.sqrt(lam[1] / lam[0])


def polygon_elongation(poly):
    """Second-moment elongation of a closed CCW polygon: ``sqrt(l1 / l2)`` of the
    eigenvalues l1 >= l2 of its central area second-moment tensor. Exactly the axis ratio
    of an ellipse, the side ratio of a rectangle and that of any affine image
    ``diag(a, b)`` of a regular polygon, in any orientation; >= 1.

    Beside the paper's height / width (:func:`measures`), it is the elongation that a notch
    in the outline cannot move by much: a notch changes the integrals by its own area
    times its distance squared, while it moves a centre-line extent by its whole depth
    when the line runs through it (doc/results/validation.md, "Elongation from second moments")."""
    _, _, mom = _polygon_moments(poly)
    return _axis_ratio(*mom)


def line_extent(poly, value, axis):
    """Extent of a closed polygon along a line: for ``axis=0`` the vertical line
    ``x = value`` (extent in y), for ``axis=1`` the horizontal line ``y = value``
    (extent in x). It is the distance between the outermost intersections of the line
    with the polygon edges, so for a non-convex outline that the line crosses more than
    twice, the gaps in between are included. Returns (extent, (low, high))."""
    q = np.asarray(poly, dtype=float)
    u = q[:, axis] - value
    v = q[:, 1 - axis]
    u1, v1 = np.roll(u, -1), np.roll(v, -1)
    hits = [v[u == 0]]
    cross = u * u1 < 0
    hits.append(v[cross] + (v1[cross] - v[cross]) * u[cross] / (u[cross] - u1[cross]))
    hits = np.concatenate(hits)
    if hits.size == 0:
        name = "x" if axis == 0 else "y"
        raise ValueError(f"the line {name} = {value:.6g} misses the outline")
    lo, hi = float(hits.min()), float(hits.max())
    return hi - lo, (lo, hi)


def measures(xy, max_edge=None):
    """Shape of the tissue outline (:func:`outline`) as a dict:

    - ``area``, ``perimeter``: of the outline polygon of peripheral bead centres.
    - ``centroid``: area centroid of that polygon, (x, y).
    - ``height``, ``width``: extent of the outline along the vertical line x = centroid x
      and along the horizontal line y = centroid y (outermost intersections with the
      polygon; see :func:`line_extent`).
    - ``elongation``: ``height / width`` (doc/model.md, paper section 2.5: for a rectangular
      tissue, the vertical symmetry axis over the horizontal one). Measured in the fixed
      x-y frame, so it is not rotation invariant; it may be below 1.
    - ``elongation_pca``: the second-moment elongation of the outline polygon
      (:func:`polygon_elongation`: sqrt of the eigenvalue ratio of its area second-moment
      tensor), rotation invariant and >= 1; normalised as ``ELpca/ELpca0``. Reported beside
      the paper's ``elongation``, which a notch of the outline on a centre line moves by the
      notch's depth (near-square tissues: doc/results/validation.md).
    - ``outline``: the bead indices of the outline (counter-clockwise).
    """
    p = _points(xy)
    idx = outline(p, max_edge)
    poly = p[idx]
    area, centroid, mom = _polygon_moments(poly)
    perimeter = float(np.sum(np.hypot(*(np.roll(poly, -1, axis=0) - poly).T)))
    height, _ = line_extent(poly, centroid[0], axis=0)
    width, _ = line_extent(poly, centroid[1], axis=1)
    return dict(area=float(area), perimeter=perimeter, elongation=height / width,
                centroid=(float(centroid[0]), float(centroid[1])), height=height, width=width,
                elongation_pca=_axis_ratio(*mom), outline=idx)


def side_bow(xy, band):
    """How far each side of a rectangular (axis-aligned) tissue bends inward, as a dict
    left/right/bottom/top -> distance (same units as ``xy``).

    A side's beads are those within ``band`` of the extreme coordinate on that side; the
    bow is the distance of the one nearest the side's middle from the chord joining the
    side's two end beads, positive towards the tissue's centre (a concave, inward-bent
    side), negative outward. The paper (section 4.2) reports slightly inward-bent fresh
    macroscale tissue."""
    p = _points(xy)
    centre = p.mean(axis=0)
    bows = {}
    for name, axis, sign in (("left", 0, -1), ("right", 0, 1), ("bottom", 1, -1),
                             ("top", 1, 1)):
        along = 1 - axis
        depth = sign * p[:, axis]
        side = p[depth > depth.max() - band]
        side = side[np.argsort(side[:, along])]
        if len(side) < 3:
            raise ValueError(f"the {name} side has {len(side)} beads within band {band}: "
                             "need at least 3 (widen the band)")
        first, last = side[0], side[-1]
        middle = side[np.argmin(np.abs(side[:, along] - centre[along]))]
        t = (middle[along] - first[along]) / (last[along] - first[along])
        chord = first[axis] + t * (last[axis] - first[axis])
        bows[name] = float(sign * (chord - middle[axis]))
    return bows


def elongation_pca(xy, max_edge=None, source="outline"):
    """Major/minor axis ratio ``sqrt(l1 / l2)`` of the eigenvalues l1 >= l2 of the second
    moment (covariance) matrix: of the area enclosed by the outline polygon
    (``source="outline"``, default) or of the bead positions (``source="beads"``).

    For a rectangle or an ellipse (area moments) this is exactly the side or axis ratio,
    whatever the orientation; it is always >= 1 and rotation invariant, unlike the
    symmetry-axis elongation of :func:`measures` (height / width in the x-y frame), which
    is the paper's definition. The bead version weighs every bead equally, so a denser
    periphery pulls it towards the outline."""
    p = _points(xy)
    if source == "outline":
        return polygon_elongation(p[outline(p, max_edge)])
    if source == "beads":
        _check_points(p)
        q = p - p.mean(axis=0)
        return _axis_ratio((q[:, 0] ** 2).sum(), (q[:, 1] ** 2).sum(), (q[:, 0] * q[:, 1]).sum())
    raise ValueError(f"source must be 'outline' or 'beads', got {source!r}")


def normalise(m, fresh):
    """Normalised morphology ``{"A/A0", "P/P0", "EL/EL0"}`` of measures ``m`` relative to
    the fresh-state measures ``fresh`` (dicts from :func:`measures`, or any dicts with
    ``area``, ``perimeter``, ``elongation``). Adds ``"ELpca/ELpca0"`` when both carry
    ``elongation_pca``."""
    out = {}
    for key, name in (("A/A0", "area"), ("P/P0", "perimeter"), ("EL/EL0", "elongation")):
        if name not in m or name not in fresh:
            raise ValueError(f"normalise needs '{name}' in both dicts")
        if not fresh[name] > 0:
            raise ValueError(f"fresh {name} must be > 0, got {fresh[name]}")
        out[key] = float(m[name]) / float(fresh[name])
    if "elongation_pca" in m and "elongation_pca" in fresh:
        out["ELpca/ELpca0"] = float(m["elongation_pca"]) / float(fresh["elongation_pca"])
    return out


def shrinkage(xy, xy_fresh, max_edge=None):
    """Per-bead local area shrinkage ``1 - a / a0``, shape (n,).

    The local area of a bead is one third of the area of the kept Delaunay triangles
    around it (:func:`triangles`). The triangulation is made once, on the fresh positions
    ``xy_fresh`` (``max_edge`` applies to them), and the same triangles (bead indices) are
    measured in ``xy``: the beads are matched by index, so both arrays must list the same
    beads in the same order (e.g. sorted by id). Triangle areas are signed with the fresh
    orientation, so a triangle turned over counts negative. Beads in no kept triangle get
    NaN. A uniform scaling by ``s`` gives ``1 - s**2`` everywhere."""
    p = _points(xy)
    p0 = _points(xy_fresh, "xy_fresh")
    if p.shape != p0.shape:
        raise ValueError(f"xy has {len(p)} beads, xy_fresh has {len(p0)}: they must match "
                         "bead by bead")
    tri = triangles(p0, max_edge)
    q = p - p.mean(axis=0)
    q0 = p0 - p0.mean(axis=0)
    a0 = np.bincount(tri.ravel(), np.repeat(_signed_areas(q0, tri), 3), len(p)) / 3
    a = np.bincount(tri.ravel(), np.repeat(_signed_areas(q, tri), 3), len(p)) / 3
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(a0 > 0, 1 - a / np.where(a0 > 0, a0, 1), np.nan)
