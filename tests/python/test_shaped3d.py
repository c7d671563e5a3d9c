# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The 3-D shaped tensor model (cgms.shaped3d; doc/model.md, "The 3-D tensor model
(prototype)"): the fresh Kelvin cell and its neighbours, the gradient against differences,
invariance under rigid motions that rotate every F, a fresh block relaxing back to an
isotropic state, a uniform dried block in balance at the volume its water and the EOS
prescribe, and a layer of held hexagonal prisms that is the 2-D model."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import cgmstest  # noqa: F401 - puts python/ on the path
from cgms import material, shaped, shaped3d as s3, shaped3d_cells as cells, tissue
from cgms import shaped3d_hessian as s3h, shaped3d_relax, shaped_tensor as st
from test_shaped import assert_matches_differences, central

MAT = material.read("apple")
EPS = np.finfo(float).eps
L = MAT["x_ref"]


def units(n):
    """Positions in units of x_ref, F as it is: both of order one."""
    return np.concatenate([np.full(3 * n, L), np.ones(9 * n)])


def test_kelvin_cell_and_its_neighbours():
    """The BCC lattice's Voronoi cell is the truncated octahedron of edge e = a / (2
    sqrt 2): 8 regular hexagons (3 sqrt(3) / 2 e^2), 6 squares (e^2), volume a^3 / 2 =
    8 sqrt(2) e^3; in a 3 x 3 x 3 block the centre cell has all 14 neighbours, a corner
    cell 4 (3 square, 1 hexagonal face), and no bond is longer than the square faces'."""
    cell = cells.polyhedron(cells.bcc_vectors(L))
    a = 2 * L / math.sqrt(3)
    e = a / (2 * math.sqrt(2))
    assert [len(v) for v in cell["vertices"]] == [6] * 8 + [4] * 6
    np.testing.assert_allclose(cell["S0"][:8], 1.5 * math.sqrt(3) * e * e, rtol=1e-12)
    np.testing.assert_allclose(cell["S0"][8:], e * e, rtol=1e-12)
    assert cell["volume"] == pytest.approx(a ** 3 / 2, rel=1e-12)
    assert np.allclose(cell["a0"].sum(axis=0), 0, atol=1e-12 * L * L)   # a closed surface
    pts, vec = cells.block(3, 3, 3, L)
    face, bonds = cells.fresh_neighbours(pts, vec)
    count = (face >= 0).sum(axis=1)
    centre = np.argmin(np.linalg.norm(pts, axis=1))
    assert count[centre] == 14 and count.min() == 4
    assert len(pts) == 27 + 8
    length = np.linalg.norm(pts[bonds[:, 1]] - pts[bonds[:, 0]], axis=1)
    assert length.max() <= a * (1 + 1e-12)
    # each face's neighbour sits across it, and the bond back uses the opposite face
    for i, k in bonds:
        j = list(face[i]).index(k)
        np.testing.assert_allclose(pts[k] - pts[i], vec[j], atol=1e-12 * L)
        assert list(face[k]).index(i) == list(map(tuple, vec)).index(tuple(-vec[j]))


def dried_state(s=0.5, seed=3, iso=0.0, size=(3, 3, 2)):
    """A block of ``size`` at dryness ``s``: beads shrunk towards s^(1/3) and jittered by
    4 um, every F s^(1/3) times a random stretch of +-20 % (some faces stretched, most
    wrinkled), rim bonds scaled by beta != 1, one non-neighbour pair inside the LJ radius."""
    pts, vec = cells.block(*size, L)
    geo = s3.build(pts, vec, MAT, dict(soft=0.05, beta_a=1.1, beta_b=0.05, kg_ratio=0.3,
                                       iso=iso))
    lev = s3.at_level(geo, s)
    rng = np.random.default_rng(seed)
    f = s ** (1 / 3)
    x = pts * f + rng.normal(0, 4e-6, pts.shape)
    i, k = lev["pairs"][np.argmin(np.linalg.norm(x[lev["pairs"][:, 0]] - x[lev["pairs"][:, 1]],
                                                 axis=1))]
    x[k] = x[i] + 0.85 * lev["r_lj"] * (x[k] - x[i]) / np.linalg.norm(x[k] - x[i])
    F = f * (np.eye(3) + rng.uniform(-0.2, 0.2, (geo["n"], 3, 3)))
    return s3.join(x, F), lev


