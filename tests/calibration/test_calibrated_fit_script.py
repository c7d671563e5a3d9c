# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""studies/calibration/fit.py --hold: a held parameter is never handed to the minimiser
(neither as fitted nor with a bound), so it keeps the start material's value; a name that
is not one of the paper's four is refused in one line. cgms.calibration.calibrate itself is
replaced by a recorder: what is checked is the script's choice of parameters, not the fit."""

import math
import sys

import pytest

from cgmstest import ROOT

sys.path.insert(0, str(ROOT / "studies" / "calibration"))
import fit  # noqa: E402


@pytest.fixture
def calls(monkeypatch):
    seen = []

    def recorder(data, material, references, out, parameters, start=None, bounds=None,
                 **kwargs):
        seen.append({"material": str(material),
                     "parameters": list(parameters), "start": dict(start or {}),
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


def test_lj_slope_start_and_its_upper_bound(calls, tmp_path, monkeypatch):
    """--lj-slope replaces the start material's lj_slope (nothing else), and --also lj_slope
    searches it up to where the cutoff 1.35 r0 (1 + lj_slope ln s) still holds the built
    lattice (spacing r0) at the driest level, with 1 % to spare: 1.35 (1 + limit ln 0.8)
    = 1.01."""
    from cgms import material

    monkeypatch.chdir(ROOT)
    assert fit.main(["--lj-slope", "0.07", "--also", "lj_slope", "--levels", "1,0.8",
                     "--out", str(tmp_path)]) == 0
    used = material.read(calls[0]["material"])
    apple = material.read("apple")
    assert used["lj_slope"] == 0.07
    assert {k: v for k, v in used.items() if k != "lj_slope"} == \
        {k: v for k, v in apple.items() if k != "lj_slope"}
    limit = 0.07 * calls[0]["bounds"]["lj_slope"][1]
    assert 1.35 * (1 + limit * math.log(0.8)) == pytest.approx(1.01, rel=1e-12)
    assert "lj_slope" in calls[0]["parameters"] and "lj_slope" in calls[-1]["parameters"]


def test_lj_slope_whose_cutoff_misses_the_lattice_is_refused(calls, tmp_path, monkeypatch):
    """At s = 0.3 lj_slope 0.25 gives a cutoff of 1.35 (1 + 0.25 ln 0.3) = 0.94 r0: every
    bead of the built lattice would start isolated; refused in one line, nothing run."""
    monkeypatch.chdir(ROOT)
    with pytest.raises(SystemExit) as stop:
        fit.main(["--lj-slope", "0.25", "--levels", "1,0.8,0.6,0.4,0.3",
                  "--out", str(tmp_path)])
    assert "lj_slope 0.25" in str(stop.value) and "s = 0.3" in str(stop.value)
    assert not calls
    # 0.2 is inside (cutoff 1.025 r0): accepted
    assert fit.main(["--lj-slope", "0.2", "--levels", "1,0.8,0.6,0.4,0.3",
                     "--out", str(tmp_path / "b")]) == 0


def test_without_kS_skips_the_kS_stage_and_needs_the_paper_fit(calls, tmp_path, monkeypatch):
    """--without-kS runs the paper stages only; with the default --install-fit kS it would
    leave nothing to install: refused in one line, nothing run."""
    monkeypatch.chdir(ROOT)
    assert fit.main(["--levels", "1,0.8,0.6", "--direct", "--without-kS", "--install-fit",
                     "paper", "--out", str(tmp_path)]) == 0
    assert len(calls) == 1 and "k_S" not in calls[0]["parameters"]
    calls.clear()
    with pytest.raises(SystemExit) as stop:
        fit.main(["--without-kS", "--out", str(tmp_path / "b")])
    assert "--without-kS" in str(stop.value) and "--install-fit paper" in str(stop.value)
    assert not calls
