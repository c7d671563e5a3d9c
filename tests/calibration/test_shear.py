# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shear test of cgms.shear (doc/calibration.md, "k_S from the fine model's shear
stiffness"): CGMS's measured shear modulus of a block against a linear-elastic oracle built
on tests/reference.py (finite-difference stiffness of the NumPy forces, held rows
prescribed, the rest solved), and the fine model's shear test on a small block against
Newton's third law and the work-energy balance."""

import math

import numpy as np
import pytest

import reference
from cgms.mfc import model as mfc_model
from cgms import model, shear
from cgmstest import APPLE, CUTOFF, MAT, require_lammps

S = 1.0


def oracle_forces(xy, mat, s=S):
    """Forces on every bead (n, 2) at the quasi-static balance (every bead at P = -Pi,
    fix cgms/fluid's ``minimize balance``), damping off, from reference.py."""
    sv = np.full(len(xy), s)
    l0p = model.fresh_perimeter(mat) * np.ones_like(sv)
    geo = reference.fluid_state(xy, sv, np.ones_like(sv), l0p, mat, CUTOFF)
    c = 0.5 * (mat["k_T"] * (-s * mat["Pi_f"] - mat["P_f"])
               - mat["k_PA"] * (geo["perim"] - geo["ldeq"]))
    force, _, _ = reference.pair_forces(xy, np.zeros_like(xy), sv, c, mat, CUTOFF,
                                        damping=False)
    return force


def oracle_shear_modulus(xy, row, mat, step=1e-4):
    """Clamped shear modulus (N/m) of the linearised block: stiffness K = -dF/dx by central
    differences of :func:`oracle_forces` (``step`` x_ref), bottom row held, top row moved
    by gamma * gap along x, the other beads solved from K_ff u_f = -K_fh u_h; the stress is
    the force the agent applies to the top row over the block's width."""
    n = len(xy)
    h = step * mat["x_ref"]
    K = np.empty((2 * n, 2 * n))
    for j in range(2 * n):
        dx = np.zeros(2 * n)
        dx[j] = h
        plus = oracle_forces(xy + dx.reshape(n, 2), mat).ravel()
        minus = oracle_forces(xy - dx.reshape(n, 2), mat).ravel()
        K[:, j] = -(plus - minus) / (2 * h)
    held = np.repeat((row == 0) | (row == row.max()), 2)
    top_x = np.zeros(2 * n, bool)
    top_x[0::2] = row == row.max()
    gap, length = shear.row_gap(xy, row), shear.width(xy, row)
    u = np.zeros(2 * n)
    u[top_x] = gap   # gamma = 1: linear
    free = ~held
    u[free] = np.linalg.solve(K[np.ix_(free, free)], -K[np.ix_(free, held)] @ u[held])
    applied = (K @ u)[top_x].sum()     # the agent balances the block's force -K u
    return applied / length


@pytest.mark.parametrize("k_s", [0.0, 0.5])
def test_cgms_shear_modulus_against_oracle(tmp_path, k_s):
    """8 x 5 block (38 beads), apple, fresh: the modulus LAMMPS measures (FIRE to 1e-13 N
    at 0.5 % shear) equals the linearised NumPy oracle's at the same free state within
    1 %; the response is linear and elastic; with k_S the modulus is of the order
    of the infinite lattice's sqrt(3)/2 k_S (doc/calibration.md derives it) and without
    it two orders smaller (the paper's forces hardly resist shear)."""
    require_lammps()
    xy, row = shear.block(8, 5, MAT["x_ref"])
    result = shear.cgms(xy, row, APPLE, S, tmp_path, overrides=f"k_S {k_s}")
    got = shear.summarise(result)
    mat = dict(MAT, k_S=k_s)
    expected = oracle_shear_modulus(result["xy"], row, mat)
    assert got["converged"] and got["held_drift"] == 0.0
    shear_rows = [r for r in result["rows"] if r["kind"] == "shear"]
    # the smallest strain, 0.5 %, against the linear oracle (k_S = 0: the secant modulus
    # grows by 3 % up to 2 %, so the larger strains are not linear enough for 1 %)
    assert shear_rows[0]["stress"] / shear_rows[0]["strain"] == pytest.approx(expected, rel=1e-2)
    assert got["G_clamped_linearity"] < 0.05
    for r in shear_rows:   # third law: the held rows' reactions balance
        np.testing.assert_allclose(r["bottom_force"], -np.asarray(r["top_force"]),
                                   atol=1e-3 * abs(r["top_force"][0]))
    if k_s:
        assert 0.5 < got["G_clamped"] / (math.sqrt(3) / 2 * k_s) < 1.2
    else:
        assert got["G_clamped"] < 1e-2 * math.sqrt(3) / 2 * 0.5


