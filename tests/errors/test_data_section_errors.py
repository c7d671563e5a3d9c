# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A data file's CGMS section is checked line by line (issue 26, "Data-file sections").

A tissue is run a few steps and written with write_data; its CGMS section is then spoilt
one way at a time: a value out of its column's range (NaN, infinite, negative, zero where
the column needs a positive value, a dryness above 1), a bead's line twice (so another bead
has none), a bead without a line, a "no state" line with other values. Each stops with an
ERROR that names the bead, the column, the value and the cure, where it used to give the
bead the fresh state without a word (or, for masses and l0p, to blame the time step or
k_S later). The natural 'read_data FILE' of such a file names the keyword that reads it."""

import re

import pytest

from cgmstest import header, make_tissue, physics, read_dump, run_lmp
from plugin.test_lammps_data_file import reread

pytestmark = pytest.mark.lammps

COLUMNS = ["dryness", "mf", "ms", "mf0", "l0p", "rho", "area", "dmdt"]
NBEADS = 16


@pytest.fixture(scope="module")
def dried(tmp_path_factory):
    """The text of a data file with a CGMS section (a 4 x 4 tissue after 20 steps)."""
    folder = tmp_path_factory.mktemp("dried")
    make_tissue(folder, ncols=4, nrows=4, s=0.6)
    run_lmp(folder, header() + physics() + "run 20\nwrite_data dried.data\n")
    return (folder / "dried.data").read_text()


def section(text):
    """(start, end) line indices of the CGMS section's bead lines."""
    lines = text.splitlines()
    head = next(k for k, line in enumerate(lines) if line.split("#")[0].strip() == "CGMS")
    return lines, head + 2, head + 2 + NBEADS


def with_line(text, bead, values, new_id=None):
    """``text`` with bead ``bead``'s CGMS line replaced by ``values`` (the 8 columns),
    under ``new_id`` if given."""
    lines, first, last = section(text)
    for k in range(first, last):
        if lines[k].split()[0] == str(bead):
            lines[k] = " ".join([str(new_id or bead)] + [str(v) for v in values])
    return "\n".join(lines) + "\n"


def row(text, bead):
    lines, first, last = section(text)
    return next(lines[k].split()[1:] for k in range(first, last)
                if lines[k].split()[0] == str(bead))


def run_reread(folder, text, nprocs=1, fix_keyword=True, tail="run 0\n"):
    (folder / "mid.data").write_text(text)
    return run_lmp(folder, reread(nprocs, "", fix_keyword=fix_keyword) + tail, nprocs=nprocs,
                   check=False)


def error_line(proc):
    return next((r for r in proc.stdout.splitlines() if "ERROR" in r), "")


BAD = [  # column, value, what the message says about it
    ("mf0", "nan", "mf0 = nan, not a finite number"),
    ("mf0", "-5e-11", "mf0 = -5e-11: it must be > 0 (or -1 for a bead without a fluid state)"),
    ("mf0", "0", "mf0 = 0: it must be > 0"),
    ("dryness", "0", "dryness = 0, outside (0, 1]"),
    ("dryness", "1.5", "dryness = 1.5, outside (0, 1]"),
    ("dryness", "-nan", "dryness = -nan, not a finite number"),
    ("mf", "-1e-12", "mf = -1e-12: it must be > 0"),
    ("mf", "inf", "mf = inf, not a finite number"),
    ("ms", "-1e-12", "ms = -1e-12: it must be >= 0"),
    ("ms", "nan", "ms = nan, not a finite number"),
    ("l0p", "0", "l0p = 0: it must be > 0"),
    ("rho", "0", "rho = 0: it must be > 0"),
    ("area", "-1e-9", "area = -1e-09: it must be >= 0"),
    ("dmdt", "-inf", "dmdt = -inf, not a finite number"),
]


@pytest.mark.parametrize("column, value, message", BAD, ids=[f"{c}={v}" for c, v, _ in BAD])
def test_a_bad_value_names_bead_column_value_and_cure(tmp_path, dried, column, value, message):
    values = row(dried, 7)
    values[COLUMNS.index(column)] = value
    proc = run_reread(tmp_path, with_line(dried, 7, values))
    assert proc.returncode != 0
    error = error_line(proc)
    assert "the line of bead 7 in the data file's CGMS section has " + message in error, error
    assert "correct the line" in error   # the cure
    # not the later symptoms the bad value used to cause
    assert not re.search(r"time step|k_S|unstable|fresh reference", proc.stdout)


def test_the_original_file_reads_and_runs(tmp_path, dried):
    """the checks pass the file write_data wrote (the control of the cases above)"""
    proc = run_reread(tmp_path, dried, tail="run 10\n")
    assert proc.returncode == 0, proc.stdout[-2000:]
    assert "fresh reference cell" not in proc.stdout


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_a_duplicated_line_is_named_at_read_data(tmp_path, dried, nprocs):
    """bead 5's line twice, bead 2's gone: read_data stops, naming both lines"""
    proc = run_reread(tmp_path, with_line(dried, 2, row(dried, 5), new_id=5), nprocs=nprocs)
    error = error_line(proc)
    assert proc.returncode != 0
    assert re.search(r"bead 5 has two lines in the CGMS section \(lines \d+ and \d+\)", error), \
        error
    assert "give every bead exactly one line" in error


