# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The dynamics stops at rest with steady=dict(rest=...) (cgms.run.rest_test, study.REST):
what is left of the fastest bead's path, its speed times the decay time of that speed, is
below study.REST, where the residual and speed thresholds alone stopped with micrometres
to go."""

import math

import pytest

from cgms import run, study, tissue
from cgmstest import APPLE, MAT


@pytest.fixture
def small_tissue(tmp_path):
    xy = tissue.rectangle(0.9e-3, 0.8e-3, MAT["x_ref"])
    tissue.write_data(tmp_path / "tissue.data", xy, 3 * MAT["x_ref"])
    return tmp_path / "tissue.data"


#: the fallback's dynamics, stopped at rest
AT_REST = dict(study.FALLBACK["steady"], rest=study.REST)


def test_rest_needs_a_positive_distance_and_is_asked_for():
    for bad in (0, -1e-7, float("nan")):
        with pytest.raises(ValueError, match="rest"):
            run.rest_test(1000, 5e-8, bad)
    # cgms main's dynamics and the fallback: as before
    assert run.STEADY_DEFAULTS["rest"] is None and "rest" not in study.FALLBACK["steady"]
    assert "ave/time" not in run.tissue_script("t.data", "m.cgms", 0.6)
    assert "ave/time" in run.tissue_script("t.data", "m.cgms", 0.6, dt=study.FALLBACK["dt"],
                                           steady=AT_REST)


@pytest.mark.lammps
def test_dynamics_stops_with_less_than_rest_left(small_tissue, tmp_path):
    """33 beads, the paper's apple at s = 0.6, the fallback's dynamics at rest. The same run
    stopped one check earlier (a serial LAMMPS run repeats its trajectory bit for bit) gives the
    speed before; from the two speeds, the remaining path v T / ln(v_before / v) is below
    REST (to the rounding of exp and log, 1e-9), and the speed fell. With the residual and
    speed thresholds alone (the old criterion) the run stops far earlier, with more than
    REST to go by the same estimate."""
    steady = AT_REST
    dt = study.FALLBACK["dt"]
    every = dict(run.STEADY_DEFAULTS, **steady)["every"]
    stop = study.relax(small_tissue, APPLE, 0.6, tmp_path / "stop", method="dynamics", dt=dt,
                       steady=steady)
    assert stop["converged"]
    before = study.relax(small_tissue, APPLE, 0.6, tmp_path / "before", method="dynamics",
                         dt=dt, steady=dict(steady, max_steps=stop["steps"] - every))
    assert before["steps"] == stop["steps"] - every
    assert remaining(before["speed"], stop["speed"], every * dt) < study.REST * (1 + 1e-9)
    # the old criterion: the residual and speed thresholds alone
    old = dict(steady, rest=None)
    early = study.relax(small_tissue, APPLE, 0.6, tmp_path / "old", method="dynamics", dt=dt,
                        steady=old)
    prior = study.relax(small_tissue, APPLE, 0.6, tmp_path / "old-", method="dynamics", dt=dt,
                        steady=dict(old, max_steps=early["steps"] - every))
    assert early["steps"] < stop["steps"]
    assert remaining(prior["speed"], early["speed"], every * dt) > study.REST


def remaining(v_before, v, interval):
    """What is left of a path whose speed fell from ``v_before`` to ``v`` over ``interval``,
    decaying exponentially: v tau, tau = interval / ln(v_before / v); infinite when the
    speed did not fall."""
    return v * interval / math.log(v_before / v) if v_before > v else math.inf
