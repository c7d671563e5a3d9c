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
                     "bounds": dict(bounds or {}), "levels": sorted(references)})
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


def test_direct_fits_all_levels_at_once(calls, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    assert fit.main(["--levels", "1,0.8,0.6", "--direct", "--out", str(tmp_path)]) == 0
    assert [c["levels"] for c in calls] == [[0.6, 0.8, 1.0]] * 2    # paper-3, then kS
    calls.clear()
    assert fit.main(["--levels", "1,0.8,0.6", "--out", str(tmp_path / "b")]) == 0
    assert [c["levels"] for c in calls][:2] == [[0.8, 1.0], [0.6, 0.8, 1.0]]


def test_k_S_fit_starts_from_the_start_materials_k_S(calls, tmp_path, monkeypatch):
    """A start material with a measured k_S(s) starts the k_S fit there (its exponent is
    held: not a fitted name); without one the fit starts at 0.02 N/m."""
    monkeypatch.chdir(ROOT)
    start = tmp_path / "apple-ks.cgms"
    start.write_text((ROOT / "potentials" / "apple.cgms").read_text()
                     + "k_S 2.9\nk_S_exponent 6\n")
    assert fit.main(["--material", str(start), "--mfc", "reference/mfc/calibration",
                     "--levels", "1,0.8", "--out", str(tmp_path / "a")]) == 0
    assert calls[-1]["start"]["k_S"] == 2.9
    assert "k_S_exponent" not in calls[-1]["parameters"]
    calls.clear()
    assert fit.main(["--levels", "1,0.8", "--out", str(tmp_path / "b")]) == 0
    assert calls[-1]["start"]["k_S"] == 0.02
