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

from . import model, shaped, shaped_glue, shaped_mean, superpose
from .shaped_shear import net_shear_modulus, shear_energy as _shear_energy, \
    shear_table as _shear_table
from . import shaped_target as target

#: parameters beyond cgms.shaped.DEFAULTS: kg_ratio, the lamella's compatibility stiffness
#: k_g in units of the wall's stretch stiffness EA / x_ref; the gap law between the cells'
#: fluids (doc/model.md, "The gap between the cells"): ``strip`` "chord" (the strip of
#: ``lamella`` d_p runs along the chords) or "contour" (along the walls' own length,
#: max(chord, rest) smoothed over ``smooth`` times the fresh stretch of a wall); ``void``,
#: the intercellular space of a turgid cell as a fraction of its polygon, open while its
#: walls are stretched and closed, smoothly, as their mean strain falls from
#: ``void_onset`` times the fresh strain to zero
#: ``iso``: the share of the bond target that follows only the cell's size and rotation,
#: sqrt(det F) R(F), rather than its whole deformation F (0: the whole F; 1: the network
#: ignores the cells' flattening, as the MFC's centroid network nearly does)
#: ``iso_rim``: the iso of the bonds of class ``rim_class`` instead (None: ``iso`` for
#: every bond): "rim", the bonds between two boundary cells (those beta scales), or
#: "boundary", every bond with a boundary cell at one end at least
#: ``dev_mean``: the share of the neighbourhood's mean deviatoric stretch (the anticonformal
#: part of F) in every bond target (0: off), over the cells within ``dev_hops`` steps
#: (:mod:`cgms.shaped_mean`)
#: ``net_shear``: the bead network's own shear, a free traceless tensor T_i per cell that
#: every bond of the cell follows (None: off, T absent from the state), with its shear
#: modulus mu(s) (N/m): a number, or [[s, mu], ...] interpolated as ln mu linear in s and
#: held beyond the ends (:func:`net_shear_modulus`); ``shear_smooth``: the weight of the
#: differences of T between bonded cells (0: each cell's shear free of its neighbours')
#: ``glue``: the shared walls' agreement, k_w / 2 sum |F_i d_e + F_k d_e'|^2 over every wall
#: two cells share (e in cell i, e' the same wall in cell k, d_e' = -d_e fresh), with k_w
#: = ``glue`` k_g (0: off). The middle lamella glues the two cells along the wall, so both
#: see one wall: the jump F_k - F_i may only stretch across it (Hadamard's compatibility),
#: and a cell's flattening passes to its neighbours through their shared walls
#: ``wall_pool``: one wall law per cell on its chord perimeter sum_e |F d_e| against the sum
#: of its walls' rest lengths (False: one law per wall). The walls then share their length,
#: so a cell's energy no longer prefers an axis of its hexagon (doc/results/
#: shaped-results.md, "2026-12-03 (fifth session)")
DEFAULTS = dict(shaped.DEFAULTS, kg_ratio=1.0, strip="chord", void=0.0, void_onset=0.5,
                smooth=0.25, iso=0.0, iso_rim=None, rim_class="rim", dev_mean=0.0,
                dev_hops=2, net_shear=None, shear_smooth=0.0, glue=0.0, wall_pool=False)


def _cof(F):
    """d det(F) / dF for a stack of 2x2 matrices (n, 2, 2)."""
    return np.stack([np.stack([F[:, 1, 1], -F[:, 1, 0]], -1),
                     np.stack([-F[:, 0, 1], F[:, 0, 0]], -1)], 1)


