# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shaped tensor model in three dimensions (issue 30, item 1; doc/model.md, "The 3-D
tensor model (prototype)"): a NumPy prototype.

Cell i has its bead x_i and a 3x3 deformation F_i of its fresh polyhedron (the lattice's
Voronoi cell, :mod:`cgms.shaped3d_cells`). Its volume is det(F_i) V0, a face of fresh
vector area a0 = S0 n0 has the area |cof(F_i) a0| (Nanson: cof F = det(F) F^-T). One
potential,

    E = sum_i E_fluid(V_i) + sum_faces E_membrane(S_f, S_rest)
        + k_g / 2 sum_(fresh bonds ik) |x_k - x_i - f (G(F_i) + G(F_k)) d0_ik / 2|^2 + E_LJ,

with the 2-D laws of :mod:`cgms.shaped` (imported, one copy of each formula): the Tait law
at fixed fluid mass on the fluid volume V = det(F) V0 - w sum_f S_f, the wall law on face
areas (stiff above the rest area, wrinkling at a constant tension below it, with ``soft``
stiffness beyond), the LJ repulsion between non-neighbours. G(F) = (1 - iso) F + iso
det(F)^(1/3) R(F), R the rotation of F's polar decomposition. State vector z = [x (n, 3),
F (n, 3, 3)] flattened. Units SI.
"""

import math

import numpy as np
import scipy.sparse as sp

from . import model, shaped
from . import shaped3d_cells as cells

#: parameters beyond cgms.shaped.DEFAULTS (whose wall_EA and buckle are a wall of the
#: material's height: the membrane modulus is wall_EA / height, E t, and the wrinkling
#: tension buckle / height): ``kg_ratio``, the compatibility stiffness k_g in units of the
#: membrane modulus; ``iso``, the share of the bond target that follows the cell's size
#: and rotation only; ``rest_power`` p, a face's rest area c(s)^p S0 / (1 + eps)^p (2: the
#: wall contracts in both directions; 1: along one, as a held prism's side walls in 2-D);
#: ``caps``, the faces without a neighbour vector (a prism layer's top and bottom): "walls"
#: (membranes as every face) or "held" (plates that hold the layer: no membrane, no strip,
#: and the fresh balance and the relaxation keep the layer's thickness)
DEFAULTS = dict(shaped.DEFAULTS, kg_ratio=1.0, iso=0.0, rest_power=2, caps="walls")

_NEXT, _AFTER = np.array([1, 2, 0]), np.array([2, 0, 1])

def build(points, vectors, mat, params=None, caps=()):
    """Everything fixed for a tissue built at ``points`` (n, 3) on a lattice whose Voronoi
    neighbours are ``vectors`` (and ``caps``, :func:`cgms.shaped3d_cells.polyhedron`):
    the cell polyhedron, the fresh neighbours and bonds, the fresh strain that balances
    turgor, the fresh fluid volume and the non-neighbour pairs."""
    p = dict(DEFAULTS, **(params or {}))
    if p["caps"] not in ("walls", "held"):
        raise ValueError(f"caps must be 'walls' or 'held', not {p['caps']!r}")
    if p["rest_power"] not in (1, 2):
        raise ValueError(f"rest_power must be 1 or 2, not {p['rest_power']!r}")
    x0 = np.asarray(points, float)
    n = len(x0)
    cell = cells.polyhedron(vectors, caps)
    face, bonds = cells.fresh_neighbours(x0, cell["neighbours"])
    nv, nf = len(cell["neighbours"]), len(cell["S0"])
    is_cap = np.arange(nf) >= nv
    held = p["caps"] == "held"
    wall = ~is_cap | (not held)               # faces with a membrane and a strip
    K_A = p["wall_EA"] / mat["height"]
    w = p["lamella"] * mat["pectin"]
    # fresh balance under the dilation the cell is free to make, D = I less the held
    # caps' normals: H P_f dV_f = sum_f T dS_f at a uniform tension T
    D = np.eye(3)
    if held:
        for nrm in cell["n0"][is_cap]:
            D = D - 0.5 * np.outer(nrm, nrm)   # each normal twice (top and bottom)
        if not (np.allclose(D, np.diag(np.round(np.diag(D))), atol=1e-12)
                and np.all(np.isin(np.round(np.diag(D)), (0.0, 1.0)))):
            raise ValueError("held caps must come in opposite pairs along the axes x, y or "
                             "z (a layer's top and bottom); build the layer in that frame")
    gS = cell["S0"] * (np.trace(D) - np.einsum("fi,ij,fj->f", cell["n0"], D, cell["n0"]))
    T = mat["P_f"] * (cell["volume"] * np.trace(D) - w * gS[wall].sum()) / gS[wall].sum()
    eps = (1 + T / K_A) ** (1 / p["rest_power"]) - 1
    nonnb = np.ones((n, n), bool)
    nonnb[bonds[:, 0], bonds[:, 1]] = nonnb[bonds[:, 1], bonds[:, 0]] = False
    boundary = np.any(face < 0, axis=1)
    nb = len(bonds)
    cols = np.concatenate([np.arange(nb)] * 2)
    ends = sp.csr_matrix((np.ones(2 * nb), (bonds.T.ravel(), cols)), shape=(n, nb))
    incidence = sp.csr_matrix((np.repeat([-1.0, 1.0], nb), (bonds.T.ravel(), cols)),
                              shape=(n, nb))
    return dict(p, n=n, x0=x0, mat=mat, cell=cell, face=face, bonds=bonds,
                bond0=x0[bonds[:, 1]] - x0[bonds[:, 0]], wall=wall, held=held, D=D,
                boundary=boundary, rim=boundary[bonds[:, 0]] & boundary[bonds[:, 1]],
                K_A=K_A, tau=p["buckle"] / mat["height"], w=w, k_g=p["kg_ratio"] * K_A,
                eps=eps, tension0=T, V_f0=cell["volume"] - w * cell["S0"][wall].sum(),
                pairs=np.argwhere(np.triu(nonnb, 1)), ends=ends, incidence=incidence)


def at_level(geo, s):
    """Per level: fluid volume s V_f0 at turgor s P_f, rest areas (c(s) / (1 + eps))^p
    S0 (eqn 9's c), the rim bonds' factor beta(s), the LJ radius r(s)."""
    mat = geo["mat"]
    c = float(model.perimeter_contraction(mat, s))
    beta = geo["beta_a"] + geo["beta_b"] * math.log(s)
    rest = geo["cell"]["S0"] * (c / (1 + geo["eps"])) ** geo["rest_power"]
    return dict(geo, s=s, beta=beta, V_f=s * geo["V_f0"], P_T=s * mat["P_f"], rest=rest,
                f_bond=np.where(geo["rim"], beta, 1.0), r_lj=float(model.lj_radius(mat, s)))


def split(z, n):
    """(x (n, 3), F (n, 3, 3)) of a state vector."""
    z = np.asarray(z, float)
    return z[:3 * n].reshape(n, 3), z[3 * n:12 * n].reshape(n, 3, 3)


def join(x, F):
    return np.concatenate([np.ravel(x), np.ravel(F)])


def fresh_state(geo):
    """The built tissue: beads where they were built, every F the identity."""
    return join(geo["x0"], np.broadcast_to(np.eye(3), (geo["n"], 3, 3)))


def cofactor(F):
    """cof(F) = det(F) F^-T for a stack (n, 3, 3): cof_ij = F_(i+1)(j+1) F_(i+2)(j+2) -
    F_(i+1)(j+2) F_(i+2)(j+1), indices mod 3."""
    a, b = F[:, _NEXT], F[:, _AFTER]
    return a[:, :, _NEXT] * b[:, :, _AFTER] - a[:, :, _AFTER] * b[:, :, _NEXT]


def faces(F, geo):
    """Per cell and face: the current vector area cof(F) a0 (n, f, 3) and area (n, f)."""
    c = np.einsum("nij,fj->nfi", cofactor(F), geo["cell"]["a0"])
    return c, np.sqrt(np.sum(c * c, axis=-1))


def face_area_gradient(F, c, S, weight):
    """sum_f weight[n, f] dS_nf / dF_n (n, 3, 3). From d cof(F) = cof(F) tr(F^-1 dF) -
    det(F) F^-T dF^T F^-T (det F > 0): dS/dF = S F^-T - c (F^-1 c)^T / S for c = cof(F)
    a0, S = |c|."""
    Finv = np.linalg.inv(F)
    Fc = np.einsum("nij,nfj->nfi", Finv, c)
    ws = weight / S
    return (np.sum(weight * S, axis=1)[:, None, None] * Finv.transpose(0, 2, 1)
            - np.einsum("nf,nfi,nfj->nij", ws, c, Fc))


def fluid_volume(F, S, geo):
    """The fluid's volume per cell: det(F) V0 less a slab of w over every wall face."""
    det = np.linalg.det(F)
    return det * geo["cell"]["volume"] - geo["w"] * S[:, geo["wall"]].sum(axis=1), det


def polar(F):
    """The rotation R = P Q^T of F = P diag(sigma) Q^T (det F > 0) with P, sigma, Q."""
    P, sig, Qt = np.linalg.svd(F)
    return P @ Qt, P, sig, Qt


def polar_adjoint(Gbar, P, sig, Qt):
    """d(R : Gbar)/dF for R the polar rotation: with A = P^T dF Q, dR = P W Q^T, W_ij =
    (A_ij - A_ji) / (sigma_i + sigma_j) (finite for det F > 0), so the adjoint is P C Q^T
    with C_ij = (B_ij - B_ji) / (sigma_i + sigma_j), B = P^T Gbar Q."""
    B = np.einsum("nai,nab,njb->nij", P, Gbar, Qt)
    C = (B - B.transpose(0, 2, 1)) / (sig[:, :, None] + sig[:, None, :])
    return np.einsum("nia,nab,nbj->nij", P, C, Qt)


def bond_map(F, iso):
    """G(F) = (1 - iso) F + iso det(F)^(1/3) R(F) per cell, and what its adjoint needs."""
    if not iso:
        return F, None
    R, P, sig, Qt = polar(F)
    det = np.linalg.det(F)
    phi = np.cbrt(det)
    return (1 - iso) * F + iso * phi[:, None, None] * R, (R, P, sig, Qt, det, phi)


def compatibility(x, F, lev):
    """The middle lamella's compatibility k_g / 2 sum_b |m_b|^2, m_b = x_k - x_i - f_b
    (G_i + G_k) d0_b / 2: energy, dE/dx (n, 3), dE/dF (n, 3, 3)."""
    i, k = lev["bonds"][:, 0], lev["bonds"][:, 1]
    d0, f, k_g, iso = lev["bond0"], lev["f_bond"], lev["k_g"], lev["iso"]
    G, aux = bond_map(F, iso)
    m = x[k] - x[i] - 0.5 * f[:, None] * np.einsum("bij,bj->bi", G[i] + G[k], d0)
    gx = lev["incidence"] @ (k_g * m)
    outer = -0.5 * k_g * f[:, None, None] * m[:, :, None] * d0[:, None, :]   # dE/dG
    Gbar = (lev["ends"] @ outer.reshape(-1, 9)).reshape(F.shape)
    gF = Gbar
    if aux is not None:
        R, P, sig, Qt, det, phi = aux
        dphi = (phi / (3 * det))[:, None, None] * cofactor(F)     # d det^(1/3) / dF
        gF = (1 - iso) * Gbar + iso * (phi[:, None, None] * polar_adjoint(Gbar, P, sig, Qt)
                                       + np.einsum("nij,nij->n", Gbar, R)[:, None, None] * dphi)
    return 0.5 * k_g * float(np.sum(m * m)), gx, gF


def energy(z, lev, gradient=True):
    """Total energy (J) of state ``z`` and, with ``gradient``, dE/dz. A state with a cell
    of non-positive fluid volume (or det F <= 0) has infinite energy (NaN gradient)."""
    n, mat = lev["n"], lev["mat"]
    x, F = split(z, n)
    c, S = faces(F, lev)
    V, det = fluid_volume(F, S, lev)
    if np.any(V <= 0) or np.any(det <= 0):
        return (np.inf, np.full(len(z), np.nan)) if gradient else np.inf
    K, wall = mat["K"], lev["wall"]
    e_w, de_w = shaped.wall_energy(S[:, wall], lev["rest"][wall], lev["K_A"], lev["tau"],
                                   lev["soft"])
    E_lj, g_lj = shaped.lj_energy(x, lev)
    E_c, gx_c, gF_c = compatibility(x, F, lev)
    E = (shaped.fluid_energy(V, lev["V_f"], lev["P_T"], K, 1.0).sum() + e_w.sum() + E_c
         + E_lj)
    if not gradient:
        return E
    f1 = -shaped.tait_pressure(V, lev["V_f"], lev["P_T"], K)         # dE/dV
    dEdS = np.zeros_like(S)
    dEdS[:, wall] = de_w - lev["w"] * f1[:, None]
    gF = (f1 * lev["cell"]["volume"])[:, None, None] * cofactor(F) \
        + face_area_gradient(F, c, S, dEdS) + gF_c
    return E, join(g_lj + gx_c, gF)


def forces(z, lev):
    """Largest force on a bead (N) and largest generalised force dE/dF / x_ref on a shape
    tensor (N), over the degrees of freedom :func:`free` leaves."""
    g = energy(z, lev)[1] * free(lev)
    n = lev["n"]
    return float(np.abs(g[:3 * n]).max()), float(np.abs(g[3 * n:]).max() / bond_unit(lev))


def bond_unit(lev):
    """The solver's unit of length: the shortest fresh bond (x_ref without bonds)."""
    return float(np.linalg.norm(lev["bond0"], axis=1).min()) if len(lev["bond0"]) \
        else lev["mat"]["x_ref"]


def free(lev):
    """1 for every number of the state that moves, 0 for those held: with ``caps``
    "held", the beads' and the F's components along the caps' normal (F keeps n n^T)."""
    n = lev["n"]
    if not lev["held"]:
        return np.ones(12 * n)
    inplane = np.diag(lev["D"]) > 0.5       # the caps' normals are lattice axes
    keep = np.outer(inplane, inplane).astype(float)   # F_ab moves where a and b do
    return join(np.broadcast_to(inplane.astype(float), (n, 3)),
                np.broadcast_to(keep, (n, 3, 3)))


def cell_measures(z, lev):
    """Per cell: fluid volume, wall area (each face's max(area, rest area): a wrinkled
    wall keeps its rest area in its folds), the principal stretches of F (sorted), and
    the fluid's pressure."""
    x, F = split(z, lev["n"])
    _, S = faces(F, lev)
    V, _ = fluid_volume(F, S, lev)
    wall = lev["wall"]
    return dict(volume=V, wall_area=np.maximum(S[:, wall], lev["rest"][wall]).sum(axis=1),
                stretches=np.sort(np.linalg.svd(F, compute_uv=False), axis=1),
                pressure=shaped.tait_pressure(V, lev["V_f"], lev["P_T"], lev["mat"]["K"]))
