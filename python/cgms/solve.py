# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states by Newton's method on the quasi-static problem (doc/model.md).

At steady state every bead holds ``P = -Pi``. With the pressures held there, the CGMS
forces are the gradient of a potential (``fix cgms/fluid`` reports it as its scalar and
adds it to ``pe``), so the steady geometry is a minimum of that potential. The dynamics
reaches it slowly: long-wavelength modes of a large tissue are barely damped. Newton's
method does not follow the transient:

- forces and energy come from LAMMPS (``fix cgms/fluid ... balance yes``, ``run 0``);
- the Jacobian is built by finite differences of those forces, many beads at a time:
  a bead's force depends only on beads within two cutoffs, so beads more than four
  cutoffs apart can be displaced together (a graph colouring; Curtis, Powell and Reid);
- each step solves the sparse linear system with SciPy's SuperLU; the step is shortened
  so that no bead moves by more than 5 % of the spacing relative to a neighbour (a
  step must not carry beads across a cutoff), and it is taken when the potential falls;
  when it does not, or the direction is not downhill, the matrix is shifted
  (Levenberg-Marquardt) until it is.

Where the potential is convex this converges quadratically (every microscale tissue,
5 to 22 iterations). Large tissues have soft, unstable modes at their corners, along
which Newton steps only creep; the solver then stops and says so (``stalled``,
``converged`` false). Measurements: doc/results/performance.md.

