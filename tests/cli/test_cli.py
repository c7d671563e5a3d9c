# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The command line and the Python side never crash, never lose or mix results, and name
the real cause (issue 12, sections 2 and 4-6; doc/errors.md, "Command line and Python").

Most cases stop before LAMMPS runs. Those that need finished levels use cgmstest's
stand-in for study.relax (the ``fake`` fixture), so the folder logic is tested without
LAMMPS."""

import csv
import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from cgms import folders, material, study, tissue
from cgmstest import APPLE, ROOT, XREF, fake_relax, reached, run_cli

SMALL = ["--width", "0.6", "--height", "0.6"]


def listing(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


# --------------------------------------------------------------------------- section 2

def test_resume_with_other_options_is_refused(fake, capsys):
    """A study folder records what defines it; a resume with another --set, --method,
    --width, --cv or material refuses and leaves the finished levels alone."""
    base = ["study", *SMALL, "--dryness", "1,0.3", "--out", "d"]
    assert run_cli(capsys, *base, "--set", "k_T 1e-10")[0] == 0
    before = (fake / "d/tissue/level.s0.3.json").read_text()
    for other in (["--set", "k_T 5e-10"], ["--set", "k_T 1e-10", "--method", "dynamics"],
                  ["--set", "k_T 1e-10", "--width", "0.9"],
                  ["--set", "k_T 1e-10", "--cv", "0.05"]):
        status, err, _ = run_cli(capsys, *base, "--resume", *other)
        assert status == 1 and ("another setup" in err or "another tissue" in err), (other, err)
    assert (fake / "d/tissue/level.s0.3.json").read_text() == before
    status, err, _ = run_cli(capsys, *base, "--resume", "--set", "k_T 1e-10")
    assert status == 0, err


def test_levels_that_print_alike_are_kept_apart(fake, capsys):
    assert study.level_name(0.3) == "s0.3" and study.level_name(1.0) == "s1"
    assert study.level_name(0.3) != study.level_name(0.30000001)
    assert run_cli(capsys, "study", *SMALL, "--dryness", "0.3,0.30000001", "--out", "d")[0] == 0
    a = json.loads((fake / "d/tissue/level.s0.3.json").read_text())
    b = json.loads((fake / "d/tissue/level.s0.30000001.json").read_text())
    assert a["dryness"] == 0.3 and b["dryness"] == 0.30000001
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "0.3,0.3", "--out", "e")
    assert status == 2 and "given twice" in err and not (fake / "e").exists()


@pytest.mark.parametrize("target", [0.85, 0.95, 1.0])
def test_target_above_the_start_dryness_is_bracketed(fake, target):
    """X/X0 reached is above s for s above about 0.8 (CGMS: s = 0.85 reaches 0.87): the
    search must still find the start."""
    found = study.target_moisture(_data(fake), APPLE, target, fake / "t", xtol=1e-6)
    assert reached(found["initial"]) == pytest.approx(target, abs=1e-5)


def _data(folder):
    path = folder / "tissue.data"
    if not path.exists():
        tissue.write_data(path, tissue.rectangle(0.6e-3, 0.6e-3, XREF), 3 * XREF)
    return path


def test_target_beyond_the_fresh_tissue_says_what_it_reaches(fake):
    with pytest.raises(ValueError, match=r"ends below X/X0 = 1.2 \(it reaches 1.1000\)"):
        study.target_moisture(_data(fake), APPLE, 1.2, fake / "t")


# --------------------------------------------------------------------------- section 4

def test_out_that_is_a_file(fake, capsys):
    (fake / "f").write_text("mine")
    status, err, _ = run_cli(capsys, "study", *SMALL, "--out", "f")
    assert status == 1 and "--out f is a file, not a folder" in err
    assert (fake / "f").read_text() == "mine"
    status, err, _ = run_cli(capsys, "study", *SMALL, "--out", "f/sub")
    assert status == 1 and "cannot write in f/sub: Not a directory" in err


def test_read_only_or_full_disk_says_so(fake, capsys, monkeypatch):
    """Read-only file system at the folder, full disk at a result: one line each, no
    traceback, and no level file cut short (results are written whole or not at all)."""
    real_mkdir = type(fake).mkdir

    def read_only(self, *a, **k):
        if self.name == "ro":
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(self))
        return real_mkdir(self, *a, **k)

    monkeypatch.setattr(type(fake), "mkdir", read_only)
    status, err, _ = run_cli(capsys, "study", *SMALL, "--out", "ro")
    assert status == 1 and "cannot write in ro: Read-only file system" in err

    def full(fh):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    real_write = folders.write_atomic
    monkeypatch.setattr(folders, "write_atomic",
                        lambda path, write, **kw: real_write(
                            path, full if path.suffix == ".json" and "level" in path.name
                            else write, **kw))
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "1", "--out", "full")
    assert status == 1 and "No space left on device" in err
    assert not list((fake / "full").rglob("level.*.json"))
    assert not list((fake / "full").rglob("*.tmp"))


def test_damaged_result_is_named_on_resume(fake, capsys):
    assert run_cli(capsys, "study", *SMALL, "--dryness", "1,0.3", "--out", "d")[0] == 0
    bad = fake / "d/tissue/level.s0.3.json"
    bad.write_text("")   # as a kill during a non-atomic write left it
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "1,0.3", "--out", "d",
                          "--resume")
    assert status == 1 and str(bad.relative_to(fake)) in err and "delete it" in err
    (fake / "d/tissue/level.s1.npy").unlink()
    bad.unlink()
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "1,0.3", "--out", "d",
                          "--resume")
    assert status == 1 and "level.s1.npy" in err


def test_resume_needs_an_existing_out(fake, capsys):
    status, err, _ = run_cli(capsys, "study", *SMALL, "--resume")
    assert status == 1 and "give the folder with --out" in err
    status, err, _ = run_cli(capsys, "study", *SMALL, "--resume", "--out", "missing")
    assert status == 1 and "--resume: missing does not exist" in err
    assert listing(fake) == []


def test_two_commands_never_share_a_folder(fake, capsys):
    """The second command on a folder in use stops at once and names it; the folder's
    own lock is what tells (flock: also across processes)."""
    assert run_cli(capsys, "study", *SMALL, "--dryness", "1", "--out", "d")[0] == 0
    with folders.claim(fake / "d", "study", resume=True):
        status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "1", "--out", "d",
                              "--resume")
        assert status == 1 and "in use by another cgms command" in err
        # a second process too
        code = ("import sys; sys.path.insert(0, sys.argv[1]); from cgms import folders\n"
                "try:\n    with folders.claim(sys.argv[2], 'study', True): pass\n"
                "except folders.FolderError as e: print(e); sys.exit(3)\n")
        proc = subprocess.run([sys.executable, "-c", code, str(ROOT / "python"),
                               str(fake / "d")], capture_output=True, text=True, timeout=60)
        assert proc.returncode == 3 and "in use" in proc.stdout


CALIBRATE = ["calibrate", "--reference", "1=ref.txt"]


# every command refuses a bad option before it makes anything (usage error, status 2)
@pytest.mark.parametrize("args,message", [
    (["study", "--width", "-1"], "argument --width: must be a positive number, got -1"),
    (["study", "--height", "nan"], "argument --height: must be a positive number"),
    (["study", "--cv", "-0.1"], "argument --cv: must be a number >= 0"),
    (["study", "--residual", "-1"], "argument --residual: must be a positive number"),
    (["study", "--dryness", "1.5"], "level 1.5 is outside (0, 1]"),
    (["study", "--dryness", "0.3,abc"], "'abc' is not a number"),
    (["study", "--max-steps", "0"], "must be at least 1"),
    (["mfc", "single", "--dryness", "1,1.5"], "level 1.5 is outside (0, 1]"),
    (["mfc", "single", "--dryness", "0.3,abc"], "'abc' is not a number"),
    (["mfc", "single", "--ftol", "0"], "argument --ftol: must be a positive number"),
    (["mfc", "single", "--max-iterations", "0"], "argument --max-iterations: must be at least 1"),
    (["target", "0"], "argument target: must be a positive number"),
    (["target", "-0.5"], "must be a positive number"),
    (["target", "0.6", "--xtol", "0"], "argument --xtol: must be a positive number"),
    (CALIBRATE + ["--workers", "0"], "argument --workers: must be at least 1"),
    (CALIBRATE + ["--max-evaluations", "0"], "argument --max-evaluations: must be at least 1"),
    (CALIBRATE + ["--start", "k_T=abc"], "--start: bad value in 'k_T=abc'"),
])
def test_bad_options_create_nothing(fake, capsys, args, message):
    status, err, _ = run_cli(capsys, *args)
    assert status == 2 and message in err, err
    assert listing(fake) == []


# --------------------------------------------------------------------------- section 5

MATERIAL_CASES = {
    "missing diameter": ("diameter", None, "CGMS parameter diameter is missing"),
    "duplicate key": ("k_T", "k_T 1e-10\nk_T 2e-10",
                      "line 9: parameter k_T given twice"),
    "unknown key": ("k_T", "k_T 1e-10\nk_X 1", "line 9: unknown CGMS parameter 'k_X'"),
    "negative diameter": ("diameter", "diameter -150e-6",
                          "CGMS parameter diameter = -0.00015 must be > 0"),
    "zero diameter": ("diameter", "diameter 0", "CGMS parameter diameter = 0 must be > 0"),
    "value not a number": ("K", "K abc", "line 23: value 'abc' of parameter K is not a number"),
    "three words": ("K", "K 2e7 Pa", "line 23: expected 'name value'"),
    "perim_a above perim_b": ("perim_a", "perim_a 0.95",
                              "perim_a (0.95) must be below perim_b (0.9)"),
    "infinite value": ("k_PA", "k_PA inf", "value 'inf' of parameter k_PA is not finite"),
}


def material_file(folder, name, replacement):
    """apple.cgms with the line of ``name`` replaced (None: removed)."""
    lines = []
    for line in open(APPLE).read().splitlines():
        if line.split("#", 1)[0].split()[:1] == [name]:
            if replacement is not None:
                lines.extend(replacement.splitlines())
        else:
            lines.append(line)
    path = folder / "bad.cgms"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("case", sorted(MATERIAL_CASES))
def test_material_file_rules(tmp_path, capsys, monkeypatch, case):
    """The plugin's rules, with the file and line in the message, in the library and at
    the command line (which stops before it creates anything)."""
    name, replacement, message = MATERIAL_CASES[case]
    path = material_file(tmp_path, name, replacement)
    with pytest.raises(ValueError) as err:
        material.read(path)
    assert message in str(err.value) and str(path) in str(err.value), str(err.value)
    monkeypatch.chdir(tmp_path)
    status, text, _ = run_cli(capsys, "study", "--material", str(path), "--out", "out")
    assert status == 2 and message in text and not (tmp_path / "out").exists()


def test_material_that_is_a_folder_or_not_text(tmp_path, capsys):
    with pytest.raises(FileNotFoundError, match="not found"):
        material.read(tmp_path)
    (tmp_path / "bin.cgms").write_bytes(b"k_T \xff\xfe\n")
    with pytest.raises(ValueError, match=r"bin.cgms: cannot be read"):
        material.read(tmp_path / "bin.cgms")


@pytest.mark.parametrize("overrides,message", [
    ("diameter 0", "diameter = 0 must be > 0"),
    ("k_S -1", "k_S = -1 must be >= 0"),
    ("Pi_f 2e5", "Pi_f = 200000 must be < 0"),
    ("k_X 1", "unknown CGMS parameter 'k_X'"),
])
def test_set_is_checked_before_anything_is_built(fake, capsys, overrides, message):
    """--set 'diameter 0' once built an 18 072-bead tissue at 8 um spacing before LAMMPS
    refused it."""
    status, err, _ = run_cli(capsys, "study", *SMALL, "--set", overrides, "--out", "d")
    assert status == 2 and message in err, err
    assert listing(fake) == []


# --------------------------------------------------------------------------- section 6

def tissue_cli(folder, *args):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "cgms.tissue", *args], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("args,message", [
    (["disc", "0.01"], "the disc of radius 0.01 mm holds 1 bead(s) at spacing 150.85 um; "
                       "a tissue needs at least 3"),
    (["rect", "1", "1", "--inset", "-0.1"], "inset must be a finite number >= 0, got -0.0001"),
    (["rect", "1", "1", "--cv", "5"], "--cv 5: lognormal diameters clipped at half the mean "
                                      "would average 1.25 x the material's 150 um"),
    (["rect", "1", "1", "--cv", "0.5", "--dist", "normal"], "average 1.04 x"),
])
def test_tissue_builder_refuses(tmp_path, args, message):
    proc = tissue_cli(tmp_path, *args)
    assert proc.returncode == 2 and message in proc.stderr, proc.stderr
    assert "Traceback" not in proc.stderr and listing(tmp_path) == []


def test_clipped_mean_is_the_sample_mean():
    """tissue.clipped_mean against a large sample of cell_diameters (independent: the
    quantile grid against random draws)."""
    for cv, dist in ((0.3, "normal"), (1.0, "lognormal"), (0.1, "lognormal")):
        d = tissue.cell_diameters(400_000, 1.0, cv, seed=5, dist=dist)
        assert tissue.clipped_mean(cv, dist) == pytest.approx(d.mean(), rel=3e-3)


def test_study_cv_is_checked_like_the_builder(fake, capsys):
    status, err, _ = run_cli(capsys, "study", *SMALL, "--cv", "5", "--out", "d")
    assert status == 2 and "--cv 5" in err and listing(fake) == []


# --------------------------------------------------------------------------- section 3

@pytest.mark.lammps
def test_lammps_error_is_shown_in_cli_terms_from_the_whole_line(tmp_path, capsys, monkeypatch):
    """LAMMPS's Python module cuts its error message at 100 characters; the command line
    reads the whole ERROR line from the log, names the log, and says the cause and cure in
    its own options, with no advice about FIRE (which did not fail). lj_slope 5 makes the
    LJ radius at s = 0.3 negative: the lowest dryness, 0.8187, is at the line's end."""
    monkeypatch.chdir(tmp_path)
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "0.3", "--set",
                             "lj_slope 5", "--out", "d")
    log = (tmp_path / "d/tissue/log.s0.3.lammps").read_text()
    line = next(x for x in log.splitlines() if x.startswith("ERROR"))
    assert len(line) > 100 and line.index("0.8187") > 100   # beyond what the module passes on
    assert status == 1 and "(LAMMPS log: d/tissue/log.s0.3.lammps)" in err, err
    assert "LJ radius is not positive; --dryness levels above 0.8187, or another lj_slope " \
        "(--set)" in err, err
    assert "FIRE" not in err and not [w for w in LAMMPS_WORDS if w in err], err


