# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""What a cell of the shaped tensor model asks of its bonds (doc/model.md, "A coarse model
with cell shape", the tensor variant): the bond target G d0 of the lamella's
compatibility, from the cell's deformation F (its whole F, or only its size and rotation
sqrt(det F) R(F), ``iso``), with the network's own shear T, and its first and second
derivatives in the cell's numbers; and the cell's deviatoric stretch, which
:mod:`cgms.shaped_mean` averages. Plain functions on stacks of cells; the energy that
uses them is :mod:`cgms.shaped_tensor`'s.
"""

import numpy as np

_DP = np.array([1.0, 0.0, 0.0, 1.0])        # d(a + d)/dF, F flattened (a, b, c, d)
_DQ = np.array([0.0, -1.0, 1.0, 0.0])       # d(c - b)/dF


def iso_scale(F, T=None):
    """phi = sqrt(J) / r with r = |(a + d, c - b)|, so that phi [[p, -q], [q, p]] =
    sqrt(J) R(F), R the rotation of F's polar decomposition; J = det F, or with the
    network's shear ``T`` (n, 2) J = det F + |T|^2, which keeps the network map's
    determinant at det F (:func:`bond_target`). Returns p, q, phi and phi's first (n, m)
    and second (n, m, m) derivatives in the cell's m = 4 numbers of F (6 with T: F, T)."""
    a, b, c, d = F[:, 0, 0], F[:, 0, 1], F[:, 1, 0], F[:, 1, 1]
    m = 4 if T is None else 6
    J = a * d - b * c
    p, q = a + d, c - b
    r = np.hypot(p, q)
    gJ = np.zeros((len(F), m))
    gJ[:, :4] = np.stack([d, -c, -b, a], -1)
    D2 = np.zeros((m, m))
    D2[0, 3] = D2[3, 0] = 1.0
    D2[1, 2] = D2[2, 1] = -1.0
    if T is not None:
        J = J + T[:, 0] ** 2 + T[:, 1] ** 2
        gJ[:, 4:] = 2 * T
        D2[4, 4] = D2[5, 5] = 2.0
    dp, dq = np.zeros(m), np.zeros(m)
    dp[:4], dq[:4] = _DP, _DQ
    gr = (p[:, None] * dp + q[:, None] * dq) / r[:, None]
    hr = ((np.outer(dp, dp) + np.outer(dq, dq))[None] - gr[:, :, None] * gr[:, None, :]) \
        / r[:, None, None]
    phi = np.sqrt(J) / r
    gphi = phi[:, None] * (gJ / (2 * J[:, None]) - gr / r[:, None])
    hphi = (gphi[:, :, None] * gphi[:, None, :] / phi[:, None, None]
            + phi[:, None, None] * (D2[None] / (2 * J[:, None, None])
                                    - gJ[:, :, None] * gJ[:, None, :] / (2 * J ** 2)[:, None, None]
                                    - hr / r[:, None, None]
                                    + gr[:, :, None] * gr[:, None, :] / (r ** 2)[:, None, None]))
    return p, q, phi, gphi, hphi


def linear(iso):
    """True when every bond target is F d0 (iso 0 for all: the compatibility is linear)."""
    return np.ndim(iso) == 0 and not iso


def bond_target(F, d0, iso, order=1, T=None):
    """v = G d0 per bond, G = (1 - iso) F + iso sqrt(J) R(F) + T, T = [[u, v], [v, -u]]
    the network's own shear of the cell (``T`` (b, 2) its (u, v), or None: no shear) and J
    = det F + |T|^2, so that det(sqrt(J) R + T) = det F: the network shears at the cells'
    area. Returns v with dv/d(F, T) (b, 2, m) and, with ``order`` 2, d2v (b, 2, m, m), m = 4
    without T, 6 with. ``iso`` a number or one per bond."""
    if np.ndim(iso):
        iso = np.asarray(iso, float)[:, None]
        v, dv, *d2v = bond_target(F, d0, 1.0, order, T)
        lin = bond_target(F, d0, 0.0, 1, T)
        out = ((1 - iso) * lin[0] + iso * v,
               (1 - iso[:, :, None]) * lin[1] + iso[:, :, None] * dv)
        return out + (iso[:, :, None, None] * d2v[0],) if order == 2 else out
    m = 4 if T is None else 6
    e = d0                                       # (M d0)_c = p e_c + q h_c
    h = np.stack([-d0[:, 1], d0[:, 0]], -1)
    p, q, phi, gphi, hphi = iso_scale(F, T)
    Fd = np.einsum("bcj,bj->bc", F, d0)
    Md = p[:, None] * e + q[:, None] * h
    v = (1 - iso) * Fd + iso * phi[:, None] * Md
    gF = np.zeros((len(F), 2, m))
    for c in range(2):
        gF[:, c, 2 * c:2 * c + 2] = d0
    gM = np.zeros((len(F), 2, m))
    gM[:, :, :4] = e[:, :, None] * _DP + h[:, :, None] * _DQ
    dv = (1 - iso) * gF + iso * (Md[:, :, None] * gphi[:, None, :] + phi[:, None, None] * gM)
    if T is not None:                            # T d0 = (u e_x + v e_y, v e_x - u e_y)
        v = v + np.stack([T[:, 0] * d0[:, 0] + T[:, 1] * d0[:, 1],
                          T[:, 1] * d0[:, 0] - T[:, 0] * d0[:, 1]], -1)
        dv[:, 0, 4], dv[:, 0, 5] = dv[:, 0, 4] + d0[:, 0], dv[:, 0, 5] + d0[:, 1]
        dv[:, 1, 4], dv[:, 1, 5] = dv[:, 1, 4] - d0[:, 1], dv[:, 1, 5] + d0[:, 0]
    if order == 1:
        return v, dv
    cross = gphi[:, None, :, None] * gM[:, :, None, :]
    d2v = iso * (Md[:, :, None, None] * hphi[:, None] + cross + cross.transpose(0, 1, 3, 2))
    return v, dv, d2v


def deviatoric(F):
    """Each cell's deviatoric stretch (n, 2, 2): the anticonformal part of F, F - M / 2
    with M = [[p, -q], [q, p]] (p = F_11 + F_22, q = F_21 - F_12), which is (V - tr V / 2)
    R for F = V R, the cell's flattening at its size, in its own frame; and its derivative
    dD/dF (n, 2, 2, 4), a constant (D is linear in F)."""
    a, b, c, d = F[:, 0, 0], F[:, 0, 1], F[:, 1, 0], F[:, 1, 1]
    u, v = 0.5 * (a - d), 0.5 * (b + c)
    D = np.stack([np.stack([u, v], -1), np.stack([v, -u], -1)], 1)
    dD = np.array([[[0.5, 0, 0, -0.5], [0, 0.5, 0.5, 0]], [[0, 0.5, 0.5, 0], [-0.5, 0, 0, 0.5]]])
    return D, np.broadcast_to(dD, (len(F), 2, 2, 4))