def kinds(z, lev):
    """Faces stretched, faces wrinkled, LJ pairs inside their radius."""
    x, F = s3.split(z, lev["n"])
    _, S = s3.faces(F, lev)
    rest = lev["rest"][None, :]
    r = np.linalg.norm(x[lev["pairs"][:, 0]] - x[lev["pairs"][:, 1]], axis=1)
    return (int(np.sum(S > rest)), int(np.sum(S < rest * (1 - lev["tau"] / lev["K_A"]))),
            int(np.sum(r < lev["r_lj"])))


@pytest.mark.parametrize("iso", [0.0, 1.0, 0.4])
def test_gradient_is_the_derivative_of_the_energy(iso):
    z, lev = dried_state(iso=iso)
    stretched, wrinkled, lj = kinds(z, lev)
    assert stretched > 0 and wrinkled > 0 and lj > 0
    assert np.all(lev["f_bond"][lev["rim"]] != 1) and lev["rim"].any()
    u = units(lev["n"])
    E, g = s3.energy(z, lev)
    assert_matches_differences(g * u, lambda y: s3.energy(y * u, lev, gradient=False),
                               z / u, 1e-5, abs(E))


def test_hessian_is_the_derivative_of_the_gradient():
    """The exact Hessian (iso 0) against differences of the gradient; its rounding scale
    is a gradient entry's largest terms, the fluid's (K + |P|) V0 and 14 faces' |dE/dS| S,
    and it is symmetric to the rounding of its products."""
    z, lev = dried_state(s=0.4, seed=5)
    u = units(lev["n"])
    Hs = s3h.hessian(z, lev).toarray() * np.outer(u, u)
    x, F = s3.split(z, lev["n"])
    _, S = s3.faces(F, lev)
    _, de = shaped.wall_energy(S, lev["rest"], lev["K_A"], lev["tau"], lev["soft"])
    scale = (MAT["K"] + MAT["P_f"]) * lev["cell"]["volume"] + 14 * np.abs(de * S).max()
    assert_matches_differences(Hs, lambda y: s3.energy(y * u, lev)[1] * u, z / u, 1e-5, scale)
    np.testing.assert_allclose(Hs, Hs.T, rtol=0, atol=64 * EPS * np.abs(Hs).max())
    with pytest.raises(NotImplementedError, match="iso 0"):
        s3h.hessian(*dried_state(iso=1.0))


def test_rigid_motions_that_rotate_every_F_leave_the_energy():
    """x -> R x + t and F_i -> R F_i leave E unchanged and rotate the gradient; the forces
    sum to zero and the torque, with the couples on the F (sum_i g_F : W F_i for each
    rotation generator W), vanishes; each a sum of m terms, exact to m eps times the sum
    of the terms' magnitudes."""
    z, lev = dried_state(s=0.3, seed=7, iso=1.0, size=(3, 3, 3))
    n = lev["n"]
    E, g = s3.energy(z, lev)
    x, F = s3.split(z, n)
    gx, gF = s3.split(g, n)
    m = 64 * 14 * n
    assert np.all(np.abs(gx.sum(axis=0)) <= m * EPS * np.abs(gx).sum())
    r = x - x.mean(axis=0)
    for axis in np.eye(3):
        W = np.cross(np.eye(3), axis).T            # W v = axis x v
        terms = np.einsum("na,ab,nb->n", gx, W, r), np.sum(gF * (W @ F), axis=(1, 2))
        torque = terms[0].sum() + terms[1].sum()
        assert abs(torque) <= m * EPS * (np.abs(gx).sum() * np.abs(r).max()
                                         + np.sum(np.abs(gF) * np.abs(W @ F)))
    R = _rotation(np.array([0.3, -0.5, 0.8]), 0.9)
    z2 = s3.join(x @ R.T + np.array([3e-4, -2e-4, 1e-4]), R @ F)
    E2, g2 = s3.energy(z2, lev)
    scale = MAT["K"] * lev["cell"]["volume"] * n
    assert abs(E2 - E) <= m * EPS * scale
    gx2, gF2 = s3.split(g2, n)
    np.testing.assert_allclose(gx2, gx @ R.T, rtol=0, atol=m * EPS * np.abs(gx).max())
    np.testing.assert_allclose(gF2, R @ gF, rtol=0, atol=m * EPS * np.abs(gF).max())