Serial only: the lammps instance runs in this process.
"""

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

from . import morphology


class LammpsForces:
    """Energy and forces of the beads of a LAMMPS instance at given positions (id order).

    The instance must use pair cgms and ``fix cgms/fluid ... balance yes`` (so that the
    pressures are held at -Pi) with damping off, and have run once."""

    def __init__(self, lmp):
        self.lmp = lmp
        self.evaluations = 0

    def positions(self):
        x = np.ctypeslib.as_array(self.lmp.gather_atoms("x", 1, 3)).reshape(-1, 3)
        return x[:, :2].copy()

    def __call__(self, xy):
        """(energy, forces (n, 2)) at positions ``xy`` (n, 2), by ``run 0``."""
        lmp = self.lmp
        x = np.ctypeslib.as_array(lmp.gather_atoms("x", 1, 3)).reshape(-1, 3)
        x[:, :2] = xy
        lmp.scatter_atoms("x", 1, 3, np.ctypeslib.as_ctypes(x.ravel()))
        lmp.command("run 0 post no")
        self.evaluations += 1
        f = np.ctypeslib.as_array(lmp.gather_atoms("f", 1, 3)).reshape(-1, 3)
        return lmp.get_thermo("pe"), f[:, :2].copy()


def colour(xy, separation):
    """Greedy colouring: beads of one colour are more than ``separation`` apart, each
    bead taking the smallest colour none of its near beads has yet. Returns an array of
    colours 0..k-1."""
    tree = cKDTree(xy)
    near = tree.query_ball_point(xy, separation)
    # plain lists and sets: a NumPy call per bead cost 10 times more (20 273 beads, about
    # 110 near beads each: 0.68 s per colouring, 20 colourings in a fresh solve)
    colours = [-1] * len(xy)
    # sweep in lattice order so the greedy choice packs colours regularly
    for i in np.lexsort((xy[:, 0], xy[:, 1])).tolist():
        used = {colours[j] for j in near[i]}
        c = 0
        while c in used:
            c += 1
        colours[i] = c
    return np.array(colours)


def jacobian(forces, xy, f0, colours, pairs, step):
    """Sparse dF/dx (2n x 2n, coordinates interleaved x0 y0 x1 y1 ...) by forward
    differences, one force evaluation per colour and direction. ``pairs``: the bead pairs
    within the reach of a displacement (a bead's displacement changes forces only on
    itself and on these partners)."""
    n = len(xy)
    # rows i influenced by column bead j: j itself and its partners
    rows_j = np.concatenate([np.arange(n), pairs[:, 0], pairs[:, 1]])
    cols_j = np.concatenate([np.arange(n), pairs[:, 1], pairs[:, 0]])
    rows, cols, vals = [], [], []
    for c in range(colours.max() + 1):
        moved = colours == c
        sel = moved[cols_j]  # entries whose column bead is displaced in this group
        ri, cj = rows_j[sel], cols_j[sel]
        for d in range(2):
            x1 = xy.copy()
            x1[moved, d] += step
            _, f1 = forces(x1)
            df = (f1 - f0) / step
            for e in range(2):
                rows.append(2 * ri + e)
                cols.append(2 * cj + d)
                vals.append(df[ri, e])
    rows, cols, vals = (np.concatenate(a) for a in (rows, cols, vals))
    # ``reach`` is a Euclidean bound on two neighbour hops: entries beyond the true
    # pattern are rounding noise, and keeping them would double the fill of the LU
    keep = np.abs(vals) > 1e-9 * np.abs(vals).max()
    return sp.csc_matrix((vals[keep], (rows[keep], cols[keep])), shape=(2 * n, 2 * n))


def colouring_holds(xy, colours, separation):
    """Whether beads of each colour are still more than ``separation`` apart."""
    for c in range(colours.max() + 1):
        members = xy[colours == c]
        if len(members) > 1 and cKDTree(members).query_pairs(separation):
            return False
    return True


def step_accepted(energy, force, trial_energy, trial_force, step, rounding):
    """Whether a Newton step from a state of ``energy`` and ``force`` to one of
    ``trial_energy`` and ``trial_force`` is taken: a sufficient decrease of the potential
    (Armijo, c = 1e-4), or, once the change is below the energy's rounding (``rounding``
    relative; a larger energy rounds coarser), a smaller largest force."""
    if trial_energy <= energy - 1e-4 * (np.ravel(force) @ np.ravel(step)):
        return True
    return bool(abs(trial_energy - energy) < rounding * abs(energy)
                and np.abs(trial_force).max() < np.abs(force).max())


def without_rigid_motion(xy, delta):
    """``delta`` (2n, interleaved) minus its translation and rotation about the centroid."""
    d = delta.reshape(-1, 2)
    r = xy - xy.mean(0)
    d = d - d.mean(0)
    rot = np.column_stack([-r[:, 1], r[:, 0]])
    d = d - (np.sum(d * rot) / np.sum(rot * rot)) * rot
    return d.ravel()


#: a step of a kept factorisation (:func:`newton`'s ``factor``) that leaves the largest
#: force above this fraction of the one before says the matrix is stale: the next
#: iteration builds the Jacobian anew (a fresh one contracts quadratically; a stale one
#: linearly, at a rate that grows with the change since it was built)
STALE = 0.5


def newton(forces, xy, cutoff, ftol=1e-13, max_iterations=60, step=None, max_move=None,
           stall=12, log=None, factor=None, max_jacobians=None, ordering="minimum-degree"):
    """Minimise the quasi-static potential from positions ``xy``: returns (xy, info).

    ``cutoff``: the largest pair cutoff (m). ``ftol``: stop when the largest force
    component on any bead is below this (N); ``info["converged"]`` says whether it was.
    ``stall``: also stop when in this many iterations neither the largest force has
    halved nor the potential fallen by 1e-4 of itself:
    the potential is then not convex around the beads (a soft, unstable mode, seen at
    the corners of large dried tissues), and Newton steps only creep along it.
    ``step``: finite-difference displacement (m; default 1e-7 of the bead spacing).
    ``max_move``: largest displacement of a bead relative to a neighbour in one iteration
    (m; default 5 % of the bead spacing), so a step cannot carry a bead across a
    neighbour's cutoff.
    ``factor``: a dict that keeps the factorised matrix of the last Jacobian (and the
    colouring) across calls: an iteration first tries the kept one (one force evaluation
    and a back substitution instead of a Jacobian of about 100 evaluations and a
    factorisation), and builds a new one when that step is refused or contracts the
    largest force by less than :data:`STALE` (warm-started solves of a slowly changing
    problem, cgms.drying). ``max_jacobians``: stop after building this many.
    ``ordering``: of the sparse factorisation, "minimum-degree" (SuperLU's on A + A^T)
    or "geometric" (:func:`nested_dissection` of the beads: 1.6-1.9 times faster on
    20 273 beads, 17.8 M entries in L + U against 20.2 M; the step it gives differs from
    the other's by 6e-8 of itself, about the linear solve's own error there, residual
    2.5e-8, but such a difference can tip a creeping solve onto another path, which
    stalled one microscale level of cgms study: so only cgms dry's warm solves use it)."""
    # a bead's force depends on beads two neighbour hops away: within two cutoffs
    reach = 2.04 * cutoff
    separation = 2 * reach
    spacing = morphology.spacing(xy)
    step = step or 1e-7 * spacing
    max_move = max_move or 0.05 * spacing
    factor = {} if factor is None else factor
    if factor.get("n") != len(xy):
        factor.clear()
        factor["n"] = len(xy)
    if factor.get("colours") is None:
        factor["colours"] = colour(xy, separation)
    colours = factor["colours"]
    info = dict(iterations=0, evaluations=0, colours=int(colours.max() + 1), history=[],
                stalled=False, jacobians=0, reused=0)
    start = time.perf_counter()
    energy, f = forces(xy)
    mu = 0.0
    tries = 0
    for it in range(max_iterations):
        fmax = np.abs(f).max()
        info["history"].append((it, energy, fmax, time.perf_counter() - start))
        if log:
            log(f"newton {it:3d}  E {energy:.12e}  fmax {fmax:.3e}  mu {mu:.2e}  tries {tries}  "
                f"{time.perf_counter() - start:.1f} s")
        if fmax < ftol:
            break
        past = info["history"][-stall - 1:]
        if len(past) > stall and fmax > 0.5 * past[0][2] and \
                past[0][1] - energy < 1e-4 * abs(energy):
            info["stalled"] = True
            break
        reached = cKDTree(xy).query_pairs(reach, output_type="ndarray")
        # neighbours (within one cutoff), for the limit on relative moves
        gaps = np.linalg.norm(xy[reached[:, 0]] - xy[reached[:, 1]], axis=1)
        pairs = reached[gaps < 0.5 * reach]
        if factor.get("lu") is not None:
            kept = _kept_step(forces, xy, energy, f, factor["lu"], pairs, max_move)
            if kept is not None:
                xy, energy, f = kept
                info["reused"] += 1
                info["iterations"] = it + 1
                if np.abs(f).max() > STALE * fmax:
                    factor["lu"] = None
                continue
            factor["lu"] = None
        if max_jacobians is not None and info["jacobians"] >= max_jacobians:
            break
        # a shrinking tissue brings beads of one colour closer together: colour again
        # when it has (the greedy colouring costs as much as 50 force evaluations)
        if not colouring_holds(xy, colours, separation):
            colours = factor["colours"] = colour(xy, separation)
        jac = jacobian(forces, xy, f, colours, reached, step)
        info["jacobians"] += 1
        hess = -0.5 * (jac + jac.T)
        diag = np.abs(hess.diagonal())
        scale = diag.mean()
        rhs = f.ravel()
        tries = 0
        while True:
            tries += 1
            # the potential does not change under rigid motion: a small shift keeps the
            # matrix regular, and the rigid part of the step is removed below
            shift = max(mu, 1e-10) * scale
            shifted = (hess + sp.diags(np.full(len(rhs), shift))).tocsc()
            try:
                lu = _factorise(shifted, xy, reach, ordering)
                delta = lu.solve(rhs)
            except RuntimeError:  # singular
                delta = None
            if delta is not None:
                delta = without_rigid_motion(xy, delta)
            ok = delta is not None and np.all(np.isfinite(delta)) and rhs @ delta > 0
            if ok:
                delta = _limited(delta, pairs, max_move)
                trial = xy + delta.reshape(-1, 2)
                e1, f1 = forces(trial)
                if step_accepted(energy, f, e1, f1, delta, rounding=1e-11):
                    xy, energy, f = trial, e1, f1
                    mu = mu / 10 if mu > 1e-8 else 0.0
                    factor["lu"] = lu
                    break
            # not a descent direction (the matrix is indefinite), or no decrease: damp
            mu = max(10 * mu, 1e-5)
            if mu > 1e6:
                raise RuntimeError("Newton step found no decrease of the potential")
        info["iterations"] = it + 1
    fmax = float(np.abs(f).max())
    factor["xy"] = xy
    info.update(evaluations=forces.evaluations, seconds=time.perf_counter() - start,
                fmax=fmax, energy=energy, converged=fmax < ftol)
    return xy, info


def nested_dissection(xy, width, leaf=64):
    """An elimination order of the beads at ``xy`` by geometric nested dissection: the
    beads are cut at the median of their longer extent by a band of half-width ``width``
    (beads more than 2 ``width`` apart across it have no matrix entry in common), each
    side is ordered so in turn, then the band; pieces of at most ``leaf`` beads keep
    their order. Returns the bead indices in elimination order."""
    order = []
    pending = [(np.arange(len(xy)), None)]
    # post-order without recursion: a piece's band follows both of its sides
    while pending:
        idx, band = pending.pop()
        if band is not None:
            order.append(band)
            continue
        if len(idx) <= leaf:
            order.append(idx)
            continue
        p = xy[idx]
        axis = int(np.ptp(p[:, 1]) > np.ptp(p[:, 0]))
        mid = np.median(p[:, axis])
        below, above = p[:, axis] < mid - width, p[:, axis] > mid + width
        band = idx[~below & ~above]
        if len(band) == len(idx):           # too thin to cut: one piece
            order.append(idx)
            continue
        pending += [(band, band), (idx[above], None), (idx[below], None)]
    return np.concatenate(order)


class _Permuted:
    """A factorisation of A[perm][:, perm] that solves A x = b."""

    def __init__(self, lu, perm):
        self.lu, self.perm = lu, perm

    def solve(self, rhs):
        x = np.empty_like(rhs)
        x[self.perm] = self.lu.solve(rhs[self.perm])
        return x


def _factorise(matrix, xy, reach, ordering):
    """SuperLU of the symmetric ``matrix`` (2n x 2n, coordinates interleaved), with
    diagonal pivots in the given ``ordering`` (:func:`newton`); ``reach``: the farthest
    two beads with an entry in common."""
    options = dict(SymmetricMode=True)
    # symmetric ordering and diagonal pivots: partial pivoting would wreck the ordering
    # (minutes instead of seconds for 20 000 beads)
    if ordering == "minimum-degree":
        return spla.splu(matrix, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                         options=options)
    if ordering != "geometric":
        raise ValueError(f"ordering must be 'minimum-degree' or 'geometric', not {ordering!r}")
    beads = nested_dissection(xy, 0.5 * reach)
    perm = np.column_stack([2 * beads, 2 * beads + 1]).ravel()
    lu = spla.splu(matrix[perm][:, perm].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                   options=options)
    return _Permuted(lu, perm)


def _limited(delta, pairs, max_move):
    """``delta`` scaled so that no neighbour pair's relative displacement exceeds
    ``max_move``: what carries a bead across a neighbour's cutoff is its displacement
    relative to its neighbours, and a tissue-wide contraction may move the edges much
    further in one step."""
    d = delta.reshape(-1, 2)
    move = np.abs(d[pairs[:, 0]] - d[pairs[:, 1]]).max()
    return delta * (max_move / move) if move > max_move else delta


def _kept_step(forces, xy, energy, f, lu, pairs, max_move):
    """The step of a kept factorisation from ``xy`` (limited as :func:`newton` limits
    its steps), as (xy, energy, forces) if it is taken, else None."""
    rhs = f.ravel()
    delta = without_rigid_motion(xy, lu.solve(rhs))
    if not (np.all(np.isfinite(delta)) and rhs @ delta > 0):
        return None
    delta = _limited(delta, pairs, max_move)
    trial = xy + delta.reshape(-1, 2)
    e1, f1 = forces(trial)
    if not step_accepted(energy, f, e1, f1, delta, rounding=1e-11):
        return None
    return trial, e1, f1
