# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Serial vs 2 MPI ranks, newton on vs off, and restart continuity, with lmp -in scripts."""

import numpy as np
import pytest

from cgmstest import PLUGIN, XREF, header, make_tissue, physics, read_dump, run_lmp

pytestmark = pytest.mark.lammps

DUMP = ("dump d all custom {every} {name} id x y vx vy c_cg[*] c_proc\n"
        "dump_modify d format float %.17g sort id\n")
CG = "compute cg all property/atom mf pressure area\ncompute proc all property/atom proc\n"


def trajectory(folder, nprocs, steps=1000, newton="on", pair_args="", extra=""):
    script = (header(newton=newton, processors=nprocs) + physics(pair_args) + CG
              + DUMP.format(every=steps, name="traj.dump") + extra + f"run {steps}\n")
    run_lmp(folder, script, nprocs=nprocs)
    return read_dump(folder / "traj.dump")


def max_rel_diff(a, b):
    return {
        "position": np.max(np.abs(np.c_[a["x"] - b["x"], a["y"] - b["y"]])) / XREF,
        "velocity": np.max(np.abs(np.c_[a["vx"] - b["vx"], a["vy"] - b["vy"]]))
        / np.max(np.abs(np.c_[a["vx"], a["vy"]])),
        "fluid mass": np.max(np.abs(a["c_cg[1]"] - b["c_cg[1]"]) / a["c_cg[1]"]),
        "pressure": np.max(np.abs(a["c_cg[2]"] - b["c_cg[2]"])) / np.max(np.abs(a["c_cg[2]"])),
    }


@pytest.fixture
def drifting_tissue(tmp_path):
    # a 2 m/s drift carries every bead about 1.3 lattice spacings in 1000 steps, so beads
    # cross the boundary between the two sub-domains; damping sees relative motion only
    make_tissue(tmp_path, ncols=12, nrows=10, jitter=0.05, seed=5, s=(0.3, 1.0), vscale=1e-2,
                drift=(2.0, 0.0), margin=5.0)
    return tmp_path


@pytest.mark.mpi
def test_one_and_two_ranks_agree(drifting_tissue, tmp_path_factory):
    serial = trajectory(drifting_tissue, 1)
    other = tmp_path_factory.mktemp("np2")
    for f in ("tissue.data", "state.in"):
        (other / f).write_bytes((drifting_tissue / f).read_bytes())
    parallel = trajectory(other, 2)
    first = read_dump_first(other / "traj.dump")
    moved = np.count_nonzero(first["c_proc"] != parallel["c_proc"])
    assert moved >= 5, f"only {moved} beads changed sub-domain: the test does not test migration"
    for name, diff in max_rel_diff(serial, parallel).items():
        assert diff < 1e-10, f"{name} differs by {diff:.2e} between 1 and 2 ranks"


@pytest.mark.mpi
def test_newton_on_and_off_agree(drifting_tissue, tmp_path_factory):
    on = trajectory(drifting_tissue, 2, steps=300, newton="on")
    other = tmp_path_factory.mktemp("newton_off")
    for f in ("tissue.data", "state.in"):
        (other / f).write_bytes((drifting_tissue / f).read_bytes())
    off = trajectory(other, 2, steps=300, newton="off")
    for name, diff in max_rel_diff(on, off).items():
        assert diff < 1e-10, f"{name} differs by {diff:.2e} between newton on and off"


def read_dump_first(path):
    """First frame of a dump (the one at step 0)."""
    text = path.read_text().split("ITEM: TIMESTEP")[1]
    first = path.with_suffix(".first")
    first.write_text("ITEM: TIMESTEP" + text)
    return read_dump(first)


