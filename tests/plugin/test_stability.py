# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The default scheme runs every uniform dryness in [0.1, 1] stably at the paper's time
step (doc/model.md: the paper's literal inertia does not)."""

import numpy as np
import pytest

from cgms import model
from cgmstest import header, make_tissue, physics, read_dump, run_lmp

pytestmark = pytest.mark.lammps

STEPS = 60000


def relax(folder, s, fix_args="", steps=STEPS):
    make_tissue(folder, jitter=0.05, seed=21, s=s)
    script = header() + physics(fix_args=fix_args) + (
        "compute cg all property/atom pressure mf\n"
        "thermo_style custom step pe f_fl[1] f_fl[2] f_fl[3] f_fl[4]\n"
        f"thermo {steps // 10}\n"
        f"dump d all custom {steps} end.dump id x y c_cg[*]\n"
        "dump_modify d format float %.17g sort id\n"
        f"run {steps}\n")
    proc = run_lmp(folder, script, check=False)
    return proc


@pytest.mark.parametrize("s", [1.0, 0.6, 0.3, 0.1])
def test_default_is_stable_at_paper_time_step(tmp_path, s):
    proc = relax(tmp_path, s)
    assert proc.returncode == 0, proc.stdout[-3000:]
    end = read_dump(tmp_path / "end.dump")
    assert all(np.all(np.isfinite(v)) for v in end.values())
    rows = [line.split() for line in proc.stdout.splitlines()
            if line.strip().split() and line.split()[0] == str(STEPS)]
    residual, speed = float(rows[-1][2]), float(rows[-1][4])
    # the pressures have balanced the osmotic potential and the tissue has nearly stopped
    assert residual < 5e-3, residual
    assert speed < 5e-3, speed


@pytest.mark.parametrize("s", [0.2, 0.1])
def test_dried_corners_survive_long_runs(tmp_path, s):
    """At low dryness a corner bead's far neighbour sits at the cutoff; when it leaves,
    the bead's virtual cell shrinks by a third in one step and its pressure jumps by
    about K (1.5^7 - 1). The explicit mass update then overshoots to a negative mass
    (seen at step 155 311 for s = 0.1); the default implicit update must ride it out."""
    proc = relax(tmp_path, s, steps=300000)
    assert proc.returncode == 0, proc.stdout[-3000:]
    end = read_dump(tmp_path / "end.dump")
    assert all(np.all(np.isfinite(v)) for v in end.values())


def test_paper_literal_inertia_is_unstable_when_dried(tmp_path):
    """doc/model.md: with the inertial mass scaled by dryness, dt = 1e-7 s is above the
    explicit damping limit below s of about 0.75. The run must stop at setup with an
    ERROR that gives the limit, not produce NaNs or a torn tissue."""
    proc = relax(tmp_path, 0.3, fix_args="inertia fluid", steps=2000)
    assert proc.returncode != 0
    error = [line for line in proc.stdout.splitlines() if "ERROR" in line]
    assert error and "above the stability limit of the damping" in error[0], error
    limit = float(error[0].split("about ")[1].split()[0])
    # doc/model.md: unstable at 5e-8 s, stable at 3e-8 s for this case
    assert 3e-8 < limit < 5e-8, limit


def test_literal_inertia_runs_below_its_limit(tmp_path):
    proc = relax(tmp_path, 0.3, fix_args="inertia fluid", steps=2000)
    limit = float(proc.stdout.split("about ")[1].split()[0])
    # the fluid mass, and with it the limit, falls by about a quarter as the tissue dries
    script = (tmp_path / "in.test").read_text().replace("timestep 1e-7", f"timestep {0.6 * limit}")
    proc = run_lmp(tmp_path, script, check=False)
    assert proc.returncode == 0, proc.stdout[-2000:]


def test_estimated_time_step_limit(tmp_path):
    """f_fl[5] is the smallest per-bead limit, min(2 m / (1.5 N k_d), 2 / omega) (fix doc
    page); with the paper's inertia at s = 0.3 it is the damping limit, and the fix's
    runtime check accepts a step 10 % below it and stops 10 % above it (over a few steps:
    with the paper's inertia the mass, and so the limit, falls as the beads lose water)."""
    from cgmstest import MAT, new_lammps, working_directory
    make_tissue(tmp_path, jitter=0.05, seed=21, s=0.3)
    lmp = new_lammps()
    try:
        with working_directory(tmp_path):
            # the limit does not depend on the time step; 1e-7 s would be refused at setup
            lmp.commands_string(header() + physics(fix_args="inertia fluid").replace(
                "timestep 1e-7", "timestep 1e-8"))
        lmp.command("thermo_style custom step f_fl[5]")
        lmp.command("run 0")
        limit = lmp.extract_fix("fl", 0, 1, 4)
        n = lmp.extract_global("nlocal")
        m = np.array(lmp.numpy.extract_atom("rmass")[:n])
        cg = np.array(lmp.numpy.extract_fix("fl", 1, 2))[:n]
    finally:
        lmp.close()
    nn, side, rho, s = cg[:, 2], cg[:, 3], cg[:, 8], cg[:, 1]
    damping = model.damping_dt_limit(m, nn, MAT["k_d"])
    turgor = model.turgor_dt_limit(MAT, m, nn, side, rho, s)
    assert limit == pytest.approx(min(damping.min(), turgor.min()), rel=1e-12)
    assert limit == pytest.approx(damping.min(), rel=1e-12)  # damping is what limits here
    runs_below_stops_above(tmp_path, physics(fix_args="inertia fluid"), limit, 20,
                           "above the stability limit of the damping")


def runs_below_stops_above(folder, physics_text, limit, steps, message):
    """A run at 0.9 of a time-step limit goes ``steps`` steps; at 1.1 of it the fix's
    runtime check stops it with ``message``."""
    for factor, ok in ((0.9, True), (1.1, False)):
        script = header() + physics_text.replace(
            "timestep 1e-7", f"timestep {factor * limit!r}") + f"run {steps}\n"
        proc = run_lmp(folder, script, check=False)
        assert (proc.returncode == 0) == ok, proc.stdout[-2000:]
        if not ok:
            assert message in proc.stdout + proc.stderr


def test_cell_shape_stiffness_time_step_limit(tmp_path):
    """k_S (an extension) is a spring network of about 2 k_S per pair: the fix takes
    sqrt(m / (2 k_S N)) as its limit. On the fresh lattice at 1e-7 s that is k_S = 972 N/m
    for N = 6; measured on a fresh 10 x 12 tissue: 1000 N/m ran, 1200 ran on to a residual
    of 26 (garbage) before the check. With k_S 800 it is the smallest limit, f_fl[5]
    reports it, and the runtime check accepts 0.9 of it and stops at 1.1."""
    from cgmstest import new_lammps, working_directory
    make_tissue(tmp_path, jitter=0.0, seed=1, s=1.0)
    lmp = new_lammps()
    try:
        with working_directory(tmp_path):
            lmp.commands_string(header() + physics(material_overrides="k_S 800"))
        lmp.command("thermo_style custom step f_fl[5]")
        lmp.command("run 0")
        limit = lmp.extract_fix("fl", 0, 1, 4)
        n = lmp.extract_global("nlocal")
        m = np.array(lmp.numpy.extract_atom("rmass")[:n])
        nn = np.array(lmp.numpy.extract_fix("fl", 1, 2))[:n, 2]
    finally:
        lmp.close()
    assert limit == pytest.approx(model.shape_dt_limit(m, nn, 800).min(), rel=1e-12)
    # 0.9 of the limit runs 3 000 steps (the stiffest mode's period is a few steps
    # there: a blow-up would show), 1.1 is stopped by the check. That 1200 N/m at 1e-7 s
    # went wrong without an error was measured before the check existed.
    runs_below_stops_above(tmp_path, physics(material_overrides="k_S 800"), limit, 3000,
                           "stability limit of the cell-shape stiffness k_S = 800")


@pytest.mark.parametrize("scheme,dt,steps", [
    ("", 1e-7, 50000),  # the default: fresh inertia, implicit mass transfer, exact density
    ("inertia fluid transfer/scheme explicit density rate", 2e-8, 250000),  # the paper's
])
def test_default_and_literal_schemes_share_the_steady_state(tmp_path, scheme, dt, steps):
    """Issue 6: the steady state does not depend on the scheme. Newton's quasi-static
    state of a dried tissue (every bead at P = -Pi, forces balanced) is left alone by the
    default scheme at the paper's time step and by the paper's literal scheme (fluid
    inertia, explicit Euler mass transfer, rate form of the density) at a time step below
    its damping limit, over the same 5 ms: A, P, EL and X/X0 stay within 1e-8 (issue 6
    asks for 1e-4), the pressure residual below 1e-9. (This shows the two schemes share
    this fixed point; relaxing to it from elsewhere is slow for both, see the creep in
    doc/results/validation.md.)"""
    from cgms import morphology, run, tissue
    from cgmstest import APPLE, XREF
    xy = tissue.rectangle(1.25e-3, 1.5e-3, XREF)  # the 86-bead calibration tissue
    tissue.write_data(tmp_path / "t.data", xy, 4 * XREF)
    lmp = run.open_lammps()
    try:
        lmp.commands_string(run.tissue_script(tmp_path / "t.data", APPLE, 0.3, method="newton"))
        assert run.solve_newton(lmp)["converged"]
        start = run.steady_state(lmp)
        # the same beads, now with the dynamics of the chosen scheme
        lmp.commands_string("\n".join([
            "unfix fluid",
            "pair_style cgms",
            f"pair_coeff * * {APPLE}",
            f"fix fluid all cgms/fluid dryness 0.3 {scheme}",
            "fix_modify fluid energy no",
            f"timestep {dt}",
            f"run {steps}"]))
        end = run.steady_state(lmp)
    finally:
        lmp.close()
    assert end["residual"] < 1e-9, end["residual"]
    a, b = morphology.measures(start["xy"]), morphology.measures(end["xy"])
    for key in ("area", "perimeter", "elongation"):  # measured: 3e-10 or less
        assert b[key] == pytest.approx(a[key], rel=1e-8), key
    assert end["moisture"] == pytest.approx(start["moisture"], rel=1e-8)


@pytest.mark.parametrize("scheme,dt", [
    ("", 1e-7),  # the default
    ("inertia fluid transfer/scheme explicit density rate", 2e-8),  # the paper's literal one
])
def test_both_schemes_relax_from_the_lattice_to_the_same_state_with_shape_stiffness(
        tmp_path, scheme, dt):
    """Issue 6, from elsewhere: with the cell-shape stiffness k_S 0.5 (an extension, off by
    default) the soft shear modes that make the paper's model creep are gone, and both
    schemes, started from the fresh lattice, relax to Newton's state of the same model:
    after 20 ms A, P, EL within 1e-6 (measured 1.3e-8, 30 ms: 1e-9; issue 6 asks for
    1e-4), residual below 1e-6."""
    from cgms import morphology, run, tissue
    from cgmstest import APPLE, XREF
    xy = tissue.rectangle(1.25e-3, 1.5e-3, XREF)  # the 86-bead calibration tissue
    tissue.write_data(tmp_path / "t.data", xy, 4 * XREF)
    lmp = run.open_lammps()
    try:
        lmp.commands_string(run.tissue_script(tmp_path / "t.data", APPLE, 0.3, method="newton",
                                              overrides="k_S 0.5"))
        assert run.solve_newton(lmp)["converged"]
        target = morphology.measures(run.steady_state(lmp)["xy"])
    finally:
        lmp.close()
    lmp = run.open_lammps()
    try:
        lmp.commands_string(run.tissue_script(tmp_path / "t.data", APPLE, 0.3, dt=dt,
                                              fix_args=scheme, overrides="k_S 0.5",
                                              steady=dict(max_steps=0)))
        lmp.command("unfix halt")  # a fixed simulated time, not the steady-state test
        lmp.command(f"run {int(round(0.02 / dt))}")
        end = run.steady_state(lmp)
    finally:
        lmp.close()
    assert end["residual"] < 1e-6, end["residual"]
    got = morphology.measures(end["xy"])
    for key in ("area", "perimeter", "elongation"):
        assert got[key] == pytest.approx(target[key], rel=1e-6), key
    # the run did move: the lattice is 10 % or more away from that state in area
    assert abs(morphology.measures(xy)["area"] / target["area"] - 1) > 0.1
