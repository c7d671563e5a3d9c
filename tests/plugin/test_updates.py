# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Per-bead updates from one step to the next: mass transfer (eqn 7, explicit Euler),
the literal rate form of the density (eqns 5-6), and the inertial mass of each mode."""

import re

import numpy as np
import pytest

from cgms import model
from cgmstest import MAT, header, make_tissue, new_lammps, physics, working_directory
from test_reference import COLUMNS, assert_close

pytestmark = pytest.mark.lammps
lammps = pytest.importorskip("lammps", reason="no LAMMPS Python module (./cgms setup)")
LMP_STYLE_ATOM = lammps.LMP_STYLE_ATOM
LMP_TYPE_ARRAY = lammps.LMP_TYPE_ARRAY


def two_states(folder, fix_args):
    """The plugin's per-bead array and masses after N steps and after one more step."""
    lmp = new_lammps()
    states = []
    try:
        with working_directory(folder):
            lmp.commands_string(header() + physics(fix_args=fix_args))
            for steps in (200, 1):
                lmp.command(f"run {steps}")
                nlocal = lmp.extract_global("nlocal")
                order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
                cg = np.array(lmp.numpy.extract_fix("fl", LMP_STYLE_ATOM, LMP_TYPE_ARRAY))
                state = {name: cg[:nlocal][order, k] for k, name in enumerate(COLUMNS)}
                state["rmass"] = np.array(lmp.numpy.extract_atom("rmass")[:nlocal])[order]
                states.append(state)
    finally:
        lmp.close()
    return states


@pytest.mark.parametrize("scheme", ["implicit", "explicit"])
@pytest.mark.parametrize("density", ["exact", "rate"])
def test_mass_transfer_and_density_update(tmp_path, density, scheme):
    make_tissue(tmp_path, jitter=0.05, seed=3, s=(0.3, 1.0), vscale=1e-3)
    old, new = two_states(tmp_path, f"density {density} transfer/scheme {scheme}")
    dt = 1e-7
    rate = old["dmdt"]  # the rate the step applies (eqn 7, or its implicit form)
    assert np.abs(rate).max() > 0
    assert_close("fluid mass", new["mf"], old["mf"] + dt * rate, rtol=1e-14)
    if density == "exact":
        want = new["mf"] / (MAT["height"] * new["area"])
    else:
        want = old["rho"] * (1 - (new["area"] - old["area"]) / old["area"]) \
            + dt * rate / (MAT["height"] * old["area"])
    assert_close("density", new["rho"], want, rtol=1e-14)
    # the default inertia is the fresh mass, constant
    assert_close("rmass", new["rmass"], (1 + MAT["solid_ratio"]) * new["mf0"], rtol=1e-15)


def test_literal_inertia_follows_fluid_mass(tmp_path):
    make_tissue(tmp_path, jitter=0.02, seed=3, s=0.9)
    old, new = two_states(tmp_path, "inertia fluid")
    assert_close("rmass", new["rmass"], new["mf"] + new["ms"], rtol=1e-15)
    assert not np.array_equal(old["rmass"], new["rmass"])


def test_rate_and_exact_density_stay_close(tmp_path):
    """Integrated exactly, eqns (5)-(6) give rho = m_f / (h A); the rate form's drift over
    a run is first order in the time step and small."""
    make_tissue(tmp_path, jitter=0.05, seed=3, s=0.6)
    exact = two_states(tmp_path, "density exact")[1]
    rate = two_states(tmp_path, "density rate")[1]
    drift = np.max(np.abs(rate["rho"] - exact["rho"]) / exact["rho"])
    assert 0 < drift < 1e-3, drift


def test_restart_keeps_dryness_when_fix_omits_it(tmp_path):
    from cgmstest import PLUGIN
    make_tissue(tmp_path, s=0.4)
    lmp = new_lammps()
    try:
        with working_directory(tmp_path):
            lmp.commands_string(header() + physics() + "run 500\nwrite_restart r.restart\n")
            before = lmp.numpy.extract_fix("fl", 0, 1, 0)
            lmp.commands_string(f"clear\nplugin load {PLUGIN}\nread_restart r.restart\n"
                                "comm_modify vel yes\nneighbor 1.5e-5 bin\n"
                                "fix fl all cgms/fluid\nfix nve all nve\nrun 0\n")
            nlocal = lmp.extract_global("nlocal")
            cg = np.array(lmp.numpy.extract_fix("fl", LMP_STYLE_ATOM, LMP_TYPE_ARRAY))[:nlocal]
            assert np.all(cg[:, COLUMNS.index("dryness")] == 0.4)
            assert lmp.numpy.extract_fix("fl", 0, 1, 0) == pytest.approx(before, rel=1e-12)
    finally:
        lmp.close()


