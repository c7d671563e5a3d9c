# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The state of fix cgms/transport (every bead's moisture column, the drying time, the water
balance) under every LAMMPS mechanism that carries or changes state: re-definition, restart
(also under another fix ID), data files (which cannot carry the columns), atom deletion and
creation, sorting and migration between ranks; and the steps, keyword values and parameter
files it must refuse (doc/fix_cgms_transport.rst).

Where the operations are the same as in the uninterrupted run (re-definition, restart: the
same arithmetic on the same doubles in the same order) the results must be bit-identical. Where the summation order changes (other ranks, sorting) they may differ by
rounding only: each moisture step is solved to a relative residual of ``tolerance`` (1e-14),
which bounds the relative error of the step's solution by that residual times the condition
number of the column-preconditioned matrix; with Fourier numbers of order one across the
in-plane couplings that number is below 100, so each step adds at most 1e-12 and 20 steps
at most 2e-11 (asserted: 1e-10)."""

import numpy as np
import pytest

from cgmstest import PLUGIN, read_dump, run_lmp
from cgms import tissue
from cgms.drying import transport
from test_fix_transport import A, CUT, PARAMS_FILE, jittered, read_params

LAYERS = 4
ARGS = f"{PARAMS_FILE} layers {LAYERS} dt 10 adapt 0.05 600 heat yes"
NOUT = 14            # the outputs every test prints; output 15 only where it is tested
ROUNDING = 1e-10     # other summation orders (module docstring)
BALANCE = 1e-12      # 20 steps, each closing to the CG's 1e-14 of the water it moves


def head(processors=None):
    return [f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
            f"processors {processors} 1 1" if processors else "",
            "atom_style cgms", "atom_modify map array sort 0 0"]


def forces():
    return [f"pair_style zero {CUT!r}", "pair_coeff * *", f"neighbor {0.1 * CUT!r} bin"]


def outputs(fix="tr", last=NOUT):
    return ["thermo_style custom step " + " ".join(f"f_{fix}[{k}]" for k in range(1, last + 1)),
            "thermo_modify format float %.17g", "thermo 1"]


def dump(fix="tr"):
    return (f"write_dump all custom out.dump id f_{fix}[1] f_{fix}[2] f_{fix}[3] f_{fix}[4] "
            "modify format float %.17g")


def rows(stdout, last=NOUT):
    """Thermo rows (step and the global outputs 1 to ``last``) of every run in ``stdout``."""
    found = []
    for line in stdout.splitlines():
        words = line.split()
        if len(words) == last + 1 and words[0].isdigit():
            found.append([float(w) for w in words])
    return np.array(found)


def first_error(proc):
    return next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")


def run(folder, lines, nprocs=1, check=True):
    folder.mkdir(exist_ok=True)
    if not (folder / "t.data").exists():
        tissue.write_data(folder / "t.data", jittered(), 3 * A, overwrite=True)
    return run_lmp(folder, "\n".join(lines) + "\n", nprocs=nprocs, check=check)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """20 moisture steps in one go, serially: (thermo rows, final per-bead outputs)."""
    folder = tmp_path_factory.mktemp("reference")
    proc = run(folder, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs() + ["run 10", "run 10", dump()])
    return rows(proc.stdout), read_dump(folder / "out.dump")


def same(result, reference):
    """Bit-identical final outputs and per-bead columns."""
    (rows_a, dump_a), (rows_b, dump_b) = result, reference
    assert rows_a[-1][0] == rows_b[-1][0]
    assert np.array_equal(rows_a[-1], rows_b[-1]), (rows_a[-1], rows_b[-1])
    for key in ("f_tr[1]", "f_tr[2]", "f_tr[3]", "f_tr[4]"):
        assert np.array_equal(dump_a[key], dump_b[key]), key


def test_redefinition_keeps_columns_and_time(tmp_path, reference):
    """'fix tr ...' again (the idiom to change the air) continues the tissue: with the same
    air bit for bit as if nothing happened; with wetter air from the same state, time and
    steps counting on and the water balance closed."""
    proc = run(tmp_path / "same", head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 10", f"fix tr all cgms/transport {ARGS}", "run 10", dump()])
    same((rows(proc.stdout), read_dump(tmp_path / "same" / "out.dump")), reference)

    proc = run(tmp_path / "humid", head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 10", f"fix tr all cgms/transport {ARGS} humidity 0.6"] + outputs()
               + ["run 10"])
    got, ref = rows(proc.stdout), reference[0]
    at10 = ref[ref[:, 0] == 10][0]
    after = got[got[:, 0] == 10]
    assert np.array_equal(after[0], at10)        # the state the first fix left ...
    assert np.array_equal(after[1][[1, 3, 5, 6, 14]], at10[[1, 3, 5, 6, 14]])   # ... taken over
    last = got[-1]
    assert last[14] == 20 and last[1] > at10[1]          # time and steps count on
    assert ref[-1][3] < last[3] < at10[3]                # it dries on, slower in wetter air
    assert abs(last[7]) < BALANCE


def test_restart_under_another_id(tmp_path, reference):
    """A fix defined after read_restart under another ID than the one written takes the
    columns, the drying time and the balance over: bit-identical to the run in one go."""
    folder = tmp_path / "r"
    run(folder, head() + ["read_data t.data"] + forces() + [f"fix tr all cgms/transport {ARGS}"]
        + outputs() + ["run 10", "write_restart r.restart"])
    (folder / "out.dump").unlink(missing_ok=True)
    proc = run(folder, [f"plugin load {PLUGIN}", "read_restart r.restart"] + forces()
               + [f"fix dry all cgms/transport {ARGS}"] + outputs("dry")
               + ["run 10", dump("dry")])
    dump_b = {k.replace("f_dry", "f_tr"): v for k, v in read_dump(folder / "out.dump").items()}
    same((rows(proc.stdout), dump_b), reference)


@pytest.mark.parametrize("layers", [LAYERS + 4, LAYERS - 2])
def test_restart_with_other_layers_is_refused_first(tmp_path, layers):
    """A restart file's columns hold LAYERS layers; a fix of another layer count defined
    after read_restart is refused before its store is made (LAMMPS hands a new fix
    property/atom as many values as it holds, so a larger store read past the file's rows
    into uninitialised memory and ran on without a word: valgrind, 7 errors)."""
    run(tmp_path, head() + ["read_data t.data"] + forces() + [f"fix tr all cgms/transport {ARGS}",
                                                              "run 5", "write_restart r.restart"])
    other = ARGS.replace(f"layers {LAYERS}", f"layers {layers}")
    proc = run(tmp_path, [f"plugin load {PLUGIN}", "read_restart r.restart"] + forces()
               + [f"fix dry all cgms/transport {other}", "run 1"], check=False)
    error = first_error(proc)
    assert f"the state of {LAYERS} layers; this fix has layers {layers}" in error, \
        proc.stdout[-2000:]


def coupled(data, lines):
    """A 42-bead CGMS tissue whose fix cgms/fluid takes its dryness from the transport."""
    from cgmstest import APPLE
    return head() + ["comm_modify vel yes", f"read_data {data}", "neighbor 1.5e-5 bin",
                     "neigh_modify every 1 delay 0 check yes", "pair_style cgms",
                     f"pair_coeff * * {APPLE}"] + lines


def test_dried_data_file_is_not_restarted_fresh(tmp_path):
    """A tissue dried by the transport and written by write_data: the data file carries
    the fluid state (section CGMS) but cannot carry the columns (a row is longer than the
    256 characters read_data reads of a line). Read back, the transport refuses to start it
    at X0 and names the cure (a restart file), instead of undoing its drying silently."""
    from cgmstest import XREF
    tissue.write_data(tmp_path / "c.data", tissue.hex_rectangle(6, 7, XREF), 4 * XREF,
                      overwrite=True)
    proc = run(tmp_path, coupled("c.data", [
        "fix fluid all cgms/fluid dryness 1.0", "fix nve all nve", "fix 2d all enforce2d",
        "timestep 1e-7", "run 1000",
        f"fix tr all cgms/transport {ARGS} outline no every 500", "variable s atom f_tr[1]",
        "fix fluid all cgms/fluid dryness v_s every 500", "run 3000",
        'print "DRIED $(f_tr[3]:%.6f)"', "write_data dried.data nocoeff"]))
    dried = next(line for line in proc.stdout.splitlines() if line.startswith("DRIED"))
    assert float(dried.split()[1]) < 0.99
    # the loss is said where it is made: at write_data, and in the file
    assert "data files cannot carry the tissue's moisture columns" in proc.stdout
    assert "# fix cgms/transport tr: the moisture columns" in \
        (tmp_path / "dried.data").read_text()
    proc = run(tmp_path, coupled("dried.data fix CGMS NULL CGMS", [
        f"fix tr all cgms/transport {ARGS} outline no every 500", "variable s atom f_tr[1]",
        "fix fluid all cgms/fluid dryness v_s every 500", "fix nve all nve",
        "fix 2d all enforce2d", "timestep 1e-7", "run 1"]), check=False)
    error = first_error(proc)
    assert "had dried it" in error and "restart file" in error, proc.stdout[-2000:]


def test_data_file_of_the_transport_alone_is_not_restarted_fresh(tmp_path):
    """The transport alone (no fix cgms/fluid, so no fluid state in the data file shows the
    tissue dried): the note write_data leaves in the file is what read_data's scan finds,
    and the transport refuses to start the tissue at X0, naming the file's line; with that
    line deleted (the user's explicit choice) the tissue starts afresh."""
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}", "run 10", "write_data dried.data nocoeff"])
    assert "data files cannot carry the tissue's moisture columns" in proc.stdout
    again = head() + ["read_data dried.data"] + forces() + [f"fix tr all cgms/transport {ARGS}",
                                                            "run 1"]
    proc = run(tmp_path, again, check=False)
    error = first_error(proc)
    assert "written after fix cgms/transport had dried it" in error, proc.stdout[-2000:]
    text = (tmp_path / "dried.data").read_text().splitlines()
    line = next(i for i, t in enumerate(text, 1) if t.startswith("# fix cgms/transport"))
    assert f"dried.data line {line}" in error
    (tmp_path / "dried.data").write_text(
        "\n".join(t for t in text if not t.startswith("# fix cgms/transport")) + "\n")
    run(tmp_path, again)


