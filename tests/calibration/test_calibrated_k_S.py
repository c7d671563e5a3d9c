# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The cell-shape stiffness k_S (optional in a material file, 0 when absent) can be fitted
like any other parameter: named, started, passed to the runs, recovered from CGMS's own
steady states and written into the fitted material file."""

import pytest

from cgms.calibration import calibrate, fitparams
from cgms import material, study, tissue
from cgmstest import APPLE, MAT, require_lammps

LEVELS = (1.0, 0.3)


def test_k_S_is_a_parameter_though_apple_has_none(tmp_path):
    assert "k_S" not in material.read(APPLE) or material.read(APPLE)["k_S"] == 0
    with pytest.raises(ValueError, match=r"start value must be finite and non-zero.*--start "
                                         r"k_S=0.1"):
        fitparams.parse_parameters(["k_S"], MAT, LEVELS)
    params = fitparams.parse_parameters(["k_T", "k_S"], MAT, LEVELS, start={"k_S": 0.2})
    assert [p.start for p in params] == [MAT["k_T"], 0.2]
    assert fitparams.overrides(params, [2e-10, 0.3], MAT, 0.3) == "k_T 2e-10 k_S 0.3"
    fitted = fitparams.fitted_material(params, [2e-10, 0.3], MAT, LEVELS)
    path = material.write(tmp_path / "fit.cgms", APPLE, fitted, "a note")
    back = material.read(path)
    assert back["k_S"] == 0.3 and back["k_T"] == 2e-10
    assert any(line.split()[:2] == ["k_S", "0.3"] and "fitted (not in apple.cgms)" in line
               for line in path.read_text().splitlines())


def test_k_S_recovered_from_cgms_steady_states(tmp_path):
    """References at k_S = 0.4 and k_T x1.5 (CGMS's own steady states); the fit from
    k_S = 0.1 finds both within 1 %, and the start was far off (RMSD at s = 0.3)."""
    require_lammps()
    data = tmp_path / "tissue.data"
    tissue.write_data(data, tissue.rectangle(1.25e-3, 1.5e-3, MAT["x_ref"]), 3 * MAT["x_ref"])
    over = f"k_S 0.4 k_T {1.5 * MAT['k_T']!r}"
    refs = {s: study.relax(data, APPLE, s, tmp_path / "ref", method="quasistatic",
                           overrides=over)["xy"] for s in LEVELS}
    result = calibrate.calibrate(data, APPLE, refs, tmp_path / "fit", parameters=["k_T", "k_S"],
                                 start={"k_S": 0.1}, material_out=False, progress=False)
    assert result["parameters"]["k_S"] == pytest.approx(0.4, rel=1e-2)
    assert result["parameters"]["k_T"] == pytest.approx(1.5 * MAT["k_T"], rel=1e-2)
    assert result["rmsd_start"][0.3] > 100 * result["rmsd"][0.3]