def _rotation(axis, angle):
    k = axis / np.linalg.norm(axis)
    K = np.cross(np.eye(3), k).T
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def force_scale(lev):
    """The largest terms summed into one generalised force dE/dF / x_ref: the fluid's
    (K + |P|) V0 and 14 faces' tension times their area."""
    return ((MAT["K"] + MAT["P_f"]) * lev["cell"]["volume"]
            + 14 * lev["tension0"] * lev["cell"]["S0"].max()) / L


def test_fresh_block_is_in_balance():
    """At s = 1 with every F the identity, the bonds match and every face carries the
    fresh tension that balances turgor, so the forces vanish to rounding."""
    pts, vec = cells.block(3, 3, 4, L)
    geo = s3.build(pts, vec, MAT, dict(beta_a=1.0, beta_b=0.3, kg_ratio=2.0))
    lev = s3.at_level(geo, 1.0)
    fx, fF = s3.forces(s3.fresh_state(geo), lev)
    assert fx <= 64 * EPS * force_scale(lev) and fF <= 64 * EPS * force_scale(lev)
    assert geo["eps"] > 0 and geo["boundary"].sum() < geo["n"]


def test_fresh_unconstrained_block_relaxes_to_an_isotropic_state():
    """A fresh block kicked (beads by 2 um, F by up to 2 %) relaxes back to F_i = lambda
    R_i (equal principal stretches). The solver leaves a gradient g; the state is then
    within |g| / k of the steady state, k the smallest stiffness beyond the six rigid
    motions (the Hessian from differences of the exact gradient, in the solver's units),
    so each principal stretch is within that of the others (x2 for two of them), and
    lambda = 1 (the fresh block is in balance, test above)."""
    pts, vec = cells.block(3, 3, 3, L)
    geo = s3.build(pts, vec, MAT, dict(kg_ratio=0.3, iso=1.0))
    lev = s3.at_level(geo, 1.0)
    n = geo["n"]
    rng = np.random.default_rng(1)
    x, F = s3.split(s3.fresh_state(geo), n)
    z, info = shaped3d_relax.relax(s3.join(x + rng.normal(0, 2e-6, x.shape),
                               F + rng.uniform(-0.02, 0.02, F.shape)), lev, ftol=1e-10)
    assert info["converged"], info
    u = units(n)
    g = s3.energy(z, lev)[1] * u
    Hs = central(lambda y: s3.energy(y * u, lev)[1] * u, z / u, 1e-6)
    k = np.sort(np.linalg.eigvalsh(0.5 * (Hs + Hs.T)))
    assert np.all(np.abs(k[:6]) < 1e-9 * k[-1]) and k[6] > 1e-6 * k[-1]   # six rigid motions
    bound = np.linalg.norm(g) / k[6]
    sig = s3.cell_measures(z, lev)["stretches"]
    assert np.ptp(sig, axis=1).max() <= 2 * bound, (np.ptp(sig, axis=1).max(), bound)
    assert np.abs(sig - 1).max() <= bound
    assert bound < 1e-6


def uniform_stretch(lev):
    """The analytic uniform state of a block whose cells are all alike at dryness s: x =
    lambda x0, F = lambda I. Every bond matches, and the truncated octahedron's cubic
    symmetry makes sum_f S_f n_f n_f^T isotropic, so dE/dF is a multiple of I and balance
    is one equation, the virtual work of a dilation: P (3 V - 2 w S) = 2 T S, with V =
    lambda^3 V0, S = lambda^2 S0 (every face at the same area strain, tension T from the
    wall law) and P the Tait pressure of the water s V_f0 in V_f = V - w S. Returns
    lambda and that P."""
    V0, S0, w = lev["cell"]["volume"], lev["cell"]["S0"], lev["w"]

    def residual(lam):
        Vf = lam ** 3 * V0 - w * lam ** 2 * S0.sum()
        P = shaped.tait_pressure(Vf, lev["V_f"], lev["P_T"], MAT["K"])
        _, T = shaped.wall_energy(lam ** 2 * S0, lev["rest"], lev["K_A"], lev["tau"],
                                  lev["soft"])
        return P * (3 * lam ** 3 * V0 - 2 * w * lam ** 2 * S0.sum()) - 2 * np.sum(T * lam ** 2 * S0)

    f = lev["s"] ** (1 / 3)
    lam = brentq(residual, 0.9 * f, 1.1 * f, xtol=1e-15, rtol=4 * EPS)
    Vf = lam ** 3 * V0 - w * lam ** 2 * S0.sum()
    return lam, shaped.tait_pressure(Vf, lev["V_f"], lev["P_T"], MAT["K"])


