# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shared walls' agreement of the tensor variant (:mod:`cgms.shaped_tensor`, parameter
``glue``): two glued cells see one wall, so cell i's chord F_i d_e and cell k's chord
F_k d_e' of the same wall (d_e' = -d_e fresh) are held together by

    E_glue = k_w / 2 sum_(shared walls) |F_i d_e + F_k d_e'|^2,   k_w = glue k_g.

At zero energy the jump F_k - F_i only stretches across the wall (Hadamard's condition for
a piecewise-uniform deformation), so the cells' F tile a continuous tissue and a cell's
flattening passes to its neighbours. The energy is quadratic in the state: its Hessian is
the constant k_w W^T W. Measured in doc/results/shaped-results.md ("2026-12-03 (fifth
session)"). In 3-D the same term holds a shared face: both tangents of the face.
"""

import numpy as np
import scipy.sparse as sp


def shared_walls(geo):
    """The linear map z -> (F_i d_e + F_k d_e') (2 rows per wall two cells share): wall e of
    cell i faces ring point k, wall e' of cell k faces ring point i."""
    n, cell, d0 = geo["n"], geo["cell"], geo["d0"]
    facing = np.full(len(cell), -1)
    for i, ring in enumerate(geo["topo"]["rings"]):
        e = np.flatnonzero(cell == i)
        for j, point in enumerate(ring):
            if not point["ghost"]:
                facing[e[j]] = point["terms"][0][0]
    where = {(int(cell[e]), int(facing[e])): e for e in np.flatnonzero(facing >= 0)}
    pairs = [(e, where[(k, i)]) for (i, k), e in where.items() if i < k and (k, i) in where]
    rows, cols, vals = [], [], []
    for r, (e, f) in enumerate(pairs):
        for a in range(2):           # row 2r + a: sum_b F_i[a, b] d_e[b] + F_k[a, b] d_f[b]
            for w in (e, f):
                for b in range(2):
                    rows.append(2 * r + a)
                    cols.append(2 * n + 4 * cell[w] + 2 * a + b)
                    vals.append(d0[w, b])
    return sp.csr_matrix((vals, (rows, cols)), shape=(2 * len(pairs), 6 * n))


def energy(z, lev, order=1):
    """The shared walls' agreement (``glue``): energy and gradient (len(z)), with ``order``
    2 also its constant Hessian (sparse, len(z) square; not formed for the energy's many
    line-search calls), or None when off."""
    if not lev["glue"]:
        return None
    W = lev["W"]
    if W.shape[1] != len(z):    # the network's shear columns follow F's
        W = sp.hstack([W, sp.csr_matrix((W.shape[0], len(z) - W.shape[1]))]).tocsr()
    k_w = lev["glue"] * lev["k_g"]
    m = W @ z
    out = (0.5 * k_w * float(m @ m), k_w * (W.T @ m))
    return out + (k_w * (W.T @ W),) if order == 2 else out
