# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""studies/measured_drying/compare.py: the measured data of reference/drying/ read as
their sources state them, and the crossing and level look-ups against cases whose answer
is known exactly (doc/results/drying-measured.md). No LAMMPS."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
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


def test_at_level_interpolates_between_rows():
    # X/X0 falls linearly and A/A0 = 0.5 + X/X0 / 2 along it: the value at any level
    # between rows is 0.5 + level / 2 exactly (to rounding); a level never reached is None
    x = np.linspace(1.0, 0.15, 18)
    d = {"X/X0": x, "A/A0": 0.5 + x / 2}
    for level in (0.8, 0.43, 0.3):
        assert compare.at_level(d, level, "A/A0") == pytest.approx(0.5 + level / 2, abs=1e-12)
    assert compare.at_level(d, 0.1, "A/A0") is None


def test_sacilik_window_as_the_abstract_states_it():
    # the abstract: every slice "would dry perfectly within 240-460 min"
    assert compare.sacilik_window_h() == pytest.approx((240 / 60, 460 / 60), abs=1e-12)


def test_khama_end_values_as_the_abstract_states_them():
    # the abstract, oven drying: volume down 80 %, diameter 20 %, thickness 70 %; the
    # face-area ratio is (1 - 0.20)^2
    assert compare.khama_end() == pytest.approx(dict(V=0.20, L=0.30, A=0.64), abs=1e-12)


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
