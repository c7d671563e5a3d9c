# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states of the fast MFC variant by Newton's method (doc/mfc.md, "Newton").

Conjugate gradients resolve the softest modes of a large dried tissue last: the glued sheet
of cells slides and turns at a stiffness far below that of its bonds (k_b / l^2 = 1.4 N/m
against 422 N/m), so an 86-cell level creeps for tens of thousands of iterations. Newton's
method solves with the whole stiffness matrix at once and does not care how soft a mode is.

The matrix has two parts (coordinates interleaved x0 y0 x1 y1 ...):

- a sparse part ``S``: bonds, angles, pairs, and the pressure's own local term
  ``P H d2A/dx_i dx_j`` (ring neighbours only). It is built by finite differences of the
  LAMMPS forces (:class:`cgms.solve.LammpsForces`), many particles displaced at once: those
  of one colour are more than two force ranges apart (:func:`cgms.solve.colour`);
- per cell a rank-one part ``D_c g_c g_c^T`` with ``g_c = dA_c/dx`` (the shoelace gradient)
  and ``D_c = -H dP/dA`` (the stiffness of the fluid), which couples every wall particle of
  the cell. It is removed from each force difference with the cell pressures that
  ``fix mfc/pressure`` reports, and ``D_c`` measured from the same differences, so the EOS
  is written only in the fix.

