# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The bead state as LAMMPS custom per-atom vectors (issue 29): atom_style cgms keeps each
state column in a vector d_NAME, so that LAMMPS's own commands see it (dump custom, set,
compute property/atom, the library's extract_atom), and compute cgms/atom gives every
output, stored or derived, by name. A value changed with set is the one the next step
uses; copies, deletions, creations, sorting and migration carry the vectors."""

import numpy as np
import pytest
from cgms import model

from cgmstest import (MAT, PLUGIN, ROOT, header, make_tissue, new_lammps, physics, read_dump, run_lmp,
                      working_directory)

pytestmark = pytest.mark.lammps

STATE = ["dryness", "mf", "ms", "mf0", "l0p", "rho", "area", "dmdt"]
NAMES = ["cgmscoef", "dryness", "nneigh", "side", "mf", "ms", "mf0", "l0p", "rho", "pressure",
         "area", "perim", "ldeq", "dmdt"]
OUTPUTS = ("compute prop all property/atom " + " ".join(NAMES) + "\n"
           "compute cg all cgms/atom " + " ".join(NAMES) + "\n")
COLUMNS = ("id " + " ".join(f"d_{n}" for n in STATE) + " c_prop[*] c_cg[*] "
           + " ".join(f"f_fl[{k + 1}]" for k in range(len(NAMES))))


def dump_line(path, extra=""):
    return f"write_dump all custom {path} {COLUMNS}{extra} modify format float %.17g sort id\n"


@pytest.fixture
def folder(tmp_path):
    # a dryness that varies by bead and velocities: every output differs between beads
    make_tissue(tmp_path, ncols=6, nrows=5, jitter=0.08, seed=3, s=(0.5, 1.0), vscale=1e-3)
    return tmp_path


def started(folder, steps=7):
    """A lammps instance in ``folder`` after ``steps`` steps of the standard tissue."""
    lmp = new_lammps()
    with working_directory(folder):
        for line in (header() + physics() + OUTPUTS).splitlines():
            lmp.command(line)
    lmp.command(f"run {steps}")
    return lmp


def by_id(lmp, name):
    """A per-atom vector from extract_atom, ordered by bead id."""
    ids = lmp.numpy.extract_atom("id")
    return np.asarray(lmp.numpy.extract_atom(name))[np.argsort(ids)]


def check_outputs_agree(d):
    """Each stored column is the same number under every name (the same double, read
    from the same vector), and compute cgms/atom gives what compute property/atom and
    the fix's per-atom array give (the same formulas on the same state)."""
    for k, name in enumerate(NAMES):
        prop, cg, fix = d[f"c_prop[{k + 1}]"], d[f"c_cg[{k + 1}]"], d[f"f_fl[{k + 1}]"]
        np.testing.assert_array_equal(cg, prop, err_msg=f"{name}: cgms/atom vs property/atom")
        np.testing.assert_array_equal(cg, fix, err_msg=f"{name}: cgms/atom vs f_fl")
        if name in STATE:
            np.testing.assert_array_equal(d[f"d_{name}"], prop, err_msg=f"d_{name}")
    # the derived outputs are not a copy of something stored
    for name in ("pressure", "side", "perim", "ldeq", "cgmscoef"):
        assert np.ptp(d[f"c_cg[{NAMES.index(name) + 1}]"]) > 0.0, name


def test_extract_atom_gives_the_dumped_numbers(folder):
    lmp = started(folder)
    lmp.command(dump_line(folder / "a.dump"))
    d = read_dump(folder / "a.dump")
    check_outputs_agree(d)
    for name in STATE:
        assert lmp.extract_atom_datatype(f"d_{name}") == 2    # LAMMPS_DOUBLE
        np.testing.assert_array_equal(by_id(lmp, f"d_{name}"), d[f"d_{name}"], err_msg=name)
    assert np.all(d["d_mf0"] > 0.0) and np.ptp(d["d_dryness"]) > 0.0
    lmp.close()