def build(xy0, mat, params=None, spacing=None, local=False):
    """Everything fixed for a tissue built at ``xy0``: the shaped model's topology, fresh
    fluid areas and rest lengths (:func:`cgms.shaped.build`, at beta = 1), plus each wall's
    fresh vector ``d0`` (edge e of cell ``cell[e]``), each cell's fresh polygon area, the
    fresh bonds with their vectors, and the compatibility maps: the mismatch is
    ``Cx z - f Cf z``, f = beta(s) on rim bonds (both cells on the boundary), else 1.
    ``local``: the topology of :func:`cgms.shaped_local.base`, without (n, n) arrays (no
    junction map, no LJ pair list: :mod:`cgms.shaped_newton` finds the near pairs)."""
    p = dict(DEFAULTS, **(params or {}))
    sub = {k: v for k, v in p.items() if k in shaped.DEFAULTS}
    if local:
        from . import shaped_local
        geo = shaped_local.base(xy0, mat, sub, spacing)
    else:
        geo = shaped.build(xy0, mat, sub, spacing)
    x0 = geo["x0"]
    n = geo["n"]
    if not local:
        J = (geo["M"] @ x0.ravel()).reshape(-1, 2)
        a, b = J[geo["ja"]] - x0[geo["cell"]], J[geo["jb"]] - x0[geo["cell"]]
        geo["d0"] = b - a
        geo["poly_area0"] = 0.5 * np.bincount(geo["cell"],
                                              a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], minlength=n)
        geo["bonds"] = np.argwhere(np.triu(geo["topo"]["neighbours"]))
    bonds = geo["bonds"]
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
    geo.update(strip=p["strip"], void=p["void"], void_onset=p["void_onset"],
               smooth=p["smooth"], iso=p["iso"])
    if p["strip"] not in ("chord", "contour"):
        raise ValueError(f"strip must be 'chord' or 'contour', not {p['strip']!r}")
    if p["iso_rim"] is not None:
        # per-bond iso: an array (one per bond) takes the nonlinear path everywhere
        if p["rim_class"] not in ("rim", "boundary"):
            raise ValueError(f"rim_class must be 'rim' or 'boundary', not {p['rim_class']!r}")
        edge = geo["rim"] if p["rim_class"] == "rim" else \
            geo["boundary"][bonds[:, 0]] | geo["boundary"][bonds[:, 1]]
        geo["iso"] = np.where(edge, float(p["iso_rim"]), float(p["iso"]))
    geo["net_shear"] = _shear_table(p["net_shear"])
    geo["shear_smooth"] = float(p["shear_smooth"])
    if not geo["shear_smooth"] >= 0:
        raise ValueError(f"shear_smooth must be >= 0, not {p['shear_smooth']!r}")
    if geo["net_shear"] is not None and p["dev_mean"]:
        raise ValueError("net_shear and dev_mean are two network shears: use one")
    geo["dev_mean"] = float(p["dev_mean"])
    if geo["dev_mean"]:
        geo["dev_weights"] = shaped_mean.bond_weights(geo["n"], bonds, p["dev_hops"])
    if p["void"] or local:   # (shaped.build's fresh balance is this one without void)
        _fresh_with_void(geo, mat)
    geo["wall_pool"] = bool(p["wall_pool"])
    try:
        geo["glue"] = float(p["glue"])
    except (TypeError, ValueError):
        geo["glue"] = math.nan
    if not geo["glue"] >= 0:
        raise ValueError(f"glue must be a number >= 0, not {p['glue']!r}")
    if geo["glue"]:
        if local:
            raise ValueError("glue needs the dense build (the local one keeps no wall pairs)")
        geo["W"] = shaped_glue.shared_walls(geo)
    return geo


def _fresh_with_void(geo, mat):
    """Fresh fluid areas and wall rest lengths when the turgid cells hold intercellular
    space: the built lattice (F = I) balances when H P_f dA/d(eta) = T L under a uniform
    dilation (1 + eta) of an interior cell, with dA/d(eta) = 2 D (1 - void) - w L (the void
    fully open and the walls taut at the fresh strain, so neither smoothing acts)."""
    w = geo["lamella"] * mat["pectin"]
    chord0 = np.hypot(geo["d0"][:, 0], geo["d0"][:, 1])
    L = np.bincount(geo["cell"], chord0, minlength=geo["n"])
    D = geo["poly_area0"]
    i = int(np.argmax(~geo["boundary"]))
    T = mat["height"] * mat["P_f"] * (2 * D[i] * (1 - geo["void"]) - w * L[i]) / L[i]
    geo["eps"] = T / geo["wall_EA"]
    geo["rest0"] = chord0 / (1 + geo["eps"])
    geo["A_f0"] = D * (1 - geo["void"]) - w * L


