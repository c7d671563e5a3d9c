# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Build tissues: bead positions on a hexagonal lattice, written as LAMMPS data files.

Builders (positions in metres, returned as (n, 2) arrays):

* :func:`hex_rectangle` -- a patch of ``nrows`` rows of ``ncols`` beads;
* :func:`rectangle` -- the lattice filling a W x H rectangle; the default fill rule
  reproduces the bead counts of the paper's six rectangular tissues (see ``doc/tissues.md``);
* :func:`disc`, :func:`polygon` -- the lattice points inside a disc or a closed outline;
* :func:`cell_diameters` -- per-bead cell diameters for a heterogeneous tissue;
* :func:`write_data` (:mod:`cgms.positions`) -- a LAMMPS data file for ``atom_style cgms``
  (optionally with a ``Diameters`` section read through ``fix property/atom``).

Lattice: neighbouring beads ``spacing`` apart along a row, rows ``spacing*sqrt(3)/2``
apart, every other row shifted by half a spacing. ``rows_along="x"`` lays the rows
horizontally (as :func:`hex_rectangle` always did); ``rows_along="y"`` turns the lattice by
90 degrees so the rows are vertical. The new builders default to ``"y"``, the orientation
that gives the paper's tissues their counts with the paper's ``W x H`` read as width x
height and its elongation (vertical / horizontal axis) as major / minor axis.

