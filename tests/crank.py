# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Analytic solutions of Fick's second law with a convective boundary (Crank 1975, The
Mathematics of Diffusion, 2nd ed., eqs 4.53-4.54 for the plane sheet and 5.50-5.52 for the
infinite cylinder), independent of cgms.drying.transport: the mean and the local concentration
relative to the initial uniform one, the surroundings at zero."""

import numpy as np
from scipy.optimize import brentq
from scipy.special import j0, j1


def slab_roots(biot, count=200):
    """Roots beta_n of beta tan beta = Bi, one in each (n pi, n pi + pi/2)."""
    f = lambda b: b * np.sin(b) - biot * np.cos(b)
    return np.array([brentq(f, n * np.pi + 1e-12, n * np.pi + np.pi / 2 - 1e-12)
                     for n in range(count)])


def slab_mean(fourier, biot, count=200):
    """Mean of a sheet of half-thickness l: Fo = D t / l^2, Bi = h l / D (eq. 4.54)."""
    b = slab_roots(biot, count)
    fo = np.atleast_1d(fourier)[:, None]
    return np.sum(2 * biot**2 / (b**2 * (b**2 + biot**2 + biot)) * np.exp(-b**2 * fo), axis=1)


def slab_field(z, fourier, biot, count=200):
    """Local value at z/l in [0, 1] (0 the mid-plane) (eq. 4.53)."""
    b = slab_roots(biot, count)
    z = np.atleast_1d(z)[:, None]
    return np.sum(2 * biot * np.cos(b * z) / ((b**2 + biot**2 + biot) * np.cos(b))
                  * np.exp(-b**2 * fourier), axis=1)


def disc_roots(biot, count=200):
    """Roots beta_n of beta J1(beta) = Bi J0(beta)."""
    f = lambda b: b * j1(b) - biot * j0(b)
    grid = np.linspace(1e-9, count * np.pi + 2, 40 * count)
    v = f(grid)
    idx = np.nonzero(np.sign(v[:-1]) != np.sign(v[1:]))[0]
    return np.array([brentq(f, grid[i], grid[i + 1]) for i in idx])[:count]


def disc_mean(fourier, biot, count=200):
    """Mean of a cylinder of radius a: Fo = D t / a^2, Bi = h a / D (eq. 5.52)."""
    b = disc_roots(biot, count)
    fo = np.atleast_1d(fourier)[:, None]
    return np.sum(4 * biot**2 / (b**2 * (b**2 + biot**2)) * np.exp(-b**2 * fo), axis=1)


def disc_field(r, fourier, biot, count=200):
    """Local value at r/a in [0, 1] (eq. 5.51)."""
    b = disc_roots(biot, count)
    r = np.atleast_1d(r)[:, None]
    return np.sum(2 * biot * j0(b * r) / ((b**2 + biot**2) * j0(b)) * np.exp(-b**2 * fourier),
                  axis=1)


def kirchhoff_profile(z, x_hi, x_lo, b, x0=1.0):
    """Steady 1-D moisture between X(0) = x_hi and X(1) = x_lo with D(X) = D0 exp(b (X/x0
    - 1)), at z in [0, 1]. The Kirchhoff transform Phi(X) = int D dX (Crank 1975, sec.
    7.2) turns the steady flux d/dz (D dX/dz) = 0 into Phi'' = 0: Phi is linear in z, and
    Phi = D0 x0 / b exp(b (X/x0 - 1)) + const, so exp(b X / x0) is linear in z."""
    e_hi, e_lo = np.exp(b * x_hi / x0), np.exp(b * x_lo / x0)
    return x0 / b * np.log(e_hi + (e_lo - e_hi) * np.asarray(z, float))


def kirchhoff_flux(x_hi, x_lo, b, d0, length, x0=1.0):
    """Steady flux per unit area and unit solid density (m/s times X) of that profile over
    ``length``: (Phi(x_hi) - Phi(x_lo)) / length."""
    phi = lambda x: d0 * x0 / b * np.exp(b * (x / x0 - 1))
    return (phi(x_hi) - phi(x_lo)) / length