@pytest.mark.parametrize("s", [0.8, 0.5, 0.3])
def test_uniform_dried_block_has_the_volume_of_its_water(s):
    """The uniform state above is a steady state of the model (forces vanish to the
    rounding of terms of size K V0, with the walls wrinkled), and its fluid volume is its
    water's at the EOS: V_f = s V_f0 (1 + (P - s P_f) / K)^(-1/7), where the wrinkled
    walls hold only P = -2 tau S / (3 V - 2 w S), a few kPa (the water, not the walls,
    sets the volume)."""
    pts, vec = cells.block(3, 3, 3, L)
    geo = s3.build(pts, vec, MAT, dict(kg_ratio=0.3, soft=0.0))
    lev = s3.at_level(geo, s)
    lam, P = uniform_stretch(lev)
    n = geo["n"]
    z = s3.join(lam * pts, np.broadcast_to(lam * np.eye(3), (n, 3, 3)))
    _, wrinkled, lj = kinds(z, lev)
    assert wrinkled == n * 14 and lj == 0
    fx, fF = s3.forces(z, lev)
    assert fx <= 64 * EPS * force_scale(lev) and fF <= 64 * EPS * force_scale(lev)
    V = s3.cell_measures(z, lev)["volume"]
    # the fresh fluid: the Kelvin cell (edge e) less a slab of lamella d_p over its walls
    e = L / math.sqrt(6)
    V_f0 = 8 * math.sqrt(2) * e ** 3 - s3.DEFAULTS["lamella"] * MAT["pectin"] * (
        6 + 12 * math.sqrt(3)) * e * e
    expect = s * V_f0 * (1 + (P - s * MAT["P_f"]) / MAT["K"]) ** (-1 / 7)
    np.testing.assert_allclose(V, expect, rtol=64 * EPS)
    S = lam ** 2 * lev["cell"]["S0"].sum()
    wrinkle = -2 * lev["tau"] * S / (3 * lam ** 3 * lev["cell"]["volume"] - 2 * lev["w"] * S)
    assert P == pytest.approx(wrinkle, rel=1e-9)
    slack = s * V_f0 * (1 - s * MAT["P_f"] / MAT["K"]) ** (-1 / 7)
    assert abs(V[0] / slack - 1) < 1e-4         # the walls move the volume by |P| / 7 K


def prism_layer(params, s, seed=3):
    """The 2-D tensor model's small tissue and, on the same beads, a layer of hexagonal
    prisms of the material's height with its caps held, k_g matched (2-D kg_ratio EA /
    x_ref = 3-D kg_ratio K_A), and a dried, jittered 2-D state."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, L)
    geo2 = st.build(xy, MAT, params)
    pts, vec, caps = cells.prism_layer(xy, L, MAT["height"])
    K_A = geo2["wall_EA"] / MAT["height"]
    p3 = dict(params, kg_ratio=params["kg_ratio"] * geo2["wall_EA"] / L / K_A, caps="held",
              rest_power=1)
    geo3 = s3.build(pts, vec, MAT, p3, caps)
    rng = np.random.default_rng(seed)
    c = xy.mean(axis=0)
    x = c + (xy - c) * math.sqrt(s) + rng.normal(0, 4e-6, xy.shape)
    F = math.sqrt(s) * (np.eye(2) + rng.uniform(-0.25, 0.25, (geo2["n"], 2, 2)))
    return st.at_level(geo2, s), s3.at_level(geo3, s), st.join(x, F)


def embed(z2, n):
    """A 2-D state as a prism layer's: z = 0, F = diag(F_2, 1)."""
    x, F = st.split(z2, n)
    F3 = np.zeros((n, 3, 3))
    F3[:, :2, :2] = F
    F3[:, 2, 2] = 1.0
    return s3.join(np.column_stack([x, np.zeros(n)]), F3)


