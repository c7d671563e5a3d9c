# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Temperature in the fine model (doc/drying.md, "Temperature in the mechanics"): the
softening, van 't Hoff and membrane factors computed here by hand from the numbers the doc
states, the unheated parameter set unchanged, and a heated fresh cell in LAMMPS against
Laplace's law for its ring with those factors."""

import math

import pytest
from scipy.optimize import brentq

from cgms import run
from cgms.mfc import metrics as mfc_metrics, model as mfc_model, run as mfc_run, tissue as mfc_tissue

R = 8.314462618          # J/(mol K), CODATA 2018
KELVIN = 273.15
# the doc's numbers: E-modulus softening k = 0.161 1/min at 100 C, E_a = 138 kJ/mol; 10 %
# residual; 1 h at temperature; membranes intact to 50 C, gone at 60 C; reference 20 C
K100, EA, RESIDUAL, HOURS, ONSET, GONE, REF = 0.161 / 60, 138e3, 0.1, 1.0, 50.0, 60.0, 20.0


def softening(T):
    k = K100 * math.exp(-EA / R * (1 / (T + KELVIN) - 1 / (100 + KELVIN)))
    return RESIDUAL + (1 - RESIDUAL) * math.exp(-k * HOURS * 3600)


def turgor(T):
    intact = 1.0 if T <= ONSET else 0.0 if T >= GONE else (GONE - T) / (GONE - ONSET)
    return (T + KELVIN) / (REF + KELVIN) * intact


# Tolerances: the factors are a handful of floating-point operations (exp, divisions) in
# either code, so they agree to a few ulps; 1e-12 relative leaves room for the order of the
# operations and nothing for a wrong constant (the smallest change a constant of the doc
# could carry, its last printed digit, moves the factors by more than 1e-4).
EXACT = 1e-12


def test_unheated_parameter_set_is_todays():
    """No temperature: the dict has no new key and its derived values are those of the
    formulas of doc/mfc.md, computed here from the material's inputs."""
    p = mfc_model.parameters()
    assert p == mfc_model.parameters("apple", temperature=None)
    assert not {"temperature", "wall_factor", "turgor_factor"} & set(p)
    strain = p["P_f"] * p["diameter"] / (2 * 330.0)
    r0 = math.pi * p["diameter"] / (1 + strain) / 96
    assert p["wall_Et"] == 330.0 and p["lamella_k"] == 7.3 and p["lamella_E0"] == 1.45e-11
    assert p["r0_bond"] == pytest.approx(r0, rel=EXACT)
    assert p["k_bond"] == pytest.approx(330.0 * p["height"] / r0, rel=EXACT)
    assert p["k_bend"] == pytest.approx(330.0 * p["height"] * 1e-12 / (12 * r0), rel=EXACT)
    for s in (1.0, 0.6, 0.3):
        assert mfc_model.level(p, s)["turgor"] == s * p["P_f"]


@pytest.mark.parametrize("T", [0.0, 20.0, 40.0, 55.0, 60.0, 80.0, 100.0])
def test_heated_parameters_follow_arrhenius_van_t_hoff_and_the_membranes(T):
    cold = mfc_model.parameters()
    p = mfc_model.parameters(temperature=T)
    w = softening(T)
    assert p["wall_factor"] == pytest.approx(w, rel=EXACT)
    for name in ("wall_Et", "k_bond", "k_bend", "lamella_k", "lamella_E0"):
        assert p[name] == pytest.approx(w * cold[name], rel=EXACT), name
    # the wall's shape is not the temperature's: rest lengths and masses unchanged
    for name in ("r0_bond", "strain_turgid", "fluid_mass", "wall_mass", "A_ref", "P_f"):
        assert p[name] == cold[name], name
    for s in (1.0, 0.6):
        lv, lv0 = mfc_model.level(p, s), mfc_model.level(cold, s)
        assert lv["turgor"] == pytest.approx(s * 2e5 * turgor(T), rel=EXACT, abs=1e-9)
        assert {k: v for k, v in lv.items() if k != "turgor"} == \
            {k: v for k, v in lv0.items() if k != "turgor"}


def test_the_docs_factors():
    """The values doc/drying.md tables (3 digits) are the ones computed here."""
    for T, w, t in ((40, 0.998, 1.068), (60, 0.959, 0.0), (80, 0.513, 0.0)):
        p = mfc_model.parameters(temperature=T)
        assert round(p["wall_factor"], 3) == w == round(softening(T), 3)
        assert round(p["turgor_factor"], 3) == t == round(turgor(T), 3)


@pytest.mark.parametrize("T", [-0.5, 100.5, float("nan"), float("inf")])
def test_temperature_outside_liquid_water_is_refused(T):
    with pytest.raises(ValueError, match="temperature must be in 0 .. 100 C"):
        mfc_model.parameters(temperature=T)


def ring(p, k_bond, pt):
    """The steady regular 96-gon of a free fresh cell: Laplace's law for a ring of springs
    of stiffness ``k_bond`` around fluid of area A_ref at rest and turgor ``pt`` (CGMS eqn 4
    written here), solved by bisection."""
    n, r0 = p["n_wall"], p["r0_bond"]

    def eos(area):
        return pt + 2.0e7 * ((p["A_ref"] / area) ** 7 - 1)

    def residual(l):
        rc = l / (2 * math.sin(math.pi / n))
        area = n / 2 * rc * rc * math.sin(2 * math.pi / n)
        return (eos(area) * p["height"] * rc * math.sin(2 * math.pi / n)
                - 2 * k_bond * (l - r0) * math.sin(math.pi / n))

    l = brentq(residual, 0.9 * r0, 1.3 * r0, xtol=1e-18)
    rc = l / (2 * math.sin(math.pi / n))
    area = n / 2 * rc * rc * math.sin(2 * math.pi / n)
    return dict(bond=l, area=area, pressure=eos(area))


@pytest.mark.lammps
@pytest.mark.parametrize("T", [55.0, 80.0])
def test_heated_fresh_cell_in_lammps_is_the_softened_ring(tmp_path, T):
    """LAMMPS receives the heated wall and turgor: the fresh cell's bonds, area and pressure
    are the ring's with k_bond x softening(T) and turgor 2e5 x turgor(T). Within 1e-6: the
    coefficients pass through '%.10g' (1e-10) and the force test 1e-12 N against a bond
    stiffness of 400 N/m leaves 1e-15 m; 1e-6 is the existing unheated test's bound."""
    p = mfc_model.parameters(temperature=T)
    data = tmp_path / "walls.data"
    mfc_tissue.write_data(data, [[0.0, 0.0]], p, overwrite=True)
    lmp = run.open_lammps()
    try:
        lmp.commands_list(mfc_run.setup_commands(data, p))
        lmp.commands_list(mfc_run.level_commands(p, 1.0))
        report = mfc_run.relax(lmp, p, 1.0, ftol=1e-12)
        xy = mfc_run.positions(lmp)
        pressure = lmp.numpy.extract_fix("mfc", 0, 2, 0, 1)
    finally:
        lmp.close()
    assert report["converged"], report
    cold = mfc_model.parameters()
    exact = ring(cold, softening(T) * cold["k_bond"], 2e5 * turgor(T))
    cell = mfc_metrics.cells(xy, p["n_wall"])
    bonds = [math.dist(xy[i], xy[(i + 1) % len(xy)]) for i in range(len(xy))]
    assert max(abs(b / exact["bond"] - 1) for b in bonds) < 1e-6
    assert cell["area"][0] == pytest.approx(exact["area"], rel=1e-6)
    assert pressure == pytest.approx(exact["pressure"], rel=1e-6)
