# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Markers, declared once, and the rule for tests that need LAMMPS: without a build they
are skipped with the reason (the pure-Python tests run alone), unless CGMS_REQUIRE_LAMMPS
is set (./cgms test sets it), which makes a missing build fail the session."""

import os
import shutil

import pytest

from cgmstest import fake_relax, lammps_missing  # first: it puts python/ on the path
from cgms import study  # noqa: E402

MARKERS = {
    "lammps": "needs LAMMPS and the CGMS plugin (skipped without a build)",
    "mpi": "runs LAMMPS under mpirun -np 2",
    "slow": "long variant, run with CGMS_SLOW=1 -m slow",
}


def pytest_addoption(parser):
    parser.addoption("--regenerate", action="store_true",
                     help="rewrite the frozen values of tests/contract/*.yaml (then review "
                          "the diff and run each case's independent check)")


def pytest_configure(config):
    for name, text in MARKERS.items():
        config.addinivalue_line("markers", f"{name}: {text}")
    reason = lammps_missing()
    if reason and os.environ.get("CGMS_REQUIRE_LAMMPS"):
        pytest.exit(f"CGMS_REQUIRE_LAMMPS is set but {reason}", returncode=2)


def pytest_collection_modifyitems(config, items):
    reason = lammps_missing()
    no_mpirun = not shutil.which("mpirun")
    for item in items:
        if reason and (item.get_closest_marker("lammps") or item.get_closest_marker("mpi")):
            item.add_marker(pytest.mark.skip(reason=reason))
        elif no_mpirun and item.get_closest_marker("mpi"):
            item.add_marker(pytest.mark.skip(reason="mpirun not found: install openmpi-bin "
                                                    "(./cgms test does)"))


@pytest.fixture
def fake(monkeypatch, tmp_path):
    """Work in ``tmp_path`` with study.relax replaced by cgmstest.fake_relax (no LAMMPS)."""
    monkeypatch.setattr(study, "relax", fake_relax)
    monkeypatch.chdir(tmp_path)
    return tmp_path
