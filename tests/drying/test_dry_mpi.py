# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms dry`` under mpirun (doc/drying.md, Limits): one folder, the serial
result, one message, one exit status."""

import csv
import subprocess
import sys

import numpy as np
import pytest

from cgmstest import lammps_env

#: the 86-bead tissue of test_drying.py, dried to X/X0 = 0.7 (10 shape solves)
DRY = ["-m", "cgms", "dry", "--width", "1.25", "--height", "1.5", "--hours", "2", "--stop",
       "0.7", "--layers", "4", "--resolve", "0.05", "--maps", "0.9"]
MPIRUN = ["mpirun", "--oversubscribe", "-np", "2"]
#: longest a run under mpirun may take before it counts as hung (it takes about 7 s on an
#: idle machine; 120 s was once exceeded under load 7, so the bound is the suite's usual 600 s)
TIMEOUT = 600


def dry(cwd, *options, mpi=False):
    return subprocess.run((MPIRUN if mpi else []) + [sys.executable] + DRY + list(options),
                          cwd=cwd, env=lammps_env(), capture_output=True, text=True,
                          timeout=TIMEOUT)


def read_rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def own_lines(text):
    """The lines cgms wrote (mpirun adds its own notices)."""
    return [ln for ln in text.splitlines() if ln.startswith("cgms dry")]


@pytest.mark.mpi
def test_dry_under_mpirun_gives_the_serial_result(tmp_path):
    """One folder with the serial run's files, and its drying curve and shape.

    Tolerances, from the shape solver's stopping rule, as test_drying_under_mpi derives
    them for this tissue (tests/README.md, "Tolerances across configurations"), here at
    the CLI's FIRE tolerance, ftol = 1e-10 N (drying.LEVERS): each solve stops with
    |r|_2 <= sqrt(86) ftol = 9.3e-10 N, and |H+ grad m| / m is 6.7e4 /N (area), 4.7e5 /N
    (perimeter), 5.7e6 /N (elongation). Two runs, each anywhere in its ball: the area
    1.2e-4, the perimeter 8.7e-4, the elongation 1.1e-2 apart.
    - X/X0: the water leaves through faces and outline edges whose sizes are off by at
      most 8.7e-4 relative: asserted 9e-4;
    - A/A0, a ratio of two solves: 2 x 1.2e-4, plus 0.42 x the dryness error (X/X0's):
      6.1e-4, asserted 7e-4;
    - EL/EL0: 2 x 1.1e-2 plus 0.4 x 8.7e-4: asserted 2.3e-2.
    The solves' triggers agree unless a value falls within these of a threshold: the same
    rows. Every solve must have stopped on its force tolerance (the premise), which the
    logs say."""
    serial = dry(tmp_path, "--out", "serial")
    assert serial.returncode == 0, serial.stderr[-2000:]
    parallel = dry(tmp_path, "--out", "np2", mpi=True)
    assert parallel.returncode == 0, parallel.stdout[-2000:] + parallel.stderr[-2000:]
    # one folder (process 1 made none), the same files, each message once
    assert sorted(p.name for p in tmp_path.iterdir()) == ["np2", "serial"]
    files = {tag: sorted(p.name for p in (tmp_path / tag).iterdir())
             for tag in ("serial", "np2")}
    assert files["serial"] == files["np2"] and "drying.csv" in files["np2"], files
    assert len(own_lines(parallel.stdout)) == len(own_lines(serial.stdout)) == 3
    assert parallel.stderr.strip() == "", parallel.stderr
    for tag in ("serial", "np2"):
        stops = [ln for ln in (tmp_path / tag / "log.lammps").read_text().splitlines()
                 if "Stopping criterion" in ln]
        assert len(stops) > 5 and all("force tolerance" in ln for ln in stops), stops
    rows = {tag: read_rows(tmp_path / tag / "drying.csv") for tag in ("serial", "np2")}
    assert len(rows["serial"]) == len(rows["np2"]) > 10
    for key, tol in (("X/X0", 9e-4), ("A/A0", 7e-4), ("EL/EL0", 2.3e-2)):
        a, b = (np.array([float(r[key]) for r in rows[tag]]) for tag in ("serial", "np2"))
        assert np.abs(a - b).max() < tol, (key, np.abs(a - b).max())
    assert [r["solves"] for r in rows["serial"]] == [r["solves"] for r in rows["np2"]]


@pytest.mark.mpi
@pytest.mark.parametrize("options, status, words", [
    (["--temperature", "500"], 2, "--temperature must be"),           # every process
    (["--solver", "bogus"], 2, "invalid choice: 'bogus'"),             # argparse's
    (["--out", "a-file"], 1, "--out a-file is a file"),                # process 0 only
])
def test_dry_under_mpirun_refuses_once(tmp_path, options, status, words):
    """A bad option stops every process before LAMMPS starts, with the same status and
    one message, also when only process 0 (which alone claims the folder) finds it."""
    (tmp_path / "a-file").write_text("")
    proc = dry(tmp_path, *options, mpi=True)
    assert proc.returncode == status, proc.stderr
    lines = own_lines(proc.stderr)
    assert len(lines) == 1 and words in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr and proc.stdout == "", proc.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]
