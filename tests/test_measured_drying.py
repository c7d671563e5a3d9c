# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""studies/measured_drying/compare.py: the measured data of reference/drying/ read as
documented, and the curve metrics against cases whose answer is known exactly
(doc/drying-measured.md). No LAMMPS."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location(
    "measured_compare", ROOT / "studies" / "measured_drying" / "compare.py")
compare = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare)


def test_crossing_of_a_straight_line_is_exact():
    # y = 1 - t/4 on a grid that does not contain the crossings: linear interpolation
    # between two points of a straight line is exact (to rounding)
    t = np.linspace(0.0, 4.0, 14)
    y = 1 - t / 4
    assert compare.crossing(t, y, 0.5) == pytest.approx(2.0, abs=1e-12)
    assert compare.crossing(t, y, 0.1) == pytest.approx(3.6, abs=1e-12)
    assert compare.crossing(t, y, -0.1) is None          # never reached
    assert compare.crossing(t, y, 1.0) is None           # reached at the first point


def test_curve_metrics_of_a_known_offset():
    # the "model" is the measured exponential shifted by +0.02: RMS and largest difference
    # are 0.02 up to linear interpolation of the model between its points, whose error is
    # at most h^2 max|f''| / 8 (h = model spacing, f'' = exp(-t) <= 1)
    t_model = np.linspace(0.0, 8.0, 801)
    t_data = np.linspace(0.05, 7.95, 57)
    bound = (t_model[1] - t_model[0]) ** 2 / 8
    m = compare.compare_curve(t_data, np.exp(-t_data), t_model, np.exp(-t_model) + 0.02)
    assert m["rms"] == pytest.approx(0.02, abs=bound)
    assert m["signed_at_largest"] == pytest.approx(0.02, abs=bound)
    assert m["n"] == m["n_all"] == 57
    # times to 0.5 and 0.1: ln 2 and ln 10 for the data (interpolated between its points:
    # error <= h_data^2 / 8 in y, divided by the slope there), ln(1/0.48) and ln(1/0.08)
    # for the model
    h = t_data[1] - t_data[0]
    assert m["t05_data"] == pytest.approx(np.log(2), abs=h ** 2 / 8 / 0.5)
    assert m["t01_data"] == pytest.approx(np.log(10), abs=h ** 2 / 8 / 0.1)
    assert m["t05_model"] == pytest.approx(np.log(1 / 0.48), abs=bound / 0.48)
    assert m["t01_model"] == pytest.approx(np.log(1 / 0.08), abs=bound / 0.08)


def test_model_shorter_than_data_is_compared_where_it_exists():
    t = np.linspace(0.0, 10.0, 11)
    m = compare.compare_curve(t, 1 - t / 20, np.linspace(0, 5, 6), 1 - np.linspace(0, 5, 6) / 20)
    assert (m["n"], m["n_all"]) == (6, 11)
    assert m["rms"] == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("name", ["royen-v0.85", "royen-v1.1"])
def test_measured_curves_read_as_documented(name):
    # reference/drying/README.md: 173 and 143 distinct rows (the 1.1 m/s file repeats its
    # last row), starting at 4.1 and 9.9 min, X of fresh apple near 6.4 kg/kg falling to
    # near 0.26
    t, x = compare.read_measured(compare.RUNS[name]["data"])
    first = {"royen-v0.85": 4.1, "royen-v1.1": 9.9}[name] / 60
    distinct = {"royen-v0.85": 173, "royen-v1.1": 143}[name]
    assert len(np.unique(np.column_stack([t, x]), axis=0)) == distinct
    assert t[0] == pytest.approx(first, abs=0.1 / 60)
    assert np.all(np.diff(t) >= 0)
    assert 6.4 < x[0] < 6.5 and 0.25 < x[-1] < 0.30


def test_khama_end_values_are_consistent():
    # V/V0 = (D/D0)^2 L/L0 for a disc; each stated ratio is a whole per cent, so each is
    # within 0.005 and the product within 2 (0.8)(0.3)(0.005) + (0.64)(0.005) + 0.005
    d = compare.read_table(compare.REF / "khama2018_apple_slices_shrinkage_end.csv")
    for v, dd, ll, area in zip(d["V_over_V0"], d["D_over_D0"], d["L_over_L0"],
                               d["face_area_ratio_derived"]):
        assert dd ** 2 == pytest.approx(area, abs=1e-12)
        assert dd ** 2 * ll == pytest.approx(v, abs=2 * 0.8 * 0.3 * 0.005 + 0.64 * 0.005 + 0.005)


def test_every_reference_file_names_its_source():
    for path in sorted(compare.REF.glob("*.csv")):
        head = "".join(line for line in path.read_text().splitlines(True)
                       if line.startswith("#"))
        assert "Source:" in head, path.name
        assert "read" in head, path.name          # what was read, and how
