# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Sweeps along a drying ramp (``start="previous"``, ``cgms study --start previous``): each
level starts from the previous level's steady state, not from the built lattice."""

import numpy as np
import pytest

from cgms import cli, folders, morphology, positions, study, tissue
from cgmstest import APPLE, MAT

#: apple with about apple-mfc's calibrated values (a tissue that shrinks like the MFC's) and
#: an LJ radius law steep enough that the cutoff at s = 0.4, 1.35 (1 + 0.3 ln 0.4) x_ref =
#: 0.979 x_ref, no longer reaches across the built lattice (doc/calibration.md, "Five
#: levels"); the steady state at s = 0.6 (spacing about 0.77 x_ref) it still holds
STEEP = "k_T 4e-11 k_PA 0.035 beta_a 1.04 beta_b 0.02 turgid_ratio 1.03 lj_slope 0.3"


@pytest.fixture
def small_tissue(tmp_path):
    xy = tissue.rectangle(0.9e-3, 0.8e-3, MAT["x_ref"])
    tissue.write_data(tmp_path / "tissue.data", xy, 3 * MAT["x_ref"])
    return tmp_path / "tissue.data"


def ramp(data, out, levels=(1.0, 0.6, 0.4), **kwargs):
    return study.sweep(data, APPLE, out, levels=levels, progress=False, start="previous",
                       method="quasistatic", overrides=STEEP, **kwargs)


@pytest.mark.lammps
def test_ramp_starts_each_level_from_the_previous_steady_state(small_tissue, tmp_path):
    # from the built lattice s = 0.4 has no neighbours within the cutoff at step 0
    with pytest.raises(study.LammpsError, match="no neighbour within the pair cutoff.* step 0:"):
        study.relax(small_tissue, APPLE, 0.4, tmp_path / "built", method="quasistatic",
                    overrides=STEEP)
    # along the ramp it converges; levels in any order run wettest first; a trajectory
    # frame at the start of each run shows where it started
    out = tmp_path / "ramp"
    results = ramp(small_tissue, out, levels=(0.4, 1.0, 0.6), dump_every=10 ** 6)
    assert [r["dryness"] for r in results] == [1.0, 0.6, 0.4]
    assert all(r["converged"] for r in results)
    assert [r["start"] for r in results] == ["built", "s1", "s0.6"]
    for before, r in zip([None] + results[:-1], results):
        first = morphology.read_dump(f"{study.dump_file(out, r)}.traj")[0]
        assert first["timestep"] == 0
        if before is None:
            continue
        # the start is the previous level's steady state (dump: 10 significant digits) ...
        assert np.abs(first["xy"] - before["xy"]).max() < 1e-9 * MAT["x_ref"]
        # ... and the result moved on from it: the tissue shrinks further
        assert np.abs(r["xy"] - before["xy"]).max() > 0.01 * MAT["x_ref"]
    rows = study.table(results)
    assert rows[2]["A/A0"] < rows[1]["A/A0"] < 0.7
    # the level's record and its folder's setup say so
    assert folders.read_json(out / "level.s0.4.json")["start"] == "s0.6"
    assert folders.read_json(out / "sweep.json")["start"] == "previous"


@pytest.mark.lammps
def test_ramp_resumes_and_refuses_other_starts(small_tissue, tmp_path, monkeypatch):
    out = tmp_path / "ramp"
    first = ramp(small_tissue, out)
    # a resume with the same levels reads them back and runs nothing
    monkeypatch.setattr(study, "relax", lambda *a, **k: pytest.fail("level run again"))
    again = ramp(small_tissue, out)
    assert [np.array_equal(a["xy"], b["xy"]) for a, b in zip(first, again)] == [True] * 3
    # s = 0.4 was started from s = 0.6: without 0.6 it would start from s = 1
    with pytest.raises(folders.FolderError, match="s = 0.4 was started from s0.6.*from s1"):
        ramp(small_tissue, out, levels=(1.0, 0.4))
    # another start is another setup, either way
    with pytest.raises(folders.FolderError, match="another setup.*start: 'previous' there, "
                                                  "None now"):
        study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.6, 0.4), progress=False,
                    method="quasistatic", overrides=STEEP)
    monkeypatch.undo()
    built = tmp_path / "built"
    study.sweep(small_tissue, APPLE, built, levels=(1.0,), progress=False,
                method="quasistatic", overrides=STEEP)
    with pytest.raises(folders.FolderError, match="start: None there, 'previous' now"):
        ramp(small_tissue, built, levels=(1.0,))
    with pytest.raises(ValueError, match="start must be one of built, previous"):
        study.sweep(small_tissue, APPLE, tmp_path / "x", start="last")


