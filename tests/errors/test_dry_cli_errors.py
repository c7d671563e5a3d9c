# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms dry`` against bad, degenerate and awkward input (issue 26): every run
ends with a valid result or one line on stderr in the command's own terms, a non-zero
status, no traceback, no hang, no NaN, and lists only the files it wrote
(doc/errors.md, "dry")."""

import csv
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from cgmstest import ROOT, XREF, lammps_env, require_lammps, run_cli, run_lmp
from cgms import drying, positions, tissue

NOT_A_NUMBER = re.compile(r"\b(nan|inf)\b", re.IGNORECASE)
#: a small sound tissue (33 beads) and a short, cheap run: what every case adds to
SMALL = ["--width", "0.8", "--height", "0.8", "--layers", "2"]


def write(path, xy):
    positions.write_data(path, np.asarray(xy, float), 3 * XREF, overwrite=True)
    return str(path)


def one_line(err):
    """The message of a refused run: exactly one line, no traceback."""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def dry(capsys, out, *args):
    return run_cli(capsys, "dry", *args, "--out", str(out))


def files(tmp_path):
    """Input files for the cases below."""
    block = tissue.rectangle(0.8e-3, 0.8e-3, XREF)
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "x").write_text("")
    (tmp_path / "empty.data").write_text("")
    params = (ROOT / "potentials" / "apple-drying.params").read_text()
    (tmp_path / "nan.params").write_text(params.replace("X0              5.94", "X0 nan"))
    (tmp_path / "extra.params").write_text(params + "D_reff 1e-9\n")   # a misspelt name
    gab_c = [line for line in params.splitlines() if line.startswith("GAB_C")][0]
    (tmp_path / "gab_c.params").write_text(params.replace(gab_c, "GAB_C 0.5"))
    centroids = "".join(f"{i + 1} {x * 1e6!r} {y * 1e6!r}\n" for i, (x, y) in enumerate(block))
    (tmp_path / "um.txt").write_text(centroids)
    lines = open(write(tmp_path / "whole.data", block)).read().splitlines()
    (tmp_path / "cut.data").write_text("\n".join(lines[:-3]) + "\n")   # cut at a line end
    return dict(
        cut=str(tmp_path / "cut.data"),
        one=write(tmp_path / "one.data", [[0, 0]]),
        row=write(tmp_path / "row.data", [[k * XREF, 0] for k in range(6)]),
        isolated=write(tmp_path / "isolated.data", np.vstack([block, [[5e-3, 5e-3]]])),
        um=write(tmp_path / "um.data", block * 1e6),
        um_txt=str(tmp_path / "um.txt"), empty=str(tmp_path / "empty.data"),
        folder=str(tmp_path / "full"), nan_params=str(tmp_path / "nan.params"),
        extra_params=str(tmp_path / "extra.params"), gab_c=str(tmp_path / "gab_c.params"))


# each: options (FILE:<name> taken from files()), a fragment of the one line expected
REFUSED = [
    (["--width", "0.2", "--height", "0.2"], "a tissue needs at least 3"),   # 2 beads
    (["--data", "FILE:one"], "a tissue needs at least 3"),
    (["--data", "FILE:row"], "collinear"),
    (["--data", "FILE:isolated"], "the beads form 2 pieces"),
    (["--data", "FILE:um", "--frozen"], "these look like micrometres"),
    (["--data", "FILE:um_txt", "--frozen"], "these look like micrometres"),
    (["--data", "FILE:empty"], "empty.data"),
    (["--data", "FILE:folder"], "--data"),
    (["--params", "FILE:nan_params"], "X0 = nan must be positive"),
    # 2026-12-03: read and dropped unread / passed on to the fix, whose ERROR came back
    # cut short as an "internal error" after the folder was made
    (["--params", "FILE:extra_params"], "unknown parameter 'D_reff'"),
    (["--data", "FILE:cut"], "its header declares 33 atoms, its Atoms section holds 30"),
    (["--params", "FILE:gab_c"], "GAB_C = 0.5 must be above 1"),
    (["--velocity", "1e300"], "gives a Reynolds number of 2.01e+303, outside 1 to 1e+08"),
    (["--plate-length", "1e-300"], "--plate-length 1e-300 mm gives a Reynolds number"),
    (["--out", "FILE:folder"], "dry always starts a new run"),
    (["--dx-max", "1000", "--no-heat"], "--dx-max must be in (0, 1]"),
    (["--dx-max", "0"], "--dx-max must be in (0, 1]"),
    (["--layers", "0"], "--layers must be 1 to 200"),
    (["--layers", "300"], "--layers must be 1 to 200"),
    (["--layers", "150", "--thickness", "1"], "nodes 3.3 um deep"),
    (["--thickness", "1e-9"], "--thickness must be at least one cell"),
    (["--thickness", "nan"], "--thickness must be"),
    (["--width", "nan"], "--width must be positive"),
    (["--width", "-1"], "--width must be positive"),
    (["--width", "1e9"], "sizes are in millimetres"),
    (["--height", "0"], "--height must be positive"),
    (["--temperature", "nan"], "--temperature must be in -20..150"),
    (["--velocity", "inf"], "--velocity must be positive"),
    (["--velocity", "0"], "--velocity must be positive"),
    (["--plate-length", "nan"], "--plate-length must be positive"),
    (["--humidity", "-0.1"], "--humidity must be in [0, 1)"),
    (["--stop", "nan"], "--stop must be in [0, 1)"),
    (["--resolve", "inf"], "--resolve must be positive"),
    (["--newton-iterations", "0"], "--newton-iterations must be at least 1"),
    (["--set", "diameter 0"], "diameter = 0 must be > 0"),
]


@pytest.mark.parametrize("args, message", REFUSED,
                         ids=[" ".join(a) for a, _ in REFUSED])
def test_refused_before_anything_is_written(tmp_path, capsys, args, message):
    """Degenerate tissues, wrong units, non-finite or out-of-range options, a folder in
    use: one line naming the option, status != 0, and no results folder (or the given
    folder left as it was)."""
    given = files(tmp_path)
    args = [given[a[5:]] if a.startswith("FILE:") else a for a in args]
    out = tmp_path / "out"
    if "--out" in args:
        out = tmp_path / "full"
        status, err, _ = run_cli(capsys, "dry", *args)
    else:
        status, err, _ = dry(capsys, out, *args)
    assert status != 0
    line = one_line(err)
    assert message in line and line.startswith("cgms"), line
    assert "--resume" not in line
    assert not out.exists() or sorted(p.name for p in out.iterdir()) == ["x"]


def read_csv(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def assert_valid_result(out, stdout):
    """A finished run: its table exists, holds no NaN or infinity, and every file the
    last line lists exists."""
    rows = read_csv(out / "drying.csv")
    assert rows
    text = (out / "drying.csv").read_text()
    assert not NOT_A_NUMBER.search(text) and not NOT_A_NUMBER.search(stdout), stdout
    assert_listed_files_exist(out, stdout)
    return rows


def assert_listed_files_exist(out, text):
    for name in drying_outputs(text):
        assert (out / name).exists(), f"{name} listed but not written"


def drying_outputs(text):
    """The output files a message names."""
    names = re.findall(r"\b(drying\.csv|drying\.png|moisture\.png|case-hardening\.png|"
                       r"tissue\.data|log\.lammps|tissue\.X[0-9.]+\.dump)", text)
    return set(names)


AWKWARD = [
    ["--temperature", "149", "--humidity", "0.99"],
    ["--temperature", "-19"],                        # would cool the product below -20 C
    ["--temperature", "1", "--humidity", "0"],
    ["--velocity", "1e6"],
    ["--plate-length", "1e-6"],
    ["--stop", "0.99"],
    ["--stop", "0", "--humidity", "0"],
    ["--hours", "1e-9"],
    ["--faces", "0"],
    ["--faces", "1", "--no-outline"],
    ["--thickness", "50"],
    ["--dx-max", "1", "--no-heat"],
    ["--maps", "1"],
]


@pytest.mark.parametrize("args", AWKWARD, ids=[" ".join(a) for a in AWKWARD])
def test_awkward_but_legal_options(tmp_path, capsys, args):
    """Legal extremes of the air and the stepping: a valid result with no NaN and only
    written files listed, or one line and status != 0."""
    out = tmp_path / "out"
    status, err, stdout = dry(capsys, out, *SMALL, "--frozen", "--hours", "0.05", *args)
    if status == 0:
        assert_valid_result(out, stdout)
    else:
        line = one_line(err)
        assert not re.search(r"f\(a\) and f\(b\)|must have different signs", line), line
        assert_listed_files_exist(out, line)


def test_large_moisture_steps_keep_moisture_non_negative(tmp_path, capsys):
    """The largest --dx-max (1) without heat: the surface law, linearised at the start of
    a step, is a constant flux while the surface holds free water, and long steps drew it
    past the water there (X/X0 = -0.077 at the end, the faces at -0.15, before). Now the
    step is halved until every node stays non-negative, and the water balance still
    closes (each accepted step combines three exact backward Euler steps, water and
    outflow alike: 1e-10, as in test_drying)."""
    out = tmp_path / "out"
    status, err, stdout = dry(capsys, out, *SMALL, "--frozen", "--no-heat", "--dx-max", "1",
                              "--hours", "1")
    assert status == 0, err
    rows = assert_valid_result(out, stdout)
    for key in ("X/X0", "surface_X/X0", "core_X/X0"):
        assert min(float(r[key]) for r in rows) >= 0, key
    assert max(abs(float(r["balance"])) for r in rows) < 1e-10


def test_short_run_lists_only_written_files(tmp_path, capsys):
    """A run too short to reach any --maps level writes no moisture maps, and says so by
    not naming them (it named moisture.png and case-hardening.png before)."""
    out = tmp_path / "out"
    status, err, stdout = dry(capsys, out, *SMALL, "--frozen", "--hours", "0.001")
    assert status == 0, err
    assert_valid_result(out, stdout)
    assert not (out / "moisture.png").exists()
    assert "moisture.png" not in stdout and "case-hardening.png" not in stdout


def test_interrupted_run_keeps_its_results(tmp_path, capsys, monkeypatch):
    """Ctrl-C during the drying: the rows so far are written, and the message speaks of
    what dry has (no --resume, which only study and main have)."""
    step, calls = drying.Transport.move, []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 6:
            raise KeyboardInterrupt
        return step(*args, **kwargs)

    monkeypatch.setattr(drying.Transport, "move", interrupted)
    out = tmp_path / "out"
    status, err, _ = dry(capsys, out, *SMALL, "--frozen", "--hours", "1")
    assert status == 130
    line = one_line(err)
    assert "interrupted" in line and "--resume" not in line and "does not resume" in line
    assert len(read_csv(out / "drying.csv")) == 6      # the fresh state and 5 steps
    assert_listed_files_exist(out, line)


def cli(*args, cwd, timeout):
    env = lammps_env()
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "cgms", "dry", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)


@pytest.mark.parametrize("hours", ["1e9", "inf"])
def test_endless_hours_refused(tmp_path, hours):
    """--hours 1e9 or inf were accepted (with a --stop the tissue never reaches they ran
    until killed); now refused at once (a subprocess, so that a hang fails the test by
    its timeout)."""
    proc = cli(*SMALL, "--frozen", "--hours", hours, "--out", str(tmp_path / "o"),
               cwd=tmp_path, timeout=60)
    assert proc.returncode != 0
    assert "--hours must be positive and at most 1000" in one_line(proc.stderr)
    assert not (tmp_path / "o").exists()


def gab(aw, xm, c, k):
    """The GAB isotherm, written out here (Timmermann et al. 2001's form)."""
    return xm * c * k * aw / ((1 - k * aw) * (1 - k * aw + c * k * aw))


def test_equilibrium_above_stop_ends_the_run(tmp_path):
    """Air at RH 0.95 holds apple at X/X0 = 0.203 (GAB, apple-drying.params), above
    --stop 0.1: the run went on for --hours, forever with 1e9. Now it ends when the
    tissue is within 1e-3 of that equilibrium (the tissue nears it from above: its
    surface is no warmer than the air), says so, and writes its results."""
    p = drying.read_params()
    x_eq = gab(0.95, p["GAB_Xm"], p["GAB_C"], p["GAB_K"]) / p["X0"]
    out = tmp_path / "o"
    proc = cli(*SMALL, "--frozen", "--hours", "1000", "--humidity", "0.95", "--out", str(out),
               cwd=tmp_path, timeout=240)
    assert proc.returncode == 0, proc.stderr
    assert "--stop 0.1 is never reached" in proc.stdout
    assert "dries no further" in proc.stdout
    rows = assert_valid_result(out, proc.stdout)
    last = float(rows[-1]["X/X0"])
    assert x_eq <= last <= x_eq + 1e-3
    assert float(rows[-1]["t_h"]) < 1000


def write_data_file(folder):
    """A data file as LAMMPS's write_data leaves it after a run: Velocities and the CGMS
    fluid-state section."""
    xy = tissue.rectangle(1.25e-3, 1.5e-3, XREF)
    write(folder / "tissue.data", xy)
    from cgmstest import APPLE, PLUGIN
    run_lmp(folder, "\n".join([
        f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary s s p",
        "atom_style cgms", "atom_modify map array", "comm_modify vel yes",
        "read_data tissue.data", "pair_style cgms", f"pair_coeff * * {APPLE}",
        "fix fl all cgms/fluid dryness 0.9", "fix nve all nve", "fix e2 all enforce2d",
        "timestep 1e-7", "run 10", "write_data written.data"]) + "\n")
    text = (folder / "written.data").read_text()
    assert "\nCGMS" in text and "\nVelocities" in text
    return folder / "written.data"


def test_write_data_file_read_by_dry_and_study(tmp_path, capsys):
    """`study --data` reads a file of LAMMPS's write_data; `dry --data` stopped on
    LAMMPS's "Unknown identifier in data file: CGMS" with a traceback. Both read it now
    (positions, as cgms study does), and dry says that it starts from the fresh state."""
    require_lammps()
    data = write_data_file(tmp_path)
    status, err, stdout = dry(capsys, tmp_path / "d", "--data", str(data), "--hours", "0.01",
                              "--layers", "2")
    assert status == 0, err
    assert "CGMS section" in stdout and "is not read" in stdout
    assert_valid_result(tmp_path / "d", stdout)
    status, err, _ = run_cli(capsys, "study", "--data", str(data), "--dryness", "1",
                             "--out", str(tmp_path / "s"))
    assert status == 0, err


def test_lammps_stop_gives_the_whole_error_line(tmp_path, capsys):
    """A LAMMPS stop during the drying (lj_slope 5 shrinks the cutoff below the spacing at
    s = 0.94): LAMMPS's whole ERROR line (the Python module cuts it at 100 characters),
    the time and X/X0 reached, the rows so far written, only written files named."""
    require_lammps()
    out = tmp_path / "o"
    status, err, _ = dry(capsys, out, *SMALL, "--set", "lj_slope 5", "--hours", "0.1")
    assert status == 1
    line = one_line(err)
    error = line[line.index("ERROR"):]
    assert len(error) > 200 and "src/CGMS/fix_cgms_fluid" in error, line
    assert "at t = " in line and "does not resume" in line
    assert read_csv(out / "drying.csv")
    assert_listed_files_exist(out, line)


def test_material_valid_range_holds_the_shape(tmp_path, capsys):
    """potato-mfc.cgms is VALID FOR 0.6 <= s <= 1: the mechanics is never solved below
    s = 0.6 (a bead drier than that keeps the shape of 0.6), and the run says so. Before,
    the dryness went down to 0.3 (cgms study leaves such levels out)."""
    require_lammps()
    out = tmp_path / "o"
    status, err, stdout = dry(capsys, out, "--material", "potato-mfc", "--solver", "newton",
                              "--width", "1.25", "--height", "1.5", "--layers", "2",
                              "--stop", "0.4", "--maps", "0.4", "--hours", "1")
    assert status == 0, err
    assert "potato-mfc.cgms is valid for 0.6 <= s <= 1 only" in stdout
    assert_valid_result(out, stdout)
    from cgms import morphology
    s = morphology.read_dump(out / "tissue.X0.4.dump", "dryness")[-1]["columns"]["dryness"]
    assert s.min() >= 0.6 - 1e-9      # clipped at the bound (the dump's 10 digits)
    assert s.min() < 0.61             # and some bead is held there


def test_potato_mfc_default_solver(tmp_path, capsys):
    """`dry --material potato-mfc` (FIRE, warm started) flung a bead to 2e4 m at s = 0.79
    and ended in a traceback ("Too many neighbor bins"). Now: a valid result, or LAMMPS's
    line, the results so far and the way out (--solver newton)."""
    require_lammps()
    out = tmp_path / "o"
    status, err, stdout = dry(capsys, out, "--material", "potato-mfc", "--hours", "0.05")
    if status == 0:
        assert_valid_result(out, stdout)
    else:
        line = one_line(err)
        assert "LAMMPS stopped" in line and "--solver newton" in line
        assert_listed_files_exist(out, line)


def test_transport_stop_gives_its_whole_error_line(tmp_path, capsys):
    """A stop of fix cgms/transport (here: air too cold for the evaporative cooling) used
    to end as "internal error (Exception: ERROR: ...", cut at 100 characters, with "please
    report it"; now it is LAMMPS's whole line, cause and cure, after what was written."""
    require_lammps()
    out = tmp_path / "cold"
    status, err, _ = dry(capsys, out, *SMALL, "--frozen", "--hours", "0.02",
                         "--temperature", "-19")
    line = one_line(err)
    assert status == 1 and "internal error" not in line, line
    assert line.startswith("cgms dry: the moisture transport stopped: ERROR: Fix "
                           "cgms/transport: no product temperature above -20 C"), line
    assert "give warmer or more humid air" in line and "before the drying began" in line


def test_folder_filled_after_the_check_is_refused_without_resume(tmp_path, capsys, monkeypatch):
    """Two dry commands on one --out: the second checks the folder before the first has
    filled it, and its claim then refuses it; that line used to offer --resume, which dry
    does not have. (The race made certain: the folder is filled after the options' check.)"""
    from cgms.cli import dry as dry_cli
    out = tmp_path / "out"
    checked = dry_cli._tissue

    def filled_meanwhile(args, mat):
        t = checked(args, mat)
        out.mkdir()
        (out / "drying.csv").write_text("the other run's\n")
        return t
    monkeypatch.setattr(dry_cli, "_tissue", filled_meanwhile)
    status, err, _ = dry(capsys, out, *SMALL, "--frozen", "--hours", "0.01")
    line = one_line(err)
    assert status != 0 and "exists and is not empty; choose another --out" in line, line
    assert "--resume" not in line
    assert (out / "drying.csv").read_text() == "the other run's\n"