def test_python_material_rules_are_the_plugins():
    """material.PARAMETERS repeats the plugin's table of parameters (names, ranges,
    required) so that files are refused alike on both sides; read that table from the
    plugin's source and compare."""
    import re
    source = (ROOT / "src/CGMS/cgms_material.cpp").read_text()
    rows = re.findall(r'\{"(\w+)",\s*&CGMS::Material::\w+,\s*(\w+),\s*(true|false)\}', source)
    assert len(rows) >= 20, "the plugin's parameter table changed form: update this test"
    ranges = {"POSITIVE": "> 0", "NONNEGATIVE": ">= 0", "NEGATIVE": "< 0", "ANY": "finite"}
    plugin = {name: (ranges[r], req == "true") for name, r, req in rows}
    assert plugin == material.PARAMETERS


# --------------------------------------------------------------------------- --fallback

#: LAMMPS's stop when FIRE pushes a bead out of its neighbours' cutoff (apple-mfc.cgms at
#: s = 0.6; the 20 x 20 mm apple tissue at s = 0.3), as fix cgms/fluid words it
FIRE_STOP = ("ERROR on proc 0: Fix cgms/fluid: bead 20 has no neighbour within the pair cutoff "
             "(use 'isolated allow' to give isolated beads the reference cell) at step 812: "
             "its nearest bead is 0.0002071 m away; the minimizer moved it away from the "
             "tissue (cutoff 0.0002036 m): use min_style fire or cg with min_modify dmax "
             "~1e-6, which move beads in small steps")