def at_level(geo, s):
    """Per level: fluid rest area s A_f0, turgor s P_f, rest lengths contracted by eqn (9),
    the compatibility map C with the rim bonds' factor beta(s) = beta_a + beta_b ln s, LJ
    radius r(s)."""
    mat = geo["mat"]
    beta = geo["beta_a"] + geo["beta_b"] * math.log(s)
    rest = geo["rest0"] * float(model.perimeter_contraction(mat, s))
    f = np.repeat(np.where(geo["rim"], beta, 1.0), 2)
    C = sp.csr_matrix(geo["Cx"] - sp.diags(f) @ geo["Cf"])
    f_bond = np.where(geo["rim"], beta, 1.0)
    mu = None if geo["net_shear"] is None else net_shear_modulus(geo["net_shear"], s)
    return dict(geo, s=s, mu_net=mu, beta=beta, A_f=s * geo["A_f0"], P_T=s * mat["P_f"], rest=rest,
                C=C, f_bond=f_bond, r_lj=float(model.lj_radius(mat, s)),
                rest_sum=np.bincount(geo["cell"], rest, minlength=geo["n"]),
                delta=geo["smooth"] * geo["eps"] * rest,
                void_strain=geo["void_onset"] * geo["eps"])


def split(z, n):
    """(x (n, 2), F (n, 2, 2)) of a state vector (the network's shear, if any: :func:`shear`)."""
    z = np.asarray(z, float)
    return z[:2 * n].reshape(n, 2), z[2 * n:6 * n].reshape(n, 2, 2)


def join(x, F, T=None):
    return np.concatenate([np.ravel(x), np.ravel(F)] + ([] if T is None else [np.ravel(T)]))


def shear(z, n):
    """The network's shear (u, v) per cell (n, 2) of a state vector, or None (without
    ``net_shear`` a state holds x and F only)."""
    return np.asarray(z, float)[6 * n:].reshape(n, 2) if len(z) > 6 * n else None


def align(z, ref, n=None):
    """State ``z`` moved rigidly onto the positions of ``ref`` (a steady state is one up to
    a rigid motion): x -> R x + t, every F -> R F and, with the network's shear, every
    (u, v) -> R (u, v). ``n`` the number of cells (default: 6 numbers per cell, no shear)."""
    n = len(z) // 6 if n is None else n
    x, F = split(z, n)
    xr, _ = split(ref, n)
    R = superpose.rotation(x, xr)
    T = shear(z, n)     # R [[u, v], [v, -u]] = [[u', v'], [v', -u']] with (u', v') = R (u, v)
    return join(superpose.align(x, xr, "rigid"), np.einsum("ab,nbc->nac", R, F),
                None if T is None else T @ R.T)


def fresh_state(geo):
    """The built tissue: beads where they were built, every F the identity (and, with
    ``net_shear``, the network unsheared)."""
    n = geo["n"]
    return join(geo["x0"], np.broadcast_to(np.eye(2), (n, 2, 2)),
                None if geo.get("net_shear") is None else np.zeros((n, 2)))


def contour_length(chord, lev):
    """Each wall's length along its folds, the strip's length: the chord with ``strip``
    "chord"; with "contour" max(chord, rest), joined C1 over chord - rest in +-delta.
    Returns the length and its first and second derivatives in the chord."""
    if lev["strip"] == "chord":
        return chord, np.ones_like(chord), np.zeros_like(chord)
    r, d = lev["rest"], lev["delta"]
    t = chord - r
    m = np.where(t >= d, chord, np.where(t <= -d, r, r + (t + d) ** 2 / (4 * d)))
    return m, np.clip((t + d) / (2 * d), 0.0, 1.0), np.where(np.abs(t) < d, 0.5 / d, 0.0)


def void_open(S, lev):
    """The open fraction psi of a cell's intercellular space, from its chord sum S: the
    walls' mean strain e = S / (sum of rest lengths) - 1; psi = 0 for e <= 0, 1 for e >=
    ``void_strain``, the cubic 3 t^2 - 2 t^3 of t = e / void_strain between (C1). Returns
    psi and its first and second derivatives in S."""
    R, e1 = lev["rest_sum"], lev["void_strain"]
    t = np.clip((S / R - 1) / e1, 0.0, 1.0)
    inside = (t > 0) & (t < 1)
    return (t * t * (3 - 2 * t), np.where(inside, 6 * t * (1 - t), 0.0) / (e1 * R),
            np.where(inside, 6 - 12 * t, 0.0) / (e1 * R) ** 2)


