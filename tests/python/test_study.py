# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady-state sweeps: results, resuming, normalisation, target moisture, no overwriting."""

from datetime import datetime

import numpy as np
import pytest

from cgms import cli, folders, study, tissue
from cgmstest import APPLE, MAT, two_blocks

STEADY = dict(residual=1e-3, speed=1e-3, max_steps=200000)


@pytest.fixture
def small_tissue(tmp_path):
    xy = tissue.rectangle(0.9e-3, 0.8e-3, MAT["x_ref"])
    tissue.write_data(tmp_path / "tissue.data", xy, 3 * MAT["x_ref"])
    return tmp_path / "tissue.data"


@pytest.mark.lammps
def test_sweep_resumes_and_normalises(small_tissue, tmp_path, monkeypatch):
    out = tmp_path / "sweep"
    results = study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.4), progress=False,
                          steady=STEADY)
    assert [r["dryness"] for r in results] == [1.0, 0.4]
    assert all(r["converged"] for r in results)
    rows = study.table(results)
    assert rows[0]["A/A0"] == rows[0]["P/P0"] == rows[0]["EL/EL0"] == 1.0
    # dried tissue: less water, smaller and shorter outline
    assert rows[1]["X/X0"] < 0.4 and rows[1]["A/A0"] < 0.9 and rows[1]["P/P0"] < 0.97
    # a second sweep reads the finished levels back and runs nothing
    monkeypatch.setattr(study, "relax", lambda *a, **k: pytest.fail("level run again"))
    again = study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.4), progress=False,
                        steady=STEADY)
    assert np.array_equal(again[1]["xy"], results[1]["xy"])
    assert again[1]["moisture"] == results[1]["moisture"]
    # ... but not for other options: those results would be mixed with these
    with pytest.raises(folders.FolderError, match="another setup"):
        study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.4), progress=False)


@pytest.mark.lammps
def test_target_moisture_lands_on_target(small_tissue, tmp_path):
    found = study.target_moisture(small_tissue, APPLE, 0.6, tmp_path / "t", xtol=2e-3,
                                  steady=STEADY)
    assert 0.6 < found["initial"] < 1.0
    check = study.relax(small_tissue, APPLE, round(found["initial"], 4), tmp_path / "check",
                        steady=STEADY)
    assert abs(check["moisture"] - 0.6) < 5e-3, (found, check["moisture"])


def test_results_folder_is_never_reused(tmp_path):
    (tmp_path / "keep.txt").write_text("user data")
    with pytest.raises(folders.FolderError, match="not empty"):
        with folders.claim(tmp_path, "study"):
            pass
    assert (tmp_path / "keep.txt").read_text() == "user data"


@pytest.mark.lammps
def test_summary_tables_of_runs_within_one_second_keep_apart(tmp_path, monkeypatch):
    # a resume of finished levels ends within the second of the run before it: the second
    # table takes a new name instead of failing on (or overwriting) the first
    class Noon:
        @staticmethod
        def now():
            return datetime(2026, 1, 1, 12, 0, 0)
    monkeypatch.setattr(folders, "datetime", Noon)
    names = []
    for _ in range(3):
        path = folders.summary_path(tmp_path)
        study.write_csv([{"s": 1.0}], path)
        names.append(path.name)
    assert names == ["summary-120000.csv", "summary-120000-2.csv", "summary-120000-3.csv"]