def test_per_bead_cell_diameter(tmp_path):
    """A heterogeneous tissue: each new bead's fresh fluid mass and turgid perimeter
    follow its own cell diameter (doc/model.md: one reference cell per bead), here from an
    atom-style variable."""
    make_tissue(tmp_path, s=0.8)
    lmp = new_lammps()
    try:
        with working_directory(tmp_path):
            lmp.commands_string(header() + "variable d atom 140e-6+id*0.2e-6\n"
                                + physics(fix_args="diameter v_d") + "run 0\n")
            nlocal = lmp.extract_global("nlocal")
            ids = np.array(lmp.numpy.extract_atom("id")[:nlocal])
            cg = np.array(lmp.numpy.extract_fix("fl", LMP_STYLE_ATOM, LMP_TYPE_ARRAY))[:nlocal]
    finally:
        lmp.close()
    d = 140e-6 + ids * 0.2e-6
    cell = model.reference_cell(d, MAT["pectin"])
    col = {name: cg[:, k] for k, name in enumerate(COLUMNS)}
    assert_close("mf0", col["mf0"], MAT["rho0"] * MAT["height"] * cell["A_ref"], rtol=1e-14)
    assert_close("l0p", col["l0p"], model.fresh_perimeter(MAT, d), rtol=1e-14)
    assert_close("mf", col["mf"], 0.8 * col["mf0"], rtol=1e-14)


def test_balance_holds_steady_state_pressure(tmp_path):
    """'balance yes' (and 'minimize balance' under minimize): every bead at P = -Pi, no
    mass rate, and the fluid mass that fills its current cell at that density."""
    make_tissue(tmp_path, jitter=0.05, seed=2, s=(0.3, 1.0))
    lmp = new_lammps()
    try:
        with working_directory(tmp_path):
            lmp.commands_string(header() + physics(fix_args="balance yes") + "run 0\n")
            nlocal = lmp.extract_global("nlocal")
            cg = np.array(lmp.numpy.extract_fix("fl", LMP_STYLE_ATOM, LMP_TYPE_ARRAY))[:nlocal]
    finally:
        lmp.close()
    col = {name: cg[:, k] for k, name in enumerate(COLUMNS)}
    assert_close("pressure", col["pressure"], -col["dryness"] * MAT["Pi_f"], rtol=1e-12)
    assert np.all(col["dmdt"] == 0.0)
    assert_close("mf", col["mf"], col["rho"] * MAT["height"] * col["area"], rtol=1e-14)
    assert_close("rho", col["rho"], col["dryness"] * MAT["rho0"], rtol=1e-12)


def test_emptied_bead_stops_the_run(tmp_path):
    """A mass transfer that empties a bead (explicit scheme, a dryness jump from 1 to 0.3
    and a time step of 1e-4 s) stops the step it happens in, naming the bead, its fluid
    mass and the step; the pair's fluid pass applies the transfer and finds the bead, the
    fix's scan reports it before any other limit (turgor and damping are off here, so
    that nothing else stops the run first)."""
    from cgmstest import run_lmp
    make_tissue(tmp_path, s=1.0)
    script = header() + physics(pair_args="turgor no damping no",
                                fix_args="transfer/scheme explicit") + \
        "run 0\nset group all d_s 0.3\ntimestep 1e-4\nrun 3\n"
    run_lmp(tmp_path, script, check=False)
    errors = [ln for ln in (tmp_path / "log.lammps").read_text().splitlines() if "ERROR" in ln]
    assert errors, "the run did not stop"
    m = re.search(r"fluid mass of bead (\d+) became (\S+) at step (\d+): mass transfer is "
                  r"unstable; reduce the time step \(now 0.0001 s\)", errors[0])
    assert m, errors[0]
    assert float(m.group(2)) <= 0.0 and m.group(3) == "1"
