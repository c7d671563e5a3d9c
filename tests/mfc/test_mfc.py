# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The fine-scale (MFC) model, fast variant: builder, fix mfc/pressure against finite
differences and the analytic ring, single cells fresh and dried, conservation, 1 vs 2 ranks,
restart, and a tiny ``cgms mfc`` study."""

import hashlib
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq

from cgmstest import PLUGIN, ROOT, lammps_env, read_dump, run_lmp

from cgms.mfc import (metrics as mfc_metrics, model as mfc_model, run as mfc_run, sph as mfc_sph,
                      tissue as mfc_tissue)
from cgms import run, tissue

P = mfc_model.parameters()
N = P["n_wall"]


def open_cells(folder, centres, s=1.0, jitter=0.0, seed=0, extra=()):
    """A Python LAMMPS instance holding the MFC walls of ``centres`` with the levers of
    ``s``; ``jitter`` (m) displaces every wall particle at random."""
    data = folder / "walls.data"
    mfc_tissue.write_data(data, centres, P, s=s, overwrite=True)
    lmp = run.open_lammps()
    lmp.commands_list(mfc_run.setup_commands(data, P))
    lmp.commands_list(mfc_run.level_commands(P, s))
    lmp.commands_list(list(extra))
    if jitter:
        lmp.command(f"displace_atoms all random {jitter} {jitter} 0 {seed + 1} units box")
    return lmp


def eos(area, fluid_area, turgor):
    """CGMS eqn (4) with rho / rho0 = fluid area / area (written here, independent of
    cgms.mfc.model)."""
    return turgor + 2.0e7 * ((fluid_area / area) ** 7 - 1)


# --------------------------------------------------------------------------- builder

def test_summary_reports_the_second_moment_elongation():
    """A level's summary carries the tissue's second-moment elongation (ELpca, from the cell
    centroids' outline) beside the paper's EL: walls stretched by 1.2 along y stretch
    both by 1.2 (a rectangular tissue, mirror-symmetric about both centre lines at this
    size, so the tensor stays diagonal); a fresh record without ELpca (made before it)
    leaves ELpca/ELpca0 out rather than failing."""
    centres = tissue.rectangle(1.25e-3, 1.5e-3, P["x_ref"])
    xy = mfc_tissue.walls(centres, P)["xy"]
    fresh, _ = mfc_metrics.summary(xy, N)
    fresh, _ = mfc_metrics.summary(xy, N, fresh)
    dried, _ = mfc_metrics.summary(xy * [1.0, 1.2], N, fresh)
    assert fresh["ELpca/ELpca0"] == 1 and fresh["ELpca"] >= 1
    assert dried["EL/EL0"] == pytest.approx(1.2, rel=1e-12)
    assert dried["ELpca/ELpca0"] == pytest.approx(1.2, rel=1e-9)
    older = {k: v for k, v in fresh.items() if not k.startswith("ELpca")}
    assert "ELpca/ELpca0" not in mfc_metrics.summary(xy, N, older)[0]


def test_builder_cells_sit_on_the_cgms_beads():
    centres = tissue.rectangle(1.25e-3, 1.5e-3, P["x_ref"])
    w = mfc_tissue.walls(centres, P)
    assert len(centres) == 86 and len(w["xy"]) == 86 * 96
    cell = mfc_metrics.cells(w["xy"], N)
    # cell i is bead i: area centroid and mean of its wall particles
    assert np.abs(cell["centroid"] - centres).max() < 1e-12
    assert np.abs(w["xy"].reshape(-1, N, 2).mean(axis=1) - centres).max() < 1e-12
    # hexagons of the reference cell's area, counter-clockwise, 5.1545 um spacing
    assert np.allclose(cell["area"], P["A_ref"], rtol=1e-12)
    gaps = np.hypot(*np.diff(w["xy"][:N], axis=0).T)
    assert np.allclose(gaps, P["b_ref"] / 16, rtol=1e-9) and abs(gaps[0] - 5.1545e-6) < 1e-9
    # adjacent walls parallel, one pectin layer apart; adjacent cells differ in colour
    from scipy.spatial import cKDTree
    pairs = cKDTree(w["xy"]).query_pairs(9e-6, output_type="ndarray")
    other = w["cell"][pairs[:, 0]] != w["cell"][pairs[:, 1]]
    d = np.hypot(*(w["xy"][pairs[other, 0]] - w["xy"][pairs[other, 1]]).T)
    assert abs(d.min() - P["pectin"]) < 1e-12
    assert np.all(w["colour"][pairs[other, 0]] != w["colour"][pairs[other, 1]])
    assert len(mfc_tissue.fluid_points(centres[0], P)) == 656


def test_builder_cell_counts_and_bad_centres():
    from cgms.tissue import MICROSCALE
    counts = [len(tissue.rectangle(w * 1e-3, h * 1e-3, P["x_ref"])) for w, h in MICROSCALE.values()]
    assert counts == [86, 105, 149, 182, 203, 248]
    with pytest.raises(ValueError, match="closer than the cell spacing"):
        mfc_tissue.walls([[0, 0], [1e-4, 0]], P)
    with pytest.raises(ValueError, match="share a colour"):
        mfc_tissue.colours(np.array([[0, 0], [1, 0], [0.5, 0.35]]) * P["x_ref"],
                           P["x_ref"], 0.0)


# --------------------------------------------------------------------------- the fix

def fix_only(folder, centres, s, jitter, seed=0):
    """Walls with only fix mfc/pressure acting (bonds, angles, pairs zeroed)."""
    return open_cells(folder, centres, s, jitter, seed, extra=[
        "bond_coeff 1 0.0 4e-6", "angle_coeff 1 0.0", "pair_coeff * * 0.0 8e-6 8 4"])


def forces(lmp):
    lmp.command("run 0")
    n = lmp.get_natoms()
    f = np.array(lmp.gather_atoms("f", 1, 3)).reshape(n, 3)[:, :2]
    return f, lmp.numpy.extract_fix("mfc", 0, 0)


@pytest.mark.lammps
def test_fix_force_is_minus_the_energy_gradient(tmp_path):
    centres = [[0, 0], [P["x_ref"], 0]]
    lmp = fix_only(tmp_path, centres, 0.6, 4e-6, seed=3)
    try:
        f, e = forces(lmp)
        assert np.abs(f).max() > 1e-6   # cells far from rest: the check has teeth
        h = 2e-10
        rng = np.random.default_rng(1)
        for i in rng.choice(len(f), 12, replace=False):
            for d in (0, 1):
                shift = [0.0, 0.0]
                shift[d] = h
                group = f"group one id {i + 1}"
                lmp.commands_list([group, f"displace_atoms one move {shift[0]} {shift[1]} 0"])
                ep = forces(lmp)[1]
                lmp.command(f"displace_atoms one move {-2 * shift[0]} {-2 * shift[1]} 0")
                em = forces(lmp)[1]
                lmp.commands_list([f"displace_atoms one move {shift[0]} {shift[1]} 0",
                                   "group one delete"])
                fd = -(ep - em) / (2 * h)
                assert abs(fd - f[i, d]) < 1e-5 * np.abs(f).max(), (i, d, fd, f[i, d])
    finally:
        lmp.close()


@pytest.mark.lammps
def test_fix_pressure_and_newtons_third_law(tmp_path):
    centres = [[0, 0], [P["x_ref"], 0], [P["x_ref"] / 2, P["x_ref"] * math.sqrt(3) / 2]]
    lmp = fix_only(tmp_path, centres, 0.8, 3e-6, seed=7)
    try:
        f, _ = forces(lmp)
        n = lmp.get_natoms()
        x = np.array(lmp.gather_atoms("x", 1, 3)).reshape(n, 3)[:, :2].reshape(-1, N, 2)
        # the shoelace sum itself: jittered by 3 um, these rings cross themselves, which
        # the cell measures (mfc_metrics.cells) refuse
        area = 0.5 * np.sum(x[..., 0] * np.roll(x[..., 1], -1, axis=1)
                            - np.roll(x[..., 0], -1, axis=1) * x[..., 1], axis=1)
        lv = mfc_model.level(P, 0.8)
        for c in range(3):
            assert lmp.numpy.extract_fix("mfc", 0, 2, c, 0) == pytest.approx(area[c], rel=1e-12)
            assert lmp.numpy.extract_fix("mfc", 0, 2, c, 1) == pytest.approx(
                eos(area[c], 0.8 * P["A_ref"], 0.8 * 2e5), rel=1e-9)
            # the fluid's force on its own wall sums to zero, and so does its torque
            fc = f.reshape(-1, N, 2)[c]
            scale = np.abs(fc).sum()
            assert np.abs(fc.sum(axis=0)).max() < 1e-12 * scale
            r = x[c] - x[c].mean(axis=0)
            assert abs(np.sum(r[:, 0] * fc[:, 1] - r[:, 1] * fc[:, 0])) < 1e-12 * scale * 1e-4
        assert lv["turgor"] == 0.8 * 2e5
    finally:
        lmp.close()


@pytest.mark.lammps
def test_wall_bending_force_is_minus_its_energy_gradient_near_straight(tmp_path):
    """The built hexagon's sides are straight: every angle there is within 1 mrad of
    180 degrees, where LAMMPS's angle harmonic caps 1/sin(theta) and its force is no longer
    the gradient of its energy (a dried wall has 8 % of its angles there; minimisers stall
    on it). The bending alone (bonds and pairs zeroed), by central differences."""
    data = tmp_path / "walls.data"
    mfc_tissue.write_data(data, [[0.0, 0.0]], P, overwrite=True)
    lmp = run.open_lammps()
    try:
        lmp.commands_list(mfc_run.setup_commands(data, P))
        lmp.commands_list(["bond_coeff 1 0.0 4e-6", "pair_coeff * * 0.0 8e-6 8 4",
                           "displace_atoms all random 1e-9 1e-9 0 3 units box"])
        lmp.command("run 0")
        f = np.array(lmp.gather_atoms("f", 1, 3)).reshape(N, 3)[:, :2]
        # the particles along the sides, away from the hexagon's corners (whose 60-degree
        # turns are bent far beyond 1 mrad and carry 1000 x larger forces)
        side = [i for i in range(N) if 2 <= i % P["per_side"] <= P["per_side"] - 2]
        scale = np.abs(f[side]).max()
        assert scale > 1e-10   # bent: the check has teeth
        h = 1e-11
        for i in side[::3]:
            for d in (0, 1):
                move = [0.0, 0.0]
                move[d] = h
                lmp.commands_list([f"group one id {i + 1}",
                                   f"displace_atoms one move {move[0]} {move[1]} 0", "run 0"])
                ep = lmp.get_thermo("pe")
                lmp.commands_list([f"displace_atoms one move {-2 * move[0]} {-2 * move[1]} 0",
                                   "run 0"])
                em = lmp.get_thermo("pe")
                lmp.commands_list([f"displace_atoms one move {move[0]} {move[1]} 0",
                                   "group one delete"])
                fd = -(ep - em) / (2 * h)
                assert abs(fd - f[i, d]) < 1e-2 * scale, (i, d, fd, f[i, d])
    finally:
        lmp.close()


@pytest.mark.lammps
def test_fix_bad_input(tmp_path):
    data = tmp_path / "walls.data"
    mfc_tissue.write_data(data, [[0, 0]], P)
    base = [f"plugin load {PLUGIN}"] + mfc_run.setup_commands(data.name, P)
    cases = {
        "fix m all mfc/pressure height 6e-6 modulus 2e7 turgor 2e5":
            "Fix mfc/pressure needs the keyword area",
        "fix m all mfc/pressure height 6e-6 modulus 2e7 turgor 2e5 area -1":
            "Fix mfc/pressure area",
        "fix m all mfc/pressure height 6e-6 modulus 2e7 turgor 2e5 area 1e-8 colour 3":
            "Unknown fix mfc/pressure keyword colour",
        # the ring numbered clockwise: a mirror image
        "bond_coeff 1 210 4.7e-6\nvariable mx atom -x\nset group all x v_mx\nfix m all mfc/pressure height 6e-6 "
        "modulus 2e7 turgor 2e5 area 1e-8\nrun 0": "encloses area .* clockwise",
    }
    for line, message in cases.items():
        proc = run_lmp(tmp_path, "\n".join(base + [line]) + "\n", check=False)
        text = proc.stdout + proc.stderr
        assert proc.returncode != 0 and "ERROR" in text, text[-2000:]
        assert re.search(message, text), (message, text[-2000:])


# --------------------------------------------------------------------------- single cells

def ring_solution(p, s=1.0):
    """The steady regular 96-gon of a free cell (Laplace's law for a ring of springs):
    each vertex balances the pressure force P H R sin(2 pi/N) against the two bond
    tensions 2 k (l - r0) sin(pi/N); angles of a regular polygon exert no radial force."""
    n, k = p["n_wall"], p["k_bond"]
    af, pt = s * p["A_ref"], s * 2e5
    r0 = p["r0_bond"] * (1 - 0.2 / 0.9 * (1 - s))

    def residual(l):
        rc = l / (2 * math.sin(math.pi / n))
        area = n / 2 * rc * rc * math.sin(2 * math.pi / n)
        return (eos(area, af, pt) * p["height"] * rc * math.sin(2 * math.pi / n)
                - 2 * k * (l - r0) * math.sin(math.pi / n))

    l = brentq(residual, 0.5 * r0, 1.5 * r0, xtol=1e-18)
    rc = l / (2 * math.sin(math.pi / n))
    area = n / 2 * rc * rc * math.sin(2 * math.pi / n)
    return dict(bond=l, area=area, pressure=eos(area, af, pt), radius=rc)


@pytest.mark.lammps
def test_single_fresh_cell_obeys_laplace_and_the_eos(tmp_path):
    lmp = open_cells(tmp_path, [[0.0, 0.0]])
    try:
        report = mfc_run.relax(lmp, P, 1.0, ftol=1e-12)
        xy = mfc_run.positions(lmp)
        pressure = lmp.numpy.extract_fix("mfc", 0, 2, 0, 1)
    finally:
        lmp.close()
    assert report["converged"], report
    exact = ring_solution(P)
    cell = mfc_metrics.cells(xy, N)
    bonds = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    radius = np.hypot(*(xy - cell["centroid"][0]).T)
    assert np.abs(bonds / exact["bond"] - 1).max() < 1e-6
    assert np.abs(radius / exact["radius"] - 1).max() < 1e-6
    assert cell["area"][0] == pytest.approx(exact["area"], rel=1e-6)
    assert pressure == pytest.approx(exact["pressure"], rel=1e-4)
    # Laplace's law P R = wall tension (N/m of height) and MFC.md 7.4's fresh-cell checks
    tension = P["k_bond"] * (bonds.mean() - P["r0_bond"]) / P["height"]
    assert pressure * radius.mean() == pytest.approx(tension, rel=2e-3)
    assert abs(2 * math.sqrt(cell["area"][0] / math.pi) - 150e-6) < 1e-6
    assert abs(bonds.mean() / P["r0_bond"] - 1.045) < 0.003
    assert abs(cell["area"][0] / P["A_ref"] - 1) < 0.005
    assert abs(pressure - 2e5) < 5e3


@pytest.mark.parametrize("s", [0.8, 0.3])
@pytest.mark.lammps
def test_single_dried_cell_follows_its_fluid_and_wrinkles(tmp_path, s):
    lmp = open_cells(tmp_path, [[0.0, 0.0]])
    try:
        mfc_run.relax(lmp, P, 1.0, ftol=1e-10)
        lmp.command("displace_atoms all random 2e-8 2e-8 0 5 units box")  # break the symmetry
        report = mfc_run.ramp(lmp, P, 1.0, s, ftol=1e-10)
        xy = mfc_run.positions(lmp)
        pressure = lmp.numpy.extract_fix("mfc", 0, 2, 0, 1)
    finally:
        lmp.close()
    assert report["converged"], report
    cell = mfc_metrics.cells(xy, N)
    # the fluid area follows the prescribed mass (MFC.md 7.4: s +- 2 %)
    assert abs(cell["area"][0] / (s * P["A_ref"]) - 1) < 0.02
    assert pressure == pytest.approx(eos(cell["area"][0], s * P["A_ref"], s * 2e5), abs=1.0)
    # the wall cannot pass through itself: the ring stays a simple polygon
    tissue._ring(xy, "dried cell")
    rest = N * P["r0_bond"] * (1 - 0.2 / 0.9 * (1 - s))
    circle = 2 * math.sqrt(math.pi * cell["area"][0])
    if s == 0.3:   # the contracted wall is longer than the fluid's circle: it wrinkles
        assert cell["perimeter"][0] > 1.2 * circle
        assert cell["perimeter"][0] < 1.02 * rest
        assert cell["roundness"][0] < 0.7


def test_remaining_drift_of_a_geometric_series():
    # c_k = 2 x 0.8^k: what is still to come after k = 9 is 2 x 0.8^10 / (1 - 0.8)
    changes = 2 * 0.8 ** np.arange(10)
    ratio, rest = mfc_run.remaining(changes)
    assert ratio == pytest.approx(0.8, rel=1e-12)
    assert rest == pytest.approx(10 * 0.8 ** 10, rel=1e-10)
    assert mfc_run.remaining([1.0, 1.1, 1.2])[1] == math.inf      # not decaying
    assert math.isnan(mfc_run.remaining([1.0, 0.5])[1])           # too few chunks


@pytest.mark.lammps
def test_a_level_that_does_not_converge_reports_its_remaining_drift(tmp_path):
    lmp = open_cells(tmp_path, [[0.0, 0.0]])
    try:
        mfc_run.relax(lmp, P, 1.0, ftol=1e-10)
        lmp.command("displace_atoms all random 1e-7 1e-7 0 5 units box")
        report = mfc_run.relax(lmp, P, 0.6, chunk=100, max_iterations=400, ftol=1e-30, shift=0,
                               newton=None)
    finally:
        lmp.close()
    assert not report["converged"] and len(report["mean_shifts"]) == 4
    ratio, rest = mfc_run.remaining(report["mean_shifts"])
    assert report["shift_ratio"] == ratio
    # a finite remainder, or None (not inf or nan) when the shifts do not decay
    assert report["remaining_shift"] == (rest if math.isfinite(rest) else None)
    assert report["shift"] >= report["mean_shifts"][-1] > 0


@pytest.mark.lammps
def test_newton_carries_on_after_a_spent_budget(tmp_path, monkeypatch):
    """Once the minimiser's iterations are spent, Newton is called again, up to
    SPENT_NEWTON_CALLS calls, while it can lower the energy (the 203-cell tissue's s = 0.3
    was left at 2.9e-5 N after one call), and so reaches the steady state in calls too
    short for one.

    The calls' length is derived from the solver, not fixed: how many steps Newton needs
    depends on where 2000 minimiser iterations left the buckling wall, and that state is
    not reproducible across CPUs (the conjugate gradients' path amplifies the last bit:
    with the plugin's fused multiply-adds and NumPy on AVX2 it starts Newton at
    2.7e-11 J, 9.3e-7 N instead of 2.8e-11 J, 2.2e-7 N). From there one uninterrupted
    Newton takes 58 steps instead of 39 to the same minimum (energies 1e-12 apart); every
    step is downhill, backtracked from the 5 um cap to about 1 um in the non-convex
    landscape, and none stalls on rounding: calls of a fixed 10 steps simply ran out after
    5 x 10 there, at 1e-7 N. So a reference run first takes T steps in one call, and the
    calls here are ceil(T / 2) long. The first call repeats the reference's first
    ceil(T / 2) steps exactly (same binary, inputs and operations), so it ends short of
    ftol and Newton must carry on; the remaining T - ceil(T / 2) steps get
    (SPENT_NEWTON_CALLS - 1) ceil(T / 2), four times as many, for what a restart (mu
    reset to 0) may cost (measured: 2 calls, T = 39, 46, 41 and 58 with the default
    build, NumPy on AVX2, the FMA plugin, both; the second call took at most one step
    more than the reference). With one call only (the loop removed) it fails."""
    energies, length = [], [400]
    real = mfc_run._newton

    def short(lmp, p, ftol, before=None):
        energies.append(lmp.get_thermo("pe"))
        return real(lmp, p, ftol, before, iterations=length[0])

    monkeypatch.setattr(mfc_run, "_newton", short)

    def spent_budget(folder):
        folder.mkdir()
        lmp = open_cells(folder, [[0.0, 0.0]])
        try:
            mfc_run.relax(lmp, P, 1.0, ftol=1e-10, newton=None)
            lmp.command("displace_atoms all random 1e-7 1e-7 0 5 units box")
            report = mfc_run.relax(lmp, P, 0.6, chunk=2000, max_iterations=2000,
                                   ftol=1e-12, newton=1e-30)
            return report, lmp.get_thermo("fmax"), lmp.get_thermo("pe")
        finally:
            lmp.close()

    reference, _, _ = spent_budget(tmp_path / "reference")
    assert reference["converged"] and reference["newton"]["attempts"] == 1, reference
    steps = reference["newton"]["iterations"]
    assert steps >= 2, reference   # else no call is too short
    length[0] = math.ceil(steps / 2)
    energies.clear()
    report, fmax, energy = spent_budget(tmp_path / "calls")
    assert 1 < len(energies) <= mfc_run.SPENT_NEWTON_CALLS
    assert report["newton"]["attempts"] == len(energies)
    assert all(b < a for a, b in zip(energies, energies[1:] + [energy]))
    assert report["converged"] and fmax <= 1e-12, report


@pytest.mark.lammps
@pytest.mark.parametrize("fails, newton, budget, calls", [
    ((), 1e-30, 50, mfc_run.SPENT_NEWTON_CALLS),        # no progress, no failure: the cap
    ((1,), 1e-30, 50, 1),                               # the spent budget's first call fails
    ((1,), 1.0, 100, 1 + mfc_run.SPENT_NEWTON_CALLS),   # a chunk's earlier call failed
])
def test_newton_after_a_spent_budget_counts_its_calls(tmp_path, monkeypatch, fails, newton,
                                                      budget, calls):
    """The calls Newton gets once the minimiser's iterations are spent: at most
    SPENT_NEWTON_CALLS, fewer when one fails (no step lowers the energy); a call that
    failed after an earlier chunk (``newton`` 1 N: every chunk ends in a call) does not
    stop those of the spent budget. A stand-in Newton that leaves the state as it is."""
    made = []

    def stand_in(lmp, p, ftol, before=None):
        made.append(len(made) + 1)
        total = dict(before or dict(attempts=0, iterations=0, evaluations=0, seconds=0.0))
        if len(made) in fails:
            return dict(total, error="mfc newton: no step lowers the energy")
        return dict(total, attempts=total["attempts"] + 1)

    monkeypatch.setattr(mfc_run, "_newton", stand_in)
    lmp = open_cells(tmp_path, [[0.0, 0.0]], s=0.6, jitter=1e-7)
    try:
        report = mfc_run.relax(lmp, P, 0.6, chunk=50, max_iterations=budget, ftol=1e-30,
                               newton=newton)
    finally:
        lmp.close()
    assert len(made) == calls and not report["converged"]
    assert report["newton"]["attempts"] == calls - len(fails)
    assert ("error" in report["newton"]) == bool(fails)


@pytest.mark.lammps
def test_newton_stiffness_matches_the_force_differences_column_by_column(tmp_path):
    """cgms.mfc.newton builds the stiffness from few force evaluations (particles of one
    colour displaced together, the cells' fluid stiffness taken out as a rank-one term);
    against the plain finite differences, one particle at a time, on two dried cells."""
    from cgms.mfc import newton as mfc_newton
    from cgms.solve import colour
    lmp = open_cells(tmp_path, [[0.0, 0.0], [P["x_ref"], 0.0]])
    try:
        mfc_run.relax(lmp, P, 1.0, newton=None)
        mfc_run.ramp(lmp, P, 1.0, 0.6, max_iterations=2000, newton=None)
        forces = mfc_newton.CellForces(lmp)
        xy = forces.positions()
        reach = 1.3 * P["lamella_rc"]
        hess, fluid = mfc_newton.stiffness(forces, xy, N, P["height"], reach, 5e-11,
                                           colour(xy, 2 * reach))
        g = mfc_newton.area_gradient(xy, N)
        _, f0 = forces(xy)
        plain = np.zeros((2 * len(xy), 2 * len(xy)))
        for j in range(len(xy)):
            for d in (0, 1):
                xp, xm = xy.copy(), xy.copy()
                xp[j, d] += 5e-11
                xm[j, d] -= 5e-11
                plain[:, 2 * j + d] = -(forces(xp)[1] - forces(xm)[1]).ravel() / 1e-10
    finally:
        lmp.close()
    u = np.zeros((2 * len(xy), 2))
    for i in range(len(xy)):
        u[2 * i:2 * i + 2, i // N] = g[i]
    built = hess.toarray() + u @ np.diag(fluid) @ u.T
    plain = 0.5 * (plain + plain.T)
    tolerance = 1e-6 * np.abs(plain).max()
    assert np.abs(built - plain).max() < tolerance
    # the fluid's part, which couples a cell's far wall particles, is far above that
    assert np.abs(hess.toarray() - plain).max() > 1e3 * tolerance


@pytest.mark.lammps
def test_newton_finishes_a_dried_cluster_to_the_force_test(tmp_path):
    """From the minimiser's state two chunks into s = 0.6 (7 cells), Newton's method
    reaches a largest force of 1e-12 N in a few steps, at a lower energy; the minimiser
    alone is still at 1e-7 N there (doc/mfc.md, "Newton")."""
    from cgms.mfc import newton as mfc_newton
    lmp = open_cells(tmp_path, [[0.0, 0.0]] + [
        [P["x_ref"] * math.cos(a), P["x_ref"] * math.sin(a)]
        for a in np.arange(6) * math.pi / 3 + math.pi / 2])
    try:
        mfc_run.relax(lmp, P, 1.0, newton=None)
        cg = mfc_run.ramp(lmp, P, 1.0, 0.6, max_iterations=4000, newton=None, shift=0)
        report = mfc_newton.newton(lmp, P, ftol=1e-12, max_iterations=12)
        fmax = lmp.get_thermo("fmax")
    finally:
        lmp.close()
    assert cg["fmax"] > 1e-9 and not cg["converged"]
    assert report["converged"] and fmax < 1e-12, report["history"]
    assert report["energy"] < cg["energy"]


def fast_then_sph(folder, s, steps):
    """The fast variant's steady state of one cell at level ``s``, then the SPH model
    started there (the ring filled with fluid at rest at the fast variant's pressure,
    cgms.mfc.sph.write_state) and run
    ``steps`` steps of 2 ns. Returns the fast walls, the SPH walls, the SPH fluid's
    pressures (Pa) and write_state's report."""
    from cgms.mfc import sph as mfc_sph
    lmp = open_cells(folder, [[0.0, 0.0]])
    try:
        report = mfc_run.ramp(lmp, P, None, s, ftol=1e-11)
        fast = mfc_run.positions(lmp)
        colour = np.array(lmp.gather_atoms("type", 0, 1)) - 1
        fast_pressure = lmp.numpy.extract_fix("mfc", 0, 2, 0, 1)
    finally:
        lmp.close()
    assert report["converged"], report
    state = mfc_sph.write_state(folder / "sph.data", fast, colour, P, s, [fast_pressure],
                                overwrite=True)
    lmp = run.open_lammps()
    try:
        lmp.commands_list(mfc_sph.setup_commands(folder / "sph.data", P))
        lmp.commands_list(mfc_sph.level_commands(P, s, mf=state["fluid_mass"]))
        lmp.commands_list(["timestep 2e-9", f"run {steps}"])
        sph = mfc_sph.wall_positions(lmp, P)
        rho = np.array(lmp.gather_atoms("rho", 1, 1))[N:]
    finally:
        lmp.close()
    rho_r, c0 = mfc_sph.tait(P, s)
    # LAMMPS's Tait EOS, B [(rho/rho_r)^7 - 1] per slab height
    return fast, sph, c0 * c0 * rho_r / 7 * ((rho / rho_r) ** 7 - 1) / P["height"], state


@pytest.mark.lammps
def test_sph_holds_the_dried_steady_state_of_the_fast_variant(tmp_path):
    """The fast variant's dried, wrinkled steady state (s = 0.6) is a steady state of the
    SPH model: filled with SPH fluid at rest, the wall stays where it is (doc/mfc.md,
    SPH against the fast variant). The drying path itself does not reach it in SPH
    (tension on drying pairs the particles up), which this test does not cover.

    The fluid's amount is write_state's lattice count, before any SPH step: it is checked
    against the area of the region the fill samples, with the count's own error as the
    tolerance (comments below). It was checked against the ring minus the fresh
    hexagon's boundary layer (2.70 um, less than the 3.25 um margin: the hexagon's edges
    lie along the lattice), 1.8 % too little on a wrinkled ring; the count's scatter
    (+-0.8 % over lattice offsets) then crossed the 2 % asserted when the wrinkles fell
    otherwise (the FMA plugin: 2.8 %). Now within 0.8 % of a 2.2 % bound in every build;
    a margin 20 % thinner in the fill fails it (2.5 %)."""
    fast, sph, pressure, state = fast_then_sph(tmp_path, 0.6, 8000)
    cf, cs = mfc_metrics.cells(fast, N), mfc_metrics.cells(sph, N)
    assert abs(cs["area"][0] / cf["area"][0] - 1) < 5e-4
    assert abs(cs["perimeter"][0] / cf["perimeter"][0] - 1) < 5e-4
    assert np.hypot(*(cs["centroid"][0] - cf["centroid"][0])) < 5e-8
    assert np.hypot(*(sph - fast).T).max() < 0.5e-6
    # the fluid is at the fast variant's small suction (about -1 kPa), quiet
    assert abs(pressure.mean()) < 5e3 and pressure.std() < 5e3
    # its amount: the lattice points (spacing h) inside the ring and at least the margin m
    # from its polyline (cgms.mfc.sph.fill), h^2 each, count the region whose area is
    # A - m L + pi m^2 (Steiner's formula for the inner parallel set: exact while that set's
    # boundary does not cross itself; here within 5e-4 of 10x and 20x finer lattices).
    # A lattice count misses a region's area by one error per boundary cell, spread evenly
    # over +-h^2/2 (variance h^4/12); a curve of length L crosses (4/pi) L/h cells on
    # average (Cauchy-Crofton), so sigma = h^2 sqrt(L/(3 pi h)), 0.54 % here (over lattice
    # offsets the count spreads by 0.33 %: along a straight stretch the errors cancel).
    # Where the lattice falls on the ring is arbitrary: the wrinkles' pattern differs
    # between builds (walls up to 48 um apart at the same A and L), so the count does
    # (616 to 622 points): 4 sigma.
    # The region's area itself: Steiner's formula holds only while the inner parallel set
    # does not cross itself, which a tightly wrinkled ring breaks (a build whose wrinkles
    # fell otherwise: 5.6 sigma off); a lattice ten times finer counts it to sigma / 30
    h = P["fluid_spacing"] * math.sqrt(0.6)
    length = cf["perimeter"][0]
    sigma = h * h * math.sqrt(length / (3 * math.pi * h))
    ring = fast[:P["n_wall"]]
    fine = dict(P, fluid_spacing=P["fluid_spacing"] / 10)
    region = len(mfc_sph.fill(ring, fine, 0.6)) * (h / 10) ** 2
    # the count's spread over lattice offsets, measured on this ring: where wall stretches
    # run along a lattice row their errors do not cancel and the spread exceeds sigma (a
    # build whose wrinkles fell that way: 3 % off, 5.6 sigma)
    rng = np.random.default_rng(1)
    counts = [len(mfc_sph.fill(ring, P, 0.6, rng.uniform(0, h, 2))) * h * h
              for _ in range(32)]
    spread = max(sigma, float(np.std(counts, ddof=1)))
    assert abs(state["fluid_area"][0] - region) < 4 * spread


# --------------------------------------------------------------------------- LAMMPS runs

SEVEN = [[0, 0]] + [[P["x_ref"] * math.cos(a), P["x_ref"] * math.sin(a)]
                    for a in np.arange(6) * math.pi / 3 + math.pi / 2]


def cluster_script(nprocs=1, newton="on", s=1.0, steps=400, restart=None, read=None):
    """A 7-cell cluster under damped dynamics (fix nve + viscous) with every force."""
    lines = [f"plugin load {PLUGIN}"]
    if read:
        lines += ["units si", "dimension 2", f"newton {newton}", f"read_restart {read}"]
        lines += [line for line in mfc_run.setup_commands("walls.data", P, newton=newton)
                  if line.split()[0] in ("special_bonds", "angle_coeff", "pair_modify",
                                         "pair_coeff", "neighbor", "neigh_modify", "fix")]
    else:
        lines += mfc_run.setup_commands("walls.data", P, newton=newton,
                                        processors=nprocs if nprocs > 1 else None)
    lines += mfc_run.level_commands(P, s)
    lines += ["displace_atoms all random 1e-6 1e-6 0 11 units box" if not read else "",
              "fix nve all nve", "fix damp all viscous 2e-8", "timestep 5e-9",
              "compute mol all property/atom mol",
              "thermo_style custom step pe ke f_mfc[3]", "thermo 100"]
    if restart:
        lines += [f"run {steps // 2}", f"write_restart {restart}"]
        lines += [f"run {steps - steps // 2}"]
    else:
        lines += [f"run {steps}"]
    lines += ["write_dump all custom final.dump id mol type x y vx vy fx fy "
              "modify sort id format float %.17g"]
    return "\n".join(lines) + "\n"


def cluster_folder(path):
    mfc_tissue.write_data(path / "walls.data", SEVEN, P, overwrite=True)
    return path


@pytest.mark.mpi
def test_cluster_one_and_two_ranks_agree(tmp_path_factory):
    a = cluster_folder(tmp_path_factory.mktemp("np1"))
    b = cluster_folder(tmp_path_factory.mktemp("np2"))
    c = cluster_folder(tmp_path_factory.mktemp("np2off"))
    run_lmp(a, cluster_script())
    run_lmp(b, cluster_script(nprocs=2), nprocs=2)
    run_lmp(c, cluster_script(nprocs=2, newton="off"), nprocs=2)
    one, two, off = (read_dump(f / "final.dump") for f in (a, b, c))
    moved = np.hypot(one["vx"], one["vy"]).max()
    assert moved > 0   # the cluster is moving
    for other in (two, off):
        assert np.abs(one["x"] - other["x"]).max() < 1e-9 * P["x_ref"]
        assert np.abs(one["y"] - other["y"]).max() < 1e-9 * P["x_ref"]


@pytest.mark.lammps
def test_cluster_conserves_particles_molecules_and_momentum(tmp_path):
    folder = cluster_folder(tmp_path)
    script = cluster_script(steps=400).replace("fix damp all viscous 2e-8", "")
    run_lmp(folder, script)
    d = read_dump(folder / "final.dump")
    assert len(d["id"]) == 7 * N and np.array_equal(d["id"], np.arange(1, 7 * N + 1))
    assert np.array_equal(d["mol"], np.repeat(np.arange(1, 8), N))
    m = mfc_model.level(P, 1.0)["wall_mass"]
    p_total = m * np.array([d["vx"].sum(), d["vy"].sum()])
    p_scale = m * np.abs(np.c_[d["vx"], d["vy"]]).sum()
    assert p_scale > 0 and np.abs(p_total).max() < 1e-10 * p_scale
    assert np.abs([d["fx"].sum(), d["fy"].sum()]).max() < 1e-10 * np.abs(d["fx"]).sum()
    log = (folder / "log.lammps").read_text()
    assert "Dangerous builds = 0" in log or "Dangerous builds" not in log


@pytest.mark.lammps
def test_cluster_restart_continues_the_run(tmp_path_factory):
    # the uninterrupted run also stops at the half (run N; write_restart; run N): the
    # re-setup there rebuilds the neighbour lists, whose new summation order alone moves
    # a particle by 1e-9 m after 200 more steps of this strongly driven cluster
    a = cluster_folder(tmp_path_factory.mktemp("straight"))
    b = cluster_folder(tmp_path_factory.mktemp("restart"))
    run_lmp(a, cluster_script(steps=400, restart="half.restart"))
    (b / "half.restart").write_bytes((a / "half.restart").read_bytes())
    run_lmp(b, cluster_script(steps=200, read="half.restart"))
    straight, resumed = read_dump(a / "final.dump"), read_dump(b / "final.dump")
    assert np.abs(straight["x"] - resumed["x"]).max() < 1e-12 * P["x_ref"]
    assert np.abs(straight["vx"] - resumed["vx"]).max() <= 1e-9 * np.abs(straight["vx"]).max()


def test_ramp_seeds_each_dried_levels_kick(monkeypatch):
    """Each dried level of the ramp (stages included) kicks the walls with its own seed,
    ``seed + round(1e4 s)``; the fresh level is not kicked. (Before the option every study
    used seed 1: the committed references are seed 1.)"""
    commands = []

    class Recorder:
        def command(self, line):
            commands.append(line)

    monkeypatch.setattr(mfc_run, "relax",
                        lambda lmp, p, s, **options: dict(iterations=1, converged=True))
    for seed in (1, 7):
        commands.clear()
        mfc_run.ramp(Recorder(), P, 1.0, 0.85, seed=seed)
        seeds = [int(line.split()[-3]) for line in commands if line.startswith("displace")]
        assert seeds == [seed + 9500, seed + 9000, seed + 8500], commands
    commands.clear()
    mfc_run.ramp(Recorder(), P, None, 1.0, seed=7)
    assert commands == []


def test_ramp_relaxes_its_stages_to_steady_state_when_asked(monkeypatch):
    """On the chunked path (the ramp's own default) an intermediate level gets one chunk
    of minimisation at a looser force test and no Newton; on the quasi-static path (the
    reference path of cgms mfc) every level gets the options of the asked level, with
    the same kicks, and the report names the intermediate levels that did not reach their
    steady state."""
    calls = []
    monkeypatch.setattr(mfc_run, "relax",
                        lambda lmp, p, s, **options: calls.append((s, options))
                        or dict(iterations=1, converged=abs(s - 0.9) > 1e-9))

    class Recorder:
        def __init__(self):
            self.lines = []

        def command(self, line):
            self.lines.append(line)

    asked = dict(ftol=1e-10, newton=1e-6, max_iterations=20000, chunk=2000)
    chunked, steady = Recorder(), Recorder()
    report = mfc_run.ramp(chunked, P, 1.0, 0.85, **asked)
    assert [s for s, _ in calls] == pytest.approx([0.95, 0.9, 0.85])
    assert [o for _, o in calls[:2]] == [dict(asked, max_iterations=2000, ftol=1e3 * 1e-10,
                                              newton=None)] * 2
    assert calls[2][1] == asked
    assert "unsteady_stages" not in report and report["iterations"] == 3
    calls.clear()
    report = mfc_run.ramp(steady, P, 1.0, 0.85, steady_stages=True, **asked)
    assert [o for _, o in calls] == [asked] * 3
    assert steady.lines == chunked.lines and len(steady.lines) == 3
    assert report["unsteady_stages"] == pytest.approx([0.9])


# --------------------------------------------------------------------------- the command

@pytest.mark.lammps
def test_cgms_mfc_tiny_study(tmp_path):
    out = tmp_path / "study"
    cmd = [sys.executable, "-m", "cgms", "mfc", "single", "--dryness", "1,0.8", "--out",
           str(out), "--ftol", "1e-9"]
    env = lammps_env()
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), env.get("PYTHONPATH", "")])
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    folder = out / "single"
    for name in ("centroids.s1.txt", "centroids.s0.8.txt", "cells.s0.8.csv", "walls.s0.8.dump",
                 "level.s0.8.json", "state.s0.8.data"):
        assert (folder / name).exists(), name
    rec = json.loads((folder / "level.s0.8.json").read_text())
    assert rec["converged"] and abs(rec["cell_area/A0"] - 0.8) < 0.02
    from cgms import positions
    ids, xy = positions.read_centroids(folder / "centroids.s0.8.txt")
    assert ids.tolist() == [1] and np.abs(xy).max() < 1e-6
    # an existing study is not overwritten; --resume reuses the finished levels
    again = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert again.returncode != 0 and "not empty" in again.stderr
    resumed = subprocess.run(cmd + ["--resume"], env=env, capture_output=True, text=True,
                             timeout=300)
    assert resumed.returncode == 0 and "iterations" not in resumed.stdout.split("tissue")[0]
    other = subprocess.run(cmd + ["--resume", "--ftol", "1e-8"], env=env, capture_output=True,
                           text=True, timeout=300)
    assert other.returncode == 1 and "holds results of another setup (ftol" in other.stderr
    assert "Traceback" not in other.stderr
    # another kick seed is another setup: an ensemble's members never share a folder
    seeded = subprocess.run(cmd + ["--resume", "--seed", "2"], env=env, capture_output=True,
                            text=True, timeout=300)
    assert seeded.returncode == 1 and "seed: None there, 2 now" in seeded.stderr, seeded.stderr
    # so is another drying path: a chunked study never resumes a quasi-static one (the
    # default), and the refusal names the option that would
    assert json.loads((folder / "setup.json").read_text())["steady_stages"] is True
    chunked = subprocess.run(cmd + ["--resume", "--stages", "chunk"], env=env,
                             capture_output=True, text=True, timeout=300)
    assert chunked.returncode == 1 and ("dried on the quasi-static (--stages steady) path and "
                                        "this run asks for the chunked (--stages chunk) one"
                                        in chunked.stderr), chunked.stderr
    assert "resume it with --stages steady" in chunked.stderr
    for bad_seed in ("0", "-3", str(mfc_run.MAX_SEED + 1), "two"):
        refused = subprocess.run(cmd + ["--resume", "--seed", bad_seed], env=env,
                                 capture_output=True, text=True, timeout=300)
        assert refused.returncode == 2 and "--seed" in refused.stderr, refused.stderr
        assert "Traceback" not in refused.stderr
    bad = subprocess.run([sys.executable, "-m", "cgms", "mfc", "nowhere", "--out",
                          str(tmp_path / "bad")], env=env, capture_output=True, text=True)
    assert bad.returncode == 2 and "unknown tissue 'nowhere'" in bad.stderr
    assert "Traceback" not in bad.stderr


