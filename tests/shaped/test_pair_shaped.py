# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""pair_style cgms/shaped against its oracle, cgms.shaped_tensor.energy: the energy, the
forces on the beads and the generalised forces -dE/dF of the 86-cell calibration tissue in
a perturbed state (random beads and F: walls stretched and buckled, an LJ pair inside its
radius, rim bonds with beta != 1), on 1 and 2 ranks with newton on and off, for the best
parameter set and for the other branches of every law (chord strip, no void, the whole F
as the bond target).

Tolerance: every entry is a sum of at most NB + NW + 2 terms (the bead's bonds, its walls,
its fluid), each rounded to a few eps of its own size, plus the mismatch m = x_k - x_i - ...,
which inherits the rounding eps |x| of the positions; so an entry may differ by
c eps [(NB + NW + 2) term + NB k_g |x|] with c a small constant (64 here). The terms'
sizes: a cell's fluid H |P| A_poly0 and a wall's |dE/dl| |d0| (dE/dF), a bond k_g |m| and
the LJ f0 / r (beads)."""

import numpy as np
import pytest

import shapedlmp as sl
from cgms import shaped, shaped_data, shaped_tensor as st

C = 64


def term_scales(z, lev):
    """(bead-force term, dE/dF term, energy term) sizes of a state."""
    x, F, c, chord, A, e_w, de_w, m, H, K = st._terms(z, lev)
    P = np.abs(shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)).max() + K
    fF = H * P * lev["poly_area0"].max() + np.abs(de_w).max() * np.abs(lev["d0"]).max()
    fx = lev["k_g"] * (np.abs(m).max() + np.abs(x).max()) + lev["mat"]["f0_r"] / lev["r_lj"]
    energy = H * K * lev["A_f0"].sum() + np.abs(e_w).sum() + lev["k_g"] * np.sum(m * m)
    return fx, fF, energy


def forces_match_the_oracle(z, fx, fF, lev, geo):
    """Bead forces and -dE/dF from LAMMPS against the oracle's gradient at the same state,
    each within rounding of its terms (C ulps per summed term); returns the oracle's energy
    and the energy's term size."""
    E, g = st.energy(z, lev)
    n = lev["n"]
    b = shaped_data.per_bead(geo)
    terms = b["nb"].shape[1] + b["wallx"].shape[1] + 2
    sx, sF, sE = term_scales(z, lev)
    err_x = np.abs(fx + g[:2 * n].reshape(n, 2)).max()
    err_F = np.abs(fF + g[2 * n:].reshape(n, 4)).max()
    assert err_x <= C * sl.EPS * terms * sx, (err_x, sx)
    assert err_F <= C * sl.EPS * terms * sF, (err_F, sF)
    return E, sE


def compare(folder, z, lev, geo, s, params, nprocs=1, newton="on", extra=""):
    proc = sl.run(folder, geo, z, s, params, sl.APPLE, nprocs=nprocs, newton=newton,
                  extra=extra)
    pe = sl.thermo_rows(proc.stdout)[0][1]
    z_lmp, fF, fx = sl.read_state(folder / "state.dump")
    assert np.array_equal(z_lmp, z)    # the data file carries the state exactly
    E, sE = forces_match_the_oracle(z, fx, fF, lev, geo)
    assert abs(pe - E) <= C * sl.EPS * sE, (pe, E, sE)
    return fx, fF, pe


@pytest.mark.lammps
@pytest.mark.parametrize("newton", ["on", "off"])
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_forces_and_energy_match_the_oracle(tmp_path, nprocs, newton):
    xy, geo = sl.calibration_tissue(sl.BEST)
    z, lev = sl.perturbed_state(xy, geo, 0.6)
    rim = lev["rim"].any() and lev["beta"] != 1.0
    stretched = np.sum(st.cells(z, lev)[3] > lev["rest"])
    assert rim and stretched > 0 and stretched < len(lev["rest"])
    fx, fF, _ = compare(tmp_path, z, lev, geo, 0.6, sl.BEST, nprocs, newton)
    assert np.abs(fx).max() > 0 and np.abs(fF).max() > 0


