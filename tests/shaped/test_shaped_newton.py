# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""cgms.shaped_local and cgms.shaped_newton (the shaped model at scale) and the route
``cgms study --model shaped``.

The Newton steady state is checked against shaped_tensor.relax (the dense trust region)
from the same kicked start. The symmetric saddle can be left towards mirror-image
states (cells flattened along mirrored axes, the same energy), so the comparison is of
what does not depend on the choice: the bead positions, each F's singular values and
determinant. Tolerance, as test_shaped_minimize: near a strict minimum with smallest
Hessian eigenvalue lambda (rigid motions removed), two states with scaled gradients
g1, g2 lie within (|g1| + |g2|) / lambda of each other.
"""

import csv

import numpy as np
import pytest

import shapedlmp as sl
from cgms import cli, shaped_newton as sn, shaped_tensor as st, tissue
from test_shaped_minimize import scaled_gradient_norm, start

S = 0.6
FTOL = 1e-11


def test_local_build_is_the_dense_one():
    """shaped_tensor.build(local=True) (no (n, n) arrays) gives the same fixed geometry."""
    xy = tissue.rectangle(1.0e-3, 1.25e-3, sl.L)
    for params in (sl.BEST, sl.OTHER):
        a, b = st.build(xy, sl.MAT, params), st.build(xy, sl.MAT, params, local=True)
        assert np.array_equal(a["cell"], b["cell"]) and np.array_equal(a["bonds"], b["bonds"])
        assert np.array_equal(a["boundary"], b["boundary"])
        # the same sums of the same terms in another order: rounding of the lattice's size
        for key, size in (("d0", sl.L), ("poly_area0", sl.L ** 2), ("rest0", sl.L),
                          ("A_f0", sl.L ** 2)):
            assert np.abs(a[key] - b[key]).max() <= 64 * sl.EPS * size, key


def test_newton_reaches_relax_steady_state():
    xy = tissue.rectangle(0.75e-3, 0.75e-3, sl.L)
    geo = st.build(xy, sl.MAT, sl.BEST)
    lev = st.at_level(geo, S)
    n = geo["n"]
    z0 = start(geo)
    z_py, info_py = st.relax(z0, lev, ftol=FTOL, maxiter=2000)
    z_nt, info = sn.newton(z0, st.at_level(st.build(xy, sl.MAT, sl.BEST, local=True), S),
                           ftol=FTOL)
    assert info_py["converged"] and info["converged"], info
    assert max(st.forces(z_nt, lev)) <= FTOL       # the dense build's forces agree
    z_nt = st.align(z_nt, z_py)
    u = np.concatenate([np.full(2 * n, sl.L), np.ones(4 * n)])
    w = np.linalg.eigvalsh(st.hessian(z_py, lev).toarray() * np.outer(u, u))
    rigid = np.abs(w) < 1e-6 * w.max()
    assert rigid.sum() == 3 and np.all(w[~rigid] > 0)
    bound = (scaled_gradient_norm(z_nt, lev) + scaled_gradient_norm(z_py, lev)) / w[~rigid].min()
    x_nt, F_nt = st.split(z_nt, n)
    x_py, F_py = st.split(z_py, n)
    assert np.linalg.norm((x_nt - x_py) / sl.L) <= bound
    sv = np.linalg.svd(F_nt, compute_uv=False) - np.linalg.svd(F_py, compute_uv=False)
    assert np.linalg.norm(sv) <= bound
    assert np.linalg.norm(np.linalg.det(F_nt) - np.linalg.det(F_py)) \
        <= 2 * np.abs(F_py).max() * bound


def test_newton_certifies_its_steady_state_by_the_inertia():
    """newton(certify=True) counts the negative eigenvalues of the scaled Hessian at its
    final state from one factorisation's pivots (Sylvester), the rigid motions shifted off
    by twice their largest curvature: none at the steady state (whose dense spectrum is 3
    rigid modes and the rest positive; the rotation's curvature there, of the size of the
    residual gradient, is negative and was counted with the shift of RIGID_SHIFT alone),
    and at the kicked start (fluid under tension, the cells' flattening unstable) as many
    as the dense eigenvalues below -sigma."""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, sl.L)
    geo = st.build(xy, sl.MAT, sl.BEST, local=True)
    lev = st.at_level(geo, S)
    n = geo["n"]
    z0 = start(geo)
    z, info = sn.newton(z0, lev, ftol=FTOL, certify=True)
    assert info["converged"] and info["negative"] == 0
    prob = sn.Problem(lev, FTOL)
    for state in (z, z0):
        _, _, lv = prob.energy(state)
        H = prob.hessian(state, lv)
        Q = sn.rigid_modes(state, n, prob.unit)
        curvature = np.einsum("ik,ik->k", Q, H @ Q)
        sigma = 2 * np.abs(curvature).max() + sn.RIGID_SHIFT * np.abs(H.diagonal()).max()
        w = np.linalg.eigvalsh(H.toarray())
        count = sn.unstable_directions(prob, state, lv, sn.dof_order(st.split(state, n)[0], lev))
        assert count == np.sum(w < -sigma)
    rigid = np.argsort(np.abs(w))[:3]
    assert count > 0 and not np.isin(np.flatnonzero(w < -sigma), rigid).any()


def test_the_searched_start_reaches_the_kicked_starts_steady_state():
    """The study's start searched off the saddles (cgms.shaped_start, the default) and the
    kicked start it replaced reach, where the cells first flatten (s = 0.6 on the ramp 1,
    0.8, 0.6 of the calibration tissue), the same steady state up to the mirror-image
    choice of the cells' flattening axis: bead positions after a rigid superposition, each
    F's singular values and determinant within (|g1| + |g2|) / lambda (module docstring;
    the F themselves differ, flattened along another lattice axis). Every searched level
    is certified a minimum by the inertia. (At s = 0.8 the two reach different minima,
    the searched one of lower energy: doc/results/performance.md.)"""
    xy = tissue.rectangle(0.75e-3, 0.75e-3, sl.L)
    levels = (1.0, 0.8, 0.6)
    geo, searched, _ = sn.study(xy, sl.MAT, levels)
    _, kicked, _ = sn.study(xy, sl.MAT, levels, start="kicked")
    assert all(info["converged"] and info["negative"] == 0 for _, _, info in searched)
    assert all(info["converged"] for _, _, info in kicked)
    n = geo["n"]
    lev = sn.with_near_pairs(st.split(kicked[-1][1], n)[0], st.at_level(geo, levels[-1]))
    z_k = kicked[-1][1]
    z_s = st.align(searched[-1][1], z_k)
    u = np.concatenate([np.full(2 * n, sl.L), np.ones(4 * n)])
    w = np.linalg.eigvalsh(st.hessian(z_k, lev).toarray() * np.outer(u, u))
    rigid = np.abs(w) < 1e-6 * w.max()
    assert rigid.sum() == 3 and np.all(w[~rigid] > 0)
    lev_s = sn.with_near_pairs(st.split(z_s, n)[0], lev)
    bound = (scaled_gradient_norm(z_s, lev_s) + scaled_gradient_norm(z_k, lev)) / w[~rigid].min()
    (x_s, F_s), (x_k, F_k) = st.split(z_s, n), st.split(z_k, n)
    assert np.linalg.norm((x_s - x_k) / sl.L) <= bound
    sv = np.linalg.svd(F_s, compute_uv=False) - np.linalg.svd(F_k, compute_uv=False)
    assert np.linalg.norm(sv) <= bound
    assert np.linalg.norm(np.linalg.det(F_s) - np.linalg.det(F_k)) <= 2 * np.abs(F_k).max() * bound


def test_study_model_shaped_writes_its_table(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(["study", "--model", "shaped", "--width", "0.5", "--height", "0.5",
                     "--dryness", "1,0.6", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Newton (shaped)" in text
    assert "takes long" not in text      # a small tissue gets no note on its size
    assert text.count("Newton steps, largest force") == 2 and text.count(", a minimum, ") == 2
    (table,) = out.glob("summary-*.csv")
    rows = list(csv.DictReader(table.open()))
    assert [float(r["s"]) for r in rows] == [1.0, 0.6]
    assert all(r["converged"] == "True" for r in rows)
    assert float(rows[0]["A/A0"]) == 1.0 and 0.5 < float(rows[1]["A/A0"]) < 0.7
    assert all(float(r["residual"]) <= 1e-9 for r in rows)


def test_study_model_shaped_names_the_faster_route_for_a_large_tissue(tmp_path, capsys,
                                                                     monkeypatch):
    """Above SHAPED_LARGE beads (lowered here to the tiny tissue's size) the route says that
    Newton takes long and names LAMMPS minimize, before it starts."""
    from cgms.cli import study
    monkeypatch.setattr(study, "SHAPED_LARGE", 10)
    assert cli.main(["study", "--model", "shaped", "--width", "0.5", "--height", "0.5",
                     "--dryness", "1", "--out", str(tmp_path / "out")]) == 0
    assert "takes long" in capsys.readouterr().out


@pytest.mark.parametrize("option", [["--method", "newton"], ["--start", "previous"],
                                    ["--set", "k_S 0.5"], ["--fallback", "none"],
                                    ["--material", "potato"]])
def test_study_model_shaped_refuses_options_that_do_not_apply(tmp_path, capsys, option):
    out = tmp_path / "out"
    assert cli.main(["study", "--model", "shaped", "--width", "0.5", "--height", "0.5",
                     "--out", str(out)] + option) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"cgms study: {option[0]}") and "--model shaped" in err
    assert "\n" not in err and not out.exists()
