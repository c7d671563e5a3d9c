# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shaped model's shape-tensor variant (cgms.shaped_tensor; doc/model.md, "A coarse
model with cell shape"): gradient and Hessian against differences, invariance under rigid
motions that rotate every F too, the built lattice in balance, and the cells' area
following their water."""

import math

import numpy as np
import pytest

import cgmstest  # noqa: F401 - puts python/ on the path
from cgms import material, shaped, shaped_target as target, shaped_tensor as st, tissue
from test_shaped import assert_matches_differences

MAT = material.read("apple")
EPS = np.finfo(float).eps
L = MAT["x_ref"]


def units(n):
    """Positions in units of x_ref, F as it is: both of order one."""
    return np.concatenate([np.full(2 * n, L), np.ones(4 * n)])


def dried_state(s=0.5, seed=3, params=None):
    """A small tissue at dryness ``s``: beads shrunk towards sqrt(s) and jittered by 4 um,
    every F sqrt(s) times a random stretch of +-25 % (so some walls stretch, most buckle),
    ghost walls scaled by beta != 1 and one pair of non-neighbours inside the LJ radius."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    geo = st.build(xy, MAT, dict(dict(soft=0.05, beta_a=1.1, beta_b=0.05, kg_ratio=0.3),
                                 **(params or {})))
    lev = st.at_level(geo, s)
    rng = np.random.default_rng(seed)
    c = xy.mean(axis=0)
    x = c + (xy - c) * math.sqrt(s) + rng.normal(0, 4e-6, xy.shape)
    i, k = lev["pairs"][np.argmin(np.linalg.norm(x[lev["pairs"][:, 0]] - x[lev["pairs"][:, 1]],
                                                 axis=1))]
    x[k] = x[i] + 0.85 * lev["r_lj"] * (x[k] - x[i]) / np.linalg.norm(x[k] - x[i])
    F = math.sqrt(s) * (np.eye(2) + rng.uniform(-0.25, 0.25, (geo["n"], 2, 2)))
    return st.join(x, F), lev


def kinds(z, lev):
    _, _, _, chord, _ = st.cells(z, lev)
    x, _ = st.split(z, lev["n"])
    k = lev["wall_EA"] / lev["rest"]
    lb = lev["rest"] - lev["buckle"] / k
    r = np.linalg.norm(x[lev["pairs"][:, 0]] - x[lev["pairs"][:, 1]], axis=1)
    return (int(np.sum(chord > lev["rest"])), int(np.sum(chord < lb)),
            int(np.sum(r < lev["r_lj"])))


def gradient_scale(z, lev):
    """The size of the largest terms summed into one scaled gradient entry: a cell's
    fluid term H |P| A, six walls' |dE/dl| |d0|, a bead's six bonds k_g |m| x_ref."""
    x, F, c, chord, A, e_w, de_w, m, H, K = st._terms(z, lev)
    P = np.abs(shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)).max() + K / 7
    return (H * P * lev["poly_area0"].max() + 6 * np.abs(de_w).max() * L
            + 6 * lev["k_g"] * np.abs(m).max() * L)


def test_gradient_is_the_derivative_of_the_energy():
    z, lev = dried_state()
    stretched, buckled, lj = kinds(z, lev)
    assert stretched > 0 and buckled > 0 and lj > 0
    u = units(lev["n"])
    E, g = st.energy(z, lev)
    assert_matches_differences(g * u, lambda y: st.energy(y * u, lev, gradient=False),
                               z / u, 1e-5, abs(E))


def test_hessian_is_the_derivative_of_the_gradient():
    z, lev = dried_state(s=0.4, seed=5)
    u = units(lev["n"])
    Hs = st.hessian(z, lev).toarray() * np.outer(u, u)
    assert_matches_differences(Hs, lambda y: st.energy(y * u, lev)[1] * u, z / u, 1e-5,
                               gradient_scale(z, lev))
    np.testing.assert_allclose(Hs, Hs.T, rtol=0, atol=64 * EPS * np.abs(Hs).max())


