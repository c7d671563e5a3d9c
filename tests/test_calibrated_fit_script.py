# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""examples/calibration/fit.py --hold: a held parameter is never handed to the minimiser
(neither as fitted nor with a bound), so it keeps the start material's value; a name that
is not one of the paper's four is refused in one line. cgms.calibrate itself is replaced by
a recorder: what is checked is the script's choice of parameters, not the fit."""

import sys

import pytest

from cgmstest import ROOT

sys.path.insert(0, str(ROOT / "examples" / "calibration"))
import fit  # noqa: E402


@pytest.fixture
def calls(monkeypatch):
    seen = []

    def recorder(data, material, references, out, parameters, start=None, bounds=None,
                 **kwargs):
        seen.append({"parameters": list(parameters), "start": dict(start or {}),
                     "bounds": dict(bounds or {})})
        values = {k: 1.0 for k in parameters}
        return {"parameters": values, "stderr": {k: 0.0 for k in parameters},
                "rmsd": {s: 0.0 for s in references}, "seconds": 0.0, "on_bound": [],
                "correlation": [[0.0] * len(values)] * len(values), "material_file": None}

    monkeypatch.setattr(fit.calibrate, "calibrate", recorder)
    return seen


def test_held_parameter_is_not_fitted(calls, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)   # the default --mfc folder is relative to the repository
    assert fit.main(["--hold", "k_T", "--also", "turgid_ratio", "--levels", "1,0.8",
                     "--out", str(tmp_path)]) == 0
    assert len(calls) == 2    # paper-2, then kS
    for call in calls:
        assert "k_T" not in call["parameters"]
        assert "k_T" not in call["start"] and "k_T" not in call["bounds"]
        assert {"k_PA", "beta_a", "beta_b", "turgid_ratio"} <= set(call["parameters"])
        assert set(call["bounds"]) <= set(call["parameters"])
    assert "k_S" in calls[-1]["parameters"]


def test_without_hold_all_four_are_fitted(calls, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    assert fit.main(["--levels", "1,0.8", "--out", str(tmp_path)]) == 0
    assert set(fit.PAPER) <= set(calls[0]["parameters"])


def test_hold_of_an_unknown_name_is_refused(calls, tmp_path):
    with pytest.raises(SystemExit) as stop:
        fit.main(["--hold", "k_X", "--out", str(tmp_path)])
    assert "--hold k_X" in str(stop.value) and "k_T" in str(stop.value)
    assert not calls
