# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The dryness-dependent cell-shape stiffness k_S(s) = max(k_S s^n, k_S_floor) (material keys
k_S_exponent and k_S_floor, doc/pair_cgms.rst): the plugin's forces and energy against
reference.py on 1 and 2 ranks, for uniform and bead-by-bead dryness, with the floor binding
and not; n = 0 is the constant k_S and k_S_floor 0 the unfloored k_S s^n bit for bit; bad
values."""

import numpy as np
import pytest

import reference
from cgms import material, tissue
from cgmstest import (APPLE, CUTOFF, MAT, XREF, header, make_tissue, physics, read_dump,
                      run_lmp, run_tissue)

# turgor and perimeter off: the pair coefficient is then the cell-shape share alone, so
# the comparison checks k_S(s) to rounding (the full model is in test_reference.py)
PAIR = "turgor no perimeter no"
DUMP = ("dump d all custom 1 forces.dump id x y vx vy fx fy d_s\n"
        "dump_modify d format float %.17g sort id\n")


def plugin_run(folder, overrides, nprocs=1):
    """Forces (id order), positions, velocities, dryness and pe after 'run 0'."""
    script = (header(processors=nprocs) + physics(PAIR, "", overrides) + DUMP
              + "thermo_style custom step pe\nthermo_modify format float %.17g\nrun 0\n")
    out = run_lmp(folder, script, nprocs=nprocs).stdout.splitlines()
    row = out[[k for k, line in enumerate(out) if line.split()[:1] == ["Step"]][0] + 1]
    state = read_dump(folder / "forces.dump")
    state["pe"] = float(row.split()[1])
    return state


def oracle(state, mat):
    xy = np.c_[state["x"], state["y"]]
    v = np.c_[state["vx"], state["vy"]]
    s = state["d_s"]
    f, lj, _ = reference.pair_forces(xy, v, s, np.zeros_like(s), mat, CUTOFF,
                                     turgor=False, perimeter=False)
    return f, lj + reference.shape_energy(xy, s, mat, CUTOFF)


@pytest.mark.lammps
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("dryness", [(0.3, 1.0), 0.6])
def test_dryness_dependent_stiffness_matches_reference(tmp_path, nprocs, dryness):
    make_tissue(tmp_path, ncols=12, nrows=10, jitter=0.08, seed=11, s=dryness, vscale=1e-3)
    mat = dict(MAT, k_S=2.9, k_S_exponent=6.0)
    state = plugin_run(tmp_path, "k_S 2.9 k_S_exponent 6", nprocs)
    f, energy = oracle(state, mat)
    scale = np.abs(f).max()
    err = np.abs(np.c_[state["fx"], state["fy"]] - f).max()
    assert err < 1e-12 * scale, f"force error {err:.2e} of {scale:.2e}"
    assert state["pe"] == pytest.approx(energy, rel=1e-12)
    # the scaling is a real share of the force here: with a constant k_S the oracle's
    # forces differ by far more than the agreement above (k_S(0.6) = 0.047 k_S)
    constant, _ = oracle(state, dict(mat, k_S_exponent=0.0))
    assert np.abs(constant - f).max() > 0.1 * scale


# the floor the MFC's shear test gives (doc/calibration.md): k_S s^6 meets it at
# s = (0.14 / 3.4)^(1/6) = 0.588
FLOOR = "k_S 3.4 k_S_exponent 6 k_S_floor 0.14"
FLOOR_MAT = dict(MAT, k_S=3.4, k_S_exponent=6.0, k_S_floor=0.14)
CROSSOVER = (0.14 / 3.4) ** (1 / 6)


@pytest.mark.lammps
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("dryness", [0.3, 0.9, (0.3, 1.0)])
def test_floored_stiffness_matches_reference(tmp_path, nprocs, dryness):
    """The floor binds at s = 0.3, not at 0.9, and for some beads of the 0.3..1 spread."""
    tissue = make_tissue(tmp_path, ncols=12, nrows=10, jitter=0.08, seed=13, s=dryness,
                         vscale=1e-3)
    below = tissue["s"] < CROSSOVER
    if isinstance(dryness, tuple):
        assert 10 < below.sum() < tissue["n"] - 10   # both sides of the crossover
    state = plugin_run(tmp_path, FLOOR, nprocs)
    f, energy = oracle(state, FLOOR_MAT)
    scale = np.abs(f).max()
    err = np.abs(np.c_[state["fx"], state["fy"]] - f).max()
    assert err < 1e-12 * scale, f"force error {err:.2e} of {scale:.2e}"
    assert state["pe"] == pytest.approx(energy, rel=1e-12)
    # where the floor binds it is a real share of the force: without it the oracle's forces
    # differ by 10^10 times the agreement above (k_S(0.3) = 0.0025 N/m, not 0.14)
    unfloored, _ = oracle(state, dict(FLOOR_MAT, k_S_floor=0.0))
    if below.any():
        assert np.abs(unfloored - f).max() > 0.01 * scale
    else:
        assert np.array_equal(unfloored, f)


@pytest.mark.lammps
def test_floor_zero_and_exponent_zero_change_nothing(tmp_path):
    """k_S_floor 0 gives the bits of no k_S_floor line; with n = 0 a floor below k_S gives
    the bits of the constant k_S."""
    make_tissue(tmp_path, jitter=0.08, seed=14, s=(0.3, 1.0), vscale=1e-3)
    runs = {o: plugin_run(tmp_path, o) for o in (
        "k_S 3.4 k_S_exponent 6", "k_S 3.4 k_S_exponent 6 k_S_floor 0",
        "k_S 3.4", "k_S 3.4 k_S_floor 0.14")}
    for a, b in [("k_S 3.4 k_S_exponent 6", "k_S 3.4 k_S_exponent 6 k_S_floor 0"),
                 ("k_S 3.4", "k_S 3.4 k_S_floor 0.14")]:
        for column in ("fx", "fy", "pe"):
            assert np.array_equal(runs[a][column], runs[b][column]), (a, b, column)


@pytest.mark.lammps
def test_collapse_with_a_floor_names_the_dried_cells_stiffness(tmp_path):
    """The sharp step s = 1 | 0.2 on the 86-bead lattice: k_S(0.2) = 0.14 N/m (the floor) is
    below the 0.2-0.5 N/m this case needs (doc/calibration.md), the tissue collapses, and
    the error names k_S(s) and the floor, not the fresh k_S alone as the one to raise."""
    xy = tissue.hex_rectangle(10, 9, XREF, short_rows=True)
    pre = ("variable xc equal 0.5*(bound(all,xmin)+bound(all,xmax))\n"
           "variable s atom ternary(x<v_xc,1.0,0.2)")
    run = run_tissue(tmp_path, xy, dryness="v_s", steps=60000, pre=pre, coefficients=FLOOR)
    assert run.proc.returncode != 0
    assert "the tissue is collapsing" in run.error, run.error
    assert "max(k_S s^n, k_S_floor)" in run.error and "k_S_floor = 0.14 N/m" in run.error, \
        run.error


@pytest.mark.lammps
def test_exponent_zero_is_the_constant_stiffness(tmp_path):
    """n = 0 (given) and no k_S_exponent line give the same bits; n = 6 at a uniform
    s = 0.6 gives what a constant k_S 0.6^6 gives."""
    make_tissue(tmp_path, jitter=0.08, seed=12, s=(0.3, 1.0), vscale=1e-3)
    absent = plugin_run(tmp_path, "k_S 2.9")
    zero = plugin_run(tmp_path, "k_S 2.9 k_S_exponent 0")
    for column in ("fx", "fy", "pe"):
        assert np.array_equal(absent[column], zero[column]), column
    make_tissue(tmp_path, jitter=0.08, seed=12, s=0.6, vscale=1e-3)
    scaled = plugin_run(tmp_path, "k_S 2.9 k_S_exponent 6")
    constant = plugin_run(tmp_path, f"k_S {2.9 * 0.6 ** 6!r}")
    scale = np.abs(constant["fx"]).max()
    assert np.abs(scaled["fx"] - constant["fx"]).max() < 1e-13 * scale
    assert scaled["pe"] == pytest.approx(constant["pe"], rel=1e-13)


@pytest.mark.lammps
@pytest.mark.parametrize("value,message", [
    ("-1", "CGMS parameter k_S_exponent = -1 must be >= 0"),
    ("six", "value 'six' of parameter k_S_exponent is not a number"),
])
def test_bad_exponent_is_refused(tmp_path, value, message):
    make_tissue(tmp_path, s=0.8)
    script = header() + physics("", "", f"k_S 2.9 k_S_exponent {value}") + "run 0\n"
    proc = run_lmp(tmp_path, script, check=False)
    assert proc.returncode != 0
    assert "ERROR" in proc.stdout and message in proc.stdout, proc.stdout[-2000:]


@pytest.mark.lammps
@pytest.mark.parametrize("overrides,message", [
    ("k_S 3.4 k_S_floor -1", "CGMS parameter k_S_floor = -1 must be >= 0"),
    ("k_S 3.4 k_S_floor low", "value 'low' of parameter k_S_floor is not a number"),
    ("k_S 0.1 k_S_exponent 6 k_S_floor 0.14", "k_S_floor (0.14) must not exceed k_S (0.1)"),
    ("k_S_floor 0.14", "k_S_floor (0.14) must not exceed k_S (0)"),
])
def test_bad_floor_is_refused(tmp_path, overrides, message):
    make_tissue(tmp_path, s=0.8)
    script = header() + physics("", "", overrides) + "run 0\n"
    proc = run_lmp(tmp_path, script, check=False)
    assert proc.returncode != 0
    assert "ERROR" in proc.stdout and message in proc.stdout, proc.stdout[-2000:]


def test_python_reads_the_floor_by_the_plugins_rules(tmp_path):
    """cgms.material knows k_S_floor (optional, >= 0, not above k_S), as the plugin does."""
    text = open(APPLE).read()
    good = tmp_path / "good.cgms"
    good.write_text(text + "k_S 3.4\nk_S_exponent 6\nk_S_floor 0.14\n")
    assert material.read(good)["k_S_floor"] == 0.14
    assert "k_S_floor" not in material.read(APPLE)
    bad = tmp_path / "bad.cgms"
    bad.write_text(text + "k_S 0.1\nk_S_floor 0.14\n")
    with pytest.raises(ValueError, match=r"k_S_floor \(0.14\) must not exceed k_S \(0.1\)"):
        material.read(bad)
    with pytest.raises(ValueError, match=r"k_S_floor \(0.14\) must not exceed k_S \(0\)"):
        material.with_overrides(material.read(APPLE), "k_S_floor 0.14")
    with pytest.raises(ValueError, match="k_S_floor = -1 must be >= 0"):
        material.with_overrides(material.read(APPLE), "k_S 3.4 k_S_floor -1")


def test_python_reads_the_exponent_by_the_plugins_rules(tmp_path):
    """cgms.material knows k_S_exponent (optional, >= 0), as the plugin's table does."""
    text = open(APPLE).read()
    good = tmp_path / "good.cgms"
    good.write_text(text + "k_S 2.9\nk_S_exponent 6\n")
    assert material.read(good)["k_S_exponent"] == 6.0
    assert "k_S_exponent" not in material.read(APPLE)
    bad = tmp_path / "bad.cgms"
    bad.write_text(text + "k_S_exponent -1\n")
    with pytest.raises(ValueError, match="k_S_exponent = -1 must be >= 0"):
        material.read(bad)