def test_rigid_motions_that_rotate_every_F_leave_the_energy():
    """x -> R x + t and F_i -> R F_i leave E unchanged and rotate the gradient; the forces
    sum to zero and their torque, including the couples on the F (tr(g_F^T W F) with W
    the rotation generator), vanishes; each a sum of m terms, exact to m eps times the
    sum of the terms' magnitudes."""
    z, lev = dried_state(s=0.3, seed=7)
    n = lev["n"]
    E, g = st.energy(z, lev)
    x, F = st.split(z, n)
    gx, gF = st.split(g, n)
    m = 64 * len(lev["cell"])
    assert np.all(np.abs(gx.sum(axis=0)) <= m * EPS * np.abs(gx).sum())
    W = np.array([[0.0, -1.0], [1.0, 0.0]])
    r = x - x.mean(axis=0)
    WF = W @ F
    torque = np.sum(r[:, 0] * gx[:, 1] - r[:, 1] * gx[:, 0]) + np.sum(gF * WF)
    assert abs(torque) <= m * EPS * (np.sum(np.abs(r) * np.abs(gx[:, ::-1]))
                                     + np.sum(np.abs(gF) * np.abs(WF)))
    c, s = math.cos(0.7), math.sin(0.7)
    R = np.array([[c, -s], [s, c]])
    z2 = st.join(x @ R.T + np.array([3e-4, -2e-4]), R @ F)
    E2, g2 = st.energy(z2, lev)
    assert abs(E2 - E) <= m * EPS * (abs(E) + gradient_scale(z, lev))
    gx2, gF2 = st.split(g2, n)
    np.testing.assert_allclose(gx2, gx @ R.T, rtol=0, atol=m * EPS * np.abs(gx).max())
    np.testing.assert_allclose(gF2, R @ gF, rtol=0, atol=m * EPS * np.abs(gF).max())


@pytest.mark.parametrize("shape", [("rectangle", 1.25e-3, 1.5e-3), ("rectangle", 0.6e-3, 1.1e-3),
                                   ("disc", 0.5e-3)])
def test_built_lattice_is_in_balance(shape):
    """At s = 1, beta = 1 and every F the identity, the bonds match, every cell is the
    regular hexagon with uniform wall tension T balancing turgor, so the forces on beads
    and the generalised forces dE/dF / x_ref (sums of a few dozen terms of size T) vanish
    to rounding."""
    xy = getattr(tissue, shape[0])(*shape[1:], L)
    geo = st.build(xy, MAT, dict(beta_a=1.0, beta_b=0.3, kg_ratio=2.0))
    lev = st.at_level(geo, 1.0)
    assert lev["beta"] == 1.0 and geo["boundary"].sum() > 0
    fx, fF = st.forces(st.fresh_state(geo), lev)
    tension = geo["wall_EA"] * geo["eps"]
    assert fx <= 64 * 24 * EPS * tension
    assert fF <= 64 * 24 * EPS * tension


