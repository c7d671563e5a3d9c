# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states of the 3-D shaped tensor model (:mod:`cgms.shaped3d`; doc/model.md, "The
3-D tensor model (prototype)")."""

import numpy as np

from . import shaped3d as s3
from . import shaped3d_hessian as s3h


def relax(z, lev, ftol=1e-9, maxiter=20000, method="lbfgs"):
    """Steady state from ``z``, positions in units of the bond length and energy in units
    of ftol times it, so that it stops when every bead force and every dE/dF / bond length
    is below ``ftol`` (N); the held numbers (:func:`free`) stay as they are. ``method``
    "lbfgs": scipy's L-BFGS-B with the exact gradient, then (where its line search stops
    on the rounding of the Tait energy, terms of size K V) Newton-Krylov on the gradient
    alone; "newton": scipy's trust-region Newton method (``trust-exact``) with the exact
    Hessian at ``iso`` 0 (:mod:`cgms.shaped3d_hessian`), else the Hessian from central
    differences of the exact gradient (dense, 24 n gradients: small tissues only); it
    leaves the saddles that wrinkled walls make (a uniform block whose walls wrinkle
    lowers its energy by changing shape at fixed volume). Returns (z, info)."""
    from scipy.optimize import minimize
    n = lev["n"]
    L = s3.bond_unit(lev)
    z0 = np.asarray(z, float)
    mask = s3.free(lev) > 0
    unit = np.concatenate([np.full(3 * n, L), np.ones(9 * n)])[mask]
    scale = ftol * L

    def state(y):
        out = z0.copy()
        out[mask] = z0[mask] + y * unit
        return out

    def fun(y):
        E, g = s3.energy(state(y), lev)
        return E / scale, g[mask] * unit / scale

    def hess(y, h=1e-6):
        if not lev["iso"]:
            Hz = s3h.hessian(state(y), lev).toarray()[np.ix_(mask, mask)]
            return Hz * np.outer(unit, unit) / scale
        H = np.empty((len(y), len(y)))
        for j in range(len(y)):
            e = np.zeros(len(y))
            e[j] = h
            H[j] = (fun(y + e)[1] - fun(y - e)[1]) / (2 * h)
        return 0.5 * (H + H.T)

    y0 = np.zeros(mask.sum())
    if method == "newton":
        res = minimize(fun, y0, jac=True, hess=hess, method="trust-exact",
                       options=dict(maxiter=min(maxiter, 500), gtol=1.0,
                                    initial_trust_radius=0.02, max_trust_radius=0.2))
    elif method == "lbfgs":
        res = minimize(fun, y0, jac=True, method="L-BFGS-B",
                       options=dict(maxiter=maxiter, maxfun=2 * maxiter, gtol=1.0, ftol=0.0,
                                    maxcor=30))
    else:
        raise ValueError(f"method must be 'lbfgs' or 'newton', not {method!r}")
    y, message = res.x, str(res.message)
    if np.abs(fun(y)[1]).max() > 1.0:
        import scipy.optimize as so
        NoConvergence = getattr(so, "NoConvergence", None)
        if NoConvergence is None:     # scipy < 1.11 keeps it in a module it deprecates
            import warnings
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)
                from scipy.optimize.nonlin import NoConvergence
        try:
            y = so.newton_krylov(lambda v: fun(v)[1], y, f_tol=0.5, maxiter=50)
            message += "; polished by Newton-Krylov on the gradient"
        except (NoConvergence, ValueError) as err:
            message += f"; Newton-Krylov polish failed ({type(err).__name__})"
    zs = state(y)
    fx, fF = s3.forces(zs, lev)
    return zs, dict(fmax=max(fx, fF), iterations=int(res.nit), converged=max(fx, fF) <= ftol,
                    message=message)
