# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Bad input, second part (issue 6): the cases tests/errors/test_style_input.py does not
cover. Each asserts the specific message: LAMMPS's own where it is clear (data files,
restart files, unwritable outputs), the plugin's, or the Python tools' (tissue builder
command line, morphology).

LAMMPS: the fix without the pair style, data files with missing, extra or non-numeric
columns, a truncated or corrupt restart file, a restart file read without the plugin,
outputs that cannot be written, and fix cgms/fluid keywords test_style_input.py leaves out.
Python: ``python3 -m cgms.tissue`` given an empty or self-intersecting outline, a
negative size or an output it cannot write (a message and exit status, no traceback,
no file), and cgms.morphology given a dump without the needed columns."""

import os
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cgmstest import APPLE, PLUGIN, ROOT, XREF, make_tissue, run_lmp
from cgms import morphology, tissue


def script(pair="pair_style cgms", coeff=f"pair_coeff * * {APPLE}",
           fix="fix fl all cgms/fluid dryness 0.5", read="read_data tissue.data", pre="",
           tail="run 10", plugin=True):
    return "\n".join([f"plugin load {PLUGIN}" if plugin else "", "units si", "dimension 2",
                      "boundary f f p", "atom_style cgms", "comm_modify vel yes", pre, read,
                      "neighbor 1.5e-5 bin", pair, coeff, fix, "fix nve all nve",
                      "timestep 1e-7", tail]) + "\n"


def first_error(proc):
    """The first ERROR line (LAMMPS writes it to the screen, stdout)."""
    return next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")


def lammps_error(folder, text):
    proc = run_lmp(folder, text, check=False)
    assert proc.returncode != 0, proc.stdout[-2000:]
    return first_error(proc)


@pytest.fixture
def folder(tmp_path):
    make_tissue(tmp_path, ncols=4, nrows=4)
    return tmp_path


# ------------------------------------------------------------------------------- pair / fix

@pytest.mark.parametrize("pair,coeff", [
    ("", ""),                                                    # no pair style at all
    ("pair_style lj/cut 2e-4", "pair_coeff * * 1e-20 1e-4"),     # another pair style
    ("pair_style hybrid/overlay cgms lj/cut 2e-4",               # cgms inside hybrid
     f"pair_coeff * * cgms {APPLE}\npair_coeff * * lj/cut 1e-20 1e-4"),
], ids=["none", "lj-cut", "hybrid-overlay"])
def test_fix_without_pair_cgms(folder, pair, coeff):
    """(pair cgms without the fix is in test_style_input.py)"""
    error = lammps_error(folder, script(pair=pair, coeff=coeff))
    assert "Fix cgms/fluid requires pair_style cgms" in error, error


FIX_CASES = {
    "every without variable": ("fix fl all cgms/fluid dryness 0.5 every 100", "",
                               "Fix cgms/fluid every needs a variable dryness"),
    "every negative": ("fix fl all cgms/fluid dryness v_s every -1", "variable s equal 0.5",
                       "Fix cgms/fluid every must be >= 0"),
    "dryness without value": ("fix fl all cgms/fluid dryness", "",
                              "Fix cgms/fluid keyword dryness needs a value"),
    "inertia value": ("fix fl all cgms/fluid inertia heavy", "",
                      "Fix cgms/fluid inertia must be 'fresh' or 'fluid', not 'heavy'"),
    "per-bead dryness out of range": ("fix fl all cgms/fluid dryness v_s",
                                      "variable s atom 1.3-0.1*id",
                                      "Fix cgms/fluid: dryness 1.2 of bead 1 is out of range"),
}


@pytest.mark.parametrize("case", sorted(FIX_CASES))
def test_fix_keywords(folder, case):
    fix, pre, message = FIX_CASES[case]
    error = lammps_error(folder, script(fix=fix, pre=pre))
    assert message in error, error


@pytest.mark.parametrize("pair,message", [
    ("pair_style cgms cutoff/lj 0.9", "Pair style cgms cutoff/lj must be > 1"),
    ("pair_style cgms turgor maybe", "Expected boolean parameter instead of 'maybe'"),
])
def test_pair_keywords(folder, pair, message):
    error = lammps_error(folder, script(pair=pair))
    assert message in error, error


# ------------------------------------------------------------------------------- data files

def data_with_line(folder, k, replacement):
    """The data file as bad.data with the k-th Atoms line replaced (None: the file ends
    before that line, a truncated file)."""
    lines = (folder / "tissue.data").read_text().splitlines()
    first = lines.index("Atoms # cgms") + 2
    lines = lines[:first + k] if replacement is None else \
        lines[:first + k] + [replacement] + lines[first + k + 1:]
    (folder / "bad.data").write_text("\n".join(lines) + "\n")


DATA_CASES = {
    "missing column": ("3 1 1.0e-4 2.0e-4", "Incorrect format in Atoms section of data file"),
    "extra column": ("3 1 1.0e-4 2.0e-4 0.0 7", "Incorrect format in Atoms section of data file"),
    "non-numeric coordinate": ("3 1 abc 2.0e-4 0.0",
                               "Expected floating point parameter instead of 'abc'"),
    "nan coordinate": ("3 1 nan 2.0e-4 0.0", "Expected floating point parameter instead of 'nan'"),
    "non-numeric id": ("three 1 1e-4 2.0e-4 0.0", "Expected integer parameter instead of 'three'"),
    "atom type": ("3 2 1e-4 2.0e-4 0.0", "Invalid atom type 2 in Atoms section of data file"),
    "truncated": (None, "Unexpected end of data file"),
}


@pytest.mark.parametrize("case", sorted(DATA_CASES))
def test_data_file_atoms_section(folder, case):
    line, message = DATA_CASES[case]
    data_with_line(folder, 2, line)
    error = lammps_error(folder, script(read="read_data bad.data"))
    assert message in error, error


DIAMETER_CASES = {
    "non-numeric": ("3 big", "Invalid format in Diameters section of data file '3 big'"),
    "extra column": ("3 1e-4 5", "Incorrect format in Diameters section of data file"),
    "missing line": ("", "Unexpected end of data file while reading section Diameters"),
    "negative": ("3 -0.00015", "Fix cgms/fluid: cell diameter -0.00015 of bead 3 must be > 0"),
}


@pytest.mark.parametrize("case", sorted(DIAMETER_CASES))
def test_data_file_diameters_section(tmp_path, case):
    """The Diameters section of tissue.write_data, read through fix property/atom."""
    line, message = DIAMETER_CASES[case]
    xy = tissue.hex_rectangle(4, 4, XREF)
    tissue.write_data(tmp_path / "good.data", xy, 4 * XREF, diameters=np.full(16, 150e-6))
    text = (tmp_path / "good.data").read_text()
    bad = re.sub(r"\n3 1\.4999+\de-04\n|\n3 0\.000149+\d*\n", "\n" + line + ("\n" if line else ""),
                 text)
    assert bad != text
    (tmp_path / "bad.data").write_text(bad)
    error = lammps_error(tmp_path, script(
        pre="fix diam all property/atom d_diameter",
        read="read_data bad.data fix diam NULL Diameters",
        fix="variable d atom d_diameter\nfix fl all cgms/fluid dryness 0.5 diameter v_d",
        tail="run 0"))
    assert message in error, error


def test_data_file_with_diameters_needs_the_property_fix(tmp_path):
    xy = tissue.hex_rectangle(4, 4, XREF)
    tissue.write_data(tmp_path / "tissue.data", xy, 4 * XREF, diameters=np.full(16, 150e-6))
    error = lammps_error(tmp_path, script())
    assert "Unknown identifier in data file: Diameters" in error, error


# ------------------------------------------------------------------------------- restarts

@pytest.fixture
def restart(folder):
    """A good restart file (beads 1..16 with the distinct dryness 0.5 + 0.01 id) and its
    bytes."""
    run_lmp(folder, script(fix="variable s atom 0.5+0.01*id\nfix fl all cgms/fluid dryness v_s",
                           tail="run 10\nwrite_restart good.restart"))
    return folder, (folder / "good.restart").read_bytes()


def read_restart_script(name="bad.restart", plugin=True):
    return "\n".join([f"plugin load {PLUGIN}" if plugin else "", f"read_restart {name}",
                      "comm_modify vel yes", "neighbor 1.5e-5 bin", "fix fl all cgms/fluid",
                      "fix nve all nve", "timestep 1e-7", "run 10"]) + "\n"


def test_good_restart_reads(restart):
    folder, _ = restart
    proc = run_lmp(folder, read_restart_script("good.restart"))
    assert proc.returncode == 0


@pytest.mark.parametrize("fraction", [0.95, 0.5, 0.05])
def test_truncated_restart(restart, fraction):
    folder, raw = restart
    (folder / "bad.restart").write_bytes(raw[:int(len(raw) * fraction)])
    error = lammps_error(folder, read_restart_script())
    assert "Incomplete or corrupted LAMMPS restart file" in error, error


@pytest.mark.parametrize("content", [b"", b"this is not a restart file\n",
                                     bytes(np.random.default_rng(0).integers(0, 256, 4000,
                                                                            dtype=np.uint8))],
                         ids=["empty", "text", "random"])
def test_not_a_restart_file(restart, content):
    folder, _ = restart
    (folder / "bad.restart").write_bytes(content)
    error = lammps_error(folder, read_restart_script())
    assert "Invalid LAMMPS restart file" in error, error


def test_restart_with_a_corrupt_bead_state(restart):
    """A NaN written over bead 3's dryness (found by its unique value 0.53): LAMMPS reads
    the file, and fix cgms/fluid's range check names the bead."""
    folder, raw = restart
    value = struct.pack("<d", 0.5 + 0.01 * 3)
    assert raw.count(value) == 1
    (folder / "bad.restart").write_bytes(raw.replace(value, struct.pack("<d", float("nan"))))
    error = lammps_error(folder, read_restart_script())
    assert "Fix cgms/fluid: dryness nan of bead 3 is out of range" in error, error