@pytest.mark.parametrize("s", [0.8, 0.5, 0.3])
def test_area_follows_water_in_a_dried_block(s):
    """Relaxed at dryness s (walls that only buckle, soft = 0), each cell's fluid area is
    its water's, s A_f0, up to the fluid's compression. Its pressure follows from the
    steady state by virtual work of dilating its F: H P (2 A_poly - w L) = sum_e w'_e l_e +
    (compatibility's dE/dF) : F; with the bound |P| <= dP from the magnitudes of those
    terms, A / A_f = (1 + (P - s P_f) / K)^(-1/7) lies between its values at -+2 dP (x2:
    the solver leaves forces up to ftol). The walls are slack, so dP stays far below the
    fresh turgor: the water, not the walls, sets the area."""
    xy = tissue.rectangle(0.6e-3, 0.6e-3, L)
    geo = st.build(xy, MAT, dict(soft=0.0, kg_ratio=0.3))
    lev = st.at_level(geo, s)
    z = st.fresh_state(geo)
    x, F = st.split(z, geo["n"])
    c = x.mean(axis=0)
    z, info = st.relax(st.join(c + (x - c) * math.sqrt(s), F * math.sqrt(s)), lev, ftol=1e-10)
    assert info["converged"], info
    x, F, cv, chord, A, e_w, de_w, m, H, K = st._terms(z, lev)
    n, cell = lev["n"], lev["cell"]
    gc = st.split(lev["k_g"] * (lev["C"].T @ m), n)[1]
    work = np.bincount(cell, np.abs(de_w) * chord, minlength=n) + np.abs(
        np.sum(gc * F, axis=(1, 2)))
    w = lev["lamella"] * MAT["pectin"]
    Lc = np.bincount(cell, chord, minlength=n)
    dP = work / (H * (2 * lev["poly_area0"] * np.linalg.det(F) - w * Lc))
    P_T = lev["P_T"]
    lo = (1 + (2 * dP - P_T) / K) ** (-1 / 7)
    hi = (1 + (-2 * dP - P_T) / K) ** (-1 / 7)
    ratio = A / lev["A_f"]
    assert np.all((lo <= ratio) & (ratio <= hi)), (ratio, lo, hi)
    assert np.all(dP < 0.1 * MAT["P_f"])


def assert_derivatives(z, lev):
    """Gradient against differences of the energy, Hessian against differences of the
    gradient, in units where x and F are of order one (and the network's shear, if any)."""
    u = np.concatenate([units(lev["n"]), np.ones(len(z) - 6 * lev["n"])])
    E, g = st.energy(z, lev)
    assert_matches_differences(g * u, lambda y: st.energy(y * u, lev, gradient=False),
                               z / u, 1e-5, abs(E))
    Hs = st.hessian(z, lev).toarray() * np.outer(u, u)
    assert_matches_differences(Hs, lambda y: st.energy(y * u, lev)[1] * u, z / u, 1e-5,
                               gradient_scale(z, lev))


#: the gap law of the contour strip and the intercellular space (shaped_tensor.DEFAULTS);
#: ``smooth`` and ``void_onset`` widened so that the jittered state below puts walls
#: inside the C1 joins and cells inside the void's transition
GAP = dict(strip="contour", lamella=0.39, void=0.063, void_onset=2.0, smooth=2.0)


def gap_kinds(z, lev):
    """Walls inside the contour's smoothing band, cells inside the void's transition."""
    _, _, _, chord, _ = st.cells(z, lev)
    band = int(np.sum(np.abs(chord - lev["rest"]) < lev["delta"]))
    S = np.bincount(lev["cell"], chord, minlength=lev["n"])
    e = S / lev["rest_sum"] - 1
    return band, int(np.sum((e > 0) & (e < lev["void_strain"])))


@pytest.mark.parametrize("s, seed", [(0.9, 11), (0.7, 5)])
def test_gap_law_derivatives(s, seed):
    """The contour strip and the void (both C1 joins, second derivatives piecewise) in
    the gradient and the Hessian, with walls inside the joins and cells inside the void's
    transition; differences as for the plain law."""
    z, lev = dried_state(s=s, seed=seed, params=GAP)
    band, opening = gap_kinds(z, lev)
    assert band > 0 and opening > 0, (band, opening)
    assert_derivatives(z, lev)