def _det_derivatives(F, lev):
    """D = det(F) A_poly0 per cell, dD/dF (n, 4) and d2 det(F)/dF2 (4, 4, the same for all)."""
    det = F[:, 0, 0] * F[:, 1, 1] - F[:, 0, 1] * F[:, 1, 0]
    D2 = np.zeros((4, 4))
    D2[0, 3] = D2[3, 0] = 1.0
    D2[1, 2] = D2[2, 1] = -1.0
    return (det * lev["poly_area0"], lev["poly_area0"][:, None] * _cof(F).reshape(-1, 4),
            D2)


def _chord_derivatives(c, chord, lev):
    """Per wall dl/dF (e, 4) and d2l/dF2 (e, 4, 4) of its chord l = |F d0|."""
    u = c / chord[:, None]
    d0 = lev["d0"]
    gl = (u[:, :, None] * d0[:, None, :]).reshape(-1, 4)
    P = (np.eye(2)[None] - u[:, :, None] * u[:, None, :]) / chord[:, None, None]
    l2 = np.einsum("eac,ebd->eabcd", P, d0[:, :, None] * d0[:, None, :]).reshape(-1, 4, 4)
    return gl, l2


def _per_cell(values, lev):
    """Sum per-wall arrays (e, ...) onto their cells (n, ...)."""
    out = np.zeros((lev["n"],) + values.shape[1:])
    np.add.at(out, lev["cell"], values)
    return out


def fluid_area(F, c, chord, lev, order=0):
    """The fluid's area per cell, A = D (1 - void psi) - w sum_e m(l_e): the polygon D =
    det(F) A_poly0 less the intercellular space (open while the walls are stretched,
    :func:`void_open`) and less a strip of w = ``lamella`` d_p along each wall
    (:func:`contour_length`). With ``order`` 1 also dA/dF (n, 4), with 2 also d2A/dF2
    (n, 4, 4)."""
    w = lev["lamella"] * lev["mat"]["pectin"]
    g_v = lev["void"]
    D, gD, D2 = _det_derivatives(F, lev)
    m, m1, m2 = contour_length(chord, lev)
    S = np.bincount(lev["cell"], chord, minlength=lev["n"])
    psi, p1, p2 = void_open(S, lev) if g_v else (np.zeros(lev["n"]),) * 3
    A = D * (1 - g_v * psi) - w * np.bincount(lev["cell"], m, minlength=lev["n"])
    if order == 0:
        return A
    gl, l2 = _chord_derivatives(c, chord, lev)
    gS = _per_cell(gl, lev)
    gA = gD * (1 - g_v * psi)[:, None] - g_v * (D * p1)[:, None] * gS \
        - w * _per_cell(m1[:, None] * gl, lev)
    if order == 1:
        return A, gA
    cross = gD[:, :, None] * gS[:, None, :]
    hA = ((1 - g_v * psi)[:, None, None] * lev["poly_area0"][:, None, None] * D2[None]
          - g_v * (p1[:, None, None] * (cross + cross.transpose(0, 2, 1))
                   + (D * p2)[:, None, None] * gS[:, :, None] * gS[:, None, :]
                   + (D * p1)[:, None, None] * _per_cell(l2, lev))
          - w * _per_cell(m2[:, None, None] * gl[:, :, None] * gl[:, None, :]
                          + m1[:, None, None] * l2, lev))
    return A, gA, hA


def mismatch(z, lev):
    """Every bond's mismatch m_b (flattened, 2 per bond)."""
    T = shear(z, lev["n"])
    if target.linear(lev["iso"]) and not lev["dev_mean"] and T is None:
        return lev["C"] @ z
    x, F = split(z, lev["n"])
    i, k = lev["bonds"][:, 0], lev["bonds"][:, 1]
    t = (target.bond_target(F[i], lev["bond0"], lev["iso"], T=None if T is None else T[i])[0]
         + target.bond_target(F[k], lev["bond0"], lev["iso"], T=None if T is None else T[k])[0])
    m = x[k] - x[i] - 0.5 * lev["f_bond"][:, None] * t
    if lev["dev_mean"]:
        m = m - shaped_mean.shift(target.deviatoric(F)[0], lev)
    return np.ravel(m)