def restart_pair(folder, pair_args, nprocs):
    """Run 2N steps straight; and N steps, write_restart, clear, read_restart, N steps.
    Returns (uninterrupted, restarted, interrupted-without-restart) final frames."""
    n = 100
    tail = physics(pair_args).split("\n", 2)[2]  # the fixes and timestep, not the pair
    straight = header() + physics(pair_args) + CG + DUMP.format(every=2 * n, name="a.dump") \
        + f"run {2 * n}\n"
    run_lmp(folder, straight, nprocs=nprocs)
    first = header() + physics(pair_args) + CG + DUMP.format(every=2 * n, name="b.dump") \
        + f"run {n}\nwrite_restart state.restart\nrun {n}\n"
    run_lmp(folder, first, nprocs=nprocs)
    second = "\n".join([
        f"plugin load {PLUGIN}",
        "read_restart state.restart",
        "comm_modify vel yes",
        "neighbor 1.5e-5 bin",
        "neigh_modify every 1 delay 0 check yes",
        "fix sprop all property/atom d_s",  # its values come back from the restart file
        "variable s atom d_s",
        tail,
        CG,
        DUMP.format(every=n, name="c.dump"),
        f"run {n}",
    ])
    run_lmp(folder, second, nprocs=nprocs)
    return read_dump(folder / "a.dump"), read_dump(folder / "c.dump"), read_dump(folder / "b.dump")


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_restart_equals_uninterrupted_run(tmp_path, nprocs):
    """Without damping every force depends on positions and restart-file state only, so
    a restarted run must follow the uninterrupted one. (Undamped, the tissue is not
    stable for long: the runs are kept short.)"""
    make_tissue(tmp_path, jitter=0.05, seed=9, s=(0.6, 0.8), vscale=1e-3)
    straight, restarted, _ = restart_pair(tmp_path, "damping no", nprocs)
    for name, diff in max_rel_diff(straight, restarted).items():
        assert diff < 1e-10, f"{name} differs by {diff:.2e} after restart"


def test_restart_with_damping_equals_split_run(tmp_path):
    """With damping the force at setup uses the full-step velocity (as any LAMMPS run that
    is split in two does), so the restarted run is compared with the same split run
    without the restart file: the file must carry every bit of state."""
    make_tissue(tmp_path, jitter=0.05, seed=9, s=(0.3, 1.0), vscale=1e-2)
    _, restarted, split = restart_pair(tmp_path, "", 1)
    for name, diff in max_rel_diff(split, restarted).items():
        assert diff < 1e-10, f"{name} differs by {diff:.2e} after restart"


@pytest.mark.mpi
def test_quasistatic_energy_with_cell_shape_term_agrees_across_ranks(drifting_tissue,
                                                                     tmp_path_factory):
    """The potential under 'balance yes' with k_S (a sum over pairs that cross the
    sub-domain boundary): 1 rank, 2 ranks with newton on and off give the same value."""
    values = {}
    for nprocs, newton, shape in ((1, "on", "k_S 0.5"), (2, "on", "k_S 0.5"),
                                  (2, "off", "k_S 0.5"), (1, "on", "")):
        folder = tmp_path_factory.mktemp(f"np{nprocs}{newton}{bool(shape)}")
        for f in ("tissue.data", "state.in"):
            (folder / f).write_bytes((drifting_tissue / f).read_bytes())
        script = (header(newton=newton, processors=nprocs)
                  + physics("damping no", "balance yes", shape)
                  + "thermo_style custom step pe f_fl\nthermo_modify format float %.17g\n"
                  + "run 0\n")
        out = run_lmp(folder, script, nprocs=nprocs).stdout.splitlines()
        row = out[[k for k, line in enumerate(out) if line.split()[:1] == ["Step"]][0] + 1]
        values[(nprocs, newton, shape)] = [float(w) for w in row.split()[1:]]
    serial = values.pop((1, "on", "k_S 0.5"))
    without = values.pop((1, "on", ""))
    # the k_S part is a real share of the potential here (pe and the fix scalar)
    assert abs(serial[1] - without[1]) > 1e-3 * abs(without[1])
    for key, got in values.items():
        assert got == pytest.approx(serial, rel=1e-12), key