@pytest.mark.parametrize("field", ["version", "size"])
def test_restart_from_another_plugin_version(restart, field):
    """The material record is stored after a tag, a format version and its size:
    a file with another version or size (patched here, as a plugin version with other
    parameters would write it) stops with an error instead of being read wrongly. (A file
    of the plugin before k_S, which has no such header, was checked by hand: refused.)"""
    folder, raw = restart
    tag = struct.pack("<i", 0x43474D53)
    start = raw.find(tag)
    assert start > 0 and raw.count(tag) == 1
    version, size = struct.unpack("<ii", raw[start + 4:start + 12])
    assert version >= 1 and size > 100  # the record: name/value text of the material
    header = (version + 1, size) if field == "version" else (version, size - 8)
    patched = raw[:start] + tag + struct.pack("<ii", *header) + raw[start + 12:]
    (folder / "bad.restart").write_bytes(patched)
    error = lammps_error(folder, read_restart_script())
    assert "restart file was written by another version of the CGMS plugin" in error, error


def test_restart_without_the_plugin(restart):
    folder, _ = restart
    error = lammps_error(folder, read_restart_script("good.restart", plugin=False))
    assert "Unrecognized atom style 'cgms'" in error, error


def test_missing_restart_file(restart):
    folder, _ = restart
    error = lammps_error(folder, read_restart_script("nowhere.restart"))
    assert "Cannot open restart file nowhere.restart: No such file or directory" in error