def test_wall_data_file_is_written_whole_or_not_at_all(tmp_path):
    """A write that fails half-way (here: a title UTF-8 cannot encode) leaves no file that a
    resumed study would take for its walls; a file already there is kept."""
    path = tmp_path / "walls.data"
    with pytest.raises(UnicodeEncodeError):
        mfc_tissue.write_data(path, [[0.0, 0.0]], P, title="\ud800")
    assert list(tmp_path.iterdir()) == []
    path.write_text("the user's work\n")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        mfc_tissue.write_data(path, [[0.0, 0.0]], P)
    assert path.read_text() == "the user's work\n"
    mfc_tissue.write_data(path, [[0.0, 0.0]], P, overwrite=True)
    assert f"{P['n_wall']} atoms" in path.read_text()


def test_study_resume_names_a_damaged_record_and_keeps_close_levels_apart(tmp_path):
    """A level record cut short (the run killed while writing it) stops the resume with a
    message naming the file, not a JSON traceback; levels that %g would round alike get
    files of their own. Both checks read only records: no LAMMPS run."""
    from cgms.mfc import study as mfc_study
    folder = tmp_path / "single"
    folder.mkdir()
    (folder / "level.s1.json").write_text('{"s": 1.0, "cell_area/A0"')
    with pytest.raises(ValueError, match=r"level\.s1\.json is damaged"):
        mfc_study.dry([[0.0, 0.0]], P, folder, levels=(1.0,))
    assert mfc_study.level_name(0.3) != mfc_study.level_name(0.30000001)