@pytest.mark.parametrize("shape", [("rectangle", 1.25e-3, 1.5e-3), ("disc", 0.5e-3)])
def test_built_lattice_with_gap_law_is_in_balance(shape):
    """The fresh strain of the gap law (void open, walls taut) balances the built lattice
    as the plain law's does, and the void takes its fraction of every fresh polygon."""
    xy = getattr(tissue, shape[0])(*shape[1:], L)
    params = dict(GAP, void_onset=0.5, smooth=0.25)
    geo = st.build(xy, MAT, params)
    lev = st.at_level(geo, 1.0)
    fx, fF = st.forces(st.fresh_state(geo), lev)
    tension = geo["wall_EA"] * geo["eps"]
    assert fx <= 64 * 24 * EPS * tension
    assert fF <= 64 * 24 * EPS * tension
    w = params["lamella"] * MAT["pectin"]
    L0 = np.bincount(geo["cell"], np.hypot(*geo["d0"].T), minlength=geo["n"])
    np.testing.assert_allclose(geo["A_f0"], geo["poly_area0"] * (1 - params["void"]) - w * L0,
                               rtol=16 * EPS)
    _, _, _, _, A = st.cells(st.fresh_state(geo), lev)
    np.testing.assert_allclose(A, geo["A_f0"], rtol=16 * EPS)


@pytest.mark.parametrize("iso", [0.5, 1.0])
def test_isotropic_compatibility_derivatives(iso):
    """The bond target (1 - iso) F d0 + iso sqrt(det F) R(F) d0 (nonlinear in F) in the
    gradient and the Hessian; rim bonds scaled by beta != 1 (dried_state)."""
    z, lev = dried_state(s=0.6, seed=9, params=dict(GAP, iso=iso))
    assert_derivatives(z, lev)


def test_isotropic_target_ignores_the_cells_flattening():
    """With iso 1 the bond target of F = R diag(k, 1/k) sqrt(J) is sqrt(J) R d0: a cell's
    flattening at fixed area leaves it, its rotation turns it."""
    rng = np.random.default_rng(2)
    d0 = rng.normal(size=(5, 2))
    th, J, k = 0.4, 0.3, 1.8
    R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    F = np.broadcast_to(math.sqrt(J) * R @ np.diag([k, 1 / k]) @ R.T @ R, (5, 2, 2))
    v, _ = target.bond_target(np.ascontiguousarray(F), d0, 1.0)
    np.testing.assert_allclose(v, math.sqrt(J) * d0 @ R.T, rtol=0, atol=16 * EPS)


@pytest.mark.parametrize("rim_class", ["rim", "boundary"])
def test_per_bond_iso_derivatives(rim_class):
    """``iso_rim``: the bonds of the tissue's edge with their own iso (here 0, the cells'
    whole F) beside the interior's 1, in the gradient and the Hessian."""
    z, lev = dried_state(s=0.6, seed=9, params=dict(GAP, iso=1.0, iso_rim=0.0,
                                                      rim_class=rim_class))
    edge = lev["iso"] == 0.0
    assert 0 < edge.sum() < len(edge)
    assert_derivatives(z, lev)


def test_per_bond_iso_of_one_value_is_the_uniform_iso():
    """One iso given per bond gives the energy and gradient of that iso for all (to
    rounding: the per-bond path sums the same terms in another grouping)."""
    z, lev = dried_state(s=0.6, seed=9, params=dict(GAP, iso=0.7))
    _, lev_b = dried_state(s=0.6, seed=9, params=dict(GAP, iso=0.7, iso_rim=0.7))
    assert np.ndim(lev_b["iso"]) == 1
    E, g = st.energy(z, lev)
    E_b, g_b = st.energy(z, lev_b)
    assert abs(E_b - E) <= 64 * EPS * (abs(E) + gradient_scale(z, lev))
    np.testing.assert_allclose(g_b, g, rtol=0, atol=64 * EPS * np.abs(g).max())


@pytest.mark.parametrize("iso, hops", [(1.0, 2), (0.6, 1)])
def test_neighbourhood_flattening_derivatives(iso, hops):
    """``dev_mean``: every bond also follows the mean deviatoric stretch of the cells
    within ``dev_hops`` steps (cgms.shaped_mean), beside its own cells' target, in the
    gradient and the Hessian; rim bonds scaled by beta != 1."""
    z, lev = dried_state(s=0.6, seed=9, params=dict(GAP, iso=iso, dev_mean=0.3,
                                                      dev_hops=hops))
    assert lev["dev_weights"].nnz > 2 * len(lev["bonds"])
    assert_derivatives(z, lev)