def test_quasistatic_state_is_a_steady_state_of_the_dynamics(small_tissue, tmp_path):
    """doc/model.md: at steady state P = -Pi, so the geometry solves the force balance with
    the pressures fixed. The FIRE solution must be at rest under the full dynamics (mass
    transfer, damping, everything): started there, the beads must not move."""
    qs = study.relax(small_tissue, APPLE, 0.4, tmp_path / "qs", method="quasistatic")
    assert qs["converged"] and qs["residual"] < 1e-9
    start = tmp_path / "from_qs.data"
    tissue.write_data(start, qs["xy"], 5 * MAT["x_ref"])
    dyn = study.relax(start, APPLE, 0.4, tmp_path / "dyn",
                      steady=dict(residual=1e-12, speed=1e-12, max_steps=50000))
    moved = np.abs(dyn["xy"] - qs["xy"]).max() / MAT["x_ref"]
    assert moved < 1e-3, moved
    assert abs(dyn["moisture"] - qs["moisture"]) < 1e-4
    # and the dynamics from the built lattice heads there: closer with a tighter threshold
    loose = study.relax(small_tissue, APPLE, 0.4, tmp_path / "loose",
                        steady=dict(residual=1e-3, speed=1e-3, max_steps=400000))
    tight = study.relax(small_tissue, APPLE, 0.4, tmp_path / "tight",
                        steady=dict(residual=1e-5, speed=1e-5, max_steps=2000000))
    gap = [np.abs(r["xy"] - qs["xy"]).max() for r in (loose, tight)]
    assert gap[1] < gap[0], gap


def test_sensitivity_settings_scale_the_named_parameter():
    from cgms.calibration import sensitivity
    mat = {"k_T": 1e-10, "k_PA": 2.0, "beta_a": 1.0311, "beta_b": 0.1088}
    assert sensitivity.setting_args(mat, "k_T", 10.0) == ("", "k_T 1e-09")
    assert sensitivity.setting_args(mat, "beta", None) == ("periphery no", "")
    pair, over = sensitivity.setting_args(mat, "beta", 1.1)
    assert pair == "" and over.split()[0::2] == ["beta_a", "beta_b"]
    assert float(over.split()[1]) == 1.1 * 1.0311


@pytest.mark.lammps
def test_newton_level_matches_fire_and_logs_progress(small_tissue, tmp_path):
    """--method newton through the study: converged, the same X/X0 and shape as the FIRE
    solve, a dump for OVITO and a progress log with one line per iteration. Tolerance
    from the stopping rules (tests/README.md, "Tolerances across configurations"): FIRE's
    largest bead force and Newton's largest component below 1e-13 N leave residuals of at
    most (sqrt(n) + sqrt(2n)) 1e-13 = 1.4e-12 N (n = 33), which move the area by at most
    |H+ grad A| / A = 8.6e4 /N times that, 1.2e-7, the perimeter (1.9e5 /N) 2.6e-7, and
    the moisture, set by the bead areas, less: asserted 1e-6."""
    from cgms import morphology
    newton = study.relax(small_tissue, APPLE, 0.4, tmp_path / "n", method="newton")
    fire = study.relax(small_tissue, APPLE, 0.4, tmp_path / "f", method="quasistatic",
                       steady=dict(max_steps=100000))
    assert newton["converged"] and newton["fmax"] < 1e-13 and fire["converged"]
    assert newton["moisture"] == pytest.approx(fire["moisture"], rel=1e-6)
    a, b = morphology.measures(newton["xy"]), morphology.measures(fire["xy"])
    for key in ("area", "perimeter"):
        assert a[key] == pytest.approx(b[key], rel=1e-6)
    assert (tmp_path / "n" / "tissue.s0.4.dump").stat().st_size > 0
    lines = (tmp_path / "n" / "newton.s0.4.log").read_text().splitlines()
    assert len(lines) == newton["steps"] + 1 and lines[-1].startswith("newton")
    # max_steps bounds the iterations, and the result says it did not converge
    capped = study.relax(small_tissue, APPLE, 0.4, tmp_path / "c", method="newton",
                         steady=dict(max_steps=2))
    assert capped["steps"] == 2 and not capped["converged"] and capped["fmax"] > 1e-13


