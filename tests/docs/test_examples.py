# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Every example input runs to its end (serially and on 2 ranks) and reaches steady state."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from cgmstest import LMP, PLUGIN, ROOT, lammps_env

pytestmark = pytest.mark.lammps

EXAMPLES = sorted((ROOT / "examples").glob("*/in.*"))


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.parent.name)
def test_example_runs(tmp_path, example, nprocs):
    shutil.copy(example, tmp_path)
    env = lammps_env()
    # the examples rely on the environment that build/env.sh sets
    env["LAMMPS_PLUGIN_PATH"] = str(Path(PLUGIN).parent)
    env["LAMMPS_POTENTIALS"] = str(ROOT / "potentials")
    cmd = [LMP, "-in", example.name, "-log", "log.lammps"]
    if nprocs > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(nprocs)] + cmd
    proc = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:]
    match = re.search(r"steady state after (\d+) steps: residual (\S+),", proc.stdout)
    assert match, proc.stdout[-2000:]
    assert float(match.group(2)) < 1e-3
