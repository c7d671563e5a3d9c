# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""How well determined a converged level of a `cgms mfc` study is (doc/mfc.md, "Newton"):

- the largest force left, after Newton's method has been run on it once more;
- the softest modes of the stiffness there (the smallest eigenvalues of ``S + U D U^T``,
  shift-invert Lanczos, the rigid motions of the free tissue removed): all positive means
  a minimum, and the smallest says how flat its valley is (N/m; the bonds: 422 N/m);
- every wall particle kicked at random by up to ``kick`` (m) and solved again as a level is
  (:func:`cgms.mfc.run.relax`: conjugate gradients, then Newton): how far the cell
  centroids land from where they were (RMSD after the best rigid motion, largest). A
  wrinkled wall has many minima close together; this says how closely the model itself
  fixes the centroids.

    source build/env.sh
    /usr/bin/python3 studies/mfc/steady.py <folder>/calibration 0.3 [kick ...]

The folder needs ``state.s<s>.data`` and ``lamella.txt`` (a study with the lamella set in the
fresh tissue)."""

import sys
import time

import numpy as np
import scipy.sparse.linalg as spla

from cgms.mfc import (metrics as mfc_metrics, model as mfc_model, newton as mfc_newton,
                      run as mfc_run)
from cgms import run, superpose
from cgms.solve import colour, without_rigid_motion


def centroids(lmp, p):
    return mfc_metrics.cells(mfc_run.positions(lmp), p["n_wall"])["centroid"]


def softest(lmp, p, count=6):
    """The ``count`` smallest eigenvalues (N/m) of the stiffness at the current state,
    rigid motions projected out."""
    forces = mfc_newton.CellForces(lmp)
    xy = forces.positions()
    reach = 1.3 * p["lamella_rc"]
    hess, fluid = mfc_newton.stiffness(forces, xy, p["n_wall"], p["height"], reach, 5e-11,
                                       colour(xy, 2 * reach))
    forces(xy)
    g = mfc_newton.area_gradient(xy, p["n_wall"])
    whole = mfc_newton.matrix(hess, fluid, g, p["n_wall"])
    sigma = -1e-6   # N/m, below every mode: (K - sigma) is regular
    solve = mfc_newton.woodbury(hess, fluid, g, p["n_wall"], -sigma)

    def rigidless(v):
        return without_rigid_motion(xy, v)

    m = hess.shape[0]
    op = spla.LinearOperator((m, m), matvec=lambda v: rigidless(whole @ rigidless(v)),
                             dtype=float)
    inverse = spla.LinearOperator((m, m), matvec=lambda v: rigidless(solve(rigidless(v))),
                                  dtype=float)
    values = spla.eigsh(op, k=count + 3, sigma=sigma, OPinv=inverse, which="LM",
                        return_eigenvectors=False)
    values = np.sort(values)
    # the three rigid motions come back as the eigenvalue 0 of the projected matrix
    return values[np.abs(values) > 1e-9 * np.abs(hess.diagonal()).mean()][:count]


def main(folder, s, kicks=(1e-8, 1e-7)):
    p = mfc_model.parameters()
    rest = np.loadtxt(f"{folder}/lamella.txt", ndmin=2).reshape(-1, 2)[:, 1]
    lmp = run.open_lammps(log="none")
    lmp.commands_list(mfc_run.setup_commands(f"{folder}/state.s{s:g}.data", p, rest=rest))
    lmp.commands_list(mfc_run.level_commands(p, s))
    lmp.command("run 0 post no")
    print(f"s = {s:g}: largest force as stored {lmp.get_thermo('fmax'):.2e} N")
    r = mfc_newton.newton(lmp, p, ftol=1e-12)
    print(f"  Newton to 1e-12 N: {r['iterations']} steps, fmax {r['fmax']:.2e} N")
    t = time.perf_counter()
    values = softest(lmp, p)
    print("  softest modes (N/m): " + ", ".join(f"{v:.3g}" for v in values)
          + f" ({time.perf_counter() - t:.0f} s)")
    base = centroids(lmp, p)
    state = mfc_run.positions(lmp)
    forces = mfc_newton.CellForces(lmp)
    for k, kick in enumerate(kicks):
        forces(state)
        lmp.command(f"displace_atoms all random {kick:.10g} {kick:.10g} 0 {17 + k} units box")
        r = mfc_run.relax(lmp, p, s)
        c = centroids(lmp, p)
        far = np.hypot(*(superpose.align(c, base, "rigid") - base).T).max()
        print(f"  kicked by up to {kick * 1e6:g} um and solved again ({r['iterations']} CG "
              f"iterations, Newton {r['newton'] and r['newton']['iterations']} steps, fmax "
              f"{r['fmax']:.1e} N): centroids RMSD "
              f"{superpose.rmsd(c, base, 'rigid') * 1e6:.4f} um after the best rigid motion, "
              f"largest {far * 1e6:.4f} um")
    lmp.close()


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]), *[tuple(float(a) for a in sys.argv[3:])]
         if sys.argv[3:] else ())