def test_deviatoric_stretch_is_the_flattening_at_the_cells_size():
    """D(F) = (V - tr V / 2) R for F = V R: zero for a scaled rotation, traceless and
    symmetric for a pure stretch (sqrt(J) (k - 1/k) / 2 along its axes), rotated with the
    cell (D(Q F) = Q D(F)); exact to rounding."""
    th, J, k = 0.4, 0.3, 1.8
    Q = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    P = np.array([[math.cos(1.1), -math.sin(1.1)], [math.sin(1.1), math.cos(1.1)]])
    V = math.sqrt(J) * P @ np.diag([k, 1 / k]) @ P.T
    D, _ = target.deviatoric(np.stack([math.sqrt(J) * Q, V, V @ Q, Q @ V]))
    np.testing.assert_allclose(D[0], 0.0, rtol=0, atol=16 * EPS)
    want = math.sqrt(J) * (k - 1 / k) / 2 * P @ np.diag([1.0, -1.0]) @ P.T
    np.testing.assert_allclose(D[1], want, rtol=0, atol=16 * EPS)
    np.testing.assert_allclose(D[2], want @ Q, rtol=0, atol=16 * EPS)
    np.testing.assert_allclose(D[3], Q @ D[1], rtol=0, atol=16 * EPS)


def test_neighbourhood_flattening_is_invariant_under_rigid_motions():
    """D(Q F) = Q D(F): rotating every bead and F leaves the energy with the term."""
    z, lev = dried_state(s=0.3, seed=7, params=dict(iso=1.0, dev_mean=0.5, dev_hops=2))
    n = lev["n"]
    E, g = st.energy(z, lev)
    x, F = st.split(z, n)
    c, s = math.cos(0.7), math.sin(0.7)
    R = np.array([[c, -s], [s, c]])
    E2, g2 = st.energy(st.join(x @ R.T + np.array([3e-4, -2e-4]), R @ F), lev)
    m = 64 * len(lev["cell"])
    assert abs(E2 - E) <= m * EPS * (abs(E) + gradient_scale(z, lev))
    np.testing.assert_allclose(st.split(g2, n)[1], R @ st.split(g, n)[1], rtol=0,
                               atol=m * EPS * np.abs(g).max())


def test_neighbourhood_flattening_off_leaves_the_committed_model():
    """``dev_mean`` 0 (the default) takes the committed path: the same energy, gradient
    and Hessian bit for bit as parameters without the key."""
    params = dict(GAP, iso=1.0, beta_b=0.04, soft=0.002)
    z, lev = dried_state(s=0.6, seed=9, params=params)
    _, lev0 = dried_state(s=0.6, seed=9, params=dict(params, dev_mean=0.0, dev_hops=3))
    assert "dev_weights" not in lev0
    E, g = st.energy(z, lev)
    E0, g0 = st.energy(z, lev0)
    assert E0 == E and np.array_equal(g0, g)
    assert (st.hessian(z, lev) != st.hessian(z, lev0)).nnz == 0


def test_neighbourhood_weights():
    """Each bond's weights sum to one and reach the cells within dev_hops steps of either
    end; a bad dev_hops is refused by name."""
    from cgms import shaped_mean
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    geo = st.build(xy, MAT, dict(dev_mean=0.5, dev_hops=1))
    w = geo["dev_weights"].toarray()
    np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=0, atol=16 * EPS)
    nbr = geo["topo"]["neighbours"] | np.eye(geo["n"], dtype=bool)
    for b, (i, k) in enumerate(geo["bonds"]):
        np.testing.assert_array_equal(w[b] > 0, nbr[i] | nbr[k])
    with pytest.raises(ValueError, match="dev_hops"):
        shaped_mean.bond_weights(geo["n"], geo["bonds"], 1.5)


