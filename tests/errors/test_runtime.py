# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""LAMMPS errors that name the real cause (issue 12, sections 2 and 3): each case once
stopped with advice about something else (the time step, 'isolated allow', a collapsing
tissue) or ran on with a wrong state. doc/errors.md tables what the user sees."""

import numpy as np
import pytest

from cgmstest import header, make_tissue, physics, run_lmp

pytestmark = pytest.mark.lammps


def first_error(proc):
    assert proc.returncode in (0, 1), f"crash (status {proc.returncode}):\n{proc.stdout[-3000:]}"
    return next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")


@pytest.fixture
def folder(tmp_path):
    make_tissue(tmp_path, ncols=4, nrows=4, s=0.8)
    return tmp_path


def error_of(folder, pair_args="", fix_args="", overrides="", body="run 10\n", pre=""):
    script = header() + pre + physics(pair_args, fix_args, overrides) + body
    proc = run_lmp(folder, script, check=False)
    assert proc.returncode != 0, proc.stdout[-2000:]
    return first_error(proc)


def test_negative_time_step(folder):
    error = error_of(folder, body="timestep -1e-7\nrun 10\n")
    assert "requires a positive time step (timestep is -1e-07 s)" in error, error


def test_bead_created_during_run(folder):
    """fix deposit adds a bead the fix never initialised: say so, not 'mass transfer'"""
    body = ("region top block 0 6e-4 7e-4 8e-4 -1e-4 1e-4\n"
            "fix dep all deposit 1 1 2 4711 region top near 1e-4 attempt 200\n"
            "run 10\n")
    error = error_of(folder, body=body)
    assert "appeared during the run" in error and "fix deposit" in error, error


def add_bead(folder, xy):
    """append bead 17 at xy to the 16-bead tissue (and a dryness for it)"""
    data = (folder / "tissue.data").read_text().replace("16 atoms", "17 atoms")
    (folder / "tissue.data").write_text(data.rstrip() + f"\n17 1 {xy[0]:.17g} {xy[1]:.17g} 0.0\n")
    with open(folder / "state.in", "a") as f:
        f.write("set atom 17 d_s 0.8\n")


def bead_position(folder, ident):
    for line in (folder / "tissue.data").read_text().splitlines():
        words = line.split()
        if len(words) == 5 and words[0] == str(ident) and words[1] == "1":
            return float(words[2]), float(words[3])
    raise AssertionError(f"bead {ident} not in the data file")


def test_coincident_beads(folder):
    add_bead(folder, bead_position(folder, 6))
    error = error_of(folder)
    assert "beads 6 and 17 are 0 m apart at setup" in error \
        or "beads 17 and 6 are 0 m apart at setup" in error, error
    assert "at the same position" in error


def test_beads_closer_than_the_pectin_layer(folder):
    x, y = bead_position(folder, 6)
    add_bead(folder, (x + 5e-6, y))
    error = error_of(folder)
    assert "apart at setup, closer than the pectin layer d_p = 8e-06 m" in error, error
    assert "6" in error and "17" in error


def test_non_finite_velocity(folder):
    pre = "variable big atom 1e300*1e300\nset atom 3 vx v_big\n"
    error = error_of(folder, pre=pre)
    assert "bead 3 has a non-finite velocity (vx = inf) at setup" in error, error


def test_beta_a_not_positive(folder):
    error = error_of(folder, overrides="beta_a -1")
    assert "CGMS parameter beta_a = -1 must be > 0" in error, error


def test_beta_not_positive_at_the_dryness(folder):
    """beta(0.8) > 0 but beta(0.3) = 1.0311 + ln 0.3 < 0 with beta_b 1"""
    lowest = np.exp(-1.0311 / 1.0)
    error = error_of(folder, overrides="beta_b 1",
                     body="fix fl all cgms/fluid dryness 0.3\nrun 10\n")
    assert "periphery factor beta = beta_a + beta_b ln s" in error, error
    assert f"needs a dryness above exp(-beta_a/beta_b) = {lowest:.4g}" in error, error


@pytest.mark.parametrize("pair_args,overrides", [("cutoff 1e-3", ""), ("", "pectin 2e-4")],
                         ids=["cutoff", "pectin"])
def test_cutoff_wrong_from_the_start(folder, pair_args, overrides):
    """30-45 neighbours at step 0: the cutoff does not fit the spacing, not 'collapsing'"""
    error = error_of(folder, pair_args=pair_args, overrides=overrides)
    assert "neighbours within the pair cutoff" in error and "at setup" in error, error
    assert "collapsing" not in error


@pytest.mark.parametrize("dryness", ["1e-6", "1e-300"])
def test_dryness_below_the_lj_radius_limit(folder, dryness):
    lowest = np.exp(-1 / 0.0809)
    error = error_of(folder, body=f"fix fl all cgms/fluid dryness {dryness}\nrun 10\n")
    assert f"at dryness {float(dryness):.6g} the LJ radius r0 (1 + lj_slope ln s)" in error, error
    assert f"needs a dryness above exp(-1/lj_slope) = {lowest:.4g}" in error, error


def test_low_dryness_from_a_fresh_tissue(folder):
    """s = 0.05 on a fresh tissue: the dryness-scaled cutoff is below the spacing; the error
    says so (and what a fresh tissue allows) instead of only 'use isolated allow'"""
    error = error_of(folder, body="fix fl all cgms/fluid dryness 0.05\nrun 10\n")
    assert "has no neighbour within the pair cutoff" in error, error
    assert "at dryness 0.05 the cutoff is" in error and "a fresh tissue keeps its neighbours" \
        in error, error


def test_minimize_with_lammps_default_dmax(folder):
    """LAMMPS's default dmax 0.1 (m in SI units): the fix bounds it, says so, and cg
    converges"""
    script = header() + physics() + "minimize 0 1e-10 500 5000\n"
    proc = run_lmp(folder, script, check=False)
    assert proc.returncode == 0, first_error(proc)
    warning = next(line for line in proc.stdout.splitlines() if "min_modify dmax" in line)
    assert "set min_modify dmax ~1e-6" in warning
    assert "Stopping criterion = force tolerance" in proc.stdout \
        or "Stopping criterion = energy tolerance" in proc.stdout, proc.stdout[-2000:]


@pytest.mark.lammps
def test_minimize_warns_when_it_ends_on_a_folded_tissue(tmp_path):
    """A LAMMPS script's own minimize lands on a tissue folded onto itself without a word
    unless the fix says so at its end (the first apple-mfc fit, against the LJ-lamella MFC
    reference, folds every bead into its second shell at s = 0.4; apple at the same s stays
    a hexagonal tissue)."""
    from cgms import run, tissue
    from cgmstest import MAT, PLUGIN, ROOT

    data = tmp_path / "tissue.data"
    tissue.write_data(data, tissue.rectangle(0.9e-3, 0.8e-3, MAT["x_ref"]), 3 * MAT["x_ref"])
    seen = {}
    first_fit = ("k_T 1.2105476322578275e-11 k_PA 0.009739309213328667 beta_a "
                 "1.2678326862424814 beta_b 0.004352216119618972 k_S 0.34106708264650915")
    for name, overrides in (("apple", ""), ("apple-mfc", first_fit)):
        folder = tmp_path / name
        folder.mkdir()
        script = f"plugin load {PLUGIN}\n" + run.tissue_script(
            data, ROOT / "potentials" / "apple.cgms", 0.4, method="quasistatic",
            overrides=overrides)
        seen[name] = run_lmp(folder, script).stdout
    assert "minimize ended on a tissue folded onto itself" in seen["apple-mfc"]
    assert "folded" not in seen["apple"]


@pytest.mark.lammps
def test_folded_refuses_a_tissue_in_pieces(tmp_path):
    """run.folded, which a study calls on every level's steady state, names a
    tissue that came apart (a minimiser ends on one without a word: FIRE left a 105-bead
    tissue in 11 pieces with lj_slope at its bound). Two blocks 3 spacings apart, each a
    sound hexagonal tissue, are refused; one block is not."""
    from cgms import run, tissue
    from cgmstest import MAT, ROOT, new_lammps, two_blocks, working_directory

    block, apart = two_blocks()
    seen = {}
    for name, xy in (("one", block), ("two", apart)):
        folder = tmp_path / name
        folder.mkdir()
        tissue.write_data(folder / "tissue.data", xy, 3 * MAT["x_ref"])
        lmp = new_lammps()
        with working_directory(folder):
            lmp.commands_string(run.tissue_script(folder / "tissue.data",
                                                  ROOT / "potentials" / "apple.cgms", 1.0,
                                                  method="newton"))
        seen[name] = run.folded(lmp)
        lmp.close()
    assert seen["one"] is None
    assert seen["two"].startswith(f"the steady state came apart: 2 pieces, {len(block)} of "
                                  f"{len(apart)} beads away from the largest one"), seen["two"]