def test_set_changes_the_state_the_next_step_uses(folder):
    """rho = m_f / (h A) (the default density form): a new m_f changes the density and the
    pressure at the next setup, and the next step's mass transfer starts from it."""
    lmp = started(folder)
    before = by_id(lmp, "d_mf")
    new = before[4] * (1.0 + 1e-3)
    lmp.command(f"set atom 5 d_mf {new!r}")
    assert by_id(lmp, "d_mf")[4] == new
    lmp.command("run 0")
    mf, rho, area = (by_id(lmp, f"d_{n}") for n in ("mf", "rho", "area"))
    assert mf[4] == new, "setup replaced the value set"
    # two roundings of m_f / (h A)
    assert rho[4] == pytest.approx(new / (MAT["height"] * area[4]), rel=4.5e-16)
    dmdt = by_id(lmp, "d_dmdt")
    lmp.command("run 1")
    # m_f(n+1) = m_f(n) + dt dm_f/dt(n), one rounding
    assert by_id(lmp, "d_mf")[4] == pytest.approx(new + 1e-7 * dmdt[4], rel=2.3e-16)
    # the other beads kept theirs
    np.testing.assert_array_equal(mf[:4], before[:4])
    lmp.close()


def test_set_dryness_counts_without_the_dryness_keyword(folder):
    """Without its dryness keyword fix cgms/fluid keeps the dryness the beads hold: a value
    set is the one the pressure reference and the equilibrium perimeter use."""
    lmp = new_lammps()
    with working_directory(folder):
        for line in header().splitlines() + physics().replace(" dryness v_s", "").splitlines():
            lmp.command(line)
    lmp.command("compute cg all cgms/atom ldeq l0p")
    lmp.command("run 2")
    ldeq_fresh = by_id(lmp, "d_l0p")[3] * 1.0    # l_d = l0' at s = 1
    lmp.command("set atom 4 d_dryness 0.9")
    lmp.command("run 0")
    dryness = by_id(lmp, "d_dryness")
    assert dryness[3] == 0.9 and np.all(np.delete(dryness, 3) == 1.0)
    ids = lmp.numpy.extract_atom("id")
    ldeq = np.asarray(lmp.numpy.extract_compute("cg", 1, 2))[np.argsort(ids)][:, 0]
    # eqn (9) at the dryness set (cgms.model, the Python twin of cgms_laws.h); one
    # product, two roundings of the factor's evaluation order at most
    assert ldeq[3] == pytest.approx(ldeq_fresh * model.perimeter_contraction(MAT, 0.9),
                                    rel=1e-15)
    assert ldeq[3] < ldeq_fresh
    lmp.close()


def test_set_out_of_range_refused(folder):
    lmp = started(folder, steps=1)
    lmp.command("set atom 3 d_mf -1e-12")
    with pytest.raises(Exception, match=r"bead 3 has mf = -1e-12: it must be > 0"):
        lmp.command("run 0")
    lmp.close()


def test_set_before_the_data_line_is_taken_over_refused(folder):
    lmp = started(folder, steps=3)
    lmp.command("unfix sprop")    # header() defines it again after read_data
    lmp.command(f"write_data {folder / 'state.data'}")
    lmp.close()
    script = header(data="state.data fix CGMS NULL CGMS") + physics()
    proc = run_lmp(folder, script + "set atom 2 d_ms 1e-12\nrun 0\n", check=False)
    assert proc.returncode != 0
    assert "bead 2 has a line in the data file's CGMS section" in proc.stdout
    assert "its ms was changed after read_data" in proc.stdout
    # after a setup the bead's own state rules: set then run keeps the value
    run_lmp(folder, script + "run 0\nset atom 2 d_ms 1e-12\nrun 0\n"
            f"write_dump all custom b.dump id d_ms modify format float %.17g\n")
    assert read_dump(folder / "b.dump")["d_ms"][1] == 1e-12