def test_neighbourhood_weights_of_the_local_build():
    """The local build (cgms.shaped_local, no (n, n) arrays) gives every bond the same
    neighbourhood weights as the dense build; its bonds may come in another order."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    dense, local = (st.build(xy, MAT, dict(dev_mean=0.5, dev_hops=2), local=flag)
                    for flag in (False, True))
    row = {tuple(sorted(b)): r for r, b in enumerate(local["bonds"])}
    assert sorted(row) == sorted(tuple(sorted(b)) for b in dense["bonds"])
    order = [row[tuple(sorted(b))] for b in dense["bonds"]]
    np.testing.assert_array_equal(local["dev_weights"][order].toarray(),
                                  dense["dev_weights"].toarray())


#: the network's own shear (``net_shear``): a modulus table over s (N/m)
SHEAR_TABLE = [[0.3, 0.4], [0.6, 0.1], [1.0, 2.5]]


def sheared_state(iso, s=0.6, seed=9, smooth=0.0):
    """:func:`dried_state` with the network's shear on and every cell's (u, v) random
    within +-0.1, so that the shear terms of the target and of J are exercised."""
    z, lev = dried_state(s=s, seed=seed, params=dict(GAP, iso=iso, net_shear=SHEAR_TABLE,
                                                     shear_smooth=smooth))
    T = np.random.default_rng(seed).uniform(-0.1, 0.1, (lev["n"], 2))
    return np.concatenate([z, T.ravel()]), lev


@pytest.mark.parametrize("iso, smooth", [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 3.0)])
def test_network_shear_derivatives(iso, smooth):
    """Bond targets G d0 + T d0 with J = det F + |T|^2 in the isotropic part, and the
    shear energy 2 mu A0 |T|^2 (with its smoothness over the bonds), in the gradient and
    the Hessian against differences."""
    assert_derivatives(*sheared_state(iso, smooth=smooth))


def test_network_shear_keeps_the_cells_area_and_is_invariant():
    """sqrt(det F + |T|^2) R(F) + T has the determinant det F (the network shears at the
    cells' area); rotating every bead, F and (u, v) leaves the energy; align undoes it."""
    z, lev = sheared_state(1.0, s=0.3, seed=7)
    n = lev["n"]
    x, F = st.split(z, n)
    T = st.shear(z, n)
    p, q, phi, _, _ = target.iso_scale(F, T)
    N = phi[:, None, None] * np.stack([np.stack([p, -q], -1), np.stack([q, p], -1)], 1) \
        + np.stack([np.stack([T[:, 0], T[:, 1]], -1), np.stack([T[:, 1], -T[:, 0]], -1)], 1)
    np.testing.assert_allclose(np.linalg.det(N), np.linalg.det(F), rtol=0, atol=64 * EPS)
    c, s = math.cos(0.7), math.sin(0.7)
    R = np.array([[c, -s], [s, c]])
    moved = st.join(x @ R.T + np.array([3e-4, -2e-4]), R @ F, T @ R.T)
    E = st.energy(z, lev, gradient=False)
    m = 64 * len(lev["cell"])
    assert abs(st.energy(moved, lev, gradient=False) - E) <= m * EPS * (
        abs(E) + gradient_scale(z, lev))
    back = st.align(moved, z, n)
    np.testing.assert_allclose(back, z, rtol=0, atol=1e-12)


def test_network_shear_modulus_table():
    """mu(s): the table's values at its points, ln mu linear between, held beyond; a bad
    table or both network shears at once are refused by name."""
    t = st._shear_table(SHEAR_TABLE)
    for s, mu in SHEAR_TABLE:
        assert st.net_shear_modulus(t, s) == pytest.approx(mu, rel=4 * EPS)
    assert st.net_shear_modulus(t, 0.45) == pytest.approx(math.sqrt(0.4 * 0.1), rel=1e-12)
    assert st.net_shear_modulus(t, 0.1) == pytest.approx(0.4, rel=4 * EPS)
    assert st.net_shear_modulus(st._shear_table(0.7), 0.3) == 0.7
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    for bad in (-1.0, [[0.3, 0.0]], [0.3, 0.4]):
        with pytest.raises(ValueError, match="net_shear"):
            st.build(xy, MAT, dict(net_shear=bad))
    with pytest.raises(ValueError, match="shear_smooth"):
        st.build(xy, MAT, dict(net_shear=0.5, shear_smooth=-1))
    with pytest.raises(ValueError, match="net_shear and dev_mean"):
        st.build(xy, MAT, dict(net_shear=0.5, dev_mean=0.5))


def test_network_shear_off_leaves_the_state_and_the_committed_model():
    """Without ``net_shear`` (the default) a state holds x and F only, and the energy,
    gradient and Hessian are those of the committed path bit for bit; with it, a state
    without shear (T = 0) has the committed energy, and its fresh state is in balance."""
    params = dict(GAP, iso=1.0, beta_b=0.04, soft=0.002)
    z, lev = dried_state(s=0.6, seed=9, params=params)
    assert lev["mu_net"] is None and st.shear(z, lev["n"]) is None
    _, lev_s = dried_state(s=0.6, seed=9, params=dict(params, net_shear=SHEAR_TABLE))
    zs = np.concatenate([z, np.zeros(2 * lev["n"])])
    E, g = st.energy(z, lev)
    Es, gs = st.energy(zs, lev_s)
    assert Es == pytest.approx(E, rel=64 * EPS, abs=0)
    np.testing.assert_allclose(gs[:6 * lev["n"]], g, rtol=0,
                               atol=64 * EPS * gradient_scale(z, lev) / L)
    xy = tissue.rectangle(1.25e-3, 1.5e-3, L)
    geo = st.build(xy, MAT, dict(GAP, iso=1.0, net_shear=SHEAR_TABLE, void_onset=0.5,
                                 smooth=0.25))
    fx, fF = st.forces(st.fresh_state(geo), st.at_level(geo, 1.0))
    tension = geo["wall_EA"] * geo["eps"]
    assert len(st.fresh_state(geo)) == 8 * geo["n"]
    assert max(fx, fF) <= 64 * 24 * EPS * tension


@pytest.mark.parametrize("iso, shear", [(1.0, False), (0.0, False), (1.0, True)])
def test_shared_walls_derivatives(iso, shear):
    """The shared walls' agreement (``glue``, cgms.shaped_glue) in the gradient and the
    Hessian against differences, alone and beside the network's shear."""
    if shear:
        z, lev = sheared_state(iso, smooth=0.0)
        geo = st.build(tissue.rectangle(0.75e-3, 0.75e-3, L), MAT,
                       dict(soft=0.05, beta_a=1.1, beta_b=0.05, kg_ratio=0.3, iso=iso,
                            net_shear=SHEAR_TABLE, glue=2.0))
        lev = st.at_level(geo, lev["s"])
    else:
        z, lev = dried_state(params=dict(iso=iso, glue=2.0))
    assert st.shaped_glue.energy(z, lev)[0] > 0
    assert_derivatives(z, lev)


def test_shared_walls_pair_every_inner_wall_once():
    """Every wall between two cells is paired once with its twin in the other cell (the
    twin's fresh vector is the opposite one), free walls stay out; a uniform deformation of
    every cell, any F, costs nothing; a jump across one wall only (F_k = F_i + a n^T, n the
    wall's normal) costs nothing, a jump along it does; off is no term at all."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    geo = st.build(xy, MAT, dict(glue=1.0))
    W = geo["W"]
    bonds = len(geo["bonds"])
    assert W.shape[0] == 2 * bonds    # one shared wall per fresh bond
    d0 = geo["d0"]
    z = st.fresh_state(geo)
    assert np.abs(W @ z).max() <= 64 * EPS * np.abs(d0).max()
    n = geo["n"]
    x, _ = st.split(z, n)
    G = np.array([[0.7, 0.2], [-0.1, 0.5]])
    zg = st.join(x, np.broadcast_to(G, (n, 2, 2)))
    assert np.abs(W @ zg).max() <= 64 * EPS * np.abs(d0).max()
    # cell i's wall facing bead k: a jump a n^T across it leaves that wall's row at zero
    i, k = geo["bonds"][0]
    e = np.flatnonzero(geo["cell"] == i)
    ring = geo["topo"]["rings"][i]
    e = e[[j for j, p in enumerate(ring) if not p["ghost"] and p["terms"][0][0] == k][0]]
    t = d0[e] / np.linalg.norm(d0[e])
    nrm = np.array([-t[1], t[0]])
    cols = lambda c: set(range(2 * n + 4 * c, 2 * n + 4 * c + 4))  # noqa: E731
    r = [r for r in range(0, W.shape[0], 2)
         if cols(i) & set(W[r].indices) and cols(k) & set(W[r].indices)]
    assert len(r) == 1                # the one wall cells i and k share
    F = np.broadcast_to(np.eye(2), (n, 2, 2)).copy()
    F[k] += np.outer([0.3, -0.2], nrm)
    assert np.linalg.norm((W @ st.join(x, F))[r[0]:r[0] + 2]) <= 64 * EPS * np.abs(d0).max()
    F[k] = np.eye(2) + np.outer([0.3, -0.2], t)
    assert np.linalg.norm((W @ st.join(x, F))[r[0]:r[0] + 2]) == pytest.approx(
        np.linalg.norm([0.3, -0.2]) * np.linalg.norm(d0[e]), rel=64 * EPS)
    lev = st.at_level(st.build(xy, MAT, {}), 0.6)
    assert st.shaped_glue.energy(z, lev) is None
    for bad in (-1.0, float("nan"), "strong", None):
        with pytest.raises(ValueError, match=r"^glue must be a number >= 0, not "):
            st.build(xy, MAT, dict(glue=bad))


@pytest.mark.parametrize("s", [0.8, 0.4])
def test_pooled_walls_derivatives(s):
    """One wall law per cell on its chord perimeter (``wall_pool``): gradient and Hessian
    against differences, with some cells' perimeters stretched and most buckled."""
    assert_derivatives(*dried_state(s=s, params=dict(wall_pool=True)))


def test_pooled_walls_of_a_uniform_strain_are_the_walls_law():
    """Every wall stretched alike (F = (1 + e) I on the built lattice): the pooled law
    EA / (2 R) (L - R)^2 equals the sum of the walls' own EA / (2 r) (l - r)^2; with
    the walls unequal it is lower (the walls share their length)."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    for pool in (False, True):
        geo = st.build(xy, MAT, dict(wall_pool=pool))
        lev = st.at_level(geo, 1.0)
        x, _ = st.split(st.fresh_state(geo), geo["n"])
        z = st.join(x, np.broadcast_to(1.01 * np.eye(2), (geo["n"], 2, 2)))
        e = st._terms(z, lev)[5].sum()
        zs = st.join(x, np.broadcast_to(np.diag([1.03, 0.99]), (geo["n"], 2, 2)))
        if not pool:
            per_wall, per_wall_sheared = e, st._terms(zs, lev)[5].sum()
    # (L - R) cancels: its rounding is eps L, relative to the stretch L - R of the state
    stretch = 1.01 * (1 + geo["eps"]) - 1
    assert e == pytest.approx(per_wall, rel=64 * EPS / stretch)
    assert st._terms(zs, lev)[5].sum() < per_wall_sheared
