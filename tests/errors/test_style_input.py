# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Bad input stops with a LAMMPS ERROR that names the problem."""

import pytest

from cgmstest import APPLE, PLUGIN, make_tissue, run_lmp

pytestmark = pytest.mark.lammps

GOOD = {
    "units": "units si",
    "dimension": "dimension 2",
    "atom_style": "atom_style cgms",
    "comm": "comm_modify vel yes",
    "pair": "pair_style cgms",
    "coeff": f"pair_coeff * * {APPLE}",
    "fix": "fix fl all cgms/fluid dryness 0.5",
}


def script(**change):
    c = dict(GOOD, **change)
    return "\n".join([f"plugin load {PLUGIN}", c["units"], c["dimension"], "boundary f f p",
                      c["atom_style"], c["comm"], "read_data tissue.data",
                      "neighbor 1.5e-5 bin", c["pair"], c["coeff"], c["fix"], "fix nve all nve",
                      "timestep 1e-7", "run 10"]) + "\n"


CASES = {
    "units": (dict(units="units metal"), "Pair style cgms requires units si"),
    "dimension": (dict(dimension="dimension 3"), "requires dimension 2"),
    "atom style": (dict(atom_style="atom_style atomic"), "requires atom_style cgms"),
    "no fix": (dict(fix=""), "requires fix cgms/fluid"),
    "no ghost velocities": (dict(comm=""), "requires 'comm_modify vel yes'"),
    "two fixes": (dict(fix="fix fl all cgms/fluid\nfix f2 all cgms/fluid"),
                  "Only one fix cgms/fluid"),
    "dryness zero": (dict(fix="fix fl all cgms/fluid dryness 0"), "dryness 0 is out of range"),
    "dryness above one": (dict(fix="fix fl all cgms/fluid dryness 1.2"), "out of range"),
    "fix keyword": (dict(fix="fix fl all cgms/fluid wetness 0.5"),
                    "Unknown fix cgms/fluid keyword 'wetness'"),
    "pair keyword": (dict(pair="pair_style cgms friction yes"),
                     "Unknown pair style cgms keyword 'friction'"),
    "small cutoff": (dict(pair="pair_style cgms cutoff 1e-4"),
                     "is not above the lattice spacing"),
    "negative coefficient": (dict(coeff=f"pair_coeff * * {APPLE} k_T -1"),
                             "k_T = -1 must be > 0"),
    "negative shape stiffness": (dict(coeff=f"pair_coeff * * {APPLE} k_S -0.5"),
                                 "k_S = -0.5 must be >= 0"),
    "unknown parameter": (dict(coeff=f"pair_coeff * * {APPLE} k_X 1"),
                          "unknown CGMS parameter 'k_X'"),
    "non-numeric parameter": (dict(coeff=f"pair_coeff * * {APPLE} k_T soft"),
                              "value 'soft' of parameter k_T is not a number"),
    "missing file": (dict(coeff="pair_coeff * * nowhere.cgms"),
                     "Cannot open CGMS material file nowhere.cgms"),
    "one type pair": (dict(coeff=f"pair_coeff 1 1 {APPLE}"), "must start with * *"),
    "dryness variable": (dict(fix="fix fl all cgms/fluid dryness v_nothing"),
                         "Variable nothing for fix cgms/fluid dryness does not exist"),
    "group": (dict(fix="group g id 1\nfix fl g cgms/fluid"), "must be applied to group all"),
    "diameter": (dict(fix="fix fl all cgms/fluid diameter -1e-4"), "diameter -0.0001 must be > 0"),
    "diameter variable": (dict(fix="variable d atom 1e-4-id*1e-5\nfix fl all cgms/fluid diameter v_d"),
                          "cell diameter 0 of bead 10 must be > 0"),
    "dryness variable style": (dict(fix="variable t string abc\nfix fl all cgms/fluid dryness v_t"),
                               "must be equal- or atom-style"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_input_gives_error(tmp_path, case):
    make_tissue(tmp_path, ncols=4, nrows=4)
    change, message = CASES[case]
    proc = run_lmp(tmp_path, script(**change), check=False)
    assert proc.returncode != 0
    errors = [line for line in proc.stdout.splitlines() if "ERROR" in line]
    assert errors and message in errors[0], f"expected {message!r}, got {errors}"


def material_file_case(tmp_path, text):
    (tmp_path / "bad.cgms").write_text(text)
    make_tissue(tmp_path, ncols=4, nrows=4)
    proc = run_lmp(tmp_path, script(coeff="pair_coeff * * bad.cgms"), check=False)
    assert proc.returncode != 0
    return "\n".join(line for line in proc.stdout.splitlines() if "ERROR" in line)


def test_material_file_missing_parameter(tmp_path):
    text = "\n".join(line for line in open(APPLE).read().splitlines()
                     if not line.startswith("K "))
    assert "CGMS parameter K is missing" in material_file_case(tmp_path, text)


def test_material_file_malformed_line(tmp_path):
    text = open(APPLE).read() + "\nL_p 1 2\n"
    assert "expected 'name value'" in material_file_case(tmp_path, text)


def test_material_file_wrong_units(tmp_path):
    text = open(APPLE).read().replace("UNITS: si", "UNITS: metal")
    assert "requires metal units but si units are in use" in material_file_case(tmp_path, text)


def test_isolated_bead(tmp_path):
    make_tissue(tmp_path, ncols=4, nrows=4)
    data = (tmp_path / "tissue.data").read_text().replace("16 atoms", "17 atoms")
    (tmp_path / "tissue.data").write_text(data.rstrip() + "\n17 1 -5e-4 -5e-4 0.0\n")
    proc = run_lmp(tmp_path, script(), check=False)
    assert "bead 17 has no neighbour" in proc.stdout
    ok = run_lmp(tmp_path, script(fix="fix fl all cgms/fluid dryness 0.5 isolated allow"),
                 check=False)
    assert ok.returncode == 0, ok.stdout[-2000:]


def test_hybrid_atom_style_refused(tmp_path):
    make_tissue(tmp_path, ncols=4, nrows=4)
    text = script(atom_style="atom_style hybrid cgms sphere").replace(
        "read_data tissue.data", "region b block 0 1e-3 0 1e-3 -1e-4 1e-4\ncreate_box 1 b")
    proc = run_lmp(tmp_path, text, check=False)
    assert proc.returncode != 0
    assert "Atom style cgms cannot be used as a sub-style of atom_style hybrid" in proc.stdout


def test_replicate_stops_cleanly(tmp_path):
    """replicate builds a second Atom without plugin styles: LAMMPS must stop with an
    ERROR, not crash. (The fix property/atom CGMS that atom_style cgms defines for data
    files makes replicate refuse first.)"""
    make_tissue(tmp_path, ncols=4, nrows=4)
    text = f"plugin load {PLUGIN}\nunits si\ndimension 2\natom_style cgms\n" \
           "read_data tissue.data\nreplicate 2 1 1\n"
    proc = run_lmp(tmp_path, text, check=False)
    assert proc.returncode == 1
    assert "ERROR: Cannot replicate with fixes that store per-atom quantities" in proc.stdout
