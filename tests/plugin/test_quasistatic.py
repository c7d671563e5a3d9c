# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The quasi-static problem: with every bead's pressure held at -Pi (``balance yes``, or
``minimize``), fix cgms/fluid reports a potential whose gradient is minus the CGMS forces,
so that LAMMPS minimisers and cgms.solve can work on it.

Checked two ways: the plugin's energy against finite differences of itself (forces), and
against the potential written down from doc/model.md with reference.py's geometry."""

import numpy as np
import pytest

import reference
from cgms import model
from cgmstest import (APPLE, CUTOFF, MAT, XREF, header, make_tissue, new_lammps, physics,
                      working_directory)

pytestmark = pytest.mark.lammps


def session(folder, pair_args="damping no", fix_args="balance yes", overrides=""):
    lmp = new_lammps()
    with working_directory(folder):
        lmp.commands_string(header() + physics(pair_args, fix_args, overrides))
    lmp.command("thermo_style custom step pe f_fl")
    lmp.command("run 0")
    return lmp


def energy_forces(lmp, xy):
    """pe and forces (id order) with the beads at ``xy``."""
    from cgms import solve
    return solve.LammpsForces(lmp)(xy)


@pytest.mark.parametrize("seed,pair_args,overrides", [
    (3, "damping no", ""), (4, "damping no periphery no", ""),
    (5, "damping no attraction no", ""), (6, "damping no", "k_S 0.5"),
    (8, "damping no", "k_S 2.9 k_S_exponent 6")])
def test_energy_gradient_is_minus_force(tmp_path, seed, pair_args, overrides):
    info = make_tissue(tmp_path, jitter=0.08, seed=seed, s=(0.3, 1.0))
    lmp = session(tmp_path, pair_args, overrides=overrides)
    try:
        x0 = info["xy"]
        e0, f0 = energy_forces(lmp, x0)
        h = 1e-9  # m, about 1e-5 of the bead spacing
        rng = np.random.default_rng(seed)
        worst = 0.0
        for i in rng.choice(info["n"], 15, replace=False):
            for d in range(2):
                xp, xm = x0.copy(), x0.copy()
                xp[i, d] += h
                xm[i, d] -= h
                grad = (energy_forces(lmp, xp)[0] - energy_forces(lmp, xm)[0]) / (2 * h)
                worst = max(worst, abs(grad + f0[i, d]))
        assert worst < 1e-6 * np.abs(f0).max(), worst
    finally:
        lmp.close()


@pytest.mark.parametrize("k_s", [0.0, 0.5])
def test_energy_matches_model(tmp_path, k_s):
    """pe = LJ energy + sum_i [-k_T/2 (P_i - P_f) sum_k x_ik + k_PA (l_i - l_d,i)^2 / (4 g_i)
    + k_S/2 sum_k (x_ik - xbar_i)^2] with P_i = -Pi_i = s_i |Pi_f| and g_i = dl_i/dx_ik,
    from reference.py's geometry."""
    info = make_tissue(tmp_path, jitter=0.1, seed=7, s=(0.2, 1.0))
    lmp = session(tmp_path, overrides=f"k_S {k_s}" if k_s else "")
    try:
        pe, _ = energy_forces(lmp, info["xy"])
        fix_energy = lmp.extract_fix("fl", 0, 0)  # global scalar
    finally:
        lmp.close()
    s, xy = info["s"], info["xy"]
    l0p = model.fresh_perimeter(MAT) * np.ones_like(s)
    expected = reference.quasistatic_energy(xy, s, l0p, dict(MAT, k_S=k_s), CUTOFF)
    _, lj, _ = reference.pair_forces(xy, np.zeros_like(xy), s, np.zeros_like(s), MAT, CUTOFF,
                                     turgor=False, perimeter=False, damping=False)
    assert fix_energy == pytest.approx(expected, rel=1e-9)
    assert pe == pytest.approx(expected + lj, rel=1e-9)