@pytest.mark.lammps
def test_command_line_material_overrides(tmp_path, capsys):
    """--set replaces material parameters for every level (here the extension k_S, which
    moves the dried beads), and is checked before anything runs: a bad one ends the command
    with exit status 2 (a bad option), not a traceback, and creates nothing."""
    common = ["study", "--width", "0.9", "--height", "0.8", "--dryness", "0.4"]
    assert cli.main(common + ["--out", str(tmp_path / "plain")]) == 0
    assert cli.main(common + ["--set", "k_S 0.5", "--out", str(tmp_path / "shape")]) == 0
    assert "k_S 0.5" in (tmp_path / "shape" / "tissue" / "log.s0.4.lammps").read_text()
    plain = np.load(tmp_path / "plain" / "tissue" / "level.s0.4.npy")
    shape = np.load(tmp_path / "shape" / "tissue" / "level.s0.4.npy")
    assert np.abs(plain - shape).max() > 1e-3 * MAT["x_ref"]
    with pytest.raises(SystemExit) as stop:
        cli.main(common + ["--set", "k_S soft", "--out", str(tmp_path / "bad")])
    assert stop.value.code == 2 and "value 'soft' of k_S is not a number" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()
    assert cli.main(common + ["--set", "k_X 1", "--out", str(tmp_path / "unknown")]) == 2
    assert "unknown CGMS parameter 'k_X'" in capsys.readouterr().err
    assert not (tmp_path / "unknown").exists()


def test_material_overrides_rederive_the_reference_cell():
    """--set 'diameter ...' changes x_ref and, like the plugin (r0 = 0 selects x_ref), the
    default LJ radius with it; a given r0 is kept; a new name (k_S) is added."""
    from cgms import material
    mat = material.read(APPLE)
    bigger = material.with_overrides(mat, "diameter 1.6e-4 k_S 0.5")
    assert bigger["x_ref"] > mat["x_ref"]
    assert bigger["r0"] == bigger["x_ref"] and bigger["k_S"] == 0.5
    fixed = material.with_overrides(mat, "r0 1e-4 diameter 1.6e-4")
    assert fixed["r0"] == 1e-4
    with pytest.raises(ValueError, match="pairs"):
        material.with_overrides(mat, "k_S")


@pytest.mark.lammps
def test_folded_steady_state_is_refused(small_tissue, tmp_path):
    """A minimiser lands on a tissue folded onto itself without a word (the dynamics stops
    on it): the first apple-mfc fit (against the LJ-lamella MFC reference) at s = 0.4,
    below the range it was fitted in, folds every bead into its second shell. The level
    must stop with the cause, not print 'converged'."""
    first_fit = ("k_T 1.2105476322578275e-11 k_PA 0.009739309213328667 beta_a "
                 "1.2678326862424814 beta_b 0.004352216119618972 k_S 0.34106708264650915")
    with pytest.raises(study.LammpsError, match=r"folded onto itself: bead \d+ has \d+ neigh"):
        study.relax(small_tissue, APPLE, 0.4, tmp_path / "qs", method="quasistatic",
                    overrides=first_fit)
    healthy = study.relax(small_tissue, APPLE, 0.4, tmp_path / "ok", method="quasistatic")
    assert healthy["converged"]


@pytest.mark.lammps
def test_a_level_in_pieces_is_refused_by_every_method(tmp_path, monkeypatch):
    """The dynamics reaches a steady state on a tissue in pieces without a word, as a
    minimiser does: two sound blocks 3 spacings apart (no pair links them) settle each on
    its own. A level of every method, and the --fallback dynamics path, must stop with
    the cause instead of printing 'converged'; one block alone is a level."""
    for name, xy in zip(("one", "two"), two_blocks()):
        tissue.write_data(tmp_path / f"{name}.data", xy, 3 * MAT["x_ref"])
    came_apart = r"s = 1: LAMMPS stopped: the steady state came apart: 2 pieces"
    for method in ("dynamics", "quasistatic", "newton"):
        with pytest.raises(study.LammpsError, match=came_apart):
            study.relax(tmp_path / "two.data", APPLE, 1.0, tmp_path / method, method=method,
                        steady=STEADY)
    # the fallback: the quasi-static solve stops, the dynamics after it ends in pieces
    solve = study.relax

    def stopped(*args, method="dynamics", **kwargs):
        if method != "dynamics":
            raise study.LammpsError(1.0, "stopped to test the fallback", "log")
        return solve(*args, method=method, **kwargs)

    monkeypatch.setattr(study, "relax", stopped)
    with pytest.raises(study.LammpsError, match=came_apart):
        study.sweep(tmp_path / "two.data", APPLE, tmp_path / "fallback", levels=(1.0,),
                    progress=False, fallback="dynamics", method="quasistatic", steady=STEADY)
    assert not list((tmp_path / "fallback").glob("level.*"))    # no result written
    monkeypatch.undo()
    one = study.relax(tmp_path / "one.data", APPLE, 1.0, tmp_path / "one", method="dynamics",
                      steady=STEADY)
    assert one["converged"]


