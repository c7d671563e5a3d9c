# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shaped coarse model's NumPy prototype (cgms.shaped; doc/model.md, "A coarse model
with cell shape"): its gradient and Hessian against differences of its energy and
gradient, its invariance under rigid motions, the built lattice in balance, and the cells'
area following their water."""

import math

import numpy as np
import pytest

import cgmstest  # noqa: F401 - puts python/ on the path
from cgms import material, shaped, tissue

MAT = material.read("apple")
EPS = np.finfo(float).eps


def dried_state(s=0.5, seed=3, params=None):
    """A small tissue at dryness ``s``, shrunk towards sqrt(s), jittered by 4 um and with
    one pair of non-neighbours pushed inside the LJ radius, so that stretched, compressed
    and buckled walls, ghost walls with beta != 1 and an LJ pair all take part."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, MAT["x_ref"])
    geo = shaped.build(xy, MAT, dict(dict(soft=0.05, beta_a=1.1, beta_b=0.05), **(params or {})))
    lev = shaped.at_level(geo, s)
    rng = np.random.default_rng(seed)
    c = xy.mean(axis=0)
    x = c + (xy - c) * math.sqrt(s) * 1.05 + rng.normal(0, 4e-6, xy.shape)
    i, k = lev["pairs"][np.argmin(np.linalg.norm(x[lev["pairs"][:, 0]] - x[lev["pairs"][:, 1]],
                                                 axis=1))]
    x[k] = x[i] + 0.85 * lev["r_lj"] * (x[k] - x[i]) / np.linalg.norm(x[k] - x[i])
    return x, lev


def central(f, x, h):
    """Central differences of the scalar or array function f along every coordinate."""
    cols = []
    for j in range(x.size):
        dx = np.zeros(x.size)
        dx[j] = h
        dx = dx.reshape(x.shape)
        cols.append((np.asarray(f(x + dx)) - np.asarray(f(x - dx))) / (2 * h))
    return np.array(cols)


def assert_matches_differences(analytic, f, x, h, scale):
    """Central differences at step h have truncation error c h^2; with step 2h it is
    4 c h^2, so |D(h) - D(2h)| / 3 estimates it (Richardson). Rounding adds about
    eps |f| / h per difference. The analytic derivative must agree within 10x their sum."""
    d1, d2 = central(f, x, h), central(f, x, 2 * h)
    trunc = np.abs(d1 - d2) / 3
    rounding = 4 * EPS * scale / h
    err = np.abs(d1 - analytic)
    allowed = 10 * (trunc + rounding)
    worst = np.unravel_index(np.argmax(err / allowed), err.shape)
    assert np.all(err <= allowed), \
        f"misfit {err[worst]:.3e} at {worst}, allowed there {allowed[worst]:.3e}"


def test_gradient_is_the_derivative_of_the_energy():
    x, lev = dried_state()
    E, g = shaped.energy(x, lev)
    kinds = shaped.wall_kinds(x, lev)
    assert kinds["stretched"] > 0 and kinds["buckled"] > 0 and kinds["lj_pairs"] > 0
    assert_matches_differences(g.ravel(), lambda y: shaped.energy(y, lev, gradient=False),
                               x, 2e-9, abs(E))


def test_hessian_is_the_derivative_of_the_gradient():
    """The gradient's rounding scale is its largest terms, H |P| times a cell's size over
    the six junctions of a cell (not the net force, which nearly cancels)."""
    x, lev = dried_state(s=0.4, seed=5)
    Hs = shaped.hessian(x, lev).toarray()
    P = np.abs(shaped.cell_measures(x, lev)["pressure"]).max() + MAT["K"] / 7
    assert_matches_differences(Hs, lambda y: shaped.energy(y, lev)[1].ravel(), x, 2e-9,
                               6 * MAT["height"] * P * MAT["x_ref"])
    # M^T H_J M is symmetric to the rounding of its products (a few dozen terms an entry)
    np.testing.assert_allclose(Hs, Hs.T, rtol=0, atol=64 * EPS * np.abs(Hs).max())


def test_rigid_motions_leave_the_energy_and_sum_no_force_or_torque():
    """Translation invariance: the forces sum to zero; rotation invariance: their torque
    about any point vanishes. Each sum of m terms is exact to m eps times the sum of the
    terms' magnitudes (the forces are sums over cells, walls and pairs)."""
    x, lev = dried_state(s=0.3, seed=7)
    E, g = shaped.energy(x, lev)
    terms = np.abs(g).sum()
    m = 64 * len(lev["cell"])
    assert np.all(np.abs(g.sum(axis=0)) <= m * EPS * terms)
    r = x - x.mean(axis=0)
    torque = np.sum(r[:, 0] * g[:, 1] - r[:, 1] * g[:, 0])
    assert abs(torque) <= m * EPS * np.sum(np.abs(r) * np.abs(g[:, ::-1]))
    c, s = math.cos(0.7), math.sin(0.7)
    y = x @ np.array([[c, s], [-s, c]]) + np.array([3e-4, -2e-4])
    E2, g2 = shaped.energy(y, lev)
    assert abs(E2 - E) <= m * EPS * (abs(E) + shaped.energy_scale(x, lev))
    np.testing.assert_allclose(g2, g @ np.array([[c, s], [-s, c]]), rtol=0,
                               atol=m * EPS * np.abs(g).max())