@pytest.mark.lammps
def test_ramp_stops_before_starting_from_an_unconverged_level(small_tissue, tmp_path):
    out = tmp_path / "ramp"
    # 20 FIRE iterations do not reach the steady state at s = 1
    with pytest.raises(study.RampError, match="s = 1 did not reach its steady state.*start "
                                              "s = 0.6 from it"):
        ramp(small_tissue, out, steady=dict(max_steps=20))
    # the unconverged level is kept (its table says so); nothing started from it
    assert folders.read_json(out / "level.s1.json")["converged"] is False
    assert not (out / "level.s0.6.json").exists()
    # the last level may stay unconverged: nothing starts from it
    last = ramp(small_tissue, tmp_path / "one", levels=(1.0,), steady=dict(max_steps=20))
    assert not last[0]["converged"]


@pytest.mark.lammps
def test_ramp_needs_the_dump_of_the_previous_level(small_tissue, tmp_path, monkeypatch):
    # ... to run a level, not to read finished ones back
    whole = tmp_path / "whole"
    first = ramp(small_tissue, whole, levels=(1.0, 0.6))
    (whole / "tissue.s1.dump").unlink()
    with monkeypatch.context() as m:
        m.setattr(study, "relax", lambda *a, **k: pytest.fail("level run again"))
        again = ramp(small_tissue, whole, levels=(1.0, 0.6))
    assert np.array_equal(again[1]["xy"], first[1]["xy"])
    out = tmp_path / "ramp"
    ramp(small_tissue, out, levels=(1.0,))
    (out / "tissue.s1.dump").unlink()
    with pytest.raises(study.RampError, match="tissue.s1.dump, the steady state s = 0.6 "
                                              "starts from .* is missing"):
        ramp(small_tissue, out, levels=(1.0, 0.6))


@pytest.mark.lammps
def test_default_start_is_the_built_lattice_and_not_recorded(small_tissue, tmp_path):
    """Folders of before (no 'start' in sweep.json) resume as they were; every level of the
    default starts from the built lattice."""
    out = tmp_path / "built"
    results = study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.6), progress=False,
                          method="quasistatic", dump_every=10 ** 6)
    assert "start" not in folders.read_json(out / "sweep.json")
    assert "start" not in folders.read_json(out / "level.s0.6.json")
    built = positions.read_data(small_tissue)["xy"]
    for r in results:
        first = morphology.read_dump(f"{study.dump_file(out, r)}.traj")[0]
        assert np.abs(first["xy"] - built).max() < 1e-9 * MAT["x_ref"]
    explicit = study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.6), progress=False,
                           method="quasistatic", dump_every=10 ** 6, start="built")
    assert np.array_equal(explicit[1]["xy"], results[1]["xy"])


@pytest.mark.lammps
def test_study_command_line_start_previous(tmp_path, capsys):
    out = tmp_path / "cli"
    args = ["study", "--width", "0.9", "--height", "0.8", "--set", STEEP, "--dryness",
            "1,0.6,0.4", "--out", str(out)]
    assert cli.main(args) == 1     # from the built lattice s = 0.4 stops at step 0
    err = capsys.readouterr().err
    assert "s = 0.4: bead" in err and "is beyond the interaction cutoff" in err, err
    assert "--start previous dries the levels in turn" in err
    assert "fallback" not in err   # the dynamics stops there too: not run, not advised
    assert cli.main(args + ["--start", "previous", "--resume"]) == 1
    assert "start: None there, 'previous' now" in capsys.readouterr().err
    ramped = tmp_path / "ramped"
    args[-1] = str(ramped)
    assert cli.main(args + ["--start", "previous"]) == 0
    table = capsys.readouterr().out
    assert table.count(" yes") == 3 and "0.40" in table


@pytest.mark.lammps
def test_dynamics_ramp_starts_with_the_fluid_in_osmotic_balance(small_tissue, tmp_path):
    """From the built lattice every bead starts at its reference density s rho0, i.e.
    P = s P_f = -s Pi_f: no water moves at step 0. A ramp's start must be the same, in the
    smaller cells it starts from (else the reference cell's water, crowded into them, starts
    far above |Pi_f|: residual 36 here at s = 0.6 from s = 1, 4906 at 0.4 from 0.6)."""
    out = tmp_path / "ramp"
    results = study.sweep(small_tissue, APPLE, out, levels=(1.0, 0.6), progress=False,
                          start="previous", method="dynamics", overrides=STEEP,
                          dump_every=10 ** 6)
    assert all(r["converged"] for r in results)
    first = morphology.read_dump(f"{study.dump_file(out, results[1])}.traj",
                                 columns="pressure")[0]
    osmotic = 0.6 * -MAT["Pi_f"]
    assert np.allclose(first["columns"]["pressure"], osmotic, rtol=1e-9, atol=0)
    # and it started from s = 1's steady state, not the built lattice
    assert np.abs(first["xy"] - results[0]["xy"]).max() < 1e-9 * MAT["x_ref"]