def test_study_on_the_chunked_path_is_not_resumed_on_the_quasi_static_one(tmp_path):
    """A folder made on the chunked ramp (its record has no ``steady_stages``, as every
    set made before the quasi-static path became the default) is refused by the default
    resume with the option that continues it; a jump (stage 0) has no levels between and
    is recorded as before. Only records are read: no LAMMPS run."""
    from cgms import folders
    from cgms.mfc import study as mfc_study
    centres = [[0.0, 0.0]]
    sha = hashlib.sha256(np.ascontiguousarray(centres, float).tobytes()).hexdigest()
    old = tmp_path / "old"
    old.mkdir()
    folders.write_json(old / "setup.json", dict(centres_sha256=sha, parameters=P))
    with pytest.raises(folders.FolderError, match=r"dried on the chunked \(--stages chunk\) "
                       r"path .* resume it with --stages chunk"):
        mfc_study.dry(centres, P, old, levels=(1.0,))
    assert "steady_stages" not in json.loads((old / "setup.json").read_text())
    jump = tmp_path / "jump"
    jump.mkdir()
    folders.write_json(jump / "setup.json", dict(centres_sha256=sha, parameters=P, stage=0))
    with pytest.raises(ValueError, match=r"level\.s1\.json is damaged"):   # past the record
        (jump / "level.s1.json").write_text("{")
        mfc_study.dry(centres, P, jump, levels=(1.0,), stage=0)