#: LAMMPS's words a command-line user does not write: a CLI message must not use them
LAMMPS_WORDS = ("min_style", "min_modify", "dmax", "isolated allow", "pair_coeff",
                "pair_style", "timestep", "read_data", "ERROR")


def fire_stops_when_dry(data, material_file, dryness, out, **kwargs):
    """fake_relax, except that the quasi-static solve stops below s = 0.5, as FIRE does
    with apple-mfc.cgms at s = 0.6 (doc/calibration.md) and on the 20 x 20 mm tissue."""
    if kwargs.get("method") == "quasistatic" and dryness < 0.5:
        raise study.LammpsError(dryness, FIRE_STOP, Path(out) / "log.lammps")
    return fake_relax(data, material_file, dryness, out, **kwargs)


def table_rows(out):
    """{s: [converged, solved by ...]} of a printed study table."""
    return {line.split()[2]: line.split()[8:] for line in out.splitlines()
            if line.startswith("  tissue ") and line.split()[1].isdigit()}


def test_default_falls_back_records_marks_and_reads_back(fake, capsys, monkeypatch):
    """The default study falls back to the dynamics by itself where FIRE stops (issue 26:
    the 20 x 20 mm tissue at s = 0.3 stopped with LAMMPS's min_style advice): the level is
    the dynamics' (its dump in tissue/dynamics/, which the pictures find), the table, the
    CSV and sweep.json say which method solved each level, a resume reads the marks back
    without running anything, and a resume with --fallback none is refused."""
    monkeypatch.setattr(study, "relax", fire_stops_when_dry)
    base = ["study", *SMALL, "--dryness", "1,0.3", "--out", "e"]
    status, err, out = run_cli(capsys, *base)
    assert status == 0, err
    assert table_rows(out) == {"1.00": ["yes", "FIRE"], "0.30": ["yes", "dynamics", "(fallback)"]}
    assert "the steady state is the dynamics'" in out
    folder = fake / "e/tissue"
    record = json.loads((folder / "sweep.json").read_text())
    assert record["fallback"] == "dynamics"
    assert record["solved_by"] == {"s1": {"method": "quasistatic"},
                                   "s0.3": {"method": "dynamics (fallback)", "why": FIRE_STOP}}
    level = json.loads((folder / "level.s0.3.json").read_text())
    assert level["fallback"] == FIRE_STOP and level["method"] == "dynamics"
    assert json.loads((folder / "level.s1.json").read_text())["fallback"] == ""
    assert (folder / "dynamics/tissue.s0.3.dump").exists()
    assert (folder / "cells-pressure.png").exists()
    with open(next(folder.parent.glob("summary-*.csv"))) as fh:
        table = {r["s"]: r for r in csv.DictReader(fh)}
    assert table["0.3"]["fallback"] == FIRE_STOP and table["1.0"]["fallback"] == ""
    # a resume must use the same option ...
    status, err, _ = run_cli(capsys, *base, "--resume", "--fallback", "none")
    assert status == 1 and "another setup" in err and "fallback" in err, err
    # ... and then reads the levels back, marks included, running nothing
    monkeypatch.setattr(study, "relax", lambda *a, **k: pytest.fail("level run again"))
    for explicit in ([], ["--fallback", "dynamics"]):
        status, err, again = run_cli(capsys, *base, "--resume", *explicit)
        assert status == 0, err
        assert table_rows(again) == table_rows(out)


