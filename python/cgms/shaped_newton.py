# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states of the shaped tensor model (:mod:`cgms.shaped_tensor`) at scale: Newton's
method on its exact sparse Hessian, for tissues where ``shaped_tensor.relax`` (a dense
trust region) cannot hold the matrix. It converges (every level of tissues up to 1273
beads measured); its study starts each level off the saddles (:mod:`cgms.shaped_start`)
and certifies each state a minimum, but still needs tens of steps per level (walls
crossing their buckling point, where the Hessian jumps), each with a sparse
factorisation: slower than LAMMPS's cg, and far from a minute at 20 273 beads
(doc/results/performance.md, "The shaped model's study at scale").

Each fresh factorisation is of H + mu I in scaled variables (SciPy's SuperLU, geometric
nested dissection, diagonal pivots, so that the signs of U's diagonal are the
inertia of the matrix, Sylvester): mu is raised until the matrix is positive definite
(the model is not convex where walls buckle and cells flatten, and a kicked start sits
near the isotropic saddle), and the factorisation is kept for further (chord) steps while
they make progress; where H is indefinite the step adds a direction of negative
curvature that the factorisation gives for the cost of one solve. A step is taken when
the energy falls (Armijo) or, once the change is below the energy's rounding (the Tait
energy at fixed mass is a difference of large terms), when the largest force falls. The
LJ pairs are found afresh (k-d tree) at every state, so nothing holds (n, n) arrays.
Variables are scaled as ``relax`` scales them: positions in x_ref, the gradient in units
of ``ftol``, so "converged" is the same test as relax's and LAMMPS's ``norm max``: every
bead force and every dE/dF / x_ref at most ``ftol`` (N).
"""

import math
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from . import shaped_local, shaped_tensor as st

#: the largest step, per component: x_ref for positions, 1 for F (a step must not carry
#: beads across the LJ radius in one go)
MAX_STEP = 0.1
#: the first shift when H is not positive definite, relative to H's largest diagonal entry
MU0 = 1e-3
#: a shift this small (relative) always: the rigid motions are null modes of H
RIGID_SHIFT = 1e-12
#: print one line per trial step (to study the solver)
TRACE = False


def with_near_pairs(x, lev):
    """``lev`` with its LJ pairs (``pairs``) the non-bonded pairs closer than r_lj at
    positions ``x``: the only pairs :func:`cgms.shaped.lj_energy` counts."""
    n = lev["n"]
    keys = lev.get("bond_keys")
    if keys is None:
        keys = np.sort(shaped_local.pair_keys(np.sort(lev["bonds"], axis=1), n))
    pairs = shaped_local.neighbour_pairs(x, lev["r_lj"])
    pairs = pairs[~np.isin(shaped_local.pair_keys(pairs, n), keys, assume_unique=True)]
    return dict(lev, pairs=pairs)


def rounding(lev):
    """The energy's rounding (J): the fluid energy's terms are each of size H K A."""
    mat = lev["mat"]
    return 64 * np.finfo(float).eps * mat["height"] * mat["K"] * float(np.sum(lev["A_f0"]))


def dof_order(x, lev):
    """An elimination order of the unknowns: the beads by geometric nested dissection
    (:func:`cgms.solve.nested_dissection`; two beads share a Hessian entry only when
    bonded or closer than r_lj, so bands of half the longest such distance, with 20 %
    to spare for the level's motion, separate), each bead's x, F (and network shear). On
    20 273 beads it halves SuperLU's time against its minimum-degree ordering (7.8 s
    against 17.4 s)."""
    from . import solve
    b = lev["bonds"]
    reach = max(float(np.hypot(*(x[b[:, 1]] - x[b[:, 0]]).T).max()), lev["r_lj"])
    beads = solve.nested_dissection(x, 0.6 * reach)
    n = lev["n"]
    shear = [6 * n + 2 * beads + k for k in range(2)] if lev.get("mu_net") is not None else []
    return np.column_stack([2 * beads, 2 * beads + 1]
                           + [2 * n + 4 * beads + k for k in range(4)] + shear).ravel()


class Factors:
    """SuperLU of the symmetric A in the elimination order ``order`` with diagonal
    pivots, so that the signs of U's diagonal are A's inertia (Sylvester): ``negative``
    counts the negative pivots (None if SuperLU reordered the rows after all)."""

    def __init__(self, A, order):
        self.order = order
        self.lu = spla.splu(sp.csr_matrix(A)[order][:, order].tocsc(), permc_spec="NATURAL",
                            diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
        self.pivots = self.lu.U.diagonal()
        same = np.array_equal(self.lu.perm_r, self.lu.perm_c)
        self.negative = int(np.sum(self.pivots <= 0)) if same else None

    def solve(self, b):
        x = np.empty_like(b)
        x[self.order] = self.lu.solve(b[self.order])
        return x

    def negative_curvature(self, g):
        """A direction d of negative curvature of A: with P A P^T = L U, U = D L^T, and v
        the indicator of the negative pivots, d = P^T U^-1 v = A^-1 P^T L v and d^T A d
        = sum of 1 / D_kk over them < 0. Signed so that g.d <= 0."""
        lu = self.lu
        y = lu.solve((lu.L @ (self.pivots < 0).astype(float))[lu.perm_r])
        d = np.empty_like(y)
        d[self.order] = y
        return -d if g @ d > 0 else d


class Problem:
    """The scaled energy of one level: y = z / unit, E / (ftol x_ref)."""

    def __init__(self, lev, ftol):
        n = lev["n"]
        self.lev, self.n, self.ftol = lev, n, ftol
        L = lev["mat"]["x_ref"]
        shear = lev.get("mu_net") is not None          # the network's shear: 2 more a cell
        self.unit = np.concatenate([np.full(2 * n, L), np.ones((6 if shear else 4) * n)])
        self.scale = ftol * L
        self.rounding = rounding(lev) / self.scale
        self.evaluations = 0
        self.seconds = dict(energy=0.0, hessian=0.0, factorise=0.0)

    def energy(self, z):
        t = time.process_time()
        lv = with_near_pairs(st.split(z, self.n)[0], self.lev)
        E, g = st.energy(z, lv)
        self.evaluations += 1
        self.seconds["energy"] += time.process_time() - t
        return E / self.scale, g * self.unit / self.scale, lv

    def hessian(self, z, lv):
        t = time.process_time()
        H = st.hessian(z, lv)
        D = sp.diags(self.unit / math.sqrt(self.scale))
        H = sp.csc_matrix(D @ H @ D)
        self.seconds["hessian"] += time.process_time() - t
        return H


def newton(z, lev, ftol=1e-9, max_iterations=200, certify=False):
    """The steady state from ``z`` at level ``lev`` (:func:`cgms.shaped_tensor.at_level`,
    of a tissue built with or without ``local``). Returns (z, info): info holds fmax (N,
    as :func:`cgms.shaped_tensor.forces`), iterations (steps taken), factorisations,
    evaluations, converged, status, the CPU seconds spent in energy, Hessian and
    factorisation, and the counts of Hessians assembled, factorisations found indefinite
    (``indefinite``), steps refused and steps taken on a kept factorisation (``chord``).
    With ``certify``, a converged state's Hessian is factorised once more and ``negative``
    counts its negative eigenvalues (:func:`unstable_directions`: 0 at a minimum, more at
    a saddle); else ``negative`` is None.

    A factorisation of H + mu I (scaled variables) is kept for further steps (chord
    steps: each is a descent direction, the matrix being positive definite) while each
    step at least halves the largest force; else the Hessian is assembled and factorised
    afresh at the current state. mu is raised (x4, from 1e-3 of H's largest diagonal
    entry) until the matrix is positive definite and after a fresh factorisation's step
    is refused, and halved at a fresh factorisation that follows a step taken."""
    prob = Problem(lev, ftol)
    z = np.asarray(z, float).copy()
    E, g, lv = prob.energy(z)
    order = dof_order(st.split(z, lev["n"])[0], lev)
    mu, steps, factorisations = 0.0, 0, 0
    count = dict(hessians=0, indefinite=0, refused=0, chord=0)
    lu, fresh, relax_shift = None, False, False
    status = "iteration limit"
    while steps < max_iterations:
        if not np.all(np.isfinite(g)):
            status = "the state has a cell of non-positive fluid area"
            break
        if np.abs(g).max() <= 1.0:
            status = "converged"
            break
        if lu is None:
            H = prob.hessian(z, lv)
            count["hessians"] += 1
            top = np.abs(H.diagonal()).max()
            if relax_shift:    # the last step was taken: try a smaller shift
                mu *= 0.5
            d = None
            while True:
                t = time.process_time()
                lu = Factors(H + sp.identity(H.shape[0]) * (mu + RIGID_SHIFT * top), order)
                neg = lu.negative
                prob.seconds["factorise"] += time.process_time() - t
                factorisations += 1
                if not neg:
                    break
                count["indefinite"] += 1
                if d is None and NEG_SCALE:
                    d = lu.negative_curvature(g)
                mu = max(4 * mu, MU0 * top)
            fresh = True
        p = -lu.solve(g)
        p *= min(1.0, MAX_STEP / np.abs(p).max())
        if fresh and d is not None:
            p = p + d * (NEG_SCALE * np.abs(p).max() / np.abs(d).max())
            p *= min(1.0, MAX_STEP / np.abs(p).max())
        trial = z + p * prob.unit
        E1, g1, lv1 = prob.energy(trial)
        ok = np.isfinite(p).all() and accepted(E, g, E1, g1, p, prob.rounding)
        if TRACE:
            print(f"  step {steps} mu {mu:.1e} fresh {fresh} |g| {np.abs(g).max():.3e} "
                  f"E {E:.10e} dE {E1 - E:.3e} |p| {np.abs(p).max():.3e} {ok}")
        if ok:
            slow = np.abs(g1).max() > 0.5 * np.abs(g).max()
            z, E, g, lv = trial, E1, g1, lv1
            steps += 1
            count["chord"] += not fresh
            if slow and not fresh:
                lu = None
            fresh, relax_shift = False, True
        elif fresh:          # even a fresh factorisation's step fails: shift further
            count["refused"] += 1
            mu = max(4 * mu, MU0 * top)
            lu, relax_shift = None, False
        else:                # a kept factorisation's step fails: factorise here, same shift
            count["refused"] += 1
            lu, relax_shift = None, False
        if mu > 1e6 * top:
            status = "no step lowers the energy or the force"
            break
    negative = None
    if certify and status == "converged":
        negative = unstable_directions(prob, z, lv, order)
        factorisations += 1
    fx, fF = st.forces(z, with_near_pairs(st.split(z, lev["n"])[0], lev))
    fmax = max(fx, fF)
    return z, dict(fmax=fmax, iterations=steps, factorisations=factorisations,
                   evaluations=prob.evaluations, converged=fmax <= ftol, status=status,
                   seconds=prob.seconds, negative=negative, **count)


def rigid_modes(z, n, unit):
    """The three rigid motions at state ``z`` in scaled variables (columns, orthonormal):
    the two translations and the rotation about the beads' centroid (beads turn, every F
    turns with them: dF = W F, W the infinitesimal rotation)."""
    x, F = st.split(z, n)
    W = np.array([[0.0, -1.0], [1.0, 0.0]])
    c = x - x.mean(axis=0)
    modes = [st.join(np.tile(e, (n, 1)), np.zeros_like(F)) for e in np.eye(2)]
    modes.append(st.join(c @ W.T, np.einsum("ab,nbc->nac", W, F)))
    Q, _ = np.linalg.qr(np.column_stack(modes) / unit[:, None])
    return Q


def unstable_directions(prob, z, lv, order):
    """The number of negative eigenvalues of the (scaled) Hessian at ``z``: 0 at a
    minimum, more at a saddle; from the inertia of one factorisation of H + sigma I (None
    if SuperLU pivoted off the diagonal). The rigid motions are H's null modes only at
    zero force: off it their curvatures (Rayleigh quotients) are of the size of the
    residual gradient, of either sign, so sigma is twice the largest of them in size
    (plus RIGID_SHIFT of H's largest diagonal entry); a negative eigenvalue smaller than
    sigma in size is not counted."""
    H = prob.hessian(z, lv)
    t = time.process_time()
    Q = rigid_modes(z, prob.n, prob.unit)
    top = np.abs(H.diagonal()).max()
    sigma = 2 * np.abs(np.einsum("ik,ik->k", Q, H @ Q)).max() + RIGID_SHIFT * top
    lu = Factors(H + sp.identity(H.shape[0]) * sigma, order)
    prob.seconds["factorise"] += time.process_time() - t
    return lu.negative


#: at a fresh factorisation of an indefinite H, the step adds a direction of negative
#: curvature (:meth:`Factors.negative_curvature`) this many times the Newton step's size: a
#: ramp's levels leave their saddles in fewer steps (5 x 5 mm: 116 instead of 353 at
#: s = 0.6), though a single level from the kicked isotropic start may take more
NEG_SCALE = 3.0


def accepted(E, g, E1, g1, p, rounding):
    """A step p from (E, g) to (E1, g1) is taken when the energy falls enough (Armijo,
    c = 1e-4) or, the change being below the energy's rounding, the largest force falls."""
    if not np.isfinite(E1):
        return False
    if E1 <= E + 1e-4 * (g @ p):
        return True
    return bool(abs(E1 - E) < rounding and np.abs(g1).max() < np.abs(g).max())


def leave_saddles(z, lev, ftol, info, max_iterations, kick=1e-3, seed=1):
    """From where :func:`newton` (run with ``certify``) stopped on a saddle (``info``'s
    ``negative`` > 0: stationary, with directions of negative curvature): first every cell
    flattened alike (:func:`cgms.shaped_start.flattened_copy`), then, at a saddle again,
    every F kicked by a seeded uniform perturbation of up to ``kick`` (times sqrt(s)), and
    Newton again, until a minimum or the iteration limit. Returns (z, info), the counts
    summed over the restarts, ``saddles`` the number of restarts."""
    from . import shaped_start
    rng = np.random.default_rng(seed)
    saddles = 0
    while info["negative"] and info["iterations"] < max_iterations:
        saddles += 1
        z1 = shaped_start.flattened_copy(z, Problem(lev, ftol)) if saddles == 1 else None
        if z1 is None:
            x, F = st.split(z, lev["n"])
            z1 = st.join(x, F + rng.uniform(-kick, kick, F.shape) * math.sqrt(lev["s"]))
        z, more = newton(z1, lev, ftol, max_iterations - info["iterations"], certify=True)
        for key in ("iterations", "factorisations", "evaluations", "hessians", "indefinite",
                    "refused", "chord"):
            more[key] += info[key]
        more["seconds"] = {k: v + info["seconds"][k] for k, v in more["seconds"].items()}
        info = more
    info["saddles"] = saddles
    return z, info


#: the parameters of pair_style cgms/shaped's defaults (doc/pair_cgms_shaped.rst; the best
#: set of doc/results/shaped-results.md), beyond cgms.shaped_tensor.DEFAULTS
PAIR_DEFAULTS = {"soft": 0.002, "kg_ratio": 1.0, "strip": "contour", "lamella": 0.391,
                 "void": 0.063, "iso": 1.0, "beta_b": 0.04}


def study(xy, mat, levels, params=None, ftol=1e-9, max_iterations=1000, progress=None,
          start="searched"):
    """The shaped model's study of the tissue built at ``xy``: a drying ramp over
    ``levels`` (wettest first; :func:`cgms.shaped_tensor.ramp`, each level started from
    the previous one) solved by :func:`newton`, and one row per level
    as :func:`cgms.study.table` writes them: X/X0 (the fluid mass, fixed at s per level),
    A/A0, P/P0, EL/EL0 of the bead outline (normalised by the wettest level), steps
    (Newton steps), residual (the largest force, N), converged, wall and CPU seconds.
    ``progress(s, info)`` is called after each level. ``start``: "searched", each level
    from the previous state dilated and its flattening grown
    (:func:`cgms.shaped_start.start`), Newton's state certified a minimum by the inertia
    and, at a saddle, left (:func:`leave_saddles`); "kicked", the previous state shrunk by
    sqrt(s / s_prev) and kicked, Newton's state not certified (the study before
    2026-12-03's third session, :func:`cgms.shaped_tensor.ramp`'s default start)."""
    from . import morphology, shaped_start
    if start not in ("searched", "kicked"):
        raise ValueError(f"start must be 'searched' or 'kicked', not {start!r}")
    searched = start == "searched"
    p = dict(PAIR_DEFAULTS, **(params or {}))

    clock = []                # set when the level's start begins

    def begin(z, lev, tol):
        clock[:] = [time.time(), time.process_time()]
        return shaped_start.start(z, Problem(lev, tol))

    def solver(z, lev, tol):
        t, c = clock or (time.time(), time.process_time())
        clock.clear()
        z, info = newton(z, lev, tol, max_iterations, certify=searched)
        if searched:
            z, info = leave_saddles(z, lev, tol, info, max_iterations)
        info.update(wall=time.time() - t, cpu=time.process_time() - c)
        if progress:
            progress(lev["s"], info)
        return z, info

    geo, states = st.ramp(xy, mat, levels, p, ftol=ftol, local=True, solver=solver,
                          start=begin if searched else None)
    shapes = [morphology.measures(st.split(z, geo["n"])[0]) for _, z, _ in states]
    fresh = shapes[int(np.argmax([s for s, _, _ in states]))]
    rows = []
    for (s, z, info), m in zip(states, shapes):
        rows.append({"s": s, "X/X0": s, **morphology.normalise(m, fresh), "area": m["area"],
                     "perimeter": m["perimeter"], "elongation": m["elongation"],
                     "steps": info["iterations"], "residual": info["fmax"], "speed": "",
                     "method": "shaped-newton", "converged": info["converged"],
                     "seconds": info["wall"], "cpu_seconds": info["cpu"],
                     "factorisations": info["factorisations"]})
    return geo, states, rows
