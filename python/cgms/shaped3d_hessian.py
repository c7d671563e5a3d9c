# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The exact Hessian of the 3-D shaped tensor model's energy (:func:`cgms.shaped3d.energy`)
at ``iso`` 0, where the compatibility is linear in the state (doc/model.md, "The 3-D
tensor model (prototype)"). Per cell a 9x9 block in F: the fluid f'' gV gV^T + f' d2V/dF2,
the walls w'' gS gS^T + w' d2S/dF2, with d2 det / dF_ij dF_kl = eps_ikm eps_jln F_mn and,
for a face c = cof(F) a0 (quadratic in F: dc/dF = B, d2c constant), d2S/dF2 = (B^T B - gS
gS^T) / S + u . d2c; plus the constant k_g C^T C of the bonds and the LJ pairs.
"""

import numpy as np
import scipy.sparse as sp

from . import shaped
from . import shaped3d as s3

_LEVI = np.zeros((3, 3, 3))
for _a, _b, _c in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _LEVI[_a, _b, _c], _LEVI[_a, _c, _b] = 1.0, -1.0


def compatibility_map(lev):
    """The bonds' mismatch m = C z (3 per bond, sparse (3 b, 12 n)) at ``iso`` 0:
    m_b = x_k - x_i - f_b (F_i + F_k) d0_b / 2."""
    n, bonds, d0, f = lev["n"], lev["bonds"], lev["bond0"], lev["f_bond"]
    nb = len(bonds)
    rows, cols, vals = [], [], []
    for c in range(3):
        r = 3 * np.arange(nb) + c
        for idx, sgn in ((bonds[:, 1], 1.0), (bonds[:, 0], -1.0)):
            rows.append(r)
            cols.append(3 * idx + c)
            vals.append(np.full(nb, sgn))
        for idx in (bonds[:, 0], bonds[:, 1]):
            for p in range(3):
                rows.append(r)
                cols.append(3 * n + 9 * idx + 3 * c + p)
                vals.append(-0.5 * f * d0[:, p])
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(3 * nb, 12 * n))


def face_derivatives(F, lev):
    """Per cell and face: area S, dS/dF (n, f, 9) and d2S/dF2 (n, f, 9, 9)."""
    c, S = s3.faces(F, lev)
    a0 = lev["cell"]["a0"]
    B = np.einsum("imq,jpr,nqr,fj->nfimp", _LEVI, _LEVI, F, a0).reshape(*S.shape, 3, 9)
    u = c / S[..., None]
    gS = np.einsum("nfi,nfik->nfk", u, B)
    d2c = np.einsum("imq,jpr,fj->fimpqr", _LEVI, _LEVI, a0).reshape(len(a0), 3, 9, 9)
    hS = ((np.einsum("nfik,nfil->nfkl", B, B) - gS[..., :, None] * gS[..., None, :])
          / S[..., None, None] + np.einsum("nfi,fikl->nfkl", u, d2c))
    return S, gS, hS


def hessian(z, lev):
    """The exact second derivative of :func:`cgms.shaped3d.energy` (12 n, 12 n, sparse
    CSR), at ``iso`` 0 only."""
    if lev["iso"]:
        raise NotImplementedError("shaped3d_hessian: the exact Hessian is built for iso 0 "
                                  "only (the polar rotation's second derivative is not); "
                                  "use relax(method='newton'), which differences the gradient")
    n, mat, wall = lev["n"], lev["mat"], lev["wall"]
    x, F = s3.split(z, n)
    S, gS, hS = face_derivatives(F, lev)
    V, det = s3.fluid_volume(F, S, lev)
    V0, w, K = lev["cell"]["volume"], lev["w"], mat["K"]
    f1 = -shaped.tait_pressure(V, lev["V_f"], lev["P_T"], K)         # dE/dV
    f2 = 7 * K * lev["V_f"] ** 7 / V ** 8                              # d2E/dV2
    d2det = np.einsum("ikm,jln,xmn->xijkl", _LEVI, _LEVI, F).reshape(n, 9, 9)
    gV = V0 * s3.cofactor(F).reshape(n, 9) - w * gS[:, wall].sum(axis=1)
    hV = V0 * d2det - w * hS[:, wall].sum(axis=1)
    Sw, rest = S[:, wall], lev["rest"][wall]
    _, de_w = shaped.wall_energy(Sw, rest, lev["K_A"], lev["tau"], lev["soft"])
    d2w = shaped.wall_stiffness(Sw, rest, lev["K_A"], lev["tau"], lev["soft"])
    blocks = (f2[:, None, None] * gV[:, :, None] * gV[:, None, :] + f1[:, None, None] * hV
              + np.einsum("nf,nfk,nfl->nkl", d2w, gS[:, wall], gS[:, wall])
              + np.einsum("nf,nfkl->nkl", de_w, hS[:, wall]))
    idx = 3 * n + 9 * np.arange(n)[:, None] + np.arange(9)[None]
    rows = np.repeat(idx, 9, axis=1).ravel()
    cols = np.tile(idx, (1, 9)).ravel()
    N = 12 * n
    H = sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(N, N))
    C = compatibility_map(lev)
    H = H + lev["k_g"] * (C.T @ C)
    Hx = shaped.lj_hessian(x, lev).tocoo()
    H = H + sp.csr_matrix((Hx.data, (Hx.row, Hx.col)), shape=(N, N))
    return sp.csr_matrix(H)
