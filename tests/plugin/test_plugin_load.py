# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Loading the plugin: lmp -in serially and under mpirun, the Python module, LAMMPS's
autoload path, and the messages when something is missing."""

import subprocess
from pathlib import Path

import pytest

from cgmstest import LMP, PLUGIN, ROOT, lammps_env, new_lammps, run_lmp

pytestmark = pytest.mark.lammps

STYLES = ["pair style plugin cgms", "fix style plugin cgms/fluid"]


def check_listing(stdout, nranks):
    for style in STYLES:
        assert style in stdout, stdout[-2000:]
    assert stdout.count("Loading plugin: CGMS atom style cgms") == 1
    assert "atom_style cgms OK" in stdout
    assert f"{nranks} by 1 by 1 MPI processor grid" in stdout or nranks == 1


SCRIPT = f"""plugin load {PLUGIN}
plugin list
units si
dimension 2
atom_style cgms
print "atom_style cgms OK"
region box block 0 1e-3 0 1e-3 -1e-4 1e-4
create_box 1 box
"""


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_plugin_load_lists_styles(tmp_path, nprocs):
    check_listing(run_lmp(tmp_path, SCRIPT, nprocs=nprocs).stdout, nprocs)


def test_plugin_in_python_session():
    lmp = new_lammps()
    try:
        assert lmp.has_style("pair", "cgms")
        assert lmp.has_style("fix", "cgms/fluid")
        assert lmp.has_style("atom", "cgms")
        lmp.commands_string("units si\ndimension 2\natom_style cgms")
        assert lmp.extract_global("atom_style") == "cgms"
    finally:
        lmp.close()


def test_autoload_from_plugin_path_survives_clear(tmp_path):
    """LAMMPS_PLUGIN_PATH loads the plugin at start and again after clear."""
    script = "units si\natom_style cgms\nclear\nunits si\natom_style cgms\nprint done\n"
    (tmp_path / "in.auto").write_text(script)
    env = lammps_env()
    env["LAMMPS_PLUGIN_PATH"] = str(Path(PLUGIN).parent)
    proc = subprocess.run([LMP, "-in", "in.auto", "-log", "none"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, proc.stdout[-2000:]
    assert proc.stdout.count("Loading plugin: CGMS atom style cgms") == 2


def test_missing_plugin_file_says_so(tmp_path):
    proc = run_lmp(tmp_path, "plugin load /nonexistent/cgmsplugin.so\nunits si\n"
                   "atom_style cgms\n", check=False)
    assert proc.returncode != 0
    assert "Open of file /nonexistent/cgmsplugin.so failed" in proc.stdout
    assert "ERROR: Unrecognized atom style 'cgms'" in proc.stdout


def test_python_helper_explains_missing_plugin(monkeypatch, tmp_path):
    from cgms import run
    monkeypatch.setenv("CGMS_PLUGIN", str(tmp_path / "nothing.so"))
    with pytest.raises(FileNotFoundError, match="run './cgms setup'"):
        run.open_lammps()


@pytest.mark.parametrize("source, build, message", [
    ("/nonexistent", None, "is not a LAMMPS source tree"),
    ("LAMMPS", "/nonexistent", "is not a LAMMPS CMake build folder"),
])
def test_cmake_explains_missing_lammps(tmp_path, source, build, message):
    import os
    src = os.environ["LAMMPS_SOURCE_DIR"] if source == "LAMMPS" else source
    cmd = ["cmake", "-S", str(ROOT), "-B", str(tmp_path / "b"), f"-DLAMMPS_SOURCE_DIR={src}"]
    if build:
        cmd.append(f"-DLAMMPS_BUILD_DIR={build}")
    proc = subprocess.run(cmd, capture_output=True, text=True)
    assert proc.returncode != 0
    text = proc.stdout + proc.stderr
    assert message in text and "tools/setup.sh" in text, text[-2000:]