@pytest.mark.lammps
def test_fresh_cluster_rounds_up_widens_and_keeps_the_lamella(tmp_path):
    # MFC.md 7.4 check 3: lamella gaps settle near d_p, and the cluster widens when fresh
    lmp = open_cells(tmp_path, SEVEN)
    try:
        report = mfc_run.relax(lmp, P, 1.0)
        xy = mfc_run.positions(lmp)
    finally:
        lmp.close()
    assert report["converged"], report
    cell = mfc_metrics.cells(xy, N)
    centre = cell["centroid"][0]
    radial = np.hypot(*(cell["centroid"][1:] - centre).T)
    assert np.all(radial > 1.02 * P["x_ref"])        # the outer cells moved out (2.5 %)
    assert np.all(cell["roundness"] > 0.93)          # hexagons rounded up (0.907 at start)
    from scipy.spatial import cKDTree
    cells_of = np.repeat(np.arange(7), N)
    d, j = cKDTree(xy).query(xy, k=40)
    other = cells_of[j] != cells_of[:, None]
    nearest = np.where(other, d, np.inf).min(axis=1)
    gaps = nearest[np.isfinite(nearest) & (nearest < 12e-6)]
    assert 7.0e-6 < np.median(gaps) < 8.5e-6


def test_missing_lammps_package_is_named():
    """A LAMMPS of one's own without MOLECULE or EXTRA-PAIR gets one message naming the
    package and the CMake option, before any MFC input runs."""
    class Bare:
        def has_package(self, name):
            return name != "EXTRA-PAIR"

    with pytest.raises(RuntimeError, match=r"EXTRA-PAIR package.*-DPKG_EXTRA-PAIR=on"):
        mfc_run.require_packages(Bare())
    mfc_run.require_packages(type("Full", (), {"has_package": lambda self, n: True})())