@pytest.mark.parametrize("shape", [("rectangle", 1.25e-3, 1.5e-3), ("rectangle", 0.6e-3, 1.1e-3),
                                   ("disc", 0.5e-3)])
def test_built_lattice_is_in_balance_and_every_cell_the_same_regular_hexagon(shape):
    """At s = 1 and beta = 1 every cell, the boundary cells closed by their ghosts too, is
    the regular hexagon of side x_ref / sqrt(3), so every wall has the same tension and the
    built lattice is a steady state: the forces vanish to rounding (a force is a sum of
    a few dozen terms of the size of the wall tension). The outlines have beads with 2,
    3, 4 and 5 neighbours (narrow rectangle) and 3 and 4 (disc)."""
    xy = getattr(tissue, shape[0])(*shape[1:], MAT["x_ref"])
    geo = shaped.build(xy, MAT, dict(beta_a=1.0, beta_b=0.3))
    lev = shaped.at_level(geo, 1.0)
    assert lev["beta"] == 1.0 and geo["boundary"].sum() > 0
    J, area, chord, _ = shaped.polygons(xy, lev)
    side = MAT["x_ref"] / math.sqrt(3)
    np.testing.assert_allclose(chord, side, rtol=64 * EPS)
    np.testing.assert_allclose(area, 1.5 * math.sqrt(3) * side ** 2, rtol=64 * EPS)
    for c in (0, int(np.argmax(~geo["boundary"]))):          # a corner and an inner cell
        poly = J[lev["ja"][lev["cell"] == c]] - xy[c]
        np.testing.assert_allclose(np.linalg.norm(poly, axis=1), side, rtol=64 * EPS)
    _, g = shaped.energy(xy, lev)
    tension = geo["wall_EA"] * geo["eps"]
    assert np.abs(g).max() <= 64 * 24 * EPS * tension


def test_fresh_wall_strain_is_the_laplace_balance():
    """The fresh strain follows from turgor alone: T = H P_f (x_ref/2 - w) on a regular
    hexagon (2 A / L = x_ref / 2), T = EA eps."""
    xy = tissue.rectangle(0.6e-3, 0.6e-3, MAT["x_ref"])
    geo = shaped.build(xy, MAT)
    w = geo["lamella"] * MAT["pectin"]
    T = MAT["height"] * MAT["P_f"] * (MAT["x_ref"] / 2 - w)
    assert geo["eps"] == pytest.approx(T / geo["wall_EA"], rel=64 * EPS)


@pytest.mark.parametrize("s", [0.8, 0.5, 0.3])
def test_area_follows_water_in_a_uniform_dried_block(s):
    """Dried from the built lattice with walls that only buckle (soft = 0), every cell's
    fluid area is its water's, s A_f0, up to the fluid's compression: the walls are slack
    and can push at most with the buckling force on each, so by the Laplace law of a cell
    (virtual work of dilating it) its pressure is |P| <= dP = sum_e F_b l_e / (H (2 A -
    w L)), near 0 rather than the turgor s P_f at rest density (the MFC's dried cells:
    about -1 kPa). Then A / A_f = (1 + (P - s P_f) / K)^(-1/7) (eqn 4 at fixed mass) lies
    between its values at P = -2 dP and +2 dP (x2 for the neighbours' share). The solver's
    force tolerance moves the junctions by ftol over the fluid stiffness, far less."""
    xy = tissue.rectangle(0.6e-3, 0.6e-3, MAT["x_ref"])
    geo = shaped.build(xy, MAT, dict(soft=0.0))
    lev = shaped.at_level(geo, s)
    x, info = shaped.relax(xy, lev, ftol=1e-10)
    assert info["converged"], info
    cm = shaped.cell_measures(x, lev)
    _, area, chord, _ = shaped.polygons(x, lev)
    L = np.bincount(lev["cell"], chord)
    w = lev["lamella"] * MAT["pectin"]
    dP = lev["buckle"] * L / (MAT["height"] * (2 * area - w * L))
    P_T, K = lev["P_T"], MAT["K"]
    lo = (1 + (2 * dP - P_T) / K) ** (-1 / 7)
    hi = (1 + (-2 * dP - P_T) / K) ** (-1 / 7)
    ratio = cm["area"] / lev["A_f"]
    assert np.all((lo <= ratio) & (ratio <= hi)), (ratio, lo, hi)
    # the water, not the walls, sets the area: to the fluid compression at fresh turgor
    assert np.all(hi - 1 < 2 * MAT["P_f"] / (7 * K))