def test_dried_tissue_without_columns_is_refused(tmp_path):
    """The same for a tissue held at a dryness below 1 by fix cgms/fluid: its columns would
    start at X0, against the shape the mechanics holds."""
    from cgmstest import XREF
    tissue.write_data(tmp_path / "c.data", tissue.hex_rectangle(6, 7, XREF), 4 * XREF,
                      overwrite=True)
    proc = run(tmp_path, coupled("c.data", [
        "fix fluid all cgms/fluid dryness 0.8", "run 0", f"fix tr all cgms/transport {ARGS}",
        "variable s atom f_tr[1]", "fix fluid all cgms/fluid dryness v_s", "run 1"]),
        check=False)
    error = first_error(proc)
    assert "has a dryness below 1" in error and "give it dryness 1 first" in error, \
        proc.stdout[-2000:]


def test_deleted_beads_leave_the_balance(tmp_path):
    """delete_atoms: the water the deleted beads held leaves the balance as output 15, the
    tissue's X/X0 is that of the beads that remain, and the balance keeps closing. The
    expectations come from the per-bead means written before the deletion and the dry
    solid of each column (solids density x area x thickness,
    cgms.drying.transport.bead_geometry)."""
    xy = jittered()
    gone = [1, 2, 3, 9]
    folder = tmp_path
    tissue.write_data(folder / "t.data", xy, 3 * A, overwrite=True)
    proc = run(folder, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs(last=15)
               + ["run 10", dump(), "group gone id " + " ".join(map(str, gone)),
                  "delete_atoms group gone", "run 0", "run 10"])
    got = rows(proc.stdout, last=15)
    before = read_dump(folder / "out.dump")
    p = read_params()
    solids = p["solids_density"] * transport.bead_geometry(xy, CUT)["area"] * 2e-3
    water = solids * p["X0"] * before["f_tr[2]"]
    out = np.isin(before["id"], gone)
    at_delete = got[got[:, 0] == 10][-1]
    assert at_delete[15] == pytest.approx(water[out].sum(), rel=1e-12)
    assert at_delete[3] == pytest.approx(water[~out].sum() / (solids[~out].sum() * p["X0"]),
                                         rel=1e-12)
    assert abs(at_delete[7]) < BALANCE
    assert "4 beads deleted" in proc.stdout
    assert got[-1][14] == 20 and abs(got[-1][7]) < BALANCE