# --------------------------------------------------------------------------- the lamella

PAIR = [[0.0, 0.0], [0.0, P["x_ref"]]]   # rows along y: the shared wall is along x


def glued_pair(folder, p):
    """Two relaxed fresh cells with ``p``'s lamella: a LAMMPS instance and the lamella's
    bonds as (n, 2) 0-based pairs (none for the LJ alone). For the lamella set in the fresh
    state, the pair is relaxed without it, then its bonds are set where the walls sit."""
    data = folder / "walls.data"
    w = mfc_tissue.write_data(data, PAIR, p, overwrite=True)
    lmp = run.open_lammps()
    lmp.commands_list(mfc_run.setup_commands(data, p))
    lmp.commands_list(mfc_run.level_commands(p, 1.0))
    mfc_run.relax(lmp, p, 1.0, ftol=1e-11)
    pairs = np.zeros((0, 2), int)
    if p["lamella"] in ("bonded", "facing"):
        pairs, kind = mfc_tissue.lamella_bonds(w["xy"], w["cell"], p)
        pairs = pairs[kind == 2] if p["lamella"] == "facing" else pairs
    elif p["lamella"] == "fresh":
        xy = mfc_run.positions(lmp)
        lmp.close()
        pairs, types, rest = mfc_tissue.fresh_lamella(xy, w["cell"], p)
        mfc_tissue.write_data(folder / "glued.data", PAIR, p, xy=xy, lamella=(pairs, types))
        lmp = run.open_lammps()
        lmp.commands_list(mfc_run.setup_commands(folder / "glued.data", p, rest=rest))
        lmp.commands_list(mfc_run.level_commands(p, 1.0))
        mfc_run.relax(lmp, p, 1.0, ftol=1e-11)
    return lmp, pairs


