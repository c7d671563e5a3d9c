# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The per-bead outputs (issue 18): the per-bead row holds the state only, and fix
cgms/fluid derives the neighbour count, side, perimeter, pressure, l_d and pair
coefficient when an output asks. Every way to read them gives the numbers of the step it
is read at: compute property/atom (on demand, any step), the fix's per-atom array f_ID[k]
(filled on the steps the run's thermo and dumps write; LAMMPS refuses other steps), the
library's extract_fix after a run, and `output 1` (filled every step) as the baseline."""

import numpy as np
import pytest

from cgmstest import header, make_tissue, physics, read_dump, run_lmp

pytestmark = pytest.mark.lammps

NAMES = ["cgmscoef", "dryness", "nneigh", "side", "mf", "ms", "mf0", "l0p", "rho", "pressure",
         "area", "perim", "ldeq", "dmdt"]
PROP = "compute prop all property/atom " + " ".join(NAMES) + "\n"
COLUMNS = "id " + " ".join(f"f_fl[{k + 1}]" for k in range(14)) + " c_prop[*]"


@pytest.fixture
def folder(tmp_path):
    # a dryness that varies by bead and velocities: every output column moves each step
    make_tissue(tmp_path, ncols=6, nrows=6, jitter=0.08, seed=3, s=(0.5, 1.0), vscale=1e-3)
    return tmp_path


def dumped_run(folder, name, fix_args, thermo=10, steps=37):
    """Dumps every 10 steps and after the run (step 37, no thermo or dump step)."""
    body = (PROP + f"thermo {thermo}\n"
            f"dump d all custom 10 {name}.*.dump {COLUMNS}\n"
            "dump_modify d format float %.17g\n"
            f"run {steps}\n"
            f"write_dump all custom {name}.end.dump {COLUMNS} modify format float %.17g\n")
    run_lmp(folder, header() + physics(fix_args=fix_args) + body)
    return {step: read_dump(folder / f"{name}.{step}.dump") for step in ("10", "20", "30", "end")}


def test_every_reader_sees_the_step_it_reads(folder):
    auto = dumped_run(folder, "auto", "")
    every = dumped_run(folder, "every", "output 1")
    for step, frame in auto.items():
        for k, name in enumerate(NAMES):
            fix_col, prop_col = frame[f"f_fl[{k + 1}]"], frame[f"c_prop[{k + 1}]"]
            # the fix's array and the on-demand compute: the same numbers
            assert np.array_equal(fix_col, prop_col), (step, name)
            # filled on output steps only, or every step: the same numbers
            assert np.array_equal(fix_col, every[step][f"f_fl[{k + 1}]"]), (step, name)
        # the derived columns are filled (not left at 0)
        assert np.all(frame["f_fl[10]"] != 0.0) and np.all(frame["f_fl[3]"] > 0.0), step
    # and the state moved between the output steps
    assert not np.array_equal(auto["10"]["f_fl[10]"], auto["end"]["f_fl[10]"])


def test_read_between_output_steps_is_refused_not_stale(folder):
    """A per-atom read of the fix's array at a step that is no thermo or dump step is
    LAMMPS's 'not computed at compatible time' error (the array is not filled there);
    with output 1 it runs; compute property/atom is computed on demand at any step."""
    reads = "variable p atom f_fl[10]\ncompute pmax all reduce max v_p\n" \
            "fix avg all ave/time 7 1 7 c_pmax file pmax.txt\n"
    proc = run_lmp(folder, header() + physics() + "thermo 10\n" + reads + "run 30\n",
                   check=False)
    assert proc.returncode == 1 and "not computed at compatible time" in proc.stdout, \
        proc.stdout[-2000:]
    run_lmp(folder, header() + physics(fix_args="output 1") + "thermo 10\n" + reads + "run 30\n")
    want = np.loadtxt(folder / "pmax.txt")

    # the on-demand compute at the same steps, without output 1
    reads = PROP + "compute pmax all reduce max c_prop[10]\n" \
                   "fix avg all ave/time 7 1 7 c_pmax file pmax.txt\n"
    run_lmp(folder, header() + physics() + "thermo 10\n" + reads + "run 30\n")
    got = np.loadtxt(folder / "pmax.txt")
    assert len(got) == 5 and np.array_equal(got, want)    # steps 0, 7, ... 28


def test_extract_fix_after_run_holds_the_last_step(folder):
    """The library reads the array without asking the fix: after a run it holds the run's
    last step (37, no thermo or dump step), the numbers compute property/atom gives."""
    from cgmstest import new_lammps, working_directory
    with working_directory(folder):
        lmp = new_lammps()
        lmp.commands_string(header(plugin=False) + physics() + PROP + "thermo 10\nrun 37\n")
        n = lmp.extract_global("nlocal")
        array = np.array(lmp.numpy.extract_fix("fl", 1, 2))[:n]
        prop = np.array(lmp.numpy.extract_compute("prop", 1, 2))[:n]
        lmp.close()
    assert array.shape == (n, 14)
    assert np.array_equal(array, prop)
    assert np.all(array[:, 9] != 0.0)