def test_bead_created_in_a_freed_slot_is_refused(tmp_path):
    """A bead created after a deletion takes the freed slot, where the deleted bead's row
    lies: it must be refused as a bead without a column, not dry on with another's."""
    xy = jittered()
    x, y = xy[5]
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 2", "group one id 6", "delete_atoms group one",
                  f"create_atoms 1 single {x!r} {y!r} 0.0 units box", "run 2"], check=False)
    # delete_atoms renumbers the beads (compress yes): the new one is the last
    assert f"bead {len(xy)} has no moisture column" in first_error(proc), \
        proc.stdout[-2000:]


@pytest.mark.parametrize("deleted", ["6", "1:10"])
def test_bead_created_while_no_transport_is_defined_is_refused(tmp_path, deleted):
    """The same with the transport fix undefined (unfix) while beads are deleted and
    created: its store stays, and nothing of the transport marks the new bead. atom_style
    cgms clears a new bead's row of the store, so the fix defined again finds a bead
    without a column and refuses it, instead of drying it on with a deleted bead's
    column."""
    xy = jittered()
    x, y = xy[5]
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 2", "unfix tr", f"group gone id {deleted}", "delete_atoms group gone",
                  f"create_atoms 1 single {x!r} {y!r} 0.0 units box",
                  f"fix tr all cgms/transport {ARGS}", "run 2"], check=False)
    assert "has no moisture column" in first_error(proc), proc.stdout[-2000:]