Command line: ``python3 -m cgms.tissue --help`` (:func:`cgms.cli.tissue.tissue_main`).
"""

import math
import sys

import numpy as np

from . import morphology
from .positions import write_data  # noqa: F401 - the data-file writer, kept here for callers

ROW_PITCH = math.sqrt(3) / 2   # row distance / bead spacing
#: the paper's microscale tissues (width x height, mm) and the 86-bead calibration tissue
MICROSCALE = {
    "calibration": (1.25, 1.5),
    "1.5x1.5": (1.5, 1.5),
    "1.5x2.0": (1.5, 2.0),
    "1.5x2.5": (1.5, 2.5),
    "2.0x2.0": (2.0, 2.0),
    "2.0x2.5": (2.0, 2.5),
}
#: the fewest beads a tissue has (its outline needs three)
MIN_BEADS = 3
#: a tissue read from a file may have its median bead spacing this far from x_ref
SPACING_RANGE = (0.5, 2.0)
_TOL = 1e-9                    # relative tolerance (of the spacing) for points on an outline


# --------------------------------------------------------------------------- checks

def _positive(name, value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def _orientation(rows_along):
    if rows_along not in ("x", "y"):
        raise ValueError(f"rows_along must be 'x' or 'y', got {rows_along!r}")
    return rows_along


def _turn(xy, rows_along):
    """Lattice frame (rows along x) <-> world frame: swap the columns for rows along y."""
    return xy[:, ::-1].copy() if rows_along == "y" else xy


# --------------------------------------------------------------------------- lattices

def hex_rectangle(ncols, nrows, spacing, *, short_rows=False, rows_along="x"):
    """Centres of a hexagonal lattice patch: ``nrows`` rows of ``ncols`` beads, rows
    ``spacing*sqrt(3)/2`` apart, odd rows shifted by half a spacing. Returns (n, 2).

    ``short_rows=True``: the shifted (odd) rows hold ``ncols - 1`` beads, so that they
    lie between the beads of the long rows and the patch has straight ends
    (``hex_rectangle(10, 9, x, short_rows=True)`` is the paper's 86-bead tissue).
    ``rows_along="y"``: the rows run along y (the patch turned by 90 degrees; x and y of
    the result swapped). The first bead is at the origin."""
    if ncols < 1 or nrows < 1 or not spacing > 0:
        raise ValueError("ncols and nrows must be >= 1 and spacing > 0")
    if short_rows and ncols < 2 and nrows > 1:
        raise ValueError("short_rows needs ncols >= 2 (the shifted rows hold ncols - 1 beads)")
    _orientation(rows_along)
    j, i = np.mgrid[0:nrows, 0:ncols]
    x = (i + 0.5 * (j % 2)) * spacing
    y = j * spacing * math.sqrt(3) / 2
    keep = ~((j % 2 == 1) & (i == ncols - 1)) if short_rows else np.ones(j.shape, bool)
    xy = np.column_stack([x[keep].ravel(), y[keep].ravel()]).astype(float)
    return _turn(xy, rows_along)


def _lattice_points(lo, hi, spacing, origin):
    """All points of the lattice (rows along x, a bead at ``origin``, the row through
    ``origin`` unshifted) inside the box ``lo``-``hi`` (closed, with a tolerance)."""
    a = spacing
    dy = a * ROW_PITCH
    eps = _TOL * a
    ox, oy = origin
    j = np.arange(math.ceil((lo[1] - eps - oy) / dy), math.floor((hi[1] + eps - oy) / dy) + 1)
    if j.size == 0:
        return np.zeros((0, 2))
    shift = ox + 0.5 * a * (j % 2)
    i0 = np.ceil((lo[0] - eps - shift) / a).astype(int)
    i1 = np.floor((hi[0] + eps - shift) / a).astype(int)
    rows = [np.column_stack([s + a * np.arange(p, q + 1), np.full(max(q - p + 1, 0), oy + jj * dy)])
            for jj, s, p, q in zip(j, shift, i0, i1)]
    return np.concatenate(rows) if rows else np.zeros((0, 2))


RECTANGLE_RULES = ("paper", "centres")


def rectangle_shape(width, height, spacing, rule="paper", rows_along="y", inset=0.0):
    """Rows and beads per row of :func:`rectangle`: a dict with ``nrows``, ``long`` (beads in
    the even rows, the first row included), ``short`` (beads in the odd rows) and ``n``."""
    inset = float(inset)
    if not (math.isfinite(inset) and inset >= 0):
        raise ValueError(f"inset must be a finite number >= 0, got {inset!r}")
    w = _positive("width", width) - 2 * inset
    h = _positive("height", height) - 2 * inset
    a = _positive("spacing", spacing)
    if rule not in RECTANGLE_RULES:
        raise ValueError(f"rule must be one of {RECTANGLE_RULES}, got {rule!r}")
    along, across = (h, w) if _orientation(rows_along) == "y" else (w, h)
    if along < 0 or across < 0:
        raise ValueError(f"inset {inset!r} leaves no room in a {width!r} x {height!r} rectangle")
    dy = a * ROW_PITCH
    long = math.floor(along / a + _TOL) + 1
    if rule == "paper":
        nrows = math.floor(across / dy + _TOL)
        short = long - 1
    else:
        nrows = math.floor(across / dy + _TOL) + 1
        short = math.floor(along / a - 0.5 + _TOL) + 1
    if nrows > 1 and short < 1:
        raise ValueError(f"a {width!r} x {height!r} rectangle is too short along the rows for "
                         f"a hexagonal tissue at spacing {spacing!r} (the shifted rows would be "
                         "empty)")
    n = (nrows + 1) // 2 * long + nrows // 2 * short
    return dict(nrows=nrows, long=long, short=short, n=n)


def rectangle(width, height, spacing, *, rule="paper", rows_along="y", inset=0.0):
    """Hexagonal lattice (spacing ``spacing``, m) filling a ``width`` x ``height`` rectangle
    (x from 0 to width, y from 0 to height). Returns (n, 2), the beads centred in the
    rectangle, ordered row by row.

    Rows run along y by default (``rows_along``); call the side along the rows L and the
    other side T (L = height, T = width for rows along y). Fill rules:

    ``"paper"`` (default): ``floor(T / (spacing*sqrt(3)/2))`` rows; the first, third, ...
      row holds ``floor(L / spacing) + 1`` beads (bead centres span at most L), the rows in
      between one bead fewer. This reproduces all six rectangular tissues of the paper
      (105, 149, 182, 203, 248 and 20 273 beads with spacing x_ref = 150.85 um, W x H as
      the paper writes them); see ``doc/tissues.md``.
    ``"centres"``: every lattice point whose centre lies in the closed rectangle, the
      lattice anchored with a bead in a corner: ``floor(T/dy) + 1`` rows, shifted rows as
      many beads as fit.

    ``inset`` (m) shrinks the rectangle on every side before filling: ``inset = D/2``
    reads the tissue size as the outline of cells of diameter D rather than of centres.
    A point on the (inset) boundary counts as inside (relative tolerance 1e-9)."""
    shape = rectangle_shape(width, height, spacing, rule, rows_along, inset)
    if shape["nrows"] < 1:
        raise ValueError(f"a {width!r} x {height!r} rectangle holds no row of beads at spacing "
                         f"{spacing!r} with rule {rule!r}")
    if rule == "paper" or shape["short"] == shape["long"] - 1:
        xy = hex_rectangle(shape["long"], shape["nrows"], spacing, short_rows=True)
    else:  # the shifted rows as long as the others (ncols = long)
        xy = hex_rectangle(shape["long"], shape["nrows"], spacing)
    xy = _turn(xy, rows_along)
    centre = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    return xy - centre + np.array([float(width), float(height)]) / 2


def disc(radius, spacing, *, centre=(0.0, 0.0), rows_along="y"):
    """Lattice points (spacing ``spacing``) inside the closed disc of ``radius`` about
    ``centre`` (m), with a bead at the centre. Returns (n, 2), row by row."""
    r = _positive("radius", radius)
    a = _positive("spacing", spacing)
    _orientation(rows_along)
    c = np.asarray(centre, float)
    if c.shape != (2,) or not np.all(np.isfinite(c)):
        raise ValueError(f"centre must be a finite (x, y) pair, got {centre!r}")
    pts = _lattice_points((-r, -r), (r, r), a, (0.0, 0.0))
    pts = pts[np.hypot(pts[:, 0], pts[:, 1]) <= r + _TOL * a]
    return _turn(pts, rows_along) + c


# --------------------------------------------------------------------------- polygons

def _cross_many(p, q, r, s, eps):
    """For one segment pq and arrays of segments r[k]s[k]: do they share a point (touching
    and collinear overlap included)?"""
    def orient(a, b, c):
        v = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - \
            (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
        return np.where(np.abs(v) <= eps, 0, np.sign(v))

    def on(a, b, c):  # c within the bounding box of ab (used for collinear points)
        lo, hi = np.minimum(a, b) - 1e-12 * scale, np.maximum(a, b) + 1e-12 * scale
        return np.all((lo <= c) & (c <= hi), axis=-1)

    scale = max(float(np.max(np.abs(np.vstack([p[None], q[None], r, s])))), 1e-300)
    p, q = np.broadcast_to(p, r.shape), np.broadcast_to(q, r.shape)
    o1, o2, o3, o4 = orient(p, q, r), orient(p, q, s), orient(r, s, p), orient(r, s, q)
    proper = (o1 * o2 < 0) & (o3 * o4 < 0)
    return proper | ((o1 == 0) & on(p, q, r)) | ((o2 == 0) & on(p, q, s)) | \
        ((o3 == 0) & on(r, s, p)) | ((o4 == 0) & on(r, s, q))


def _ring(vertices, name):
    """Validated closed outline as an (m, 2) float array without a repeated closing vertex."""
    try:
        v = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: vertices must be an (m, 2) array of numbers") from None
    if v.size == 0:
        raise ValueError(f"{name} is empty: give at least 3 vertices as an (m, 2) array")
    if v.ndim != 2 or v.shape[1] != 2:
        raise ValueError(f"{name}: vertices must be an (m, 2) array, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: vertices must be finite numbers")
    if len(v) > 1 and np.array_equal(v[0], v[-1]):
        v = v[:-1]  # closed explicitly: drop the repeated first vertex
    m = len(v)
    if m < 3:
        raise ValueError(f"{name} has {m} distinct vertices; a closed outline needs at least 3")
    size = float(np.max(np.ptp(v, axis=0)))
    nxt = np.roll(v, -1, axis=0)
    edges = nxt - v
    short = np.flatnonzero(np.hypot(edges[:, 0], edges[:, 1]) <= 1e-12 * max(size, 1e-300))
    if short.size:
        k = int(short[0])
        raise ValueError(f"{name}: vertices {k} and {(k + 1) % m} coincide (zero-length edge)")
    eps = 1e-12 * size * size
    rel = v - v[0]
    far = rel[np.argmax(np.hypot(rel[:, 0], rel[:, 1]))]
    if np.all(np.abs(rel[:, 0] * far[1] - rel[:, 1] * far[0]) <= eps):
        raise ValueError(f"{name} encloses no area: all its vertices lie on a line")
    # adjacent edges share one vertex; they overlap if they fold back onto each other
    back = np.roll(edges, 1, axis=0)  # edge k-1, ending at vertex k where edge k starts
    cross = back[:, 0] * edges[:, 1] - back[:, 1] * edges[:, 0]
    fold = np.flatnonzero((np.abs(cross) <= eps) & (np.einsum("ij,ij->i", back, edges) < 0))
    if fold.size:
        k = int(fold[0])
        raise ValueError(f"{name} is self-intersecting: edges {(k - 1) % m} and {k} fold back "
                         f"over each other at vertex {k}")
    # every pair of non-adjacent edges, O(m^2) (one vectorised test per edge)
    for i in range(m - 2):
        ks = np.arange(i + 2, m if i > 0 else m - 1)
        if ks.size == 0:
            continue
        hit = _cross_many(v[i], nxt[i], v[ks], nxt[ks], eps)
        if hit.any():
            k = int(ks[np.argmax(hit)])
            p, q, r, s = v[i], nxt[i], v[k], nxt[k]
            raise ValueError(f"{name} is self-intersecting: edge {i} ({p[0]:g}, {p[1]:g})-"
                             f"({q[0]:g}, {q[1]:g}) meets edge {k} ({r[0]:g}, {r[1]:g})-"
                             f"({s[0]:g}, {s[1]:g})")
    area = 0.5 * np.sum(v[:, 0] * nxt[:, 1] - nxt[:, 0] * v[:, 1])
    if abs(area) <= 1e-12 * size * size:
        raise ValueError(f"{name} encloses no area (all vertices on a line?)")
    return v


def _rings_disjoint(a, b, names):
    size = max(np.ptp(a, axis=0).max(), np.ptp(b, axis=0).max())
    bn = np.roll(b, -1, axis=0)
    for i in range(len(a)):
        hit = _cross_many(a[i], a[(i + 1) % len(a)], b, bn, 1e-12 * size * size)
        if hit.any():
            raise ValueError(f"{names[0]} edge {i} meets {names[1]} edge {int(np.argmax(hit))}")


def _boundary_distance(pts, ring, chunk=4096):
    """Distance of each point to the closed polyline ``ring``."""
    p0 = ring
    d = np.roll(ring, -1, axis=0) - ring
    dd = np.einsum("ij,ij->i", d, d)
    out = np.empty(len(pts))
    for s in range(0, len(pts), chunk):
        q = pts[s:s + chunk, None, :] - p0[None, :, :]
        t = np.clip(np.einsum("nij,ij->ni", q, d) / dd, 0.0, 1.0)
        r = q - t[..., None] * d[None, :, :]
        out[s:s + chunk] = np.sqrt(np.einsum("nij,nij->ni", r, r).min(axis=1))
    return out


def _inside(pts, ring, tol, closed=True):
    """Points inside the polygon ``ring``: with ``closed`` the points within ``tol`` of the
    outline count as inside, without it they count as outside."""
    from matplotlib.path import Path as MplPath
    path = MplPath(np.vstack([ring, ring[:1]]), closed=True)
    within = path.contains_points(pts)
    check = np.flatnonzero(~within if closed else within)  # only these can change
    if check.size:
        near = _boundary_distance(pts[check], ring) <= tol
        within[check[near]] = closed
    return within


def _prune(pts, spacing, min_neighbours):
    """Drop, repeatedly, the points with fewer than ``min_neighbours`` lattice neighbours."""
    if min_neighbours < 1 or len(pts) == 0:
        return pts
    from scipy.spatial import cKDTree
    while len(pts):
        pairs = cKDTree(pts).query_pairs(spacing * (1 + 1e-6), output_type="ndarray")
        count = np.bincount(pairs.ravel(), minlength=len(pts))
        keep = count >= min_neighbours
        if keep.all():
            break
        pts = pts[keep]
    return pts


def polygon(vertices, spacing, *, origin=None, rows_along="y", holes=(), min_neighbours=1):
    """Lattice points (spacing ``spacing``) inside a closed polygon, given as an (m, 2)
    array of vertices in metres (either orientation; a repeated closing vertex is
    dropped). Points on the outline count as inside. Returns (n, 2), row by row.

    The lattice has a bead at ``origin`` (default: the lower-left corner of the polygon's
    bounding box). ``holes``: optional list of vertex arrays; lattice points strictly
    inside a hole are removed (points on a hole's outline are kept). Holes must lie inside
    the outline and must not touch it or each other.

    ``min_neighbours`` (default 1): lattice points with fewer lattice neighbours inside the
    outline are dropped, repeatedly (a bead alone in a sharp corner would have no
    neighbour within the interaction cutoff, an error in fix cgms/fluid); 0 keeps them.

    Raises ValueError for an empty outline, fewer than 3 vertices, coinciding consecutive
    vertices, zero area, a self-intersecting outline or hole, a non-positive spacing, and
    an outline that holds no lattice point."""
    a = _positive("spacing", spacing)
    _orientation(rows_along)
    ring = _ring(vertices, "polygon")
    rings = [_ring(h, f"hole {k}") for k, h in enumerate(holes)]
    for k, h in enumerate(rings):
        _rings_disjoint(ring, h, ("polygon", f"hole {k}"))
        if not _inside(h, ring, 0.0, closed=False).all():
            raise ValueError(f"hole {k} is not inside the polygon")
        for k2 in range(k):
            _rings_disjoint(rings[k2], h, (f"hole {k2}", f"hole {k}"))
            if _inside(h[:1], rings[k2], 0.0)[0] or _inside(rings[k2][:1], h, 0.0)[0]:
                raise ValueError(f"holes {k2} and {k} overlap")
    lo, hi = ring.min(axis=0), ring.max(axis=0)
    org = lo if origin is None else np.asarray(origin, float)
    if org.shape != (2,) or not np.all(np.isfinite(org)):
        raise ValueError(f"origin must be a finite (x, y) pair, got {origin!r}")
    if rows_along == "y":  # work in the lattice frame (rows along x)
        ring, rings = ring[:, ::-1], [h[:, ::-1] for h in rings]
        lo, hi, org = lo[::-1], hi[::-1], org[::-1]
    pts = _lattice_points(lo, hi, a, org)
    tol = _TOL * a
    if len(pts):
        pts = pts[_inside(pts, ring, tol)]
    for h in rings:
        if len(pts):
            pts = pts[~_inside(pts, h, tol, closed=False)]
    pts = _prune(pts, a, min_neighbours)
    if len(pts) == 0:
        raise ValueError(f"the polygon holds no lattice point at spacing {spacing!r}"
                         + (f" with at least {min_neighbours} neighbour(s)" if min_neighbours
                            else ""))
    return _turn(pts, rows_along)


# --------------------------------------------------------------------------- heterogeneity

def cell_diameters(n, mean, cv, seed=None, *, dist="lognormal", lower=0.5, upper=None):
    """``n`` per-bead cell diameters with the given ``mean`` (m) and coefficient of
    variation ``cv`` (standard deviation / mean), drawn with
    ``numpy.random.default_rng(seed)``.

    ``dist="lognormal"`` (default): positive and right-skewed like measured cell sizes,
    with exactly the requested mean and cv (log-space sigma^2 = ln(1 + cv^2)); clipping
    then hardly ever acts (at cv = 0.1 a draw below 0.5 mean is a 7-sigma event), so it
    does not bias the mean. ``dist="normal"``: symmetric; at cv >= 0.2 the clip at 0.5 mean
    starts to cut the tail. Every value is clipped to ``[lower*mean, upper*mean]``
    (``upper=None``: no upper bound). ``cv = 0`` gives ``n`` copies of ``mean``."""
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    mean = _positive("mean", mean)
    cv = float(cv)
    if not (math.isfinite(cv) and cv >= 0):
        raise ValueError(f"cv must be >= 0, got {cv!r}")
    if not 0 < lower < 1:
        raise ValueError(f"lower must be a fraction of the mean in (0, 1), got {lower!r}")
    if upper is not None and not upper > 1:
        raise ValueError(f"upper must be > 1 (a multiple of the mean) or None, got {upper!r}")
    if cv == 0:
        return np.full(n, mean)
    rng = np.random.default_rng(seed)
    if dist == "lognormal":
        s2 = math.log1p(cv * cv)
        d = rng.lognormal(math.log(mean) - s2 / 2, math.sqrt(s2), n)
    elif dist == "normal":
        d = rng.normal(mean, cv * mean, n)
    else:
        raise ValueError(f"dist must be 'lognormal' or 'normal', got {dist!r}")
    return np.clip(d, lower * mean, None if upper is None else upper * mean)


def clipped_mean(cv, dist="lognormal", lower=0.5, upper=None, points=20001):
    """Mean of the diameters :func:`cell_diameters` draws, as a multiple of the requested
    mean: the clipping to ``[lower, upper]`` moves it away from 1 when ``cv`` is large
    (lognormal cv = 5: 0.77). Computed on a fine grid of the distribution's quantiles."""
    from scipy import stats
    q = (np.arange(points) + 0.5) / points
    if cv == 0:
        return 1.0
    if dist == "lognormal":
        s2 = math.log1p(cv * cv)
        d = stats.lognorm.ppf(q, math.sqrt(s2), scale=math.exp(-s2 / 2))
    else:
        d = stats.norm.ppf(q, 1.0, cv)
    return float(np.clip(d, lower, upper).mean())


# --------------------------------------------------------------------------- layouts read

def check_layout(ids, xy, x_ref):
    """ValueError for bead positions no tissue has: non-finite, two beads at one place, not
    in metres (the median spacing far from x_ref), all in a row, or in pieces that no chain
    of neighbours links (LAMMPS would stop on an isolated bead, or on no area at the end).
    ``ids`` name the beads in the messages; ``x_ref``: the material's cell spacing (m)."""
    bad = np.flatnonzero(~np.isfinite(xy).all(axis=1))
    if len(bad):
        raise ValueError(f"bead id {ids[bad[0]]} has a non-finite position "
                         f"({len(bad)} bead(s) in all)")
    if len(xy) < MIN_BEADS:
        raise ValueError(f"{len(xy)} bead(s); a tissue needs at least {MIN_BEADS}")
    order = np.lexsort((xy[:, 1], xy[:, 0]))
    same = np.flatnonzero((np.diff(xy[order], axis=0) == 0).all(axis=1))
    if len(same):
        a, b = ids[order[same[0]]], ids[order[same[0] + 1]]
        raise ValueError(f"beads {a} and {b} are at the same position; remove the "
                         "duplicate")
    gap = morphology.spacing(xy)
    ratio = gap / x_ref
    if not SPACING_RANGE[0] < ratio < SPACING_RANGE[1]:
        unit = next((f" (these look like {name})" for name, scale in
                     (("micrometres", 1e6), ("millimetres", 1e3))
                     if SPACING_RANGE[0] < ratio / scale < SPACING_RANGE[1]), "")
        raise ValueError(f"neighbouring beads are {gap:.4g} m apart (median), "
                         f"{ratio:.3g} times the material's cell spacing x_ref = "
                         f"{x_ref:.4g} m: positions must be cell centres in "
                         f"metres{unit}")
    label = morphology.pieces(xy)
    if label.max() > 0:
        away = ids[label > 0]
        raise ValueError(
            f"the beads form {label.max() + 1} pieces: bead id(s) "
            f"{', '.join(str(i) for i in away[:5])}{' ...' if len(away) > 5 else ''} are "
            f"more than {morphology.MAX_EDGE_FACTOR:g} x the median spacing from the largest "
            "piece; a tissue is one piece of neighbouring cells")
    morphology.outline(xy)     # ValueError for beads all in a row


if __name__ == "__main__":   # python3 -m cgms.tissue: the builder's command line
    from .cli.tissue import tissue_main
    sys.exit(tissue_main())