def lamella_slip(folder, p, direction, force, pairs):
    """Two fresh cells glued by ``p``'s lamella, then the first held in place and the
    second pulled by ``force`` (N, spread over its wall particles) along ``direction`` (held,
    so the load has an equilibrium: two opposite forces on the two cells make a couple),
    and minimised again. Returns the slip across the lamella: the change of the relative
    position of the particle ``pairs`` (0-based) along ``direction``, averaged with the
    weights of :func:`truss_stiffness` (m)."""
    lmp, _ = glued_pair(folder, p)
    cell = np.repeat([0, 1], N)
    u = np.asarray(direction, float)
    sign = np.where(cell[pairs[:, 1]] == 1, 1.0, -1.0)   # cell 2 minus cell 1
    try:
        xy = mfc_run.positions(lmp)
        d = xy[pairs[:, 1]] - xy[pairs[:, 0]]
        weight = (d @ u / np.hypot(*d.T)) ** 2
        before = sign * (d @ u)
        f = u * force / N
        lmp.commands_list([
            "group one molecule 1", "group two molecule 2",
            "fix hold one setforce 0.0 0.0 0.0",
            f"fix pull2 two addforce {f[0]:.10g} {f[1]:.10g} 0.0", "fix_modify pull2 energy yes",
            *mfc_run.minimize_commands(1e-11, 20000)])
        xy = mfc_run.positions(lmp)
        after = sign * ((xy[pairs[:, 1]] - xy[pairs[:, 0]]) @ u)
    finally:
        lmp.close()
    return float(np.sum(weight * (after - before)) / np.sum(weight))