def test_migration_sorting_and_redefinition_on_two_ranks(tmp_path, reference):
    """On 2 ranks, beads cross between them (balance moves the cut), are sorted, and the
    fix is defined again on the rank that received them: the result equals the serial run
    to rounding (module docstring)."""
    proc = run(tmp_path, head(processors=2) + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 10", "balance 1.0 x 0.25", f"atom_modify sort 1 {A!r}",
                  f"fix tr all cgms/transport {ARGS}", "run 10", dump()], nprocs=2)
    assert "Nlocal" in proc.stdout
    got, ref = rows(proc.stdout)[-1], reference[0][-1]
    assert got[14] == ref[14] and got[1] == pytest.approx(ref[1], rel=ROUNDING)
    for k in (3, 5, 6, 8, 9, 11):
        assert got[k] == pytest.approx(ref[k], rel=ROUNDING), k
    assert abs(got[7]) < BALANCE
    moved = read_dump(tmp_path / "out.dump")
    for key in ("f_tr[2]", "f_tr[3]", "f_tr[4]"):
        assert np.abs(moved[key] - reference[1][key]).max() < ROUNDING, key


def test_long_fixed_step_is_refused_naming_dt(tmp_path):
    """Free water evaporates at a constant rate in the linearised surface law, so a long
    fixed step would drive the moisture below zero (it gave X/X0 = -16 with a water balance
    of 1e-12): refused, naming the transport keyword dt, not the MD timestep."""
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {PARAMS_FILE} dt 600 heat no"] + outputs()
               + ["run 20"], check=False)
    error = first_error(proc)
    assert "(keyword dt)" in error and "< 0" in error and "adapt" in error, proc.stdout[-2000:]