def test_a_table_without_the_fresh_level_says_what_it_is_relative_to(fake, capsys):
    """With no s = 1 level, A/A0 is 1 at the wettest level run (0.3 alone: 1.0000 for a
    dried tissue); the table says so (found with --width 20 --height 20 --dryness 0.3)."""
    status, err, out = run_cli(capsys, "study", *SMALL, "--dryness", "0.3", "--out", "d")
    assert status == 0, err
    assert ("tissue: A/A0, P/P0, EL/EL0 are relative to s = 0.3, the wettest level run; add "
            "1 to --dryness") in out
    status, err, out = run_cli(capsys, "study", *SMALL, "--dryness", "1,0.3", "--out", "e")
    assert status == 0 and "relative to" not in out


def test_a_folder_made_without_fallback_resumes_as_it_was_made(fake, capsys, monkeypatch):
    """Folders made before the fallback was the default (no 'fallback' in sweep.json, as
    --fallback none writes) resume without options, as they were made."""
    base = ["study", *SMALL, "--dryness", "1,0.3", "--out", "d"]
    assert run_cli(capsys, *base[:-3], "1", "--out", "d", "--fallback", "none")[0] == 0
    assert "fallback" not in json.loads((fake / "d/tissue/sweep.json").read_text())
    status, err, out = run_cli(capsys, *base, "--resume")
    assert status == 0, err
    assert table_rows(out) == {"1.00": ["yes", "FIRE"], "0.30": ["yes", "FIRE"]}
    status, err, _ = run_cli(capsys, *base, "--resume", "--fallback", "dynamics")
    assert status == 1 and "another setup" in err