def test_sort_delete_and_create_carry_the_state(folder):
    lmp = started(folder)
    constant = ["mf", "ms", "mf0", "l0p", "dryness"]    # what a setup does not recompute
    ids0 = np.sort(lmp.numpy.extract_atom("id"))
    before = {n: dict(zip(ids0, by_id(lmp, f"d_{n}"))) for n in constant}
    # a sort on the setup of the next run reorders the beads
    lmp.command("atom_modify sort 1 5e-5")
    slot = np.flatnonzero(lmp.numpy.extract_atom("id") == 8)[0]
    where = lmp.numpy.extract_atom("x")[slot].copy()    # a view: delete_atoms moves beads
    lmp.command("group gone id 3 8 17")
    lmp.command("delete_atoms group gone compress no")
    # a new bead where a deleted one was (among neighbours, in a slot a deleted bead freed)
    lmp.command(f"create_atoms 1 single {where[0]!r} {where[1]!r} 0.0")
    new_id = int(ids0.max()) + 1
    ids = lmp.numpy.extract_atom("id").copy()
    assert new_id in ids
    new = int(np.flatnonzero(ids == new_id)[0])
    assert lmp.numpy.extract_atom("d_mf0")[new] == -1.0    # no state: setup gives it one
    assert lmp.numpy.extract_atom("d_mf")[new] == 0.0
    lmp.command("run 0")
    order = lmp.numpy.extract_atom("id").copy()
    assert not np.array_equal(order, np.sort(order)), "no sort happened: the test tests nothing"
    for n in constant:
        values = dict(zip(order, lmp.numpy.extract_atom(f"d_{n}")))
        for tag in ids0:
            if tag in (3, 8, 17):
                assert tag not in values
            else:
                assert values[tag] == before[n][tag], (n, tag)
    assert dict(zip(order, lmp.numpy.extract_atom("d_mf0")))[new_id] > 0.0
    lmp.close()


@pytest.mark.mpi
def test_two_ranks(tmp_path):
    """Beads that change rank carry their vectors: the per-bead constants (fresh mass,
    turgid perimeter, solid mass) equal the serial run's bit for bit, and every name of
    a column gives the same number on 2 ranks as on one."""
    make_tissue(tmp_path, ncols=12, nrows=10, jitter=0.05, seed=5, s=(0.3, 1.0), vscale=1e-2,
                drift=(2.0, 0.0), margin=5.0)
    results = {}
    for nprocs in (1, 2):
        body = (OUTPUTS + "compute proc all property/atom proc\n"
                + "run 0\nwrite_dump all custom first.dump id c_proc modify sort id\n"
                + "run 600\n" + dump_line(f"end.{nprocs}.dump", " c_proc"))
        run_lmp(tmp_path, header(processors=nprocs) + physics() + body, nprocs=nprocs)
        results[nprocs] = read_dump(tmp_path / f"end.{nprocs}.dump")
    first = read_dump(tmp_path / "first.dump")
    serial, parallel = results[1], results[2]
    moved = np.count_nonzero(first["c_proc"] != parallel["c_proc"])
    assert moved >= 5, f"only {moved} beads changed rank: the test does not test migration"
    check_outputs_agree(parallel)
    for name in ("mf0", "l0p", "ms"):
        np.testing.assert_array_equal(parallel[f"d_{name}"], serial[f"d_{name}"], err_msg=name)


def test_a_custom_property_of_the_same_name_is_refused():
    lmp = new_lammps()
    for line in ("units si", "dimension 2", "atom_style atomic"):
        lmp.command(line)
    lmp.command("fix p all property/atom d_mf")
    with pytest.raises(Exception, match=r"a custom per-atom property mf exists already"):
        lmp.command("atom_style cgms")
    lmp.close()
    lmp = new_lammps()
    for line in ("units si", "dimension 2", "atom_style cgms"):
        lmp.command(line)
    with pytest.raises(Exception, match=r"already exists"):
        lmp.command("fix p all property/atom d_l0p")
    lmp.close()


def test_restart_of_the_state_row_build_reads_unchanged(tmp_path):
    """A restart file of the build that kept the state in one per-bead array
    (tests/data/README.md): the record holds the columns after the mass in the same order,
    so it reads bit for bit into the vectors."""
    data = ROOT / "tests" / "data"
    (tmp_path / "row8.restart").write_bytes((data / "row8.restart").read_bytes())
    run_lmp(tmp_path, f"plugin load {PLUGIN}\nread_restart row8.restart\n"
            "write_dump all custom new.dump id x y vx vy " + " ".join(f"d_{n}" for n in STATE)
            + " modify format float %.17g sort id\n")
    old, new = read_dump(data / "row8.dump"), read_dump(tmp_path / "new.dump")
    for k, name in enumerate(["id", "x", "y", "vx", "vy"] + STATE):
        column = name if k < 5 else f"c_p[{k - 4}]"
        np.testing.assert_array_equal(new[name if k < 5 else f"d_{name}"], old[column], name)
