# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The start of a level of the shaped model's drying ramp (:func:`cgms.shaped_newton.study`)
off the saddles that make Newton's method creep (doc/results/performance.md, "The shaped
model's study at scale"):

- :func:`start`: the previous level's state dilated isotropically (beads about their
  centroid, every F) to the stationary point of the new level's energy along the dilation,
  then, where the cells are flattened, their flattening grown to the stationary point
  along it. The previous state shrunk by sqrt(s / s_prev) is too large: its fluid is under
  tension and there every cell's flattening is unstable (two negative eigenvalues per
  cell, a saddle); at the stationary dilation it is not.
- :func:`flattened_copy`: where Newton has stopped on a saddle (the isotropic state of the
  level where the cells first flatten), every cell flattened alike at its area, F_i -> G
  F_i, G = (I + m D(a)) / sqrt(1 - m^2) with D(a) the deviatoric stretch along the axis at
  angle a: the steady state there is such a G on the saddle's cells (2 x 2 mm tissue at
  s = 0.6: m = 0.1345, every cell within 2e-4), and along it the energy falls from the
  saddle while along a straight path that changes the cells' areas it first rises.

Each one-dimensional search brackets the stationary point (steps doubling) and closes it
by Brent's method on the slope (the gradient along the path). Nothing here decides
convergence: Newton does, at the same force tolerance.
"""

import math

import numpy as np

from . import shaped_target as target, shaped_tensor as st

#: a tissue counts as flattened when its median cell's deviatoric part exceeds this share
#: of the cell's size
FLATTENED = 1e-3
#: the deviatoric stretches along x and along x = y (F flattened a, b, c, d)
DEVIATORIC = (np.array([[1.0, 0.0], [0.0, -1.0]]), np.array([[0.0, 1.0], [1.0, 0.0]]))
#: the axes (degrees) and amplitudes tried by :func:`flattened_copy`: every axis at two
#: amplitudes, then the best axis at every amplitude
AXES = np.arange(0, 180, 30)
PROBES = (0.1, 0.15)
AMPLITUDES = np.arange(5, 31) * 0.01


def stationary(slope, a, step, tol):
    """A root of ``slope`` (the energy's derivative along a path, scaled as
    :class:`cgms.shaped_newton.Problem`'s gradient) from ``a``: ``a`` itself when
    |slope(a)| <= 1 (within the force tolerance); else steps of ``step``, doubling,
    downhill until the slope changes sign (halving where the energy is infinite), then
    Brent's method to ``tol``. None when no sign change is found."""
    from scipy.optimize import brentq
    da = slope(a)
    if not np.isfinite(da):
        return None
    if abs(da) <= 1.0:
        return a
    step = math.copysign(abs(step), -da)
    for _ in range(40):
        b = a + step
        db = slope(b)
        if not np.isfinite(db):       # a cell of non-positive fluid area: nearer
            step *= 0.5
            continue
        if (db > 0) != (da > 0):
            return brentq(slope, min(a, b), max(a, b), xtol=tol)
        a, da, step = b, db, 2 * step
    return None


def _slope_along(prob, z, dz):
    dy = dz / prob.unit
    return lambda t: float(prob.energy(z + t * dz)[1] @ dy)


def flattened(z, n):
    """True when the median cell's deviatoric part, relative to its size, exceeds
    ``FLATTENED``."""
    F = st.split(z, n)[1]
    dev = np.linalg.norm(target.deviatoric(F)[0], axis=(1, 2))
    return bool(np.median(dev / np.sqrt(np.abs(np.linalg.det(F)))) > FLATTENED)


def start(z, prob):
    """The start of a level from the previous level's state ``z``: dilated to the
    stationary point, then (flattened cells) the flattening grown to the stationary point.
    ``prob``: the level's scaled energy (:class:`cgms.shaped_newton.Problem`, passed in so
    that this module does not import the solver that calls it)."""
    x, F = st.split(z, prob.n)
    T = st.shear(z, prob.n)           # the network's shear, if any, dilates with the rest
    centred = st.join(np.broadcast_to(x.mean(axis=0), x.shape), np.zeros_like(F),
                      None if T is None else np.zeros_like(T))
    t = stationary(_slope_along(prob, centred, z - centred), 1.0, 0.02, 1e-6)
    if t is not None:
        z = centred + t * (z - centred)
    if flattened(z, prob.n):
        x, F = st.split(z, prob.n)
        T = st.shear(z, prob.n)
        dz = st.join(np.zeros_like(x), target.deviatoric(F)[0],
                     None if T is None else np.zeros_like(T))
        m = stationary(_slope_along(prob, z, dz), 0.0, 0.05, 1e-6)
        if m is not None:
            z = z + m * dz
    return z


def flattened_copy(z, prob):
    """``z`` with every cell flattened alike at its area (the module's G): the axis of
    ``AXES`` with the lowest energy at the amplitudes ``PROBES``, then the amplitude of
    ``AMPLITUDES`` with the lowest energy on that axis. None when it is not below the
    energy of ``z``."""
    x, F = st.split(z, prob.n)
    T = st.shear(z, prob.n)

    def moved(m, degrees):
        a = math.radians(degrees)
        D = math.cos(2 * a) * DEVIATORIC[0] + math.sin(2 * a) * DEVIATORIC[1]
        G = (np.eye(2) + m * D) / math.sqrt(1 - m * m)
        return st.join(x, np.einsum("ab,nbc->nac", G, F), T)

    def energy(m, degrees):
        return prob.energy(moved(m, degrees))[0]

    axis = min(AXES, key=lambda a: min(energy(m, a) for m in PROBES))
    E = [energy(m, axis) for m in AMPLITUDES]
    k = int(np.argmin(E))
    return moved(AMPLITUDES[k], axis) if E[k] < prob.energy(z)[0] else None
