# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Tissue morphology (python/cgms/morphology.py) on shapes with known answers.
Needs NumPy and SciPy; no LAMMPS."""

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import ConvexHull

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))

from cgms import morphology as mo  # noqa: E402
from cgms import tissue  # noqa: E402

A = 1.5e-4  # lattice spacing (m)
H = A * math.sqrt(3) / 2  # row spacing


def rect_exact(ncols, nrows, a=A):
    """Outline area, perimeter, height and width of tissue.hex_rectangle(ncols, nrows, a).
    Every row spans (ncols - 1) a and the side edges are nearest-neighbour bonds of
    length a, so the outline is a stack of (nrows - 1) parallelograms."""
    h = a * math.sqrt(3) / 2
    return dict(area=(nrows - 1) * (ncols - 1) * a * h, perimeter=2 * (ncols - 1) * a
                + 2 * (nrows - 1) * a, height=(nrows - 1) * h, width=(ncols - 1) * a)


def hex_disc(radius, a, offset=(0.0, 0.0)):
    """Hexagonal-lattice beads (spacing a, a bead at ``offset``) within ``radius`` of the
    origin."""
    h = a * math.sqrt(3) / 2
    ni, nj = int(radius / a) + 2, int(radius / h) + 2
    j, i = np.mgrid[-nj:nj + 1, -ni:ni + 1]
    xy = np.column_stack([((i + 0.5 * (j % 2)) * a).ravel(), (j * h).ravel()]) + offset
    return xy[np.hypot(*xy.T) <= radius]


def rotate(xy, angle, shift=(0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    return xy @ np.array([[c, s], [-s, c]]) + np.asarray(shift)


# --- outline ---------------------------------------------------------------------------


@pytest.mark.parametrize("ncols,nrows", [(10, 12), (9, 11), (5, 3), (2, 2), (16, 14)])
def test_hex_rectangle_exact(ncols, nrows):
    xy = tissue.hex_rectangle(ncols, nrows, A)
    m = mo.measures(xy)
    ex = rect_exact(ncols, nrows)
    assert m["area"] == pytest.approx(ex["area"], rel=1e-12)
    assert m["perimeter"] == pytest.approx(ex["perimeter"], rel=1e-12)
    assert m["height"] == pytest.approx(ex["height"], rel=1e-12)
    assert m["width"] == pytest.approx(ex["width"], rel=1e-12)
    assert m["elongation"] == pytest.approx(ex["height"] / ex["width"], rel=1e-12)
    # the outline polygon has C2 symmetry: centroid at ((2 ncols - 1) a / 4, (nrows - 1) h / 2)
    assert m["centroid"] == pytest.approx(((2 * ncols - 1) * A / 4, (nrows - 1) * H / 2),
                                          rel=1e-12)
    # every bead of the first and last rows and of the two zig-zag sides is peripheral
    per = set(range(ncols)) | set(range((nrows - 1) * ncols, nrows * ncols)) \
        | set(range(0, nrows * ncols, ncols)) | set(range(ncols - 1, nrows * ncols, ncols))
    assert sorted(m["outline"].tolist()) == sorted(per)


def test_outline_ccw_closed_and_neighbours():
    xy = tissue.hex_rectangle(10, 12, A)
    idx = mo.outline(xy)
    poly = xy[idx]
    assert idx[0] == 0  # starts at the smallest bead index
    assert len(np.unique(idx)) == len(idx)  # simple: no bead twice, first not repeated
    assert mo.polygon_area(poly) > 0  # counter-clockwise
    # closed: consecutive beads, including last -> first, are nearest neighbours
    step = np.hypot(*(np.roll(poly, -1, axis=0) - poly).T)
    np.testing.assert_allclose(step, A, rtol=1e-12)
    # bottom row is walked left to right (CCW starts along the bottom from bead 0)
    assert idx[:10].tolist() == list(range(10))


def test_outline_independent_of_bead_order():
    xy = tissue.hex_rectangle(8, 9, A)
    perm = np.random.default_rng(1).permutation(len(xy))
    idx = mo.outline(xy[perm])
    # same beads, same cyclic CCW order
    assert set(perm[idx].tolist()) == set(mo.outline(xy).tolist())
    assert mo.polygon_area(xy[perm][idx]) == pytest.approx(mo.polygon_area(xy[mo.outline(xy)]),
                                                           rel=1e-12)


@pytest.mark.parametrize("angle,shift", [(0.3, (1e-3, -2e-3)), (math.pi / 2, (0, 0)),
                                         (2.0, (5e-2, 7e-2)), (-1.1, (-1e-4, 3e-4))])
def test_rotation_translation_invariance(angle, shift):
    xy = tissue.hex_rectangle(10, 12, A)
    xy = xy + np.random.default_rng(2).normal(0, 0.05 * A, xy.shape)  # break symmetry
    m0 = mo.measures(xy)
    m1 = mo.measures(rotate(xy, angle, shift))
    assert m1["area"] == pytest.approx(m0["area"], rel=1e-10)
    assert m1["perimeter"] == pytest.approx(m0["perimeter"], rel=1e-10)
    assert m1["elongation_pca"] == pytest.approx(m0["elongation_pca"], rel=1e-9)
    assert np.array_equal(m1["outline"], m0["outline"])
    c = rotate(np.array([m0["centroid"]]), angle, shift)[0]
    assert m1["centroid"] == pytest.approx(tuple(c), rel=1e-9, abs=1e-12 * A)


def test_symmetry_axis_elongation_is_frame_bound():
    """EL (vertical / horizontal centre line) inverts under a quarter turn; EL_pca does not."""
    xy = tissue.hex_rectangle(10, 12, A)
    m0 = mo.measures(xy)
    m1 = mo.measures(rotate(xy, math.pi / 2))
    assert m1["elongation"] == pytest.approx(1 / m0["elongation"], rel=1e-12)
    assert m1["elongation_pca"] == pytest.approx(m0["elongation_pca"], rel=1e-12)


def test_disc_area_converges():
    """A hexagonal-lattice disc: the bead-centre outline lies about half a spacing inside
    the circle, so A / (pi R^2) - 1 is about -0.9 a / R: first-order convergence."""
    R = 1e-3
    errs = []
    for a in (R / 5, R / 10, R / 20, R / 40):
        for off in ((0.0, 0.0), (0.31 * a, 0.17 * a)):
            m = mo.measures(hex_disc(R, a, off))
            err = m["area"] / (math.pi * R**2) - 1
            assert -1.2 * a / R < err < -0.6 * a / R
            assert m["elongation"] == pytest.approx(1, abs=2.5 * a / R)
            assert m["centroid"] == pytest.approx((0, 0), abs=0.3 * a)
            errs.append(abs(err))
    errs = np.array(errs).reshape(4, 2).mean(axis=1)
    ratios = errs[:-1] / errs[1:]
    assert np.all((ratios > 1.6) & (ratios < 2.5)), ratios  # error halves with the spacing


def test_disc_perimeter_staircase():
    """The outline follows nearest-neighbour bonds (three directions 60 degrees apart), so
    its length does not tend to 2 pi R but to 2 pi R * 6 / (pi sqrt 3) = 1.1027 x 2 pi R
    (mean zig-zag factor); each of the six arcs between extreme beads is a whole number
    of bonds, up to one short of 2 R / (sqrt 3 a)."""
    R = 1e-3
    limit = 6 / (math.pi * math.sqrt(3))
    for k in (10, 23, 47, 95, 131):
        a = R / k
        for off in ((0.0, 0.0), (0.31 * a, 0.17 * a), (0.5 * a, 0.2 * a)):
            ratio = mo.measures(hex_disc(R, a, off))["perimeter"] / (2 * math.pi * R)
            assert -a / R < ratio - limit <= 1e-12


def bent_rectangle(sagitta, ncols=16, nrows=14, a=A):
    """hex_rectangle with its top and bottom edges bowed inward by ``sagitta`` at the
    centre: y -> cy + (y - cy) g(x), g = 1 - (2 s / H)(1 - xi^2), xi = (x - cx) / (W / 2).
    Returns (bent beads, flat beads, g, cx, cy, H, W)."""
    flat = tissue.hex_rectangle(ncols, nrows, a)
    cx, cy = (2 * ncols - 1) * a / 4, (nrows - 1) * a * math.sqrt(3) / 4
    height = (nrows - 1) * a * math.sqrt(3) / 2
    width = np.ptp(flat[:, 0])

    def g(x):
        return 1 - (2 * sagitta / height) * (1 - ((x - cx) / (width / 2)) ** 2)

    bent = flat.copy()
    bent[:, 1] = cy + (flat[:, 1] - cy) * g(flat[:, 0])
    return bent, flat, g, cx, cy, height, width


@pytest.mark.parametrize("s_over_a", [0.25, 0.5, 1.0, 1.5])
def test_bent_outline(s_over_a):
    ncols, nrows = 16, 14
    s = s_over_a * A
    bent, flat, g, cx, cy, height, width = bent_rectangle(s, ncols, nrows)
    m0, m = mo.measures(flat), mo.measures(bent)
    # same peripheral beads in the same order
    assert np.array_equal(m["outline"], m0["outline"])
    # area: the image of the flat outline is the integral of g over it (exact: midpoint-
    # of-edges quadrature on the triangles is exact for g quadratic in x); the polygon
    # through the bent beads replaces the top and bottom parabolas by chords, adding at
    # most 2 (W / a) * |y''| a^3 / 12 = 4 s a^2 / (3 W)
    tri = mo.triangles(flat)
    p = flat[tri]
    g_mean = sum(g((p[:, k, 0] + p[:, (k + 1) % 3, 0]) / 2) for k in range(3)) / 3
    a_image = float(np.sum(mo._signed_areas(flat, tri) * g_mean))
    chord = 4 * s * A**2 / (3 * width)
    assert 0 < m["area"] - a_image < chord
    # and, roughly, two parabolic segments of area (2/3) s W are cut off the rectangle
    assert m0["area"] - m["area"] == pytest.approx(4 / 3 * s * width, rel=0.01)
    # the convex hull misses the bend
    assert ConvexHull(bent).volume > m0["area"] - 0.1 * (4 / 3 * s * width)
    # vertical centre line: the top chord spans x = cx - a/4 .. cx + 3a/4, where the
    # parabola is s d1 d2 / (W/2)^2 above its vertex (d1 = a/4, d2 = 3a/4)
    assert m["centroid"] == pytest.approx((cx, cy), rel=1e-12)
    height_exp = height - 2 * s + 2 * s * (3 * A**2 / 16) / (width / 2) ** 2
    assert m["height"] == pytest.approx(height_exp, rel=1e-12)
    # horizontal centre line y = cy crosses the side bonds between rows 6 and 7
    r6, r7 = 6 * ncols, 7 * ncols

    def cross(i, j):
        (x0, y0), (x1, y1) = bent[i], bent[j]
        return x0 + (x1 - x0) * (cy - y0) / (y1 - y0)

    width_exp = cross(r6 + ncols - 1, r7 + ncols - 1) - cross(r6, r7)
    assert m["width"] == pytest.approx(width_exp, rel=1e-12)
    assert m["elongation"] == pytest.approx(height_exp / width_exp, rel=1e-12)
    norm = mo.normalise(m, m0)
    assert norm["EL/EL0"] == pytest.approx(1 - 2 * s / height, abs=2e-3)
    assert norm["A/A0"] < 1 and norm["EL/EL0"] < 1


def test_hole_piece_and_pinch():
    # a missing interior bead is a hole: the outline is unchanged, its area counts
    xy = tissue.hex_rectangle(10, 10, A)
    full = mo.measures(xy)
    with pytest.warns(UserWarning, match="1 hole"):
        m = mo.measures(np.delete(xy, 55, axis=0))
    assert m["area"] == pytest.approx(full["area"], rel=1e-12)
    cycles = mo.boundary_cycles(np.delete(xy, 55, axis=0))
    assert [len(c) for c, _ in cycles] == [len(full["outline"]), 6]
    assert cycles[1][1] == pytest.approx(-6 * math.sqrt(3) / 4 * A**2, rel=1e-12)
    # a second, smaller piece far away is left out
    small = tissue.hex_rectangle(4, 4, A) + [20 * A, 0]
    with pytest.warns(UserWarning, match="1 other tissue piece"):
        m = mo.measures(np.vstack([xy, small]))
    assert m["area"] == pytest.approx(full["area"], rel=1e-12)
    assert np.array_equal(m["outline"], full["outline"])
    # a lone bead is ignored with a warning
    with pytest.warns(UserWarning, match="1 bead"):
        m = mo.measures(np.vstack([xy, [[-5 * A, 0]]]))
    assert m["area"] == pytest.approx(full["area"], rel=1e-12)
    # two patches touching at one bead (point reflection through the top-right corner):
    # one outline passing that bead twice, enclosing both patches
    patch = tissue.hex_rectangle(4, 4, A)
    corner = patch[-1]
    twin = 2 * corner - patch[:-1]
    both = np.vstack([patch, twin])
    with pytest.warns(UserWarning, match="twice"):
        m = mo.measures(both)
    one = mo.measures(patch)
    assert m["area"] == pytest.approx(2 * one["area"], rel=1e-12)
    assert m["perimeter"] == pytest.approx(2 * one["perimeter"], rel=1e-12)
    assert np.sum(m["outline"] == 15) == 2
    assert len(m["outline"]) == 2 * len(one["outline"])


@pytest.mark.parametrize("xy,match", [
    (np.zeros((0, 2)), "at least 3"),
    (np.array([[0.0, 0.0], [A, 0.0]]), "at least 3"),
    (np.column_stack([np.arange(6) * A, np.zeros(6)]), "collinear"),
    (np.column_stack([np.arange(6) * A, 2 * np.arange(6) * A + 1e-3]), "collinear"),
    (np.array([[0.0, 0.0], [A, 0.0], [A, 0.0], [0.0, A]]), "coincide"),
    (np.array([[0.0, 0.0], [A, 0.0], [np.nan, A]]), "non-finite"),
    (np.zeros((5, 4)), r"shape \(n, 2\)"),
    (np.zeros(6), r"shape \(n, 2\)"),
])
def test_degenerate_input_raises(xy, match):
    with pytest.raises(ValueError, match=match):
        mo.outline(xy)
    with pytest.raises(ValueError, match=match):
        mo.measures(xy)


def test_max_edge_too_small_raises():
    xy = tissue.hex_rectangle(5, 5, A)
    with pytest.raises(ValueError, match="no Delaunay triangle"):
        mo.outline(xy, max_edge=0.9 * A)
    with pytest.raises(ValueError, match="max_edge must be > 0"):
        mo.outline(xy, max_edge=0)
    # a generous max_edge takes the convex hull
    m = mo.measures(xy, max_edge=10 * A)
    assert m["area"] == pytest.approx(ConvexHull(xy).volume, rel=1e-12)


def test_three_beads():
    xy = np.array([[0.0, 0.0], [A, 0.0], [A / 2, H]])
    m = mo.measures(xy)
    assert m["outline"].tolist() == [0, 1, 2]
    assert m["area"] == pytest.approx(math.sqrt(3) / 4 * A**2, rel=1e-12)
    assert m["perimeter"] == pytest.approx(3 * A, rel=1e-12)
    # vertical line x = a/2: full height h; horizontal line y = h/3: width 2a/3
    assert m["elongation"] == pytest.approx(H / (2 / 3 * A), rel=1e-12)


# --- elongation_pca, normalise ---------------------------------------------------------


def test_elongation_pca():
    # a rectangle of beads (square lattice) 30 x 10 spacings: outline moments give 3 exactly
    x, y = np.meshgrid(np.arange(31) * A, np.arange(11) * A)
    xy = np.column_stack([x.ravel(), y.ravel()])
    for angle in (0.0, 0.4, 1.3):
        r = rotate(xy, angle, (1e-3, 2e-3))
        assert mo.elongation_pca(r) == pytest.approx(3, rel=1e-9)
        # beads: variances (n^2 - 1) / 12 per axis -> sqrt((31^2 - 1) / (11^2 - 1))
        assert mo.elongation_pca(r, source="beads") == pytest.approx(
            math.sqrt((31**2 - 1) / (11**2 - 1)), rel=1e-9)
    assert mo.measures(xy)["elongation"] == pytest.approx(1 / 3, rel=1e-12)
    with pytest.raises(ValueError, match="source"):
        mo.elongation_pca(xy, source="hull")


def rotate_polygon(poly, angle):
    c, s = math.cos(angle), math.sin(angle)
    return poly @ np.array([[c, s], [-s, c]]) + [0.3, -1.1]


@pytest.mark.parametrize("angle", [0.0, 0.7, 2.0])
def test_polygon_elongation_exact_on_ellipse_and_rectangle(angle):
    """An n-gon inscribed in an ellipse at equal parameter steps is diag(a, b) applied to a
    regular n-gon, whose second-moment tensor is isotropic: its tensor is diag(a^3 b,
    a b^3) times that one's, so the elongation is a / b exactly, for any n >= 3 and any
    orientation. A rectangle's is its side ratio. Tolerance: a sum of n products rounded
    in double precision, relative 1e-12 for n <= 100 and coordinates within 10 of 0."""
    a, b = 3.0, 1.25
    for n in (3, 4, 7, 64):
        t = 2 * math.pi * np.arange(n) / n + 0.1
        ellipse = np.column_stack([a * np.cos(t), b * np.sin(t)])
        assert mo.polygon_elongation(rotate_polygon(ellipse, angle)) == pytest.approx(
            a / b, rel=1e-12)
    rectangle = np.array([[0, 0], [2.0, 0], [2.0, 0.5], [0, 0.5]])
    assert mo.polygon_elongation(rotate_polygon(rectangle, angle)) == pytest.approx(
        4, rel=1e-12)
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    assert mo.polygon_elongation(rotate_polygon(square, angle)) == pytest.approx(1, rel=1e-12)
    with pytest.raises(ValueError, match="no positive area"):   # clockwise
        mo.polygon_elongation(rectangle[::-1])


@pytest.mark.parametrize("depth,width", [(0.1, 0.05), (0.2, 0.02), (0.05, 0.3)])
def test_notch_moves_the_papers_elongation_not_the_second_moments(depth, width):
    """A unit square with a notch (width w, depth d) in the middle of its top side, the
    case of the 1.5x1.5 MFC outline at s = 0.4. The paper's EL (centre-line height over
    width) drops to 1 - d: the vertical centre line runs down the notch. The second-moment
    elongation, from the square's moments minus the notch's (exact integrals), stays
    within a few w d of 1."""
    square = [[0, 0], [1, 0], [1, 1], [0.5 + width / 2, 1], [0.5 + width / 2, 1 - depth],
              [0.5 - width / 2, 1 - depth], [0.5 - width / 2, 1], [0, 1]]
    poly = np.array(square, float)
    area = 1 - width * depth
    cy = (0.5 - width * depth * (1 - depth / 2)) / area
    sxx = 1 / 12 - width ** 3 * depth / 12
    syy = 1 / 3 - width * (1 - (1 - depth) ** 3) / 3 - area * cy ** 2
    exact = math.sqrt(max(sxx, syy) / min(sxx, syy))
    assert mo.polygon_elongation(poly) == pytest.approx(exact, rel=1e-12)
    assert exact - 1 < 3 * width * depth
    # the paper's EL of the same outline, through measures (the beads are its corners)
    height, _ = mo.line_extent(poly, 0.5, axis=0)
    assert height == pytest.approx(1 - depth, rel=1e-12)


def test_measures_report_the_second_moment_elongation():
    """measures() carries the outline polygon's second-moment elongation beside the paper's
    EL, and normalise() its ratio to the fresh one."""
    x, y = np.meshgrid(np.arange(8) * A, np.arange(20) * A)   # mirror-symmetric: Sxy = 0
    xy = np.column_stack([x.ravel(), y.ravel()])
    m = mo.measures(xy)
    assert m["elongation_pca"] == mo.polygon_elongation(xy[m["outline"]])
    stretched = xy * [1.0, 1.1]
    n = mo.normalise(mo.measures(stretched), m)
    assert n["ELpca/ELpca0"] == pytest.approx(1.1, rel=1e-12)
    assert n["EL/EL0"] == pytest.approx(1.1, rel=1e-12)


def test_normalise():
    xy = tissue.hex_rectangle(10, 12, A)
    fresh = mo.measures(xy)
    dried = mo.measures(0.8 * xy)
    n = mo.normalise(dried, fresh)
    assert n["A/A0"] == pytest.approx(0.64, rel=1e-12)
    assert n["P/P0"] == pytest.approx(0.8, rel=1e-12)
    assert n["EL/EL0"] == pytest.approx(1, rel=1e-12)
    assert n["ELpca/ELpca0"] == pytest.approx(1, rel=1e-12)
    assert mo.normalise(fresh, fresh) == {"A/A0": 1, "P/P0": 1, "EL/EL0": 1, "ELpca/ELpca0": 1}
    with pytest.raises(ValueError, match="area"):
        mo.normalise(dict(area=1.0, perimeter=1.0, elongation=1.0),
                     dict(area=0.0, perimeter=1.0, elongation=1.0))
    with pytest.raises(ValueError, match="perimeter"):
        mo.normalise(dict(area=1.0, elongation=1.0), fresh)


# --- shrinkage -------------------------------------------------------------------------


@pytest.mark.parametrize("scale", [0.7, 0.9, 1.0])
def test_shrinkage_uniform(scale):
    fresh = tissue.hex_rectangle(10, 12, A)
    fresh = fresh + np.random.default_rng(3).normal(0, 0.03 * A, fresh.shape)
    now = rotate(scale * fresh, 0.7, (3e-3, -1e-3))
    sh = mo.shrinkage(now, fresh)
    assert sh.shape == (len(fresh),)
    np.testing.assert_allclose(sh, 1 - scale**2, atol=1e-10)


def test_shrinkage_periphery_less_than_centre():
    """A radial contraction that is strongest at the centre: r -> r (1 - c (1 - r^2 / R^2))."""
    fresh = hex_disc(1e-3, 1e-4)
    r = np.hypot(*fresh.T)
    now = fresh * (1 - 0.2 * (1 - (r / 1e-3) ** 2))[:, None]
    sh = mo.shrinkage(now, fresh)
    per = np.zeros(len(fresh), bool)
    per[mo.outline(fresh)] = True
    assert np.all(np.isfinite(sh))
    assert sh[per].mean() < 0.5 * sh[~per].mean()
    centre = np.argmin(r)
    assert sh[centre] == pytest.approx(1 - 0.8**2, abs=0.01)  # locally a uniform 0.8 scaling
    assert sh[centre] == pytest.approx(sh.max(), abs=0.01)


def test_shrinkage_loose_bead_nan_and_mismatch():
    fresh = np.vstack([tissue.hex_rectangle(5, 5, A), [[-10 * A, 0]]])
    sh = mo.shrinkage(0.9 * fresh, fresh)
    assert np.isnan(sh[-1]) and np.allclose(sh[:-1], 0.19)
    with pytest.raises(ValueError, match="bead by bead"):
        mo.shrinkage(fresh[:-1], fresh)


# --- read_dump -------------------------------------------------------------------------


def write_dump(path, frames, columns, box=((-1e-3, 3e-3), (-2e-3, 4e-3), (-1e-4, 1e-4)),
               flags="ff ff pp"):
    """frames: list of (timestep, rows); rows: list of tuples in ``columns`` order."""
    out = []
    for step, rows in frames:
        out += ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ATOMS", str(len(rows)),
                f"ITEM: BOX BOUNDS {flags}"]
        out += [" ".join(f"{v:.16e}" for v in b) for b in box]
        out.append("ITEM: ATOMS " + " ".join(columns))
        out += [" ".join(str(v) if isinstance(v, (int, np.integer)) else f"{v:.16e}"
                         for v in row) for row in rows]
    Path(path).write_text("\n".join(out) + "\n")


@pytest.fixture
def lattice_frames():
    """Two frames of a 6 x 5 lattice (fresh, then scaled by 0.8 about its centre), with
    ids 1..30 written in a shuffled order, and per-bead mf = id / 100, pressure = 10 id."""
    xy = tissue.hex_rectangle(6, 5, A) + [2e-4, 3e-4]
    n = len(xy)
    ids = np.arange(1, n + 1)
    perm = np.random.default_rng(4).permutation(n)
    c = xy.mean(axis=0)
    frames = []
    for step, scale in ((0, 1.0), (5000, 0.8)):
        pos = c + scale * (xy - c)
        rows = [(int(ids[k]), 1 + k % 2, pos[k, 0], pos[k, 1], 0.0, ids[k] / 100, 10.0 * ids[k])
                for k in perm]
        frames.append((step, rows))
    return xy, c, frames


def test_read_dump_xyz(tmp_path, lattice_frames):
    xy, c, frames = lattice_frames
    path = tmp_path / "tissue.dump"
    write_dump(path, frames, ["id", "type", "x", "y", "z", "mf", "pressure"])
    got = mo.read_dump(path, columns=["mf", "pressure"])
    assert [f["timestep"] for f in got] == [0, 5000]
    for f, scale in zip(got, (1.0, 0.8)):
        assert f["ids"].tolist() == list(range(1, 31))
        np.testing.assert_allclose(f["xy"], c + scale * (xy - c), rtol=0, atol=1e-18)
        np.testing.assert_allclose(f["columns"]["mf"], np.arange(1, 31) / 100, rtol=1e-15)
        np.testing.assert_allclose(f["columns"]["pressure"], 10.0 * np.arange(1, 31), rtol=1e-15)
        assert f["box"].shape == (3, 2) and f["box"][0, 0] == -1e-3
    m0, m1 = (mo.measures(f["xy"]) for f in got)
    assert m0["area"] == pytest.approx(rect_exact(6, 5)["area"], rel=1e-12)
    assert mo.normalise(m1, m0)["A/A0"] == pytest.approx(0.64, rel=1e-12)
    assert list(mo.read_dump(path, columns="mf")[0]["columns"]) == ["mf"]
    everything = mo.read_dump(path, columns="all")[0]["columns"]
    assert list(everything) == ["type", "mf", "pressure"]


def test_read_dump_cgms_columns(tmp_path, lattice_frames):
    """A CGMS-style dump without z (id type x y vx vy mf rho pressure)."""
    xy, c, frames = lattice_frames
    cols = ["id", "type", "x", "y", "vx", "vy", "mf", "rho", "pressure"]
    frames = [(s, [(r[0], r[1], r[2], r[3], 0.0, 0.0, r[5], 1000.0, r[6]) for r in rows])
              for s, rows in frames]
    path = tmp_path / "cgms.dump"
    write_dump(path, frames, cols)
    got = mo.read_dump(path, columns=["mf", "rho"])
    np.testing.assert_allclose(got[0]["xy"], xy, rtol=0, atol=1e-18)
    np.testing.assert_allclose(got[1]["columns"]["rho"], 1000.0)
    with pytest.raises(ValueError, match="no column 'radius'"):
        mo.read_dump(path, columns=["mf", "radius"])


def test_read_dump_missing_columns(tmp_path, lattice_frames):
    xy, c, frames = lattice_frames
    path = tmp_path / "noy.dump"
    write_dump(path, [(s, [(r[0], r[1], r[2], r[5]) for r in rows]) for s, rows in frames],
               ["id", "type", "x", "mf"])
    with pytest.raises(ValueError, match="no column 'y'"):
        mo.read_dump(path)
    path = tmp_path / "noid.dump"
    write_dump(path, [(s, [(r[1], r[2], r[3]) for r in rows]) for s, rows in frames],
               ["type", "x", "y"])
    with pytest.raises(ValueError, match="no column 'id'"):
        mo.read_dump(path)
    path = tmp_path / "notype.dump"
    write_dump(path, [(s, [(r[0], r[2], r[3], r[4]) for r in rows]) for s, rows in frames],
               ["id", "x", "y", "z"])
    assert mo.read_dump(path)[0]["ids"].tolist() == list(range(1, 31))  # no 'type' needed


def test_read_dump_scaled_and_truncated(tmp_path, lattice_frames):
    xy, c, frames = lattice_frames
    box = np.array([(-1e-3, 3e-3), (-2e-3, 4e-3), (-1e-4, 1e-4)])
    lo, length = box[:, 0], box[:, 1] - box[:, 0]
    scaled = [(s, [(r[0], r[1], (r[2] - lo[0]) / length[0], (r[3] - lo[1]) / length[1], 0.5)
                   for r in rows]) for s, rows in frames]
    path = tmp_path / "scaled.dump"
    write_dump(path, scaled, ["id", "type", "xs", "ys", "zs"], box=box)
    got = mo.read_dump(path)
    np.testing.assert_allclose(got[0]["xy"], xy, rtol=0, atol=1e-18)
    # a dump still being written: the incomplete last frame is dropped with a warning
    text = path.read_text().splitlines()
    path.write_text("\n".join(text[:-5]) + "\n")
    with pytest.warns(UserWarning, match="incomplete last frame"):
        got = mo.read_dump(path)
    assert [f["timestep"] for f in got] == [0]
    path.write_text("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n")
    with pytest.warns(UserWarning), pytest.raises(ValueError, match="no complete frame"):
        mo.read_dump(path)
    path.write_text("garbage\n")
    with pytest.raises(ValueError, match="expected 'ITEM"):
        mo.read_dump(path)


def test_read_dump_triclinic_time_units_gz(tmp_path, lattice_frames):
    """Scaled coordinates in a tilted box; ITEM: UNITS / TIME sections; gzip."""
    import gzip

    xy, c, frames = lattice_frames
    lo, hi, tilt = np.array([-1e-3, -2e-3, -1e-4]), np.array([3e-3, 4e-3, 1e-4]), 4e-4
    length = hi - lo
    bounds = [(lo[0] + min(0, tilt), hi[0] + max(0, tilt), tilt), (lo[1], hi[1], 0.0),
              (lo[2], hi[2], 0.0)]
    rows = []
    for r in frames[1][1]:
        ys = (r[3] - lo[1]) / length[1]
        rows.append((r[0], r[1], (r[2] - lo[0] - ys * tilt) / length[0], ys, r[5]))
    path = tmp_path / "tri.dump"
    write_dump(path, [(7, rows)], ["id", "type", "xs", "ys", "mf"], box=bounds,
               flags="xy xz yz ff ff pp")
    text = path.read_text().replace("ITEM: TIMESTEP\n7\n",
                                    "ITEM: UNITS\nsi\nITEM: TIME\n7e-07\nITEM: TIMESTEP\n7\n")
    with gzip.open(tmp_path / "tri.dump.gz", "wt") as fh:
        fh.write(text)
    (f,) = mo.read_dump(tmp_path / "tri.dump.gz", columns="mf")
    assert f["timestep"] == 7 and f["box"].shape == (3, 3)
    assert f["time"] == 7e-7
    np.testing.assert_allclose(f["xy"], c + 0.8 * (xy - c), rtol=0, atol=1e-17)
    np.testing.assert_allclose(f["columns"]["mf"], np.arange(1, 31) / 100, rtol=1e-15)


def test_clean_lattice_raises_no_outline_warning():
    xy = tissue.hex_rectangle(10, 12, A)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mo.measures(xy)


def test_side_bow_of_a_bent_rectangle():
    """A lattice rectangle whose left and right sides are pushed in by a parabola of depth
    0.3 at mid-height; top and bottom straight."""
    xy = tissue.hex_rectangle(20, 21, 1.0, rows_along="y")
    lo, hi = xy.min(0), xy.max(0)
    y = (xy[:, 1] - lo[1]) / (hi[1] - lo[1])
    edge = 0.3 * 4 * y * (1 - y)
    near_left = xy[:, 0] < lo[0] + 0.5
    near_right = xy[:, 0] > hi[0] - 0.5
    bent = xy.copy()
    bent[near_left, 0] += edge[near_left]
    bent[near_right, 0] -= edge[near_right]
    bows = mo.side_bow(bent, band=0.6)
    assert bows["left"] == pytest.approx(0.3, abs=0.02)
    assert bows["right"] == pytest.approx(0.3, abs=0.02)
    assert abs(bows["top"]) < 1e-9 and abs(bows["bottom"]) < 1e-9
    flat = mo.side_bow(xy, band=0.6)
    assert max(abs(v) for v in flat.values()) < 1e-9
    outward = xy.copy()
    outward[near_left, 0] -= edge[near_left]
    assert mo.side_bow(outward, band=0.6)["left"] == pytest.approx(-0.3, abs=0.02)


# --- pieces ----------------------------------------------------------------------------


def test_pieces_of_an_intact_a_torn_and_a_flung_tissue():
    """morphology.pieces (run.folded's check that a minimiser's steady state did not come
    apart): an intact lattice is one piece; a lattice cut along a row and pulled apart by 1.6
    spacings is two, the larger labelled 0; a bead moved 2 spacings out of a corner is a
    piece of its own; a gap of 1.4 spacings (below the 1.5 x spacing link) still joins."""
    xy = tissue.hex_rectangle(10, 8, A)
    assert mo.pieces(xy).max() == 0
    top = xy[:, 1] > 4.5 * H                      # rows 5-7 of 0-7: 30 of 80 beads
    for gap, count in ((1.6, 2), (1.4, 1)):
        # the closest pair across the cut is half a spacing apart in x: lift the top rows
        # until it is ``gap`` spacings apart
        lift = math.sqrt((gap * A) ** 2 - (A / 2) ** 2) - H
        torn = xy + np.where(top[:, None], [0.0, lift], 0.0)
        closest = np.min(np.hypot(*(torn[top][:, None] - torn[~top][None]).T))
        assert closest == pytest.approx(gap * A, rel=1e-12)
        label = mo.pieces(torn)
        assert label.max() + 1 == count, gap
        if count == 2:
            assert (label[~top] == 0).all() and (label[top] == 1).all()
    flung = xy.copy()
    flung[0] -= [2 * A, 0.0]
    label = mo.pieces(flung)
    assert label.max() == 1 and label[0] == 1 and (label[1:] == 0).all()