@pytest.mark.lammps
def test_calibration_runner_ramp_matches_the_study_ramp(small_tissue, tmp_path):
    """cgms.pool's ramp (fit.py --start previous): the levels of one parameter vector in
    sequence, each from the previous one's steady state; the same states as the study's."""
    from cgms.calibration import calibrate
    from cgms import pool
    levels = (1.0, 0.6, 0.4)
    swept = ramp(small_tissue, tmp_path / "study", levels=levels)
    (tmp_path / "fit").mkdir()
    (tmp_path / "built").mkdir()
    runner = pool.Runner(tmp_path / "fit", small_tissue, APPLE, "", 1, lambda line: None,
                         ramp=(0.4, 1.0, 0.6))
    try:
        records = runner.get([(s, STEEP) for s in (0.4, 1.0, 0.6)])
    finally:
        runner.close()
    assert [r["level"] for r in records] == [0.4, 1.0, 0.6]
    assert not any("error" in r for r in records), records
    for r in records:
        study_xy = next(q["xy"] for q in swept if q["dryness"] == r["level"])
        assert np.abs(np.array(r["xy"]) - study_xy).max() < 1e-12 * MAT["x_ref"] + 1e-15
    assert folders.read_json(tmp_path / "fit" / pool.SETUP)["ramp"] == [1.0, 0.6, 0.4]
    # without the ramp s = 0.4 has no steady state (every bead isolated at step 0)
    built = pool.Runner(tmp_path / "built", small_tissue, APPLE, "", 1, lambda line: None)
    try:
        rec = built.get([(0.4, STEEP)])[0]
    finally:
        built.close()
    assert "no neighbour within the pair cutoff" in rec["error"]
    refs = {}
    for q in swept[:2]:
        refs[q["dryness"]] = tmp_path / f"ref.{study.level_name(q['dryness'])}.txt"
        positions.write_centroids(refs[q["dryness"]], q["xy"])
    with pytest.raises(ValueError, match="not beta per level"):
        calibrate.calibrate(small_tissue, APPLE, refs, tmp_path / "c", parameters=["beta@*"],
                            level_start="previous")


def test_fit_script_passes_the_ramp_and_lifts_the_lj_slope_bound(tmp_path, monkeypatch):
    """studies/calibration/fit.py --start previous: every fit is asked for a ramp, and
    lj_slope may go where the LJ radius at the driest level is half of r0, (1 - 0.5) /
    -ln 0.3 = 0.4153, instead of where the cutoff still holds the built lattice, (1 -
    1.01/1.35) / -ln 0.3 = 0.2092. cgms.calibration.calibrate is replaced by a recorder."""
    import math
    import sys
    from cgmstest import ROOT
    sys.path.insert(0, str(ROOT / "studies" / "calibration"))
    import fit
    seen = []

    def recorder(data, material, references, out, parameters, start=None, bounds=None,
                 **kwargs):
        seen.append(dict(kwargs, bounds=bounds))
        return {"parameters": {k: 1.0 for k in parameters}, "stderr": {k: 0.0 for k in
                parameters}, "rmsd": {s: 0.0 for s in references}, "seconds": 0.0,
                "on_bound": [], "correlation": [[0.0] * len(parameters)] * len(parameters),
                "material_file": None}

    monkeypatch.setattr(fit.calibrate, "calibrate", recorder)
    monkeypatch.chdir(ROOT)
    args = ["--levels", "1,0.8,0.6,0.4,0.3", "--also", "lj_slope", "--lj-slope", "0.3",
            "--direct", "--without-kS", "--install-fit", "paper", "--out", str(tmp_path)]
    with pytest.raises(SystemExit, match="lj_slope 0.3: .* must be in \\[0, 0.2092\\)"):
        fit.main(args)
    assert fit.main(args + ["--start", "previous"]) == 0
    assert seen[0]["level_start"] == "previous"
    lo, hi = seen[0]["bounds"]["lj_slope"]
    assert hi * 0.3 == pytest.approx(0.5 / -math.log(0.3), rel=1e-12)
    assert 0.5 / -math.log(0.3) > 0.375 > (1 - 1.01 / 1.35) / -math.log(0.3)


@pytest.mark.lammps
def test_newton_and_fire_ramps_land_on_the_same_states(small_tissue, tmp_path):
    """Two solvers of the same steady-state equations along the same ramp (measured: 1e-7
    x_ref apart at s = 0.6 and 0.4, 2e-6 at s = 1). The tolerance is the stopping rules'
    (tests/README.md, "Tolerances across configurations"): FIRE leaves every bead's force
    below 1e-13 N and Newton every component, (sqrt(n) + sqrt(2n)) 1e-13 = 1.4e-12 N
    together (n = 33), which moves a bead by at most that times the largest block row of
    the inverse stiffness (rigid motions removed; 9.5e6 x_ref/N at s = 1, the softest
    level; 1.5e6 at s = 0.6): 1.3e-5 x_ref, asserted 2e-5."""
    fire = ramp(small_tissue, tmp_path / "fire")
    newton = study.sweep(small_tissue, APPLE, tmp_path / "newton", levels=(1.0, 0.6, 0.4),
                         progress=False, start="previous", method="newton", overrides=STEEP)
    assert all(r["converged"] for r in newton) and all(r["converged"] for r in fire)
    apart = [np.abs(a["xy"] - b["xy"]).max() / MAT["x_ref"] for a, b in zip(fire, newton)]
    assert max(apart) < 2e-5, apart