def truss_stiffness(p, direction, xy, pairs):
    """Stiffness (N/m) of the bonded lamella alone against a uniform slip of one wall
    against the other along ``direction``: sum over its bonds (``pairs`` at positions
    ``xy``) of k cos^2 of the bond's angle to the slip (small strain)."""
    d = xy[pairs[:, 1]] - xy[pairs[:, 0]]
    cos = d @ np.asarray(direction, float) / np.hypot(*d.T)
    return float(p["lamella_k"] * np.sum(cos ** 2))


@pytest.mark.parametrize("lamella", ["fresh", "bonded"])
@pytest.mark.parametrize("direction, force", [((1.0, 0.0), 2e-5), ((0.0, 1.0), 1e-4)],
                         ids=["shear", "pull"])
@pytest.mark.lammps
def test_lamella_holds_a_loaded_pair_and_the_lj_alone_gives_way(tmp_path_factory, lamella,
                                                                 direction, force):
    glued = mfc_model.parameters(lamella=lamella)
    lj = mfc_model.parameters(lamella="lj")
    lmp, pairs = glued_pair(tmp_path_factory.mktemp("pairs"), glued)
    xy = mfc_run.positions(lmp)
    lmp.close()
    # built: a wall of 17 facing pairs and 32 diagonals; a fresh free pair rounds up and
    # touches along part of it
    assert len(pairs) > 10
    held = lamella_slip(tmp_path_factory.mktemp("glued"), glued, direction, force, pairs)
    slid = lamella_slip(tmp_path_factory.mktemp("lj"), lj, direction, force, pairs)
    truss = force / truss_stiffness(glued, direction, xy, pairs)
    print(f"{lamella}: slip {held:.4g} m, truss alone {truss:.4g} m, LJ alone {slid:.4g} m")
    # the whole load crosses the lamella: the bonded one slips about what its truss allows
    # (small strain). Not exactly: the LJ on top stiffens it along the pair (measured 0.79 x
    # the truss's slip when pulled, 0.87 x for the fresh-set lamella), while LJ pairs held
    # off their rest distance soften it across, and the fresh pair's contact is short and
    # curved, so a shear also rolls one round cell on the other (measured 1.18 x built,
    # 1.79 x fresh-set when sheared)
    assert 0.5 * truss < held < 2.5 * truss, (held, truss)
    assert slid > 10 * held, (slid, held)   # the LJ alone lets the walls slide or part