@pytest.mark.parametrize("energy", ["yes", "no"])
def test_energy_is_counted_once_with_fix_modify(tmp_path, energy):
    """pair_style cgms counts the quasi-static energy in evdwl; scripts that say
    'fix_modify fl energy yes|no' (the fix added it to pe once) keep running, with pe the
    same as without the line (energy yes: not twice, with a warning)."""
    make_tissue(tmp_path, jitter=0.1, seed=7, s=(0.2, 1.0))
    pes = []
    for extra in ("", f"fix_modify fl energy {energy}"):
        lmp = new_lammps()
        lmp.command(f"log {tmp_path / f'log{len(pes)}.lammps'}")
        try:
            with working_directory(tmp_path):
                lmp.commands_string(header() + physics("damping no", "balance yes") + extra)
            lmp.command("thermo_style custom step pe evdwl f_fl")
            lmp.command("run 0")
            pes.append((lmp.get_thermo("pe"), lmp.get_thermo("evdwl"), lmp.extract_fix("fl", 0, 0)))
        finally:
            lmp.close()
    (pe, evdwl, qs), (pe_modified, _, qs_modified) = pes
    assert qs != 0.0 and qs_modified == qs
    assert pe == evdwl    # the quasi-static energy is part of the pair's
    assert pe_modified == pe
    warned = "fix_modify fl energy yes is not needed" in (tmp_path / "log1.lammps").read_text()
    assert warned == (energy == "yes")


def test_no_potential_in_dynamics(tmp_path):
    """While pressures follow the fluid mass the turgor and perimeter forces have no
    potential: the fix reports 0 and pe is the LJ energy alone (k_S = 0)."""
    make_tissue(tmp_path, seed=2, s=0.5)
    lmp = session(tmp_path, "damping no", "")
    try:
        assert lmp.extract_fix("fl", 0, 0) == 0.0
    finally:
        lmp.close()


# --- cgms.solve: the Newton solver ------------------------------------------------------

def springs(xy0, cutoff):
    """A NumPy force field with the same reach as CGMS (forces depend on neighbours of
    neighbours): E = sum_i (sum_k |x_i - x_k| - L_i)^2 / 2 over neighbours k of the
    starting lattice, L_i = 1.05 times the starting sum."""
    from scipy.spatial import cKDTree
    pairs = cKDTree(xy0).query_pairs(cutoff, output_type="ndarray")
    n = len(xy0)

    def sums(xy):
        d = xy[pairs[:, 0]] - xy[pairs[:, 1]]
        r = np.linalg.norm(d, axis=1)
        s = np.bincount(pairs[:, 0], r, n) + np.bincount(pairs[:, 1], r, n)
        return d, r, s

    target = 1.05 * sums(xy0)[2]

    class Field:
        evaluations = 0

        def __call__(self, xy):
            self.evaluations += 1
            d, r, s = sums(xy)
            excess = s - target
            u = d / r[:, None]
            w = (excess[pairs[:, 0]] + excess[pairs[:, 1]])[:, None] * u
            f = np.zeros_like(xy)
            np.add.at(f, pairs[:, 0], -w)
            np.add.at(f, pairs[:, 1], w)
            return 0.5 * np.sum(excess**2), f
    return Field()


def test_coloured_jacobian_equals_dense_one():
    from cgms import solve, tissue
    xy = tissue.hex_rectangle(8, 9, 1.0) + np.random.default_rng(0).uniform(-0.1, 0.1, (72, 2))
    field = springs(xy, 1.35)
    colours = solve.colour(xy, 4 * 1.4)
    for c in range(colours.max() + 1):  # beads of one colour are more than 5.6 apart
        pts = xy[colours == c]
        if len(pts) > 1:
            dist = np.linalg.norm(pts[:, None] - pts[None], axis=-1)
            assert dist[np.triu_indices(len(pts), 1)].min() > 5.6
    # the solver keeps a colouring while it holds: it does here, and not once the
    # beads have come 10 % closer together (the closest beads of one colour: 5.60 apart)
    assert solve.colouring_holds(xy, colours, 5.6)
    assert not solve.colouring_holds(0.9 * xy, colours, 5.6)
    _, f0 = field(xy)
    from scipy.spatial import cKDTree
    pairs = cKDTree(xy).query_pairs(2 * 1.4, output_type="ndarray")
    jac = solve.jacobian(field, xy, f0, colours, pairs, 1e-7).toarray()
    dense = np.zeros_like(jac)
    for j in range(2 * len(xy)):
        x1 = xy.copy()
        x1.ravel()[j] += 1e-7
        dense[:, j] = ((field(x1)[1] - f0) / 1e-7).ravel()
    assert np.abs(jac - dense).max() < 1e-9 * np.abs(dense).max() + 1e-12