PRISM = dict(soft=0.05, beta_a=1.1, beta_b=0.05, kg_ratio=0.3)


def test_held_prism_layer_is_the_2d_model():
    """With its caps held (plates: no membrane, no lamella slab), its side walls' rest
    area contracting along the wall only (rest_power 1) and k_g matched, a prism layer's
    energy is the 2-D tensor model's: the side face's area is its chord times H, the
    membrane law on it is the 2-D wall law with EA = K_A H, the fluid's volume is H times
    the 2-D fluid area, and the fresh balance gives the same strain. Energy and gradient
    agree to rounding, so the 2-D steady state is one of the layer (forces below the 2-D
    solver's tolerance)."""
    l2, l3, z2 = prism_layer(PRISM, 0.5)
    n = l2["n"]
    assert l3["eps"] == pytest.approx(l2["eps"], rel=1e-12)
    E2, g2 = st.energy(z2, l2)
    E3, g3 = s3.energy(embed(z2, n), l3)
    assert E3 == pytest.approx(E2, rel=1e-12)
    gx2, gF2 = st.split(g2, n)
    gx3, gF3 = s3.split(g3, n)
    np.testing.assert_allclose(gx3[:, :2], gx2, rtol=0, atol=1e-12 * np.abs(gx2).max())
    np.testing.assert_allclose(gF3[:, :2, :2], gF2, rtol=0, atol=1e-12 * np.abs(gF2).max())
    zs, info = st.relax(z2, l2, ftol=1e-9)
    assert info["converged"]
    assert max(s3.forces(embed(zs, n), l3)) <= 1e-9


def test_prism_layer_with_the_3d_rest_area_is_not_the_2d_model():
    """With the 3-D default (a wall's rest area contracts in both directions, c(s)^2),
    the held layer's side walls are held at the full height while their rest area
    shrinks: the 2-D steady state is not one of the layer (forces far above tolerance)."""
    l2, l3, z2 = prism_layer(PRISM, 0.5)
    pts, vec, caps = cells.prism_layer(tissue.rectangle(0.75e-3, 0.75e-3, L), L,
                                       MAT["height"])
    geo3 = s3.build(pts, vec, MAT, dict(PRISM, kg_ratio=l3["kg_ratio"], rest_power=2,
                                        caps="held"), caps)
    zs, info = st.relax(z2, l2, ftol=1e-9)
    assert max(s3.forces(embed(zs, l2["n"]), s3.at_level(geo3, 0.5))) > 1e-6


def test_bad_input_is_refused_with_its_cause():
    pts, vec, caps = cells.prism_layer(tissue.rectangle(0.45e-3, 0.45e-3, L), L, MAT["height"])
    with pytest.raises(ValueError, match="not closed"):
        s3.build(pts, vec, MAT, dict(caps="held"), caps[:1])
    tilted = [((0.0, 0.6, 0.8), MAT["height"] / 2), ((0.0, -0.6, -0.8), MAT["height"] / 2)]
    with pytest.raises(ValueError, match="opposite pairs"):
        s3.build(pts, vec, MAT, dict(caps="held"), tilted)
    with pytest.raises(ValueError, match="caps must be"):
        s3.build(pts, vec, MAT, dict(caps="plates"), caps)
    with pytest.raises(ValueError, match="whole number"):
        cells.block(2, 0, 2, L)
    with pytest.raises(ValueError, match="method"):
        shaped3d_relax.relax(s3.fresh_state(s3.build(pts, vec, MAT, {}, caps)),
                             s3.at_level(s3.build(pts, vec, MAT, {}, caps), 1.0),
                             method="fire")



def test_slab_fits_its_dimensions():
    """A slab holds the block whose cube corners span at most its width, depth and
    thickness: 1 x 1 x 0.4 mm at x_ref is 6 x 6 x 3 corners (cube edge 174 um) and the
    5 x 5 x 2 centres between them."""
    pts, vec = cells.slab(1e-3, 1e-3, 0.4e-3, L)
    a = 2 * L / math.sqrt(3)
    span = np.ptp(pts, axis=0)
    assert len(pts) == 6 * 6 * 3 + 5 * 5 * 2
    dims = np.array([1e-3, 1e-3, 0.4e-3])
    assert np.all(span <= dims) and np.all(span + a > dims)