def test_without_fallback_the_stop_is_in_cli_terms(fake, capsys, monkeypatch):
    """--fallback none: FIRE's stop is reported as its cause and the option that cures it,
    with none of LAMMPS's commands (its advice, min_style ... dmax, is for input scripts)."""
    monkeypatch.setattr(study, "relax", fire_stops_when_dry)
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "1,0.3", "--out", "d",
                             "--fallback", "none")
    assert status == 1 and len(err.strip().splitlines()) == 1, err
    assert "s = 0.3: the quasi-static solve (FIRE) moved bead 20 out of its neighbours' reach" \
        in err and "--fallback dynamics (the default)" in err, err
    assert not [w for w in LAMMPS_WORDS if w in err], err


def test_a_failed_fallback_names_both_stops_in_cli_terms(fake, capsys, monkeypatch):
    """Where the dynamics after FIRE stops too, the message names both stops and the cure."""
    collapse = ("ERROR on proc 0: Fix cgms/fluid: bead 7 has 9 neighbours within the cutoff at "
                "step 300, more than the 6 of a hexagonal tissue: the tissue is collapsing "
                "(beads crowding past the weak LJ repulsion), and the damping is unstable at "
                "dt = 5e-08 s; a smaller time step does not cure this. The paper's forces do "
                "not resist shear; a cell-shape stiffness (e.g. k_S 0.5 on the pair_coeff "
                "line) may prevent it (doc/pair_cgms.rst, doc/results/validation.md hard cases)")

    def both_stop(data, material_file, dryness, out, **kwargs):
        if dryness < 0.5:
            raise study.LammpsError(dryness, FIRE_STOP if kwargs["method"] == "quasistatic"
                                    else collapse, Path(out) / "log.lammps")
        return fake_relax(data, material_file, dryness, out, **kwargs)

    monkeypatch.setattr(study, "relax", both_stop)
    status, err, _ = run_cli(capsys, "study", *SMALL, "--dryness", "1,0.3", "--out", "d")
    assert status == 1 and len(err.strip().splitlines()) == 1, err
    assert "moved bead 20 out of its neighbours' reach" in err and "collapsed at step 300" \
        in err and "--set 'k_S 0.5'" in err, err
    assert not [w for w in LAMMPS_WORDS if w in err], err


