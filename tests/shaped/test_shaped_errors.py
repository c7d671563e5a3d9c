# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""pair_style cgms/shaped refuses what it cannot do with one LAMMPS ERROR that names the
cause and the cure: missing per-atom properties, a minimiser that does not move F, dynamics,
a deleted fresh neighbour, a ghost cutoff shorter than a fresh bond, bad keywords."""

import pytest

import shapedlmp as sl
from cgms import positions, shaped_tensor as st, tissue
from cgmstest import PLUGIN, run_lmp
from test_shaped_minimize import start

S = 0.6


def tissue_geo():
    xy = tissue.rectangle(0.75e-3, 0.75e-3, sl.L)
    return xy, st.build(xy, sl.MAT, sl.BEST)


def error_of(folder, commands, pair="", nprocs=1, fresh=False):
    """The ERROR line of a run of the tissue (shrunk to s, or ``fresh``) with ``commands``
    after pair_coeff."""
    xy, g = tissue_geo()
    z = st.fresh_state(g) if fresh else start(g)
    proc = sl.run(folder, g, z, S, sl.BEST, sl.APPLE, commands=commands, nprocs=nprocs,
                  check=False, extra=pair)
    assert proc.returncode != 0, proc.stdout[-2000:]
    lines = [line for line in (proc.stdout + proc.stderr).splitlines() if "ERROR" in line]
    assert lines, proc.stdout[-2000:] + proc.stderr[-2000:]
    return lines[0]


@pytest.mark.lammps
@pytest.mark.parametrize("commands, words", [
    ("min_style fire\nminimize 0 1e-9 10 100\n", ["min_style fire", "cg or sd"]),
    ("min_style quickmin\nminimize 0 1e-9 10 100\n", ["quickmin", "cg or sd"]),
    ("run 10\n", ["no integrator", "minimize"]),
    ("group gone id 9\ndelete_atoms group gone compress no\nrun 0\n",
     ["fresh neighbour 9", "deleted", "before writing"]),
    ("group gone id 9\ndelete_atoms group gone\nrun 0\n", ["IDs", "compress no"]),
])
def test_what_the_style_cannot_do_is_refused(tmp_path, commands, words):
    line = error_of(tmp_path, commands)
    for w in words:
        assert w in line, line


@pytest.mark.lammps
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_a_cutoff_short_of_the_fresh_bonds_is_refused(tmp_path, nprocs):
    """The fresh tissue at s = 0.6: its bonds are longer than the LJ radius r(0.6), and
    reach 0.5 leaves the cutoff at that radius."""
    line = error_of(tmp_path, "run 0\n", pair="reach 0.5", nprocs=nprocs, fresh=True)
    assert "raise" in line and "reach" in line, line


@pytest.mark.lammps
@pytest.mark.parametrize("pair, words", [
    ("bogus 1", ["Unknown pair style cgms/shaped keyword 'bogus'", "known:"]),
    ("strip wavy", ["strip must be contour or chord"]),
    ("iso 2", ["iso 2 is out of range"]),
    ("void", ["void needs a value"]),
])
def test_bad_keywords_are_refused(tmp_path, pair, words):
    line = error_of(tmp_path, "run 0\n", pair=pair)
    for w in words:
        assert w in line, line


@pytest.mark.lammps
def test_dryness_is_required_and_checked(tmp_path):
    xy, geo = tissue_geo()
    for pair, words in [("pair_style cgms/shaped", ["needs the dryness"]),
                        ("pair_style cgms/shaped dryness 1.5", ["dryness 1.5 is out of range"])]:
        script = sl.header(geo) + f"{pair}\n"
        from cgms import shaped_data
        shaped_data.write_data(tmp_path / "tissue.data", geo, start(geo), overwrite=True)
        proc = run_lmp(tmp_path, script, check=False)
        line = next(x for x in proc.stdout.splitlines() if "ERROR" in x)
        assert all(w in line for w in words), line


@pytest.mark.lammps
def test_missing_properties_name_the_writer(tmp_path):
    """A data file of positions alone (no shaped sections)."""
    xy, geo = tissue_geo()
    positions.write_data(tmp_path / "plain.data", xy, 4 * sl.L)
    script = "\n".join([f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
                        "atom_style atomic", "atom_modify map array", "read_data plain.data",
                        "mass 1 1.0", sl.physics(S, sl.BEST, sl.APPLE), "run 0", ""])
    proc = run_lmp(tmp_path, script, check=False)
    line = next(x for x in proc.stdout.splitlines() if "ERROR" in x)
    assert "d2_shaped_F" in line and "cgms.shaped_data.write_data" in line, line


@pytest.mark.lammps
def test_no_atom_map_is_refused(tmp_path):
    xy, geo = tissue_geo()
    from cgms import shaped_data
    shaped_data.write_data(tmp_path / "tissue.data", geo, start(geo), overwrite=True)
    script = sl.header(geo).replace("atom_modify map array sort 0 0", "atom_modify sort 0 0") \
        + sl.physics(S, sl.BEST, sl.APPLE) + "run 0\n"
    proc = run_lmp(tmp_path, script, check=False)
    line = next(x for x in proc.stdout.splitlines() if "ERROR" in x)
    assert "atom_modify map array" in line, line
