# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""studies/calibration/steady.py and compare.py, the tools behind doc/results/validation.md's
comparison with the MFC: the equal-moisture state is the one the analytic steady state
says holds s x the fresh water, and CGMS compared with its own states deviates by nothing."""

import sys

import numpy as np
import pytest
from scipy.optimize import brentq

from cgms import material, model, positions, study
from cgmstest import APPLE, ROOT, require_lammps

sys.path.insert(0, str(ROOT / "studies" / "calibration"))
import compare  # noqa: E402
import steady  # noqa: E402


@pytest.fixture(scope="module")
def states(tmp_path_factory):
    require_lammps()
    out = tmp_path_factory.mktemp("steady")
    assert steady.main(["--material", APPLE, "--out", str(out / "equal"), "--tissues",
                        "calibration", "--levels", "1,0.8", "--equal-moisture"]) == 0
    assert steady.main(["--material", APPLE, "--out", str(out / "lever"), "--tissues",
                        "calibration", "--levels", "1,0.8"]) == 0
    return out


def test_equal_moisture_state_holds_s_times_the_fresh_water(states):
    """The analytic uniform steady state (cgms.model.steady_moisture) says which dryness s0
    holds 0.8 x the fresh water; the stored level-0.8 state is the steady state at that s0
    (not at s = 0.8)."""
    mat = material.read(APPLE)
    fresh = model.steady_moisture(mat, 1.0)
    s0 = brentq(lambda s: model.steady_moisture(mat, s) - 0.8 * fresh, 0.8, 1.0, xtol=1e-8)
    assert s0 > 0.85    # far from the lever 0.8: the test can tell the two apart
    folder = states / "equal" / "calibration"
    want = study.relax(folder / "tissue.data", APPLE, s0, states / "check",
                       method="quasistatic")["xy"]
    got = np.load(folder / f"level.{study.level_name(0.8)}.npy")
    lever = np.load(states / "lever" / "calibration" / f"level.{study.level_name(0.8)}.npy")
    x_ref = mat["x_ref"]
    assert np.max(np.abs(got - want)) < 1e-3 * x_ref
    assert np.max(np.abs(lever - want)) > 1e-2 * x_ref


def test_cgms_against_itself_deviates_by_nothing(states, tmp_path):
    """compare.py with CGMS's own states as the 'MFC' (centroid files, shuffled ids):
    every deviation and RMSD is zero; against the equal-moisture states it is not."""
    mfc = tmp_path / "mfc" / "calibration"
    mfc.mkdir(parents=True)
    rng = np.random.default_rng(3)
    for s in (1.0, 0.8):
        xy = np.load(states / "lever" / "calibration" / f"level.{study.level_name(s)}.npy")
        order = rng.permutation(len(xy))
        positions.write_centroids(mfc / f"centroids.s{s:g}.txt", xy[order], order + 1)
    rows, missing = compare.compare(tmp_path / "mfc", {"self": states / "lever",
                                                       "equal": states / "equal"},
                                    tissues=["calibration"], levels=(1.0, 0.8))
    assert not missing
    mine = {(r["set"], r["s"]): r for r in rows}
    for s in (1.0, 0.8):
        r = mine["self", s]
        assert r["rmsd_um"] < 1e-6
        assert all(abs(r[f"dev {k} %"]) < 1e-9 for k in compare.KEYS + compare.EXTRA)
    assert abs(mine["equal", 0.8]["dev A/A0 %"]) > 1.0
