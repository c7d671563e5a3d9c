# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shaped coarse model with a shape tensor per cell (issue 27; doc/model.md, "A coarse
model with cell shape", the tensor variant): a NumPy prototype.

Cell i has its bead x_i and a 2x2 deformation F_i that maps its fresh polygon (the dual
polygon of :mod:`cgms.shaped` in the built tissue, ghosts closing the boundary cells) to
its current shape. The polygon's area is det(F_i) times the fresh one, its wall chords are
F_i times the fresh wall vectors, so a cell can flatten (F_i anisotropic) while the bead
network stays ordered. One potential,

    E = sum_i E_fluid(A_i) + sum_walls E_wall(|F_i d_e|, r_e)
        + k_g / 2 sum_(fresh bonds ik) |x_k - x_i - (F_i + F_k) d0_ik / 2|^2 + E_LJ,

with the fluid and wall laws of :mod:`cgms.shaped` (Tait at fixed fluid mass; a wall
stiff in stretch that buckles below its contracted rest length and then pushes with
``buckle`` plus ``soft`` EA/r times the excess contour r - l, which it holds in its folds)
and the middle lamella's compatibility (the bond between two glued cells follows their
mean deformation). The periphery factor beta(s) scales the compatible bond vector
(F_i + F_k) d0_ik / 2 of the bonds between two boundary cells, the tissue's rim (the
paper's beta pulls the boundary beads in; here the free walls hold no tension once they
buckle, so scaling their rest length would act only while they are stretched). State
vector: z = [x (n, 2), F (n, 2, 2)] flattened. Units SI.
"""

import math

import numpy as np
import scipy.sparse as sp

from . import model, shaped

#: parameters beyond cgms.shaped.DEFAULTS: kg_ratio, the lamella's compatibility stiffness
#: k_g in units of the wall's stretch stiffness EA / x_ref
DEFAULTS = dict(shaped.DEFAULTS, kg_ratio=1.0)


def _cof(F):
    """d det(F) / dF for a stack of 2x2 matrices (n, 2, 2)."""
    return np.stack([np.stack([F[:, 1, 1], -F[:, 1, 0]], -1),
                     np.stack([-F[:, 0, 1], F[:, 0, 0]], -1)], 1)


def build(xy0, mat, params=None, spacing=None):
    """Everything fixed for a tissue built at ``xy0``: the shaped model's topology, fresh
    fluid areas and rest lengths (:func:`cgms.shaped.build`, at beta = 1), plus each wall's
    fresh vector ``d0`` (edge e of cell ``cell[e]``), each cell's fresh polygon area, the
    fresh bonds with their vectors, and the compatibility maps: the mismatch is
    ``Cx z - f Cf z``, f = beta(s) on rim bonds (both cells on the boundary), else 1."""
    p = dict(DEFAULTS, **(params or {}))
    geo = shaped.build(xy0, mat, {k: v for k, v in p.items() if k in shaped.DEFAULTS},
                       spacing)
    x0 = geo["x0"]
    n = geo["n"]
    J = (geo["M"] @ x0.ravel()).reshape(-1, 2)
    a, b = J[geo["ja"]] - x0[geo["cell"]], J[geo["jb"]] - x0[geo["cell"]]
    geo["d0"] = b - a
    geo["poly_area0"] = 0.5 * np.bincount(geo["cell"], a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
                                          minlength=n)
    nb = np.triu(geo["topo"]["neighbours"])
    bonds = np.argwhere(nb)
    geo["bonds"] = bonds
    geo["bond0"] = x0[bonds[:, 1]] - x0[bonds[:, 0]]
    geo["k_g"] = p["kg_ratio"] * p["wall_EA"] / mat["x_ref"]
    geo["kg_ratio"] = p["kg_ratio"]
    # mismatch m_b (2 per bond) = x_k - x_i - f (F_i + F_k) d0 / 2, linear in z
    nbd = len(bonds)
    rx, cx, vx, rf, cf, vf = [], [], [], [], [], []
    for c in range(2):
        r = 2 * np.arange(nbd) + c
        for idx, sgn in ((bonds[:, 1], 1.0), (bonds[:, 0], -1.0)):
            rx.append(r)
            cx.append(2 * idx + c)
            vx.append(np.full(nbd, sgn))
        for idx in (bonds[:, 0], bonds[:, 1]):
            for col in range(2):   # F[idx, c, col] d0[col]
                rf.append(r)
                cf.append(2 * n + 4 * idx + 2 * c + col)
                vf.append(0.5 * geo["bond0"][:, col])
    shape = (2 * nbd, 6 * n)
    geo["Cx"] = sp.csr_matrix((np.concatenate(vx), (np.concatenate(rx), np.concatenate(cx))),
                              shape=shape)
    geo["Cf"] = sp.csr_matrix((np.concatenate(vf), (np.concatenate(rf), np.concatenate(cf))),
                              shape=shape)
    geo["rim"] = geo["boundary"][bonds[:, 0]] & geo["boundary"][bonds[:, 1]]
    return geo


def at_level(geo, s):
    """Per level: fluid rest area s A_f0, turgor s P_f, rest lengths contracted by eqn (9),
    the compatibility map C with the rim bonds' factor beta(s) = beta_a + beta_b ln s, LJ
    radius r(s)."""
    mat = geo["mat"]
    beta = geo["beta_a"] + geo["beta_b"] * math.log(s)
    rest = geo["rest0"] * float(model.perimeter_contraction(mat, s))
    f = np.repeat(np.where(geo["rim"], beta, 1.0), 2)
    C = sp.csr_matrix(geo["Cx"] - sp.diags(f) @ geo["Cf"])
    return dict(geo, s=s, beta=beta, A_f=s * geo["A_f0"], P_T=s * mat["P_f"], rest=rest,
                C=C, r_lj=float(model.lj_radius(mat, s)))


def split(z, n):
    """(x (n, 2), F (n, 2, 2)) of a state vector."""
    z = np.asarray(z, float)
    return z[:2 * n].reshape(n, 2), z[2 * n:].reshape(n, 2, 2)


def join(x, F):
    return np.concatenate([np.ravel(x), np.ravel(F)])


def fresh_state(geo):
    """The built tissue: beads where they were built, every F the identity."""
    return join(geo["x0"], np.broadcast_to(np.eye(2), (geo["n"], 2, 2)))


def cells(z, lev):
    """Per wall chord vectors and lengths, per cell fluid area and polygon area."""
    x, F = split(z, lev["n"])
    c = np.einsum("eab,eb->ea", F[lev["cell"]], lev["d0"])
    chord = np.hypot(c[:, 0], c[:, 1])
    det = F[:, 0, 0] * F[:, 1, 1] - F[:, 0, 1] * F[:, 1, 0]
    poly = det * lev["poly_area0"]
    A = shaped.fluid_area(poly, chord, lev, lev["mat"])
    return x, F, c, chord, A


def _terms(z, lev):
    mat = lev["mat"]
    x, F, c, chord, A = cells(z, lev)
    H, K = mat["height"], mat["K"]
    e_w, de_w = shaped.wall_energy(chord, lev["rest"], lev["wall_EA"], lev["buckle"],
                                   lev["soft"])
    m = lev["C"] @ z
    return x, F, c, chord, A, e_w, de_w, m, H, K


def energy(z, lev, gradient=True):
    """Total energy (J) of state ``z`` and, with ``gradient``, dE/dz. A state with a cell
    of non-positive fluid area has infinite energy (NaN gradient)."""
    x, F, c, chord, A, e_w, de_w, m, H, K = _terms(z, lev)
    n = lev["n"]
    if np.any(A <= 0):
        return (np.inf, np.full(6 * n, np.nan)) if gradient else np.inf
    E_lj, g_lj = shaped.lj_energy(x, lev)
    E = (shaped.fluid_energy(A, lev["A_f"], lev["P_T"], K, H).sum() + e_w.sum()
         + 0.5 * lev["k_g"] * m @ m + E_lj)
    if not gradient:
        return E
    f1 = -H * shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)      # dE/dA
    u = c / chord[:, None]
    w = lev["lamella"] * lev["mat"]["pectin"]
    dl = de_w - f1[lev["cell"]] * w                                     # dE/dl per wall
    gF = (f1 * lev["poly_area0"])[:, None, None] * _cof(F)
    ge = dl[:, None, None] * u[:, :, None] * lev["d0"][:, None, :]
    for a in range(2):
        for b in range(2):
            gF[:, a, b] += np.bincount(lev["cell"], ge[:, a, b], minlength=n)
    g = join(g_lj, gF) + lev["k_g"] * (lev["C"].T @ m)
    return E, g


def hessian(z, lev):
    """The exact second derivative of :func:`energy` (6n, 6n, sparse CSR): per cell a 4x4
    block in F (fluid f'' gA gA^T + f' d2A/dF2, walls w'' g g^T + w' d2l/dF2 with
    d2l/dF2 = (I - u u^T)/l (x) d0 d0^T), the constant compatibility k_g C^T C and the
    LJ pairs."""
    x, F, c, chord, A, e_w, de_w, m, H, K = _terms(z, lev)
    n, cell = lev["n"], lev["cell"]
    f1 = -H * shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)
    f2 = 7 * H * K * lev["A_f"] ** 7 / A ** 8
    k = lev["wall_EA"] / lev["rest"]
    lb = lev["rest"] - lev["buckle"] / k
    d2w = np.where(chord >= lb, k, lev["soft"] * k)
    w = lev["lamella"] * lev["mat"]["pectin"]
    u = c / chord[:, None]
    d0 = lev["d0"]
    gl = (u[:, :, None] * d0[:, None, :]).reshape(-1, 4)               # dl/dF
    P = (np.eye(2)[None] - u[:, :, None] * u[:, None, :]) / chord[:, None, None]
    l2 = np.einsum("eac,ebd->eabcd", P, d0[:, :, None] * d0[:, None, :]).reshape(-1, 4, 4)
    D2 = np.zeros((4, 4))
    D2[0, 3] = D2[3, 0] = 1.0
    D2[1, 2] = D2[2, 1] = -1.0
    gA = (lev["poly_area0"][:, None] * _cof(F).reshape(n, 4))
    sum_gl = np.zeros((n, 4))
    blocks = np.zeros((n, 4, 4))
    dl = de_w - f1[cell] * w
    ew = d2w[:, None, None] * gl[:, :, None] * gl[:, None, :] + dl[:, None, None] * l2
    for j in range(4):
        sum_gl[:, j] = np.bincount(cell, gl[:, j], minlength=n)
        for i in range(4):
            blocks[:, i, j] = np.bincount(cell, ew[:, i, j], minlength=n)
    gA = gA - w * sum_gl
    blocks += f2[:, None, None] * gA[:, :, None] * gA[:, None, :]
    blocks += (f1 * lev["poly_area0"])[:, None, None] * D2[None]
    idx = 2 * n + 4 * np.arange(n)[:, None] + np.arange(4)[None]
    rows = np.repeat(idx, 4, axis=1).ravel()
    cols = np.tile(idx, (1, 4)).ravel()
    Hm = sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(6 * n, 6 * n))
    Hm = Hm + lev["k_g"] * (lev["C"].T @ lev["C"])
    Hx = shaped.lj_hessian(x, lev).tocoo()
    Hm = Hm + sp.csr_matrix((Hx.data, (Hx.row, Hx.col)), shape=(6 * n, 6 * n))
    return sp.csr_matrix(Hm)


def cell_measures(z, lev):
    """Per cell: fluid area, contour length (sum of max(chord, rest)), elongation of its
    polygon (second-moment axis ratio, as cgms.shaped), pressure."""
    from . import morphology
    x, F, c, chord, A = cells(z, lev)
    J = (lev["M"] @ lev["x0"].ravel()).reshape(-1, 2)
    elong = np.empty(lev["n"])
    for i in range(lev["n"]):
        e = np.flatnonzero(lev["cell"] == i)
        poly = (J[lev["ja"][e]] - lev["x0"][i]) @ F[i].T
        try:
            _, _, mom = morphology._polygon_moments(poly)
            elong[i] = morphology._axis_ratio(*mom)
        except ValueError:
            elong[i] = np.nan
    return dict(area=A, perimeter=shaped.contour(chord, lev["rest"], lev), elongation=elong,
                pressure=shaped.tait_pressure(A, lev["A_f"], lev["P_T"], lev["mat"]["K"]))


def forces(z, lev):
    """Largest force on a bead (N) and largest generalised force on a shape tensor,
    dE/dF / x_ref (N)."""
    _, g = energy(z, lev)
    n = lev["n"]
    return float(np.abs(g[:2 * n]).max()), float(np.abs(g[2 * n:]).max() / lev["mat"]["x_ref"])


def relax(z, lev, ftol=1e-9, maxiter=500):
    """Steady state from ``z`` by scipy's trust-region Newton method (``trust-exact``) with
    the exact gradient and Hessian, positions in units of x_ref and energy in units of
    ftol x_ref, so that it stops when every bead force and every dE/dF / x_ref is below
    ``ftol`` (N). Returns (z, info)."""
    from scipy.optimize import minimize
    n = lev["n"]
    L = lev["mat"]["x_ref"]
    x0, F0 = split(z, n)
    c0 = x0.mean(axis=0)
    unit = np.concatenate([np.full(2 * n, L), np.ones(4 * n)])
    scale = ftol * L

    def state(y):
        x, F = split(y * unit, n)
        return join(x + c0, F)

    def fun(y):
        E, g = energy(state(y), lev)
        return E / scale, g * unit / scale

    def hess(y):
        return hessian(state(y), lev).toarray() * np.outer(unit, unit) / scale

    res = minimize(fun, join(x0 - c0, F0) / unit, jac=True, hess=hess, method="trust-exact",
                   options=dict(maxiter=maxiter, gtol=1.0, initial_trust_radius=0.02,
                                max_trust_radius=0.2))
    zs = state(res.x)
    fx, fF = forces(zs, lev)
    return zs, dict(fmax=max(fx, fF), iterations=int(res.nit), converged=max(fx, fF) <= ftol,
                    message=str(res.message))


def ramp(xy0, mat, levels, params=None, ftol=1e-9, kick=1e-3, seed=1):
    """Steady states along a drying ramp from the built tissue: each level starts from the
    previous state shrunk isotropically by sqrt(s / s_prev) (beads about their centroid,
    every F), every F kicked by a seeded uniform perturbation of up to ``kick`` (to leave
    the symmetric saddle where no cell flattens). Returns (geometry, [(s, z, info)])."""
    geo = build(xy0, mat, params)
    rng = np.random.default_rng(seed)
    z = fresh_state(geo)
    n = geo["n"]
    out = []
    prev = 1.0
    for s in levels:
        lev = at_level(geo, s)
        x, F = split(z, n)
        f = math.sqrt(s / prev)
        c = x.mean(axis=0)
        x = c + (x - c) * f
        F = F * f
        if kick and s < 1:
            F = F + rng.uniform(-kick, kick, F.shape) * math.sqrt(s)
        z, info = relax(join(x, F), lev, ftol)
        out.append((s, z, info))
        prev = s
    return geo, out
