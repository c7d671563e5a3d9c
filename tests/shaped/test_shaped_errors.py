# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""pair_style cgms/shaped refuses what it cannot do with one LAMMPS ERROR that names the
cause and the cure: missing per-atom properties, a minimiser that does not move F, dynamics,
a deleted fresh neighbour, a ghost cutoff shorter than a fresh bond, bad keywords."""

import numpy as np
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


# ---- the adversarial pass (doc/results/robustness.md, 2026-12-03) ----

MIN = "min_style cg\nmin_modify dmax 1e-6 norm max line forcezero\n"


def error_line(proc):
    assert proc.returncode != 0, proc.stdout[-2000:]
    lines = [line for line in (proc.stdout + proc.stderr).splitlines() if "ERROR" in line]
    assert lines, proc.stdout[-2000:] + proc.stderr[-2000:]
    return lines[0]


@pytest.mark.lammps
@pytest.mark.parametrize("pair, commands, words", [
    # a keyword whose value is missing in the middle takes the next keyword as its value
    ("lamella void 0.05", "run 0\n", ["keyword lamella needs a number, not 'void'"]),
    ("beta_b wide", "run 0\n", ["keyword beta_b needs a number"]),
    ("reach 1e300", "run 0\n", ["reach 1e300 is out of range", "<= 10"]),
    # values that overflow the energy or the minimiser's force norm, and the contour
    # smoothing that turns every cell inside out: refused at the first evaluation
    ("wall_EA 1e300", MIN + "minimize 0 0 20 1000\n", ["not finite", "wall_EA"]),
    ("soft 1e300", MIN + "minimize 0 0 20 1000\n", ["not finite", "soft"]),
    ("kg_ratio 1e300", MIN + "minimize 0 0 20 1000\n", ["not finite", "kg_ratio"]),
    ("beta_a 1e300", MIN + "minimize 0 0 20 1000\n", ["not finite", "beta_a"]),
    ("beta_b 1e300", "run 0\n", ["not finite", "beta_b"]),
    ("smooth 1e300", MIN + "minimize 0 0 20 1000\n", ["inside out", "smooth"]),
])
def test_values_out_of_physical_range_are_refused(tmp_path, pair, commands, words):
    line = error_of(tmp_path, commands, pair=pair)
    for w in words:
        assert w in line, line


def edited_data(folder, edit):
    """The error tissue's data file with ``edit(rows)`` applied to the rows (lists of
    words) of its shaped_nb section (bead ID, NB neighbour IDs, own ID, nwall, boundary,
    area0)."""
    xy, geo = tissue_geo()
    from cgms import shaped_data
    shaped_data.write_data(folder / "tissue.data", geo, start(geo), overwrite=True)
    lines = (folder / "tissue.data").read_text().splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("shaped_nb"))
    rows = [line.split() for line in lines[k + 2:k + 2 + geo["n"]]]
    edit(rows)
    lines[k + 2:k + 2 + geo["n"]] = [" ".join(r) for r in rows]
    (folder / "tissue.data").write_text("\n".join(lines) + "\n")
    return geo


def drop_neighbour(rows, bead, nb):
    """Bead ``bead`` forgets neighbour ``nb`` (its bond vector stays: the lists only)."""
    r = rows[bead - 1]
    ids = [w for w in r[1:7] if w != str(nb)]
    r[1:7] = ids + ["0"] * (6 - len(ids))


@pytest.mark.lammps
@pytest.mark.parametrize("edit, words", [
    (lambda rows: rows[0].__setitem__(1, "999"), ["bead 1 lists fresh neighbour 999", "write_data"]),
    (lambda rows: rows[0].__setitem__(1, "1"), ["bead 1 lists fresh neighbour 1", "the bead itself"]),
    (lambda rows: rows[1].__setitem__(2, rows[1][1]), ["bead 2 lists fresh neighbour", "twice"]),
    (lambda rows: drop_neighbour(rows, 2, 1), ["not symmetric", "write_data"]),
    (lambda rows: rows[0].__setitem__(8, "7"), ["bead 1 has fewer than 3 walls, more walls",
                                                "(6)"]),
])
def test_damaged_fresh_data_is_refused(tmp_path, edit, words):
    geo = edited_data(tmp_path, edit)
    script = sl.header(geo) + sl.physics(S, sl.BEST, sl.APPLE) + "run 0\n"
    line = error_line(run_lmp(tmp_path, script, check=False))
    for w in words:
        assert w in line, line


@pytest.mark.lammps
@pytest.mark.parametrize("commands, words", [
    ("create_atoms 1 single 3e-4 3e-4 0\nrun 0\n", ["bead 24 has no fresh data", "create_atoms"]),
    # a boundary bead: its neighbours' lists are unanswered, the deletion is the cause named
    ("group gone id 1\ndelete_atoms group gone compress no\nrun 0\n",
     ["fresh neighbour 1 no longer exists", "before writing"]),
])
def test_beads_added_or_removed_after_read_data_are_refused(tmp_path, commands, words):
    line = error_of(tmp_path, commands)
    for w in words:
        assert w in line, line


def final_state(folder, script, nprocs=1):
    run_lmp(folder, script + "write_dump all custom f.dump id x y d2_shaped_F[*] modify "
            "format float %.17g sort id\n", nprocs=nprocs)
    return np.loadtxt(folder / "f.dump", skiprows=9)


@pytest.mark.lammps
def test_dryness_changed_by_pair_style_keeps_the_state(tmp_path):
    """pair_style again with another dryness (doc: the way to change the level) keeps F and
    x and the material: the next 'run 0' evaluates the state the minimiser left."""
    xy, geo = tissue_geo()
    from cgms import shaped_data
    shaped_data.write_data(tmp_path / "tissue.data", geo, start(geo), overwrite=True)
    base = sl.header(geo) + sl.physics(S, sl.BEST, sl.APPLE) + MIN + "minimize 0 0 10 1000\n"
    before = final_state(tmp_path, base)
    after = final_state(tmp_path, base + sl.physics(0.5, sl.BEST, sl.APPLE).splitlines()[0]
                        + "\nrun 0\n")
    assert np.array_equal(before, after)


@pytest.mark.lammps
@pytest.mark.mpi
def test_sorting_and_two_ranks_rebuilding_every_step_follow_serial(tmp_path):
    """atom_modify sort and 2 ranks with a new neighbour list (exchange, sort) at every
    step: the per-atom F travels with its bead. Ten CG iterations from the same state agree
    with the serial unsorted run to rounding (the sums run in another order: 1e-9 relative
    leaves a factor 1e6 over the 1e-15 differences found, far below the 1e-3 F moves)."""
    xy, geo = tissue_geo()
    from cgms import shaped_data
    shaped_data.write_data(tmp_path / "tissue.data", geo, start(geo), overwrite=True)
    tail = sl.physics(S, sl.BEST, sl.APPLE) + MIN + "minimize 0 0 10 100000\n"
    serial = final_state(tmp_path, sl.header(geo) + tail)
    moved = sl.header(geo, nprocs=2).replace("sort 0 0", "sort 1 1e-4").replace(
        "check yes", "check no")
    other = final_state(tmp_path, moved + tail, nprocs=2)
    assert np.abs(other[:, 1:3] - serial[:, 1:3]).max() <= 1e-9 * sl.L
    assert np.abs(other[:, 3:] - serial[:, 3:]).max() <= 1e-9