Each step solves ``(S + mu I + U D U^T) dx = f`` by the Woodbury identity (a sparse LU of
``S + mu I`` and a system of one row per cell), removes the rigid motion of the step, caps
the largest displacement of a particle and takes the step when the energy falls; when it
does not, or the step is not downhill, ``mu`` grows (Levenberg-Marquardt). Serial only.
"""

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

from ..solve import LammpsForces, colour, colouring_holds, step_accepted, without_rigid_motion


def area_gradient(xy, n_wall):
    """dA/dx_i of each wall particle's cell (n, 2): ``(y_next - y_prev, x_prev - x_next) / 2``
    along its counter-clockwise ring (the shoelace area's gradient)."""
    ring = xy.reshape(-1, n_wall, 2)
    nxt, prv = np.roll(ring, -1, axis=1), np.roll(ring, 1, axis=1)
    g = 0.5 * np.stack([nxt[..., 1] - prv[..., 1], prv[..., 0] - nxt[..., 0]], axis=-1)
    return g.reshape(-1, 2)


class CellForces(LammpsForces):
    """Energy, forces and the cell pressures of ``fix mfc/pressure`` (its array, column 2)
    at given positions."""

    def __init__(self, lmp, fix_id="mfc"):
        super().__init__(lmp)
        self.fix_id = fix_id

    def pressures(self):
        n = int(self.lmp.extract_fix(self.fix_id, 0, 1, 0))   # global vector: cell count
        return np.array([self.lmp.extract_fix(self.fix_id, 0, 2, c, 1) for c in range(n)])

    def evaluate(self, xy):
        energy, f = self(xy)
        return energy, f, self.pressures()


def stiffness(forces, xy, n_wall, height, reach, step, colours):
    """The sparse part ``S`` (2n x 2n CSC, symmetrised) and the fluid stiffness per cell
    ``D`` (module doc), by central differences of the forces, two evaluations per colour
    and direction."""
    n = len(xy)
    cell = np.arange(n) // n_wall
    g = area_gradient(xy, n_wall)
    pairs = cKDTree(xy).query_pairs(reach, output_type="ndarray")
    rows_j = np.concatenate([np.arange(n), pairs[:, 0], pairs[:, 1]])
    cols_j = np.concatenate([np.arange(n), pairs[:, 1], pairs[:, 0]])
    rows, cols, vals = [], [], []
    fluid = np.zeros(cell.max() + 1)
    best = np.zeros_like(fluid)   # the largest area change seen per cell: D from it
    for c in range(colours.max() + 1):
        moved = colours == c
        sel = moved[cols_j]
        ri, cj = rows_j[sel], cols_j[sel]
        for d in range(2):
            # central differences: the softest modes of a large dried tissue are 1e-6 of
            # the bonds' stiffness, and a forward difference's error is not
            xp, xm = xy.copy(), xy.copy()
            xp[moved, d] += step
            xm[moved, d] -= step
            width = (xp - xm)[:, d]   # the steps as represented, not as asked
            _, fp, pp = forces.evaluate(xp)
            _, fm, pm = forces.evaluate(xm)
            # the fluid's part couples the whole cell: take it out, what is left is local
            df = fp - fm - height * (pp - pm)[cell, None] * g
            for e in range(2):
                rows.append(2 * ri + e)
                cols.append(2 * cj + d)
                vals.append(df[ri, e] / width[cj])
            da = _areas(xp, n_wall) - _areas(xm, n_wall)
            use = np.abs(da) > best
            fluid[use] = -height * (pp - pm)[use] / da[use]
            best[use] = np.abs(da[use])
    rows, cols, vals = (np.concatenate(a) for a in (rows, cols, vals))
    keep = np.abs(vals) > 1e-9 * np.abs(vals).max()
    jac = sp.csc_matrix((vals[keep], (rows[keep], cols[keep])), shape=(2 * n, 2 * n))
    return (-0.5 * (jac + jac.T)).tocsc(), fluid


def _areas(xy, n_wall):
    ring = xy.reshape(-1, n_wall, 2)
    nxt = np.roll(ring, -1, axis=1)
    return 0.5 * np.sum(ring[..., 0] * nxt[..., 1] - nxt[..., 0] * ring[..., 1], axis=1)


def woodbury(hess, fluid, g, n_wall, shift=0.0):
    """A solver of ``(S + shift I + U D U^T) dx = rhs`` (module doc): one sparse LU of
    ``S + shift I`` and a system of one row per cell. Returns a function of ``rhs``, or
    None when the matrix is singular."""
    m = hess.shape[0]
    ncell = len(fluid)
    u = sp.csc_matrix((g.ravel(), (np.arange(m), np.repeat(np.arange(ncell), 2 * n_wall))),
                      shape=(m, ncell))
    shifted = (hess + sp.diags(np.full(m, shift))).tocsc()
    try:
        lu = spla.splu(shifted, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options=dict(SymmetricMode=True))
        z = lu.solve(u.toarray())
        small = np.linalg.inv(np.diag(1.0 / fluid) + u.T @ z)
    except (RuntimeError, np.linalg.LinAlgError):   # singular
        return None

    def solve(rhs):
        y = lu.solve(rhs)
        return y - z @ (small @ (u.T @ y))
    return solve


def matrix(hess, fluid, g, n_wall):
    """The whole stiffness ``S + U D U^T`` as a SciPy linear operator."""
    m = hess.shape[0]
    ncell = len(fluid)
    u = sp.csc_matrix((g.ravel(), (np.arange(m), np.repeat(np.arange(ncell), 2 * n_wall))),
                      shape=(m, ncell))
    return spla.LinearOperator((m, m), matvec=lambda v: hess @ v + u @ (fluid * (u.T @ v)),
                               dtype=float)


def newton(lmp, p, ftol=1e-10, max_iterations=40, max_move=5e-6, step=5e-11, fix_id="mfc",
           log=None):
    """Minimise the fast variant's energy in the LAMMPS instance ``lmp`` (set up by
    :func:`cgms.mfc.run.setup_commands` and the levers of a level) from its current
    positions, until the largest force component is below ``ftol`` (N). ``max_move``: the
    largest displacement of a particle in one step (m); ``step``: the finite-difference
    displacement (m). Leaves LAMMPS at the result; returns a report: iterations, force
    evaluations, seconds, ``fmax``, ``energy``, ``converged``, ``history`` (iteration,
    energy, fmax, seconds)."""
    n_wall, height = p["n_wall"], p["height"]
    forces = CellForces(lmp, fix_id)
    xy = forces.positions()
    # a particle's force depends on particles within the pair cutoff, its bond partners
    # (lamella bonds below the cutoff) and two ring neighbours either side
    reach = 1.3 * p["lamella_rc"]
    separation = 2 * reach
    colours = colour(xy, separation)
    start = time.perf_counter()
    energy, f = forces(xy)
    history, mu = [], 0.0
    converged = False
    for it in range(max_iterations + 1):
        fmax = float(np.abs(f).max())
        history.append((it, energy, fmax, time.perf_counter() - start))
        if log:
            log(f"mfc newton {it:3d}  E {energy:.12e}  fmax {fmax:.3e}  mu {mu:.1e}  "
                f"{time.perf_counter() - start:.1f} s")
        converged = fmax < ftol
        if converged or it == max_iterations:
            break
        if not colouring_holds(xy, colours, separation):
            colours = colour(xy, separation)
        hess, fluid = stiffness(forces, xy, n_wall, height, reach, step, colours)
        g = area_gradient(xy, n_wall)
        rhs = f.ravel()
        scale = np.abs(hess.diagonal()).mean()
        while True:
            solve = woodbury(hess, fluid, g, n_wall, max(mu, 1e-12) * scale)
            delta = None if solve is None else solve(rhs)
            if delta is not None:
                delta = without_rigid_motion(xy, delta)
            if delta is not None and np.all(np.isfinite(delta)) and rhs @ delta > 0:
                move = np.hypot(*delta.reshape(-1, 2).T).max()
                if move > max_move:
                    delta *= max_move / move
                # backtrack along the step before damping the matrix: a step costs one
                # force evaluation, a new matrix hundreds
                for _ in range(4):
                    trial = xy + delta.reshape(-1, 2)
                    e1, f1 = forces(trial)
                    accepted = step_accepted(energy, f, e1, f1, delta, rounding=1e-14)
                    if accepted:
                        break
                    delta = 0.5 * delta
                if accepted:
                    xy, energy, f = trial, e1, f1
                    mu = mu / 10 if mu > 1e-10 else 0.0
                    break
            mu = max(10 * mu, 1e-8)
            if mu > 1e4:
                forces(xy)
                raise RuntimeError("mfc newton: no step lowers the energy")
    forces(xy)   # leave LAMMPS at the result
    return dict(iterations=len(history) - 1, evaluations=forces.evaluations,
                seconds=time.perf_counter() - start, fmax=fmax, energy=energy,
                converged=bool(converged), history=history)