def compatibility(z, lev, order=1):
    """The middle lamella's compatibility k_g / 2 sum_b |m_b|^2, m_b = x_k - x_i - f_b
    (G_i + G_k) d0_b / 2 (:func:`cgms.shaped_target.bond_target`): its energy and gradient
    (len(z)), with ``order`` 2 also its Hessian (sparse). With ``iso`` 0 and no shear the
    map is linear (lev["C"]); with ``dev_mean`` the bonds also follow the neighbourhood's
    flattening (:mod:`cgms.shaped_mean`); with ``net_shear`` each cell's own network shear
    T."""
    n, k_g = lev["n"], lev["k_g"]
    T = shear(z, n)
    if target.linear(lev["iso"]) and not lev["dev_mean"] and T is None:
        m = lev["C"] @ z
        out = (0.5 * k_g * m @ m, k_g * (lev["C"].T @ m))
        return out + (k_g * (lev["C"].T @ lev["C"]),) if order == 2 else out
    x, F = split(z, n)
    i, k = lev["bonds"][:, 0], lev["bonds"][:, 1]
    d0, f = lev["bond0"], lev["f_bond"]
    ti = target.bond_target(F[i], d0, lev["iso"], order, None if T is None else T[i])
    tk = target.bond_target(F[k], d0, lev["iso"], order, None if T is None else T[k])
    if lev["dev_mean"]:
        return shaped_mean.compatibility(x, F, lev, ti, tk, target.deviatoric(F), order)
    mc = ti[1].shape[2]                              # 4 numbers per cell, 6 with T
    m = x[k] - x[i] - 0.5 * f[:, None] * (ti[0] + tk[0])
    gx = np.zeros((n, 2))
    np.add.at(gx, k, k_g * m)
    np.add.at(gx, i, -k_g * m)
    dFi = -0.5 * f[:, None, None] * ti[1]            # dm/d(F, T)_i (b, 2, mc)
    dFk = -0.5 * f[:, None, None] * tk[1]
    gF = np.zeros((n, mc))
    np.add.at(gF, i, k_g * np.einsum("bc,bcj->bj", m, dFi))
    np.add.at(gF, k, k_g * np.einsum("bc,bcj->bj", m, dFk))
    E = 0.5 * k_g * np.sum(m * m)
    g = join(gx, gF[:, :4], None if T is None else gF[:, 4:])
    if order == 1:
        return E, g
    nb, w = len(i), 4 + 2 * mc
    Jm = np.zeros((nb, 2, w))                     # columns: x_i, x_k, (F, T)_i, (F, T)_k
    Jm[:, :, 0:2] = -np.eye(2)
    Jm[:, :, 2:4] = np.eye(2)
    Jm[:, :, 4:4 + mc] = dFi
    Jm[:, :, 4 + mc:] = dFk
    blk = k_g * np.einsum("bci,bcj->bij", Jm, Jm)
    blk[:, 4:4 + mc, 4:4 + mc] -= 0.5 * k_g * np.einsum("b,bc,bcij->bij", f, m, ti[2])
    blk[:, 4 + mc:, 4 + mc:] -= 0.5 * k_g * np.einsum("b,bc,bcij->bij", f, m, tk[2])
    idx = np.concatenate([2 * i[:, None] + np.arange(2), 2 * k[:, None] + np.arange(2),
                          _cell_columns(i, n, mc), _cell_columns(k, n, mc)], axis=1)
    rows = np.repeat(idx, w, axis=1).ravel()
    cols = np.tile(idx, (1, w)).ravel()
    N = len(z)
    return E, g, sp.csr_matrix((blk.ravel(), (rows, cols)), shape=(N, N))