def test_newton_finds_the_minimum_of_a_numpy_field():
    from cgms import solve, tissue
    xy = tissue.hex_rectangle(8, 9, 1.0)
    field = springs(xy, 1.35)
    start = xy + np.random.default_rng(1).uniform(-0.05, 0.05, xy.shape)
    x, info = solve.newton(field, start, 1.35, ftol=1e-12)
    assert info["converged"], info["fmax"]
    assert np.abs(field(x)[1]).max() < 1e-12


def test_newton_on_cgms_agrees_with_fire(tmp_path):
    """The Newton steady state of a dried tissue equals FIRE's (LAMMPS minimize) up to a
    rigid rotation. Tolerances from the stopping rules (tests/README.md, "Tolerances
    across configurations"): FIRE stops with every bead's force below 1e-13 N, Newton with
    every component below 1e-13 N, so the two residuals together are at most
    (sqrt(n) + sqrt(2n)) 1e-13 = 2.3e-12 N (n = 90), and a bead is off by at most that
    times the largest block row of the inverse stiffness H+ (7.4e6 x_ref/N here, rigid
    motions removed; cgms.solve.jacobian): 1.7e-5 x_ref, asserted 2e-5. A measure m moves
    by at most |H+ grad m| times it: the area 1.4e-7, the perimeter 3.5e-7, the
    elongation 5.1e-6 (|H+ grad m| / m = 6.0e4, 1.5e5, 2.2e6 /N): asserted 1e-5."""
    from cgms import morphology, run, tissue
    xy = tissue.hex_rectangle(9, 10, XREF)
    tissue.write_data(tmp_path / "t.data", xy, 4 * XREF)
    states = {}
    for method in ("newton", "quasistatic"):
        lmp = run.open_lammps()
        try:
            lmp.commands_string(run.tissue_script(tmp_path / "t.data", APPLE, 0.3,
                                                  method=method, steady=dict(max_steps=50000)))
            if method == "newton":
                info = run.solve_newton(lmp)
                assert info["converged"], info
            state = run.steady_state(lmp)
            if method == "quasistatic":      # FIRE stopped on its force tolerance
                assert state["steps"] < 50000, state
            states[method] = state["xy"]
        finally:
            lmp.close()
    # FIRE may turn the tissue as a whole (the potential does not change); Newton's
    # steps carry no rigid motion: compare after the best rigid superposition
    from cgms import superpose
    b = states["quasistatic"]
    a = superpose.align(states["newton"], b, "rigid")
    diff = np.abs(a - b).max() / XREF
    assert diff < 2e-5, diff
    ma, mb = morphology.measures(a), morphology.measures(b)
    for key in ("area", "perimeter", "elongation"):
        assert ma[key] == pytest.approx(mb[key], rel=1e-5), key


@pytest.mark.parametrize("s", [1.0, 0.3])
def test_steady_spacing_of_inner_beads(tmp_path, s):
    """material.steady_spacing (from l* = l_d - (k_T/k_PA)(P_f + s Pi_f), where every pair
    coefficient vanishes) is the mean neighbour distance of the inner beads of Newton's
    steady state; the LJ forces it neglects move it by less than 1e-3."""
    from scipy.spatial import cKDTree
    from cgms import material, run, tissue
    xy = tissue.rectangle(1.25e-3, 1.5e-3, XREF)
    tissue.write_data(tmp_path / "t.data", xy, 4 * XREF)
    lmp = run.open_lammps()
    try:
        lmp.commands_string(run.tissue_script(tmp_path / "t.data", APPLE, s, method="newton"))
        assert run.solve_newton(lmp)["converged"]
        end = run.steady_state(lmp)["xy"]
    finally:
        lmp.close()
    dist, _ = cKDTree(end).query(end, 7)
    inner = dist[:, 6] < 1.2 * dist[:, 1]  # six neighbours at about the same distance
    assert inner.sum() > 20
    mean = dist[inner, 1:].mean(axis=1)
    want = material.steady_spacing(material.read(APPLE), s)
    assert np.abs(mean / want - 1).max() < 1e-3


