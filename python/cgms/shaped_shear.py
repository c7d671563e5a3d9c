# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The bead network's own shear of the tensor variant (:mod:`cgms.shaped_tensor`,
parameter ``net_shear``; doc/model.md, "The network's own shear"): the modulus table mu(s)
and the shear energy with its constant Hessian."""

import numpy as np
import scipy.sparse as sp


def shear_table(value):
    """``net_shear`` as an (m, 2) array of (s, mu) rows in increasing s, or None (off)."""
    if value is None:
        return None
    t = np.array([[1.0, value]], float) if np.ndim(value) == 0 else np.array(value, float)
    if t.ndim != 2 or t.shape[1] != 2 or not np.all(t[:, 1] > 0) or not np.all(t[:, 0] > 0):
        raise ValueError(f"net_shear must be a modulus > 0 (N/m) or [[s, mu], ...] pairs "
                         f"with s > 0 and mu > 0, not {value!r}")
    return t[np.argsort(t[:, 0])]


def net_shear_modulus(table, s):
    """The network's shear modulus mu(s) (N/m) of a ``net_shear`` table: ln mu linear in s
    between its points, held beyond its ends (**Decision**: the fine model's modulus is
    measured at the levels only, and neither falls nor rises steadily between them)."""
    return float(np.exp(np.interp(s, table[:, 0], np.log(table[:, 1]))))


def shear_energy(T, lev):
    """The network's shear energy 2 mu sum_i A_poly0,i |T_i|^2 plus, with ``shear_smooth``
    c, its smoothness 2 mu c sum_(bonds ik) (A_poly0,i + A_poly0,k) / 2 |T_i - T_k|^2: the
    energy, its gradient (n, 2) and its constant Hessian in one component of T (n, n,
    sparse; the same for u and v). mu is the modulus for a shear strain T / sqrt(det F)
    over the cell's area det(F) A_poly0, in which det F cancels."""
    n, mu, A0 = lev["n"], lev["mu_net"], lev["poly_area0"]
    H1 = sp.diags(4 * mu * A0)
    c = lev["shear_smooth"]
    if c:
        i, k = lev["bonds"][:, 0], lev["bonds"][:, 1]
        w = 2 * mu * c * (A0[i] + A0[k])          # d2/dT_i^2 of w / 2 |T_i - T_k|^2
        L = sp.coo_matrix((np.concatenate([w, w, -w, -w]),
                           (np.concatenate([i, k, i, k]), np.concatenate([i, k, k, i]))),
                          shape=(n, n))
        H1 = H1 + L
    H1 = sp.csr_matrix(H1)
    g = H1 @ T
    return 0.5 * float(np.sum(T * g)), g, H1