def test_adaptive_step_keeps_moisture_non_negative(tmp_path):
    """With adapt, a step that would drain a node is halved: over 40 steps every node stays
    at or above zero, the tissue ends at the equilibrium moisture of the air (GAB at 10 %
    RH and 70 C, from cgms.drying.transport), and the water balance closes."""
    p = read_params()
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {PARAMS_FILE} dt 600 adapt 1000 600 heat no",
                  "compute low all reduce min f_tr[3] f_tr[4]"] + outputs()
               + ["thermo_style custom step f_tr[3] f_tr[7] c_low[1] c_low[2]", "run 40"])
    table = np.array([[float(w) for w in line.split()] for line in proc.stdout.splitlines()
                      if len(line.split()) == 5 and line.split()[0].isdigit()])
    assert table[:, 3:].min() >= 0.0
    assert np.abs(table[:, 2]).max() < BALANCE
    x_eq = float(transport.gab_moisture(0.1, p["GAB_Xm"], p["GAB_C"], p["GAB_K"])) / p["X0"]
    assert table[-1, 1] == pytest.approx(x_eq, rel=1e-6)


def run_coupled(tmp_path, dt):
    """A 42-bead tissue relaxed fresh, then dried by the transport with moisture steps of dt
    seconds, its dryness handed to fix cgms/fluid every 500 MD steps."""
    from cgmstest import APPLE, XREF
    tissue.write_data(tmp_path / "c.data", tissue.hex_rectangle(6, 7, XREF), 4 * XREF,
                      overwrite=True)
    lines = head() + ["comm_modify vel yes", "read_data c.data", "neighbor 1.5e-5 bin",
                      "neigh_modify every 1 delay 0 check yes", "pair_style cgms",
                      f"pair_coeff * * {APPLE}", "fix fluid all cgms/fluid dryness 1.0",
                      "fix nve all nve", "fix 2d all enforce2d", "timestep 1e-7", "run 2000",
                      f"fix tr all cgms/transport {PARAMS_FILE} layers 4 dt {dt} outline no "
                      "every 500", "variable s atom f_tr[1]",
                      "fix fluid all cgms/fluid dryness v_s every 500", "run 2000"]
    return run(tmp_path, lines, check=False)


def test_coupled_long_step_is_blamed_on_dt(tmp_path):
    """Coupled to fix cgms/fluid, a too-long moisture step used to surface as a mechanics
    error advising a smaller MD timestep; the transport now refuses it by its keyword."""
    proc = run_coupled(tmp_path, 3600)
    error = first_error(proc)
    assert "Fix cgms/transport" in error and "(keyword dt)" in error, proc.stdout[-2000:]
    assert "timestep" not in error


def test_coupled_step_too_long_for_the_mechanics_names_dt(tmp_path):
    """A moisture step that keeps the moisture non-negative (dt 900) but moves the dryness
    further in one change than the mechanics' turgor force can follow stops in fix
    cgms/fluid; its cure names the transport's step keywords, not only the MD timestep."""
    proc = run_coupled(tmp_path, 900)
    error = first_error(proc)
    assert "Fix cgms/fluid" in error and "change of dryness" in error, proc.stdout[-2000:]
    assert "fix cgms/transport" in error and "dt or adapt" in error


@pytest.mark.parametrize("fix_args, message", [
    ("velocity 0", "velocity must be > 0 m/s, got 0"),
    ("velocity -1", "velocity must be > 0 m/s, got -1"),
    ("velocity 1e300", "Reynolds number"),
    ("plate 1e-300", "Reynolds number"),
    ("surface linear 1e-3 -1", "X_eq is the equilibrium dry-basis moisture"),
    ("surface linear 0 0.1", "h_x must be > 0"),
    ("smin 0", "0 < smin <= 1"),
    ("layers 1001", "layers must be >= 1 and <= 1000"),
    ("thickness 1e-12", "singular to rounding"),
    ("dt 1e-300 adapt 1e-300 1e-300", "adaptive moisture step shrank"),
])
def test_bad_values_name_the_cause(tmp_path, fix_args, message):
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {PARAMS_FILE} {fix_args}"] + outputs()
               + ["run 3"], check=False)
    assert proc.returncode != 0
    assert message in first_error(proc), proc.stdout[-2000:]