@pytest.mark.lammps
def test_lamella_set_in_the_fresh_tissue_is_at_rest_there_and_kept_on_resume(tmp_path):
    from cgms.mfc import study as mfc_study
    p = mfc_model.parameters(lamella="fresh")
    mfc_study.dry(SEVEN, p, tmp_path, (1.0,), say=lambda line: None)
    assert not (tmp_path / "lamella.data").exists()   # set only when a dried level needs it
    mfc_study.dry(SEVEN, p, tmp_path, (1.0, 0.9), say=lambda line: None)
    fresh = np.loadtxt(tmp_path / "walls.s1.dump", skiprows=9)[:, 3:5]
    rest = dict(np.loadtxt(tmp_path / "lamella.txt"))
    text = (tmp_path / "state.s0.9.data").read_text()
    bonds = np.array([line.split()[1:4] for line in
                      text.split("Bonds\n\n", 1)[1].split("\n\n", 1)[0].splitlines()], int)
    glue = bonds[bonds[:, 0] > 1]
    assert len(bonds) - len(glue) == 7 * N   # the rings
    cell = (glue[:, 1:] - 1) // N
    assert np.all(cell[:, 0] != cell[:, 1]) and len(glue) > 6 * 16   # six shared walls
    length = np.hypot(*(fresh[glue[:, 1] - 1] - fresh[glue[:, 2] - 1]).T)
    assert np.abs(length - [rest[t] for t in glue[:, 0]]).max() <= mfc_tissue.REST_BIN / 2
    assert length.max() < math.hypot(P["pectin"], 1.05 * P["b_ref"] / 16)
    before = (tmp_path / "lamella.data").stat().st_mtime_ns
    r = mfc_study.dry(SEVEN, p, tmp_path, (1.0, 0.9, 0.85), say=lambda line: None)
    assert (tmp_path / "lamella.data").stat().st_mtime_ns == before   # read back, not remade
    assert [x["converged"] for x in r] == [True] * 3