def test_write_csv_columns_and_never_overwrites(tmp_path):
    """The one CSV writer of the tables (study, sensitivity, cgms dry, cgms mfc): chosen
    columns in order, a missing value left empty, an existing file kept."""
    path = tmp_path / "t.csv"
    study.write_csv([dict(a=1, b=0.5, c="x"), dict(a=2, c="y")], path, columns=("c", "b"))
    assert path.read_text().splitlines() == ["c,b", "x,0.5", "y,"]
    with pytest.raises(FileExistsError, match="t.csv exists"):
        study.write_csv([dict(a=3)], path)
    assert path.read_text().splitlines()[0] == "c,b"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]   # no temporary file left


@pytest.mark.lammps
def test_a_run_whose_neighbour_list_grows_gets_the_forces_of_a_first_run(small_tissue):
    """Newton (cgms.solve) evaluates forces by one 'run 0' per trial position. A later run
    whose list holds more pairs than the first (here: the tissue squeezed by 25 %, which brings the second shell into the list) must give
    the forces of a LAMMPS that runs there first. Fix cgms/fluid once sized its per-pair
    distance array only when neighbor->ncalls changed, which LAMMPS resets at every run's
    setup: the squeezed run overran it (heap corruption; Newton with apple-mfc.cgms at
    s = 0.6 ended in a segfault)."""
    from cgms import run, solve

    def instance():
        lmp = run.open_lammps()
        script = run.tissue_script(small_tissue, APPLE, 0.4, method="newton")
        lmp.commands_string(script.replace("\nrun 0\n", "\n"))   # set up, not run
        return lmp, solve.LammpsForces(lmp)

    lmp, forces = instance()
    xy = forces.positions()
    squeezed = xy.mean(axis=0) + 0.75 * (xy - xy.mean(axis=0))
    forces(xy)
    energy, after = forces(squeezed)
    lmp.close()
    lmp, forces = instance()
    want_energy, want = forces(squeezed)
    lmp.close()
    assert np.abs(want).max() > 0
    assert np.abs(after - want).max() <= 1e-12 * np.abs(want).max()
    assert energy == pytest.approx(want_energy, rel=1e-12)


def test_fallback_keeps_the_users_steady_thresholds(monkeypatch, tmp_path):
    """The dynamics fallback replaces the method, time step and step cap, not the user's
    --residual and --speed (it once ran with the defaults whatever was asked)."""
    calls = []

    def relax(data, material, dryness, out, **kwargs):
        calls.append(kwargs)
        if kwargs["method"] != "dynamics":
            raise study.LammpsError(dryness, "ERROR: Out of range atoms", None)
        return dict(converged=True)

    monkeypatch.setattr(study, "relax", relax)
    steady = dict(residual=2e-4, speed=5e-4, max_steps=1000)
    result, note = study.relax_or_fallback("t.data", "m.cgms", 0.6, tmp_path, steady=steady)
    assert note == "ERROR: Out of range atoms" and result["converged"]
    assert calls[0]["steady"] == steady
    assert calls[1]["method"] == "dynamics" and calls[1]["dt"] == study.FALLBACK["dt"]
    assert calls[1]["steady"] == dict(steady, max_steps=study.FALLBACK["steady"]["max_steps"])