def test_mfc_shear_small_block(tmp_path):
    """The fine model's test on its smallest useful block (5 x 4, 18 cells; two rows not
    held), fresh: the held particles stay put, the two held rows' reactions balance (the
    rest is at steady state), the work the agent does equals the energy the block stores
    within 5 % (the reaction is measured right: misread by 10 %, it fails), the response is linear and elastic (back to 0 leaves < 2 % of the largest
    stress), and the modulus is positive."""
    require_lammps()
    p = mfc_model.parameters(APPLE)
    xy, row = shear.block(5, 4, p["x_ref"])
    result = shear.mfc(xy, row, p, 1.0, tmp_path, strains=())
    got = shear.summarise(result)
    assert got["converged"] and got["held_drift"] == 0.0
    rows = result["rows"]
    for r in rows:
        np.testing.assert_allclose(r["bottom_force"], -np.asarray(r["top_force"]),
                                   atol=1e-2 * abs(rows[-2]["top_force"][0]))
    done = shear.work(rows, result["length"])
    stored = np.array([r["work_energy"] for r in rows])
    np.testing.assert_allclose(stored[:3], done[:3], rtol=0.05)
    assert got["G_clamped"] > 0 and got["G_clamped_linearity"] < 0.05
    assert abs(got["return_stress"]) < 0.02


def test_shear_script_settling_and_exponent():
    """studies/mfc/shear.py's summary of an MFC run: on a synthetic linear-elastic block
    (stress G gamma, stored energy the exact (G/2) gamma^2 gap width) G is recovered both
    ways and energy / work is 1; a constant stress offset (a creeping free state) moves G
    through the origin but not G with an intercept; G ~ s^6 gives the exponent 6."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "studies" / "mfc"))
    import shear as script
    G, gap, length = 0.7, 5e-4, 6e-4

    def result(offset):
        rows, last = [], 0.0
        for g in shear.GAMMAS:
            rows.append(dict(kind="shear", strain=g, stress=G * g + offset, normal=0.0,
                             move=[(g - last) * gap, 0.0], interior=g,
                             work_energy=0.5 * G * g * g * gap * length))
            last = g
        rows.append(dict(kind="back", strain=0.0, stress=offset, normal=0.0,
                         move=[-last * gap, 0.0], interior=0.0, work_energy=0.0))
        free = dict(converged=True, fmax=1e-11, shift=1e-9)
        return dict(rows=rows, length=length, gap=gap, held_drift=0.0, free=free)

    q = script.settling(result(0.0))
    assert q["G"] == pytest.approx(G) and q["G_intercept"] == pytest.approx(G)
    assert q["energy_work"] == pytest.approx(1.0) and q["back"] == pytest.approx(0.0)
    q = script.settling(result(0.1 * G * shear.GAMMAS[0]))
    assert q["G_intercept"] == pytest.approx(G) and q["G"] > 1.01 * G
    assert script.exponent(0.8, 0.8 ** 6, 0.6, 0.6 ** 6) == pytest.approx(6.0)