@pytest.mark.lammps
def test_every_branch_matches_the_oracle(tmp_path):
    """Chord strip, no void, iso 0, and a dryness where the void is half open."""
    xy, geo = sl.calibration_tissue(sl.OTHER)
    z, lev = sl.perturbed_state(xy, geo, 0.45, seed=5)
    compare(tmp_path, z, lev, geo, 0.45, sl.OTHER, extra="reach 2")   # the pushed LJ bead
    # the void's step and the contour's smoothing both in their middle at s = 0.95
    params = dict(sl.BEST, smooth=2.0, void_onset=3.0)
    xy, geo = sl.calibration_tissue(params)
    z, lev = sl.perturbed_state(xy, geo, 0.95, seed=7, spread=0.03)
    _, F, c, chord, _ = st.cells(z, lev)
    psi = st.void_open(np.bincount(lev["cell"], chord, minlength=lev["n"]), lev)[0]
    assert np.any((psi > 0) & (psi < 1))
    assert np.any(np.abs(chord - lev["rest"]) < lev["delta"])
    compare(tmp_path, z, lev, geo, 0.95, params, extra="reach 2")


@pytest.mark.lammps
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_cells_with_an_odd_number_of_walls_match_the_oracle(tmp_path, nprocs):
    """The pair evaluates a cell's walls two at a time (the last lane of a cell with an odd
    number of walls repeats its last wall and must not be summed): an irregular tissue whose
    cells have 5, 7 and 8 walls."""
    xy, _ = sl.calibration_tissue(sl.BEST)
    xy = xy + np.random.default_rng(5).uniform(-0.3, 0.3, xy.shape) * sl.L
    geo = st.build(xy, sl.MAT, sl.BEST)
    walls = np.bincount(geo["cell"])
    assert np.any(walls % 2 == 1) and np.any(walls % 2 == 0)
    z, lev = sl.perturbed_state(xy, geo, 0.6, spread=0.1)
    compare(tmp_path, z, lev, geo, 0.6, sl.BEST, nprocs, extra="reach 2")


def test_the_local_builder_gives_the_prototypes_data():
    """cgms.shaped_data.per_bead of the local build (shaped_tensor.build(local=True), for
    large tissues) against that of the prototype's whole-tissue build, on the calibration
    tissue and an irregular one: the same IDs and fresh bonds; wall vectors and polygon
    areas to rounding (a junction is placed by sums in another order: a few ulps of the
    coordinates, so 16 eps |x| per wall end and, for an area, that times the walls'
    length from the centre, 2 ends and up to NW walls)."""
    from cgms import tissue
    jittered = tissue.rectangle(1e-3, 0.8e-3, sl.L)
    jittered = jittered + np.random.default_rng(2).uniform(-0.1, 0.1, jittered.shape) * sl.L
    eps = np.finfo(float).eps
    for xy in (sl.calibration_tissue(sl.BEST)[0], jittered):
        whole = shaped_data.per_bead(st.build(xy, sl.MAT, sl.BEST))
        local = shaped_data.per_bead(st.build(xy, sl.MAT, sl.BEST, local=True))
        assert set(whole) == set(local)
        for key in ("nb", "bondx", "bondy", "nwall", "boundary"):
            assert np.array_equal(whole[key], local[key]), key
        wall = 16 * eps * np.abs(xy).max()
        for key in ("wallx", "wally"):
            np.testing.assert_allclose(local[key], whole[key], rtol=0, atol=2 * wall)
        reach = 2 * sl.L * 2 * whole["wallx"].shape[1]
        np.testing.assert_allclose(local["area0"], whole["area0"], rtol=0, atol=wall * reach)


@pytest.mark.lammps
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_the_per_list_caches_follow_the_beads(tmp_path, nprocs):
    """The pair keeps per-bead data in the local order of the neighbour list (rest lengths,
    the bonds' local neighbours, the LJ pairs without fresh neighbours): a minimisation
    that sorts the beads and builds a new list at every step (and on 2 ranks moves beads
    between ranks) ends in a state whose forces still match the oracle's."""
    xy, geo = sl.calibration_tissue(sl.BEST)
    z, lev = sl.perturbed_state(xy, geo, 0.6)
    shaped_data.write_data(tmp_path / "tissue.data", geo, z, overwrite=True)
    script = (sl.header(geo, nprocs=nprocs)
              .replace("sort 0 0", f"sort 1 {3 * sl.L}")
              .replace("check yes", "check no")
              + sl.physics(0.6, sl.BEST, sl.APPLE) + sl.output()
              + "min_style cg\nmin_modify dmax 1e-6 line forcezero\nminimize 0 0 12 100\n")
    from cgmstest import run_lmp
    proc = run_lmp(tmp_path, script, nprocs=nprocs)
    z_lmp, fF, fx = sl.read_state(tmp_path / "state.dump")
    assert not np.array_equal(z_lmp, z)    # the beads and F moved
    assert "Neighbor list builds = 0" not in proc.stdout
    forces_match_the_oracle(z_lmp, fx, fF, lev, geo)
