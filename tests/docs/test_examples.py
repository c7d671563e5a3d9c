# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Every example input runs to its end (serially and on 2 ranks) and reaches steady state,
and its serial thermo output matches its reference log ``log.<date>.<name>.g++.1``.

The reference logs are runs of this plugin, not independent results: the comparison
guards against regression (a change of a law, a default, an input) and nothing more.
What the numbers are checked against independently: the NumPy oracle
``tests/reference.py`` (test_reference.py, to 1e-10), the quasi-static steady state
against the potential (test_quasistatic.py) and the paper's statements
(doc/results/validation.md)."""

import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from cgmstest import LMP, PLUGIN, ROOT, lammps_env

pytestmark = pytest.mark.lammps

EXAMPLES = sorted((ROOT / "examples").glob("*/in.*"))

#: the unit roundoff of a double
EPS = sys.float_info.epsilon / 2


def run_example(folder, example, nprocs=1):
    """Run ``example`` in ``folder`` as its header says (the environment of build/env.sh),
    with the files it reads (the example's folder but its logs); the completed process, its
    log in ``folder/log.lammps``."""
    for path in example.parent.iterdir():
        if path.is_file() and not path.name.startswith("log."):
            shutil.copy(path, folder)
    env = lammps_env()
    # the examples rely on the environment that build/env.sh sets
    env["LAMMPS_PLUGIN_PATH"] = str(Path(PLUGIN).parent)
    env["LAMMPS_POTENTIALS"] = str(ROOT / "potentials")
    cmd = [LMP, "-in", example.name, "-log", "log.lammps"]
    if nprocs > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(nprocs)] + cmd
    return subprocess.run(cmd, cwd=folder, env=env, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL, timeout=600)


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.parent.name)
def test_example_runs(tmp_path, example, nprocs):
    proc = run_example(tmp_path, example, nprocs)
    assert proc.returncode == 0, proc.stdout[-3000:]
    match = re.search(r"steady state after (\d+) steps: residual (\S+),", proc.stdout)
    assert match, proc.stdout[-2000:]
    assert float(match.group(2)) < 1e-3


def thermo_runs(text):
    """[(columns, rows)] of a LAMMPS log, one per run or minimize: ``columns`` the thermo
    header, ``rows`` the lines under it as strings (as printed), up to its Loop time."""
    runs, current = [], None
    for line in text.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            current = (words, [])
            runs.append(current)
        elif line.startswith("Loop time"):
            current = None
        elif current and len(words) == len(current[0]):
            try:
                [float(w) for w in words]
            except ValueError:
                continue                                  # a warning inside the run
            current[1].append(words)
    return runs


def printed_unit(word):
    """One unit in the last digit ``word`` shows (1e-8 for '0.12345678', 1e-15 for
    '-1.24764e-16'); 0 for an exact integer."""
    mantissa, _, exponent = word.lower().partition("e")
    digits = mantissa.split(".")[1] if "." in mantissa else ""
    return 10.0 ** (int(exponent or 0) - len(digits)) if digits or exponent else 0.0


def reference_log(example):
    name = example.name.removeprefix("in.")
    found = sorted(example.parent.glob(f"log.*.{name}.g++.1"))
    assert len(found) == 1, f"{example.parent}: one reference log log.<date>.{name}.g++.1"
    return found[0]


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.parent.name)
def test_example_matches_reference_log(tmp_path, example):
    """Serially, every run of the example prints the reference log's thermo rows.

    Tolerance per value, from what a serial run guarantees: the same build adds in the
    same order, so it reproduces the reference bitwise and only the print's rounding is
    left, one unit in the last printed digit. A build that rounds differently (another
    compiler's contractions) perturbs each step by about EPS; the examples' dynamics and
    FIRE descents are damped, so the perturbation does not grow, and after N steps it is at
    most N EPS times the column's largest magnitude. A change of summation order that
    moves a run's stop (fix halt, FIRE's force tolerance) to another step is beyond that
    and fails here: compare with the 2-rank log ``.2`` (another summation order) and
    regenerate the logs as examples/README.md says."""
    proc = run_example(tmp_path, example)
    assert proc.returncode == 0, proc.stdout[-3000:]
    ours = thermo_runs((tmp_path / "log.lammps").read_text())
    theirs = thermo_runs(reference_log(example).read_text())
    assert len(ours) == len(theirs), "the number of runs differs from the reference log"
    for k, ((columns, rows), (ref_columns, ref_rows)) in enumerate(zip(ours, theirs)):
        assert columns == ref_columns, f"run {k}: thermo columns"
        assert [r[0] for r in rows] == [r[0] for r in ref_rows], f"run {k}: thermo steps"
        steps = int(ref_rows[-1][0])
        for c, name in enumerate(columns[1:], 1):
            scale = max(abs(float(r[c])) for r in ref_rows)
            for row, ref in zip(rows, ref_rows):
                tol = printed_unit(ref[c]) + steps * EPS * scale
                assert math.isclose(float(row[c]), float(ref[c]), rel_tol=0, abs_tol=tol), \
                    f"run {k}, step {ref[0]}, {name}: {row[c]} against the reference {ref[c]}"