def test_cell_shape_energy_is_a_potential_in_dynamics(tmp_path):
    """The k_S energy does not depend on the pressures: in a run without balance the fix
    reports it (the formula of test_energy_matches_model's k_S part), and with turgor,
    perimeter and damping off (LJ and k_S: both conservative) pe + ke is conserved."""
    info = make_tissue(tmp_path, jitter=0.1, seed=8, s=0.5, vscale=0.05)
    lmp = new_lammps()
    try:
        with working_directory(tmp_path):
            lmp.commands_string(header() + physics("damping no turgor no perimeter no",
                                                   "transfer no", "k_S 0.5"))
        lmp.command("thermo_style custom step pe ke etotal f_fl")
        lmp.command("run 0")
        fix_energy = lmp.extract_fix("fl", 0, 0)
        e0, k0 = lmp.get_thermo("etotal"), lmp.get_thermo("ke")
        lmp.command("run 2000")
        e1, k1 = lmp.get_thermo("etotal"), lmp.get_thermo("ke")
    finally:
        lmp.close()
    s, xy = info["s"], info["xy"]
    _, dist, adj = reference.pair_geometry(xy, s, MAT, CUTOFF)
    xbar = np.where(adj, dist, 0.0).sum(axis=1) / adj.sum(axis=1)
    spread = np.where(adj, dist - xbar[:, None], 0.0)
    assert fix_energy == pytest.approx(0.5 * 0.5 * (spread**2).sum(), rel=1e-9)
    # the jittered beads turn potential into kinetic energy (200 times the initial ke);
    # velocity Verlet keeps the total to 7e-5 of what moved (measured)
    moved = abs(k1 - k0)
    assert moved > 10 * k0
    assert abs(e1 - e0) < 1e-3 * moved, (e0, e1, moved)


def test_newton_step_acceptance():
    """cgms.solve.step_accepted, the rule both Newton solvers (cgms.solve and
    cgms.mfc.newton) take a step by: a quadratic energy E = |x|^2 / 2 (force -x) from
    x = (1, 1), E = 1. Armijo with c = 1e-4: a step d is taken if E(x + d) <= E - 1e-4 f.d."""
    from cgms.solve import step_accepted
    x = np.array([1.0, 1.0])
    energy, force = 0.5 * x @ x, -x
    for d, taken in (([-0.5, -0.5], True),        # halfway down: E 0.25, needs <= 0.9999
                     ([-1.999, -1.999], True),    # nearly a full overshoot: E 0.999, still down
                     ([-2.001, -2.001], False),   # past it: E 1.001, up
                     ([0.1, 0.1], False)):        # uphill
        y = x + np.array(d)
        assert step_accepted(energy, force, 0.5 * y @ y, -y, np.array(d), 1e-14) is taken, d
    # within the rounding of the energy the smaller force decides: a rotation keeps E
    y = np.array([np.sqrt(2.0), 0.0])
    step = y - x
    assert not step_accepted(energy, force, 0.5 * y @ y, -y, step, 1e-14)  # |f| 1.41 > 1
    z = np.array([0.9, -np.sqrt(2.0 - 0.81)])   # on the circle, largest force component 1.09
    assert not step_accepted(energy, force, 0.5 * z @ z, -z, z - x, 1e-14)
    w = np.array([1.0, -1.0])                   # on the circle, largest component 1 = |f|max
    assert not step_accepted(energy, force, 0.5 * w @ w, np.array([-0.5, 1.1]), w - x, 1e-14)
    assert step_accepted(energy, force, 0.5 * w @ w, np.array([-0.5, 0.5]), w - x, 1e-14)