# ------------------------------------------------------------------------------- outputs

@pytest.mark.parametrize("command,message", [
    ("write_dump all atom {path}.dump", "Cannot open dump file"),
    ("dump d all atom 1 {path}.dump\nrun 1", "Cannot open dump file"),
    ("write_restart {path}.restart", "Cannot open restart file {path}.restart: No such file"),
    ("write_data {path}.data", "Cannot open data file {path}.data: No such file"),
], ids=["write_dump", "dump", "write_restart", "write_data"])
def test_unwritable_lammps_output(folder, command, message):
    path = str(folder / "no" / "such" / "dir" / "out")
    error = lammps_error(folder, script(tail="run 0\n" + command.format(path=path)))
    assert message.format(path=path) in error, error


# ------------------------------------------------------------------------------- builder CLI

def cgms_tissue(folder, *args):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "cgms.tissue", *args], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=120)


CLI_CASES = {
    "empty outline": (["polygon", "empty.txt"], "", 2,
                      "cgms.tissue: polygon is empty: give at least 3 vertices"),
    "outline of comments only": (["polygon", "comments.txt"], "# metres\n\n", 2,
                                 "cgms.tissue: polygon is empty"),
    "self-intersecting outline": (["polygon", "bow.txt"], "0 0\n1e-3 1e-3\n1e-3 0\n0 1e-3\n", 2,
                                  "cgms.tissue: polygon is self-intersecting: edge 0"),
    "non-numeric vertex": (["polygon", "words.txt"], "0 0\n1e-3 zero\n0 1e-3\n", 2,
                           "cgms.tissue: words.txt line 2: not numbers: '1e-3 zero'"),
    "missing vertex file": (["polygon", "nowhere.txt"], None, 2,
                            "cgms.tissue: No such file or directory: nowhere.txt"),
    "negative width": (["rect", "-1", "2"], None, 2,
                       "cgms.tissue: width must be positive, got -1"),
    "negative radius": (["disc", "-0.5"], None, 2,
                        "cgms.tissue: radius must be positive, got -0.5"),
    "negative spacing": (["rect", "1", "1", "--spacing", "-5"], None, 2,
                         "cgms.tissue: spacing must be positive, got -5"),
    "negative cv": (["rect", "1", "1", "--cv", "-0.1"], None, 2,
                    "cgms.tissue: cv must be >= 0, got -0.1"),
    "output in a missing folder": (["rect", "1", "1", "--out", "no/such/dir/t.data"], None, 2,
                                   "cgms.tissue: No such file or directory: "
                                   "no/such/dir/t.data"),
    "output is a folder": (["rect", "1", "1", "--out", "adir", "--force"], None, 2,
                           "cgms.tissue: Is a directory: adir"),
}