def _cell_columns(cells, n, mc):
    """The state vector's columns of the cells' F (4) and, with mc 6, their shear (2)."""
    cols = [2 * n + 4 * cells[:, None] + np.arange(4)]
    if mc == 6:
        cols.append(6 * n + 2 * cells[:, None] + np.arange(2))
    return np.concatenate(cols, axis=1)


def cells(z, lev):
    """Per wall chord vectors and lengths, per cell fluid area."""
    x, F = split(z, lev["n"])
    c = np.einsum("eab,eb->ea", F[lev["cell"]], lev["d0"])
    chord = np.hypot(c[:, 0], c[:, 1])
    return x, F, c, chord, fluid_area(F, c, chord, lev)


def _terms(z, lev):
    mat = lev["mat"]
    x, F, c, chord, A = cells(z, lev)
    H, K = mat["height"], mat["K"]
    if lev.get("wall_pool"):
        # one wall law per cell on its chord perimeter: the walls share their length
        L = np.bincount(lev["cell"], chord, minlength=lev["n"])
        e_c, de_c = shaped.wall_energy(L, lev["rest_sum"], lev["wall_EA"], lev["buckle"],
                                       lev["soft"])
        return x, F, c, chord, A, e_c, de_c[lev["cell"]], mismatch(z, lev), H, K
    e_w, de_w = shaped.wall_energy(chord, lev["rest"], lev["wall_EA"], lev["buckle"],
                                   lev["soft"])
    return x, F, c, chord, A, e_w, de_w, mismatch(z, lev), H, K


def energy(z, lev, gradient=True):
    """Total energy (J) of state ``z`` and, with ``gradient``, dE/dz. A state with a cell
    of non-positive fluid area has infinite energy (NaN gradient)."""
    x, F, c, chord, A, e_w, de_w, m, H, K = _terms(z, lev)
    n = lev["n"]
    if np.any(A <= 0):
        return (np.inf, np.full(len(z), np.nan)) if gradient else np.inf
    E_lj, g_lj = shaped.lj_energy(x, lev)
    E_c, g_c = compatibility(z, lev)
    E = shaped.fluid_energy(A, lev["A_f"], lev["P_T"], K, H).sum() + e_w.sum() + E_c + E_lj
    T = shear(z, n)
    if T is not None:
        E_T, g_T, _ = _shear_energy(T, lev)
        E += E_T
    glue = shaped_glue.energy(z, lev)
    if glue is not None:
        E += glue[0]
    if not gradient:
        return E
    f1 = -H * shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)      # dE/dA
    _, gA = fluid_area(F, c, chord, lev, order=1)
    gl, _ = _chord_derivatives(c, chord, lev)
    gF = f1[:, None] * gA + _per_cell(de_w[:, None] * gl, lev)
    g = join(g_lj, gF, None if T is None else g_T) + g_c
    return E, g if glue is None else g + glue[1]


