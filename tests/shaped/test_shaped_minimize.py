# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states of pair_style cgms/shaped by LAMMPS's minimize (min_style cg, the shape
tensors F moved as per-atom degrees of freedom) against the oracle's trust-region Newton
method, cgms.shaped_tensor.relax, on a small built tissue at s = 0.6.

Both start from the same state: the fresh tissue shrunk by sqrt(s), every F sqrt(s) times
the identity plus a seeded kick of 1e-3 (as shaped_tensor.ramp does: the isotropic state
is a saddle that a gradient method never leaves, since on the hexagonal lattice the
gradient of an isotropic F is isotropic). Both stop at a force tolerance.

The steady state is not unique: a cell's fluid and walls see its hexagon through |F d0| and
det F, so each cell may flatten along any of the hexagon's equivalent directions (F -> F Q,
Q a symmetry of the fresh hexagon) at the same energy, and the two methods pick different
ones for some cells (measured: the beads agree to 1e-8 x_ref, the energies to 1e-21 J,
while some cells' F differ by 0.15). So the test compares what the choice leaves
unchanged: the bead positions, each F's singular values and determinant, the energy.

Tolerance: near a strict minimum z* (Hessian H, smallest eigenvalue lambda away from the
three rigid motions) a state with gradient g lies within |g| / lambda of z* (the quadratic
model; with positions in units of x_ref and F as it is, so both are of order one). The
minimum LAMMPS reaches and the oracle's are images of each other under the symmetries
above (same invariants, same Hessian spectrum), so the invariants of the two states differ
by at most Lip (|g_lammps| + |g_python|) / lambda, Lip = 1 for positions and singular
values, 2 max|F| for det F, after removing the rigid motion between the states (the energy
is invariant under x -> R x + t, F -> R F). Both gradients are measured by the oracle at the
states themselves, lambda from its exact Hessian; the energies differ by at most
(|g_lammps|^2 + |g_python|^2) / lambda plus their rounding."""

import math
import re

import numpy as np
import pytest

import shapedlmp as sl
from cgms import shaped_data, shaped_tensor as st, tissue
from cgmstest import run_lmp

S = 0.6
FTOL = 1e-11
MINIMIZE = f"""min_style cg
min_modify dmax 1e-6 norm max line forcezero
minimize 0 {FTOL} 100000 1000000
"""


def start(geo, s=S, kick=1e-3, seed=1):
    x, F = st.split(st.fresh_state(geo), geo["n"])
    c = x.mean(axis=0)
    rng = np.random.default_rng(seed)
    F = math.sqrt(s) * (F + rng.uniform(-kick, kick, F.shape))
    return st.join(c + (x - c) * math.sqrt(s), F)


def scaled_gradient_norm(z, lev):
    n = lev["n"]
    _, g = st.energy(z, lev)
    return np.linalg.norm(g * np.concatenate([np.full(2 * n, sl.L), np.ones(4 * n)]))


@pytest.mark.lammps
def test_minimize_reaches_the_oracles_steady_state(tmp_path):
    xy = tissue.rectangle(0.75e-3, 0.75e-3, sl.L)
    geo = st.build(xy, sl.MAT, sl.BEST)
    lev = st.at_level(geo, S)
    n = geo["n"]
    z0 = start(geo)
    proc = sl.run(tmp_path, geo, z0, S, sl.BEST, sl.APPLE, commands=MINIMIZE)
    z_lmp = st.align(sl.read_state(tmp_path / "state.dump")[0], z0)
    z_py, info = st.relax(z0, lev, ftol=FTOL, maxiter=2000)
    assert info["converged"], info
    assert max(st.forces(z_lmp, lev)) < 10 * FTOL, proc.stdout[-2000:]
    z_lmp = st.align(z_lmp, z_py)

    u = np.concatenate([np.full(2 * n, sl.L), np.ones(4 * n)])
    w = np.linalg.eigvalsh(st.hessian(z_py, lev).toarray() * np.outer(u, u))
    rigid = np.abs(w) < 1e-6 * w.max()
    assert rigid.sum() == 3 and np.all(w[~rigid] > 0)   # a strict minimum
    lam = w[~rigid].min()
    bound = (scaled_gradient_norm(z_lmp, lev) + scaled_gradient_norm(z_py, lev)) / lam
    x_lmp, F_lmp = st.split(z_lmp, n)
    x_py, F_py = st.split(z_py, n)
    assert np.linalg.norm((x_lmp - x_py) / sl.L) <= bound
    sv = np.linalg.svd(F_lmp, compute_uv=False) - np.linalg.svd(F_py, compute_uv=False)
    assert np.linalg.norm(sv) <= bound, (np.linalg.norm(sv), bound)
    ddet = np.linalg.det(F_lmp) - np.linalg.det(F_py)
    assert np.linalg.norm(ddet) <= 2 * np.abs(F_py).max() * bound
    E_lmp, E_py = st.energy(z_lmp, lev, gradient=False), st.energy(z_py, lev, gradient=False)
    assert abs(E_lmp - E_py) <= bound ** 2 * lam + 64 * sl.EPS * sl.MAT["height"] \
        * sl.MAT["K"] * lev["A_f0"].sum()
    # the cells flattened (the steady state is not the isotropic saddle)
    F = st.split(z_py, n)[1]
    assert np.abs(F[:, 0, 0] - F[:, 1, 1]).max() > 0.05


@pytest.mark.lammps
def test_minimize_reads_no_unset_memory(tmp_path):
    """LAMMPS's max norm (``min_modify norm max``) reads the extra per-atom values of a pair
    style in triples, so up to two past the last bead's four F values. Those were never set:
    zero in a fresh process, whatever the heap held in a long-lived one (a test session
    after many LAMMPS instances), and then the force test never passed (the doc example's
    minimize stopped on "linesearch alpha is zero"). With glibc filling fresh heap memory
    with garbage (MALLOC_PERTURB_), the doc example (doc/pair_cgms_shaped.rst) must stop
    on its force tolerance after the same iterations at the same energy as without."""
    geo = st.build(tissue.rectangle(0.75e-3, 0.75e-3, sl.L), sl.MAT)
    shaped_data.write_data(tmp_path / "tissue.data", geo, st.fresh_state(geo))
    script = (sl.header(geo) + f"pair_style cgms/shaped dryness {S}\n"
              f"pair_coeff * * {sl.APPLE}\n" + MINIMIZE.replace(f"{FTOL} 100000 1000000",
                                                                "1e-10 20000 200000"))
    stats = []
    for env in ({}, {"MALLOC_PERTURB_": "165"}, {"MALLOC_PERTURB_": "90"}):
        run_lmp(tmp_path, script, env=env)
        log = (tmp_path / "log.lammps").read_text()
        stats.append((re.search(r"Stopping criterion = (.*)", log).group(1),
                      re.search(r"Iterations, force evaluations = (.*)", log).group(1),
                      re.search(r"Energy initial, next-to-last, final = \n(.*)", log).group(1)))
    assert stats[0][0] == "force tolerance"
    assert stats[1] == stats[0] and stats[2] == stats[0]