def test_a_bead_without_a_line_is_named_at_setup(tmp_path, dried):
    """the last bead renumbered in Atoms and Velocities (ID 17): the section's line for 16
    matches no bead (fix property/atom skips it), and bead 17 gets none"""
    lines = dried.splitlines()
    for name in ("Atoms", "Velocities"):
        head = next(k for k, line in enumerate(lines) if line.split("#")[0].strip() == name)
        for k in range(head + 2, head + 2 + NBEADS):
            if lines[k].split()[0] == str(NBEADS):
                lines[k] = str(NBEADS + 1) + lines[k][len(str(NBEADS)):]
    proc = run_reread(tmp_path, "\n".join(lines) + "\n")
    error = error_line(proc)
    assert f"bead {NBEADS + 1} has no line in the data file's CGMS section" in error, error


def test_a_no_state_line_starts_fresh_and_a_spoilt_one_is_refused(tmp_path, dried):
    """'id 0 0 0 -1 0 0 0 0' (what write_data writes for a bead without a state) is read
    as such; the same with another value set is refused"""
    fresh = [0, 0, 0, -1, 0, 0, 0, 0]
    proc = run_reread(tmp_path, with_line(dried, 3, fresh), tail=(
        "compute p all property/atom dryness mf mf0\nrun 0\n"
        "write_dump all custom state.dump id c_p[*] modify sort id format float %.17g\n"))
    assert proc.returncode == 0, proc.stdout[-2000:]
    state = read_dump(tmp_path / "state.dump")
    s, mf, mf0 = state["c_p[1]"], state["c_p[2]"], state["c_p[3]"]
    # bead 3 starts fresh: dryness 1 (the fix has no dryness keyword), mf = mf0
    assert s[2] == 1.0 and mf[2] == mf0[2]
    # bead 4 keeps the file's dried state, bit for bit
    assert [s[3], mf[3], mf0[3]] == [float(row(dried, 4)[k]) for k in (0, 1, 3)]
    assert s[3] < 0.7
    spoilt = list(fresh)
    spoilt[0] = 0.5
    proc = run_reread(tmp_path, with_line(dried, 3, spoilt))
    assert "mf0 = -1 (no fluid state) but dryness = 0.5" in error_line(proc), error_line(proc)


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_natural_read_data_names_the_keyword(tmp_path, dried, nprocs):
    """'read_data mid.data' of a file with the section: the ERROR gives the command that
    reads it (LAMMPS's own "Unknown identifier in data file: CGMS" cannot)"""
    proc = run_reread(tmp_path, dried, nprocs=nprocs, fix_keyword=False)
    error = error_line(proc)
    assert "read the file with 'read_data mid.data fix CGMS NULL CGMS'" in error, proc.stdout[-2000:]


def test_write_data_before_a_run_keeps_the_state_read(tmp_path, dried):
    """a state read but not yet taken over at a setup is written again as read"""
    (tmp_path / "mid.data").write_text(dried)
    proc = run_lmp(tmp_path, reread(1, "") + "write_data again.data\n", check=False)
    assert proc.returncode == 0, proc.stdout[-2000:]
    again = (tmp_path / "again.data").read_text()
    for bead in range(1, NBEADS + 1):
        assert [float(v) for v in row(again, bead)] == [float(v) for v in row(dried, bead)]


OTHER = [  # the section, the column spoilt (None: a Masses section added), what stops it
    ("Atoms", 2, "nan", "Expected floating point parameter instead of 'nan'"),
    ("Atoms", 3, "-inf", "Expected floating point parameter instead of '-inf'"),
    ("Velocities", 1, "nan", "Expected floating point parameter instead of 'nan'"),
    ("Masses", None, "-1", "Cannot set mass for atom style cgms"),
]


@pytest.mark.parametrize("name, column, value, message", OTHER,
                         ids=[f"{n}-{v}" for n, _, v, _ in OTHER])
def test_other_sections_refuse_nan_and_masses(tmp_path, dried, name, column, value, message):
    """the rest of the file: LAMMPS refuses a NaN or infinite position or velocity, and a
    Masses section (the masses come from the CGMS section), before any step runs"""
    lines = dried.splitlines()
    if column is None:
        head = next(k for k, line in enumerate(lines) if line.startswith("Atoms"))
        lines[head:head] = ["Masses", "", f"1 {value}", ""]
    else:
        head = next(k for k, line in enumerate(lines) if line.split("#")[0].strip() == name)
        words = lines[head + 2].split()
        words[column] = value
        lines[head + 2] = " ".join(words)
    proc = run_reread(tmp_path, "\n".join(lines) + "\n")
    assert message in error_line(proc), error_line(proc)