@pytest.mark.parametrize("case", sorted(CLI_CASES))
def test_tissue_command_line(tmp_path, case):
    args, vertices, status, message = CLI_CASES[case]
    if vertices is not None:
        (tmp_path / args[1]).write_text(vertices)
    (tmp_path / "adir").mkdir()
    before = sorted(p.name for p in tmp_path.iterdir())
    proc = cgms_tissue(tmp_path, *args)
    assert proc.returncode == status, proc.stderr
    assert proc.stderr.startswith(message), proc.stderr
    assert "Traceback" not in proc.stderr and proc.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written
    assert not list((tmp_path / "adir").iterdir())


# ------------------------------------------------------------------------------- morphology

@pytest.fixture(scope="module")
def dumps(tmp_path_factory):
    """LAMMPS dumps of a 16-bead tissue with and without coordinate columns."""
    folder = tmp_path_factory.mktemp("dumps")
    make_tissue(folder, ncols=4, nrows=4, jitter=0.0)
    run_lmp(folder, script(tail="run 0\n"
                                "write_dump all custom velocities.dump id type vx vy\n"
                                "write_dump all custom xonly.dump id type x vx\n"
                                "write_dump all custom noid.dump type x y\n"
                                "write_dump all custom good.dump id type x y z"))
    return folder


@pytest.mark.parametrize("name,message", [
    ("velocities.dump", "no column 'x' and 'y' (nor xu yu, xs ys, xsu ysu) in ITEM: ATOMS "
                        "id type vx vy"),
    ("xonly.dump", "no column 'y' (nor xu yu, xs ys, xsu ysu) in ITEM: ATOMS id type x vx"),
    ("noid.dump", "no column 'id' in ITEM: ATOMS type x y"),
])
def test_morphology_of_a_dump_without_needed_columns(dumps, name, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        morphology.read_dump(dumps / name)


def test_morphology_asks_for_a_missing_per_bead_column(dumps):
    with pytest.raises(ValueError, match=re.escape("no column 'pressure' in ITEM: ATOMS "
                                                   "id type x y z")):
        morphology.read_dump(dumps / "good.dump", columns=["pressure"])


def test_morphology_of_a_data_file(dumps):
    with pytest.raises(ValueError, match=re.escape("line 1: expected 'ITEM: ...'")):
        morphology.read_dump(dumps / "tissue.data")


def test_morphology_of_a_single_row(dumps):
    """A dump is readable, but a single row of beads has no outline."""
    frame = morphology.read_dump(dumps / "good.dump")[-1]
    row = frame["xy"][frame["ids"] <= 4]  # the first row of the lattice
    with pytest.raises(ValueError, match="all 4 beads are collinear"):
        morphology.measures(row)


def test_restart_of_another_row_layout(folder):
    """A restart file written when the bead's row had 14 columns (tests/data/README.md):
    read with this build's 8 columns it would come in shifted (the first symptom seen was a
    dryness of -5.6e-5); atom_style cgms refuses it and says what to do."""
    shutil.copy(Path(__file__).parents[1] / "data" / "row14.restart", folder / "bad.restart")
    error = lammps_error(folder, read_restart_script())
    assert "Restart file has 35 values per bead where atom_style cgms reads 20" in error, error
    assert "written by another CGMS version" in error