def hessian(z, lev):
    """The exact second derivative of :func:`energy` (6n, 6n, sparse CSR): per cell a 4x4
    block in F (fluid f'' gA gA^T + f' d2A/dF2, walls w'' g g^T + w' d2l/dF2 with
    d2l/dF2 = (I - u u^T)/l (x) d0 d0^T), the constant compatibility k_g C^T C and the
    LJ pairs."""
    x, F, c, chord, A, e_w, de_w, m, H, K = _terms(z, lev)
    n = lev["n"]
    f1 = -H * shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)
    f2 = 7 * H * K * lev["A_f"] ** 7 / A ** 8
    k = lev["wall_EA"] / lev["rest"]
    lb = lev["rest"] - lev["buckle"] / k
    d2w = np.where(chord >= lb, k, lev["soft"] * k)
    _, gA, hA = fluid_area(F, c, chord, lev, order=2)
    gl, l2 = _chord_derivatives(c, chord, lev)
    if lev.get("wall_pool"):
        L = np.bincount(lev["cell"], chord, minlength=n)
        gL = _per_cell(gl, lev)
        k2 = shaped.wall_stiffness(L, lev["rest_sum"], lev["wall_EA"], lev["buckle"],
                                   lev["soft"])
        blocks = k2[:, None, None] * gL[:, :, None] * gL[:, None, :] \
            + _per_cell(de_w[:, None, None] * l2, lev)
    else:
        blocks = _per_cell(d2w[:, None, None] * gl[:, :, None] * gl[:, None, :]
                           + de_w[:, None, None] * l2, lev)
    blocks += f2[:, None, None] * gA[:, :, None] * gA[:, None, :] + f1[:, None, None] * hA
    idx = 2 * n + 4 * np.arange(n)[:, None] + np.arange(4)[None]
    rows = np.repeat(idx, 4, axis=1).ravel()
    cols = np.tile(idx, (1, 4)).ravel()
    N = len(z)
    Hm = sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(N, N))
    Hm = Hm + compatibility(z, lev, order=2)[2]
    Hx = shaped.lj_hessian(x, lev).tocoo()
    Hm = Hm + sp.csr_matrix((Hx.data, (Hx.row, Hx.col)), shape=(N, N))
    T = shear(z, n)
    if T is not None:
        H1 = _shear_energy(T, lev)[2].tocoo()
        Hm = Hm + sp.csr_matrix((np.concatenate([H1.data, H1.data]),
                                 (np.concatenate([6 * n + 2 * H1.row, 6 * n + 2 * H1.row + 1]),
                                  np.concatenate([6 * n + 2 * H1.col, 6 * n + 2 * H1.col + 1]))),
                                shape=(N, N))
    glue = shaped_glue.energy(z, lev, order=2)
    if glue is not None:
        Hm = Hm + glue[2]
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
    """Largest force on a bead (N) and largest generalised force on a shape tensor (and on
    the network's shear), dE/dF / x_ref (N)."""
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
    unit = np.concatenate([np.full(2 * n, L), np.ones(len(z) - 2 * n)])
    scale = ftol * L

    def state(y):
        y = y * unit
        y[:2 * n] += np.tile(c0, n)
        return y

    def fun(y):
        E, g = energy(state(y), lev)
        return E / scale, g * unit / scale

    def hess(y):
        return hessian(state(y), lev).toarray() * np.outer(unit, unit) / scale

    y0 = np.asarray(z, float).copy()
    y0[:2 * n] -= np.tile(c0, n)
    res = minimize(fun, y0 / unit, jac=True, hess=hess, method="trust-exact",
                   options=dict(maxiter=maxiter, gtol=1.0, initial_trust_radius=0.02,
                                max_trust_radius=0.2))
    zs = state(res.x)
    fx, fF = forces(zs, lev)
    return zs, dict(fmax=max(fx, fF), iterations=int(res.nit), converged=max(fx, fF) <= ftol,
                    message=str(res.message))


def ramp(xy0, mat, levels, params=None, ftol=1e-9, kick=1e-3, seed=1, local=False,
         solver=None, start=None):
    """Steady states along a drying ramp from the built tissue: each level starts from the
    previous state shrunk isotropically by sqrt(s / s_prev) (beads about their centroid,
    every F), every F kicked by a seeded uniform perturbation of up to ``kick`` (to leave
    the symmetric saddle where no cell flattens). ``local`` builds without (n, n) arrays
    (:func:`build`); ``solver(z, lev, ftol)`` replaces :func:`relax` (e.g.
    :func:`cgms.shaped_newton.newton`); ``start(z, lev, ftol)``, the level's start from
    the previous state, replaces the shrink and the kick (e.g.
    :func:`cgms.shaped_start.start`). Returns (geometry, [(s, z, info)])."""
    geo = build(xy0, mat, params, local=local)
    rng = np.random.default_rng(seed)
    z = fresh_state(geo)
    n = geo["n"]
    out = []
    prev = 1.0
    for s in levels:
        lev = at_level(geo, s)
        if start:
            z, info = (solver or relax)(start(z, lev, ftol), lev, ftol)
            out.append((s, z, info))
            continue
        x, F = split(z, n)
        T = shear(z, n)
        f = math.sqrt(s / prev)
        c = x.mean(axis=0)
        x = c + (x - c) * f
        F = F * f
        if kick and s < 1:
            F = F + rng.uniform(-kick, kick, F.shape) * math.sqrt(s)
        z, info = (solver or relax)(join(x, F, None if T is None else T * f), lev, ftol)
        out.append((s, z, info))
        prev = s
    return geo, out
