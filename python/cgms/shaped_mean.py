# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A coarse-grained ``iso`` for the tensor variant (issue 27; doc/model.md, "The network's
shear from the neighbourhood's flattening"): every bond of the compatibility also follows
the mean of the cells' deviatoric stretch over a neighbourhood, so that a flattening shared
by the cells around a bond shears the bead network while each cell's own does not.

Cell j's deviatoric stretch is the anticonformal part of its F, D_j = (V_j - tr V_j / 2) R_j
for F_j = V_j R_j (:func:`cgms.shaped_target.deviatoric`): its flattening at its size, in
its own frame, linear in F_j and traceless, so that cells flattened in every direction
average to no shear and to no change of area. The bond ik's mismatch gains

    - f a Dbar_ik d0_ik,    Dbar_ik = sum_j w_ikj D_j,    w_ik = (W_i + W_k) / 2,

with ``dev_mean`` a (0: off) and W_i uniform over the cells within ``dev_hops`` steps of
cell i in the fresh neighbour graph (i included). With ``dev_hops`` 0 each bond follows a
of its own two cells' flattening; with a wide neighbourhood only the flattening that the
cells around a bond share passes. D(Q F) = Q D(F) for a rotation Q, so the energy stays
invariant under x -> Q x + t, F_j -> Q F_j.

This module has the neighbourhood weights and the assembly of the compatibility with the
term; the per-cell D and its derivatives come from :mod:`cgms.shaped_tensor`, which calls
it (the module imports no other of cgms, so that there is no import cycle).
"""

import numpy as np
import scipy.sparse as sp


def bond_weights(n, bonds, hops):
    """w (b, n, sparse CSR): row ik the mean of the cells' uniform weights over their
    neighbourhoods of ``hops`` steps in the fresh neighbour graph of the ``n`` cells, whose
    edges are ``bonds`` (b, 2); sparse, so that it serves the local build at any size."""
    if hops < 0 or int(hops) != hops:
        raise ValueError(f"dev_hops must be a whole number >= 0, not {hops!r}")
    ones = np.ones(len(bonds))
    graph = sp.coo_matrix((ones, (bonds[:, 0], bonds[:, 1])), shape=(n, n))
    step = sp.csr_matrix(((graph + graph.T + sp.identity(n)) > 0).astype(float))
    reach = sp.identity(n, format="csr")
    for _ in range(int(hops)):
        reach = (reach @ step).astype(bool).astype(float)
    W = sp.diags(1.0 / np.asarray(reach.sum(axis=1)).ravel()) @ reach
    W = sp.csr_matrix(W)
    return sp.csr_matrix(0.5 * (W[bonds[:, 0]] + W[bonds[:, 1]]))


def shift(D, lev):
    """The bonds' shift f a Dbar_b d0_b (b, 2) of the cells' deviatoric stretches D
    (n, 2, 2), the part of the bond target the term adds."""
    Dbar = (lev["dev_weights"] @ D.reshape(-1, 4)).reshape(-1, 2, 2)
    return (lev["dev_mean"] * lev["f_bond"])[:, None] * np.einsum("brc,bc->br", Dbar,
                                                                   lev["bond0"])


def compatibility(x, F, lev, ti, tk, dev, order=1):
    """k_g / 2 sum_b |m_b|^2 with m_b = x_k - x_i - f (t_i + t_k) / 2 - :func:`shift`:
    energy and gradient (6n), with ``order`` 2 also the Hessian (sparse). ``ti``, ``tk``:
    the own cells' targets with their derivatives (shaped_target.bond_target, per bond);
    ``dev``: D (n, 2, 2) and its constant dD/dF (n, 2, 2, 4). The Hessian is k_g J^T J
    plus the own targets' second derivatives contracted with m, per bond on F_i and F_k
    (D is linear in F: the term adds none)."""
    n, k_g, a = lev["n"], lev["k_g"], lev["dev_mean"]
    i, k = lev["bonds"][:, 0], lev["bonds"][:, 1]
    d0, f, w = lev["bond0"], lev["f_bond"], lev["dev_weights"].tocoo()
    D, dD = dev[0], dev[1]
    m = x[k] - x[i] - 0.5 * f[:, None] * (ti[0] + tk[0]) - shift(D, lev)
    nb = len(i)
    # the Jacobian dm/dz: the own cells' columns, then the neighbourhood's
    Jm = np.zeros((nb, 2, 12))                     # columns: x_i, x_k, F_i, F_k
    Jm[:, :, 0:2] = -np.eye(2)
    Jm[:, :, 2:4] = np.eye(2)
    Jm[:, :, 4:8] = -0.5 * f[:, None, None] * ti[1]
    Jm[:, :, 8:12] = -0.5 * f[:, None, None] * tk[1]
    idx = np.concatenate([2 * i[:, None] + np.arange(2), 2 * k[:, None] + np.arange(2),
                          2 * n + 4 * i[:, None] + np.arange(4),
                          2 * n + 4 * k[:, None] + np.arange(4)], axis=1)
    rows = np.repeat(2 * np.arange(nb)[:, None] + np.arange(2), 12, axis=1)
    cols = np.repeat(idx[:, None, :], 2, axis=1).reshape(nb, 24)
    b, j = w.row, w.col
    vals = -(a * f[b] * w.data)[:, None, None] * np.einsum("prcq,pc->prq", dD[j], d0[b])
    rows_d = np.repeat(2 * b[:, None] + np.arange(2), 4, axis=1)
    cols_d = np.tile(2 * n + 4 * j[:, None] + np.arange(4), (1, 2))
    J = sp.csr_matrix((np.concatenate([Jm.ravel(), vals.ravel()]),
                       (np.concatenate([rows.ravel(), rows_d.ravel()]),
                        np.concatenate([cols.ravel(), cols_d.ravel()]))),
                      shape=(2 * nb, 6 * n))
    mf = m.ravel()
    E, g = 0.5 * k_g * mf @ mf, k_g * (J.T @ mf)
    if order == 1:
        return E, g
    blk = np.zeros((nb, 8, 8))
    blk[:, 0:4, 0:4] = -0.5 * k_g * np.einsum("b,bc,bcij->bij", f, m, ti[2])
    blk[:, 4:8, 4:8] = -0.5 * k_g * np.einsum("b,bc,bcij->bij", f, m, tk[2])
    fi = idx[:, 4:12]
    H2 = sp.csr_matrix((blk.ravel(), (np.repeat(fi, 8, axis=1).ravel(),
                                      np.tile(fi, (1, 8)).ravel())), shape=(6 * n, 6 * n))
    return E, g, sp.csr_matrix(k_g * (J.T @ J) + H2)