def test_main_lists_the_fallback_dumps(fake, capsys, monkeypatch):
    from cgms import pictures
    monkeypatch.setattr(study, "relax", fire_stops_when_dry)
    monkeypatch.setattr(pictures, "study_pictures", lambda out: [])   # tested above; slow
    status, err, out = run_cli(capsys, "main", "--dryness", "1,0.3", "--fallback", "dynamics",
                               "--out", "m")
    assert status == 0, err
    assert "levels solved by the fallback: dump and log in m/*/dynamics/" in out, out
    assert len(list(fake.glob("m/*/dynamics/tissue.s0.3.dump"))) == 6


def test_fallback_needs_a_quasistatic_method(fake, capsys):
    status, err, _ = run_cli(capsys, "study", *SMALL, "--method", "dynamics", "--fallback",
                             "dynamics", "--out", "d")
    assert status == 2 and "--fallback dynamics needs --method quasistatic or newton" in err
    assert listing(fake) == []


def test_levels_outside_the_materials_range_are_named_not_run(fake, capsys):
    """A calibrated material says in its header for which levels it holds ('VALID FOR
    0.6 <= s <= 1', potato-mfc.cgms): other levels are named in one line and not run."""
    limited = fake / "limited.cgms"
    limited.write_text(Path(APPLE).read_text() + "# fitted at three levels: VALID FOR\n"
                                           "# 0.6 <= s <= 1 ONLY.\n")
    assert study.valid_range(limited) == (0.6, 1.0) and study.valid_range(APPLE) == (0, 1)
    common = ["study", *SMALL, "--material", str(limited)]
    status, err, out = run_cli(capsys, *common, "--dryness", "1,0.6,0.3", "--out", "d")
    assert status == 0, err
    assert ("cgms: s = 0.3 not run: limited.cgms is valid for 0.6 <= s <= 1 only "
            "(its header)") in out
    assert sorted(p.name for p in (fake / "d/tissue").glob("level.*.json")) == \
        ["level.s0.6.json", "level.s1.json"]
    assert "0.30" not in "".join(line[:30] for line in out.splitlines())
    status, err, _ = run_cli(capsys, *common, "--dryness", "0.4,0.3", "--out", "e")
    assert status == 2 and "no level to run" in err and not (fake / "e").exists()


