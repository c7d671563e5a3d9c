import os
import shutil

import pytest


def pytest_configure(config):
    config.addinivalue_line("markers", "mpi: runs LAMMPS under mpirun -np 2")
    missing = [v for v in ("CGMS_LMP", "CGMS_PLUGIN") if not os.environ.get(v)]
    if missing:
        pytest.exit(f"{', '.join(missing)} not set: run the tests with './cgms test' "
                    "(it builds LAMMPS and the plugin and sets the environment)", returncode=2)
    if not shutil.which("mpirun"):
        pytest.exit("mpirun not found: install openmpi-bin (./cgms test does)", returncode=2)