@pytest.mark.parametrize("line, message", [
    ("D_ref 1e400", "D_ref = 1e400 is beyond a double"),
    ("D_ref 0", "D_ref > 0"),
    ("T_ref -300", "T_ref above absolute zero"),
    ("D_moisture 1e6", "the diffusivity of bead"),
    ("D_energy -1e10", "the diffusivity of bead"),
])
def test_bad_parameter_file_names_the_cause(tmp_path, line, message):
    """A parameter file value beyond a double, a D_ref that moves no water, a T_ref below
    absolute zero, or D_energy or D_moisture so extreme that D_eff is 0 or inf at some node
    (which used to end in 'residual -nan', an exception or a silent run)."""
    name = line.split()[0]
    text = "".join(raw if not raw.split() or raw.split()[0] != name else line + "\n"
                   for raw in PARAMS_FILE.read_text().splitlines(keepends=True))
    (tmp_path / "p.params").write_text(text)
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + ["fix tr all cgms/transport p.params"] + outputs() + ["run 3"], check=False)
    assert proc.returncode != 0
    assert message in first_error(proc), proc.stdout[-2000:]


# ------------------------------------------------ adversarial pass of 2026-12-03

def test_second_transport_fix_is_refused(tmp_path):
    """Two transport fixes under two IDs used to both step the one set of columns: each
    bead dried twice per step and the water balance was off by a quarter, silently."""
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}", f"fix tr2 all cgms/transport {ARGS}"]
               + outputs() + ["run 3"], check=False)
    assert proc.returncode != 0
    error = first_error(proc)
    assert "fix tr2 dries this tissue already" in error and "unfix tr2 first" in error, error


@pytest.mark.parametrize("when", ["before", "after"])
def test_run_without_beads_is_refused(tmp_path, when):
    """A tissue of no beads (none read, or all deleted) used to 'dry' on: drying time and
    steps counting, X/X0 0 and a drying rate of NaN."""
    deleted = ["delete_atoms group all"]
    steps = (deleted + [f"fix tr all cgms/transport {ARGS}"] + outputs() + ["run 3"]
             if when == "before" else
             [f"fix tr all cgms/transport {ARGS}"] + outputs() + ["run 3"] + deleted + ["run 3"])
    proc = run(tmp_path, head() + ["read_data t.data"] + forces() + steps, check=False)
    assert proc.returncode != 0
    assert "the system has no beads" in first_error(proc), proc.stdout[-2000:]
    assert "nan" not in proc.stdout.lower()


def test_redefinition_with_another_thickness_is_refused(tmp_path):
    """The columns keep the fresh thickness they were set up with: a fix defined again
    with another thickness used to run on as if it had not been given it."""
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 5", f"fix tr all cgms/transport {ARGS} thickness 1e-3", "run 5"],
               check=False)
    assert proc.returncode != 0
    error = first_error(proc)
    assert "set up for a slice thickness of 0.002 m" in error and "give thickness 0.002" in error


def test_until_already_past_says_no_step_is_made(tmp_path, reference):
    """A fix defined again with an until the drying has passed makes no step, and says so."""
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 10", f"fix tr all cgms/transport {ARGS} until 5"] + outputs() + ["run 5"])
    got = rows(proc.stdout)
    assert got[-1][14] == 10 and got[-1][1] == reference[0][10][1]
    assert "at or past until 5 s: this run makes no moisture step" in proc.stdout


def test_redefinition_with_another_solids_density_is_refused(tmp_path):
    """The dry solid of a column is set once: a parameter file with another solids_density
    (same X0) used to be taken without its density being used."""
    text = PARAMS_FILE.read_text()
    line = next(r for r in text.splitlines() if r.split()[:1] == ["solids_density"])
    (tmp_path / "denser.params").write_text(text.replace(line, "solids_density 200"))
    denser = ARGS.replace(str(PARAMS_FILE), "denser.params")
    proc = run(tmp_path, head() + ["read_data t.data"] + forces()
               + [f"fix tr all cgms/transport {ARGS}"] + outputs()
               + ["run 5", f"fix tr all cgms/transport {denser}", "run 5"], check=False)
    assert proc.returncode != 0
    error = first_error(proc)
    assert "hold the dry solid of solids_density" in error and "denser.params has 200" in error, \
        error