@pytest.mark.skipif(not (ROOT / "build" / "env.sh").exists(), reason="./cgms setup not run")
def test_build_env_adds_to_the_users_potentials_folders_and_does_not_grow():
    """build/env.sh puts potentials/ first in LAMMPS_POTENTIALS and keeps the user's own
    folders after it, read when sourced (not baked in at set-up time), so a set-up run
    from a sourced shell does not pile up copies. (Sourcing it twice in one shell does
    add a second copy, as to PYTHONPATH and LD_LIBRARY_PATH.) Fails on a build/env.sh
    written by the tools/setup.sh of before 611506f."""
    env = {k: v for k, v in os.environ.items() if k != "LAMMPS_POTENTIALS"}
    script = f"source '{ROOT}/build/env.sh'; printf '%s\\n' \"$LAMMPS_POTENTIALS\""
    def sourced(extra):
        out = subprocess.run(["bash", "-c", script], env=dict(env, **extra), text=True,
                             capture_output=True, check=True).stdout
        return out.strip()
    ours = str(ROOT / "potentials")
    assert sourced({}) == ours
    assert sourced({"LAMMPS_POTENTIALS": "/users/own"}) == f"{ours}:/users/own"


@pytest.mark.lammps
def test_a_spent_fire_budget_falls_back_in_lammps(tmp_path, capsys, monkeypatch):
    """The real path on a small tissue: FIRE stopped by a budget of 5 iterations (as it
    stops on the 20 x 20 mm tissue, not converged), the default study solves the level with
    the dynamics by itself, and says so in the table and in sweep.json."""
    monkeypatch.chdir(tmp_path)
    status, err, out = run_cli(capsys, "study", *SMALL, "--dryness", "1", "--max-steps", "5",
                               "--out", "d")
    assert status == 0, err
    assert table_rows(out) == {"1.00": ["yes", "dynamics", "(fallback)"]}, out
    record = json.loads((tmp_path / "d/tissue/sweep.json").read_text())
    assert record["solved_by"] == {"s1": {"method": "dynamics (fallback)",
                                          "why": "FIRE reached its iteration limit (5 "
                                                 "iterations)"}}
    assert (tmp_path / "d/tissue/dynamics/tissue.s1.dump").exists()
