# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A coarse model whose cells have a shape (issue 27; doc/model.md, "A coarse model with
cell shape"): a NumPy prototype and the future oracle of its C++ styles.

One bead per cell stays the only degree of freedom. Each cell is the polygon whose
vertices (junctions) are the centroids of the bead triangles around its bead, so every
force is a function of the bead positions. The model is one potential,

    E = sum_cells E_fluid(A_fluid) + sum_cells sum_walls E_wall(chord, rest) + E_LJ,

with the fluid at fixed mass (the Tait law of doc/model.md and of the MFC's fast variant),
walls stiff in stretch that buckle when shorter than their contracted rest length
(pushing with a constant, Euler-type force plus an optional soft stiffness), and LJ
repulsion between beads that were not neighbours in the
fresh tissue. Topology (neighbours, triangles, ghost points closing the boundary cells) is
fixed once from the built tissue: the middle lamella glues cells for good.

Every map from beads to junctions is linear (centroids, fixed rotations, the periphery
factor), so junctions are ``J = M x`` with one sparse matrix ``M`` and the gradient is
``M^T dE/dJ`` plus the LJ pairs. Plain functions on arrays; units SI.
"""

import math

import numpy as np
import scipy.sparse as sp

from . import model

#: fresh neighbour cutoff, a multiple of the built spacing (pair_style cgms's cutoff/lj)
CUTOFF = model.CUTOFF_LJ

#: parameters of the shaped model that the MFC does not fix, with their defaults
#: (doc/model.md, "A coarse model with cell shape"):
#: - wall_EA: axial stiffness E t H of one cell's wall (N); the MFC's 330 N/m x 6 um
#: - buckle: force (N) at which a wall shorter than its rest length buckles; the Euler
#:   load 4 pi^2 EI / l^2 of the MFC's wall (EI = E t^3 H / 12, t = 1 um) over a fresh
#:   wall of x_ref / sqrt(3) is 8.6e-7 N
#: - soft: stiffness of a buckled wall against further shortening, as a fraction of its
#:   stretch stiffness EA / l (0: the constant Euler-type force alone)
#: - beta_a, beta_b: periphery factor beta(s) = beta_a + beta_b ln s on the ghost points
#: - lamella: the width of the strip along each wall that is not fluid, as a fraction of
#:   the pectin layer d_p (1/2: the dual polygon reaches to the middle of the lamella)
DEFAULTS = dict(wall_EA=330.0 * 6e-6, buckle=8.6e-7, soft=0.0, beta_a=1.0, beta_b=0.0,
                lamella=0.5)


# --------------------------------------------------------------------------- topology

def _rotation(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _angle(v):
    return math.atan2(v[1], v[0])


def topology(xy, spacing, cutoff=CUTOFF):
    """Fixed topology of the built tissue ``xy`` (n, 2): a dict with

    - ``neighbours``: (n, n) bool, beads within ``cutoff * spacing``;
    - ``rings``: per bead, its ring of neighbour points counter-clockwise, each a list of
      terms ``(bead, R)`` meaning ``sum R (x_bead - x_i)`` relative to bead i (a real
      neighbour k is ``[(k, I)]``); ghost points fill every angular gap wider than a
      triangle, with ``ghost`` True;
    - the ghost points are placed by fixed rotations of the gap's two real sides, blended
      linearly, so at the built regular lattice they fall on the missing lattice points.

    A gap is a pair of angularly consecutive neighbours that are not neighbours of each
    other or more than 180 degrees apart; it gets round(angle / 60 deg) - 1 ghosts."""
    xy = np.asarray(xy, float)
    n = len(xy)
    dist = np.linalg.norm(xy[:, None] - xy[None], axis=-1)
    nb = dist < cutoff * spacing
    np.fill_diagonal(nb, False)
    rings = []
    for i in range(n):
        ks = np.flatnonzero(nb[i])
        if len(ks) == 0:
            raise ValueError(f"bead {i + 1} has no neighbour within {cutoff} x spacing")
        ang = np.array([_angle(xy[k] - xy[i]) for k in ks])
        ks = ks[np.argsort(ang)]
        ang = np.sort(ang)
        ring = []
        for j, k in enumerate(ks):
            ring.append(dict(terms=[(int(k), np.eye(2))], ghost=False))
            k2 = ks[(j + 1) % len(ks)]
            gap = (ang[(j + 1) % len(ks)] - ang[j]) % (2 * math.pi)
            if len(ks) == 1:
                gap = 2 * math.pi
            if nb[k, k2] and gap < math.pi and len(ks) > 1:
                continue
            m = max(int(round(gap / (math.pi / 3))) - 1, 0)
            phi = gap / (m + 1)
            for g in range(1, m + 1):
                w = (m + 1 - g) / (m + 1)     # weight of the walk from k
                terms = [(int(k), w * _rotation(g * phi)),
                         (int(k2), (1 - w) * _rotation(-(m + 1 - g) * phi))]
                ring.append(dict(terms=terms, ghost=True))
        rings.append(ring)
    return dict(n=n, neighbours=nb, rings=rings, spacing=float(spacing))


def triangles(topo, xy):
    """The real bead triangles (k, 3), counter-clockwise in ``xy``: triples of mutual
    fresh neighbours that are angularly consecutive around each of their beads."""
    tri = set()
    for i, ring in enumerate(topo["rings"]):
        real = [p["terms"][0][0] if not p["ghost"] else None for p in ring]
        for j in range(len(ring)):
            a, b = real[j], real[(j + 1) % len(ring)]
            if a is not None and b is not None and topo["neighbours"][a, b]:
                t = (i, a, b)
                k = t.index(min(t))
                tri.add(t[k:] + t[:k])
    return np.array(sorted(tri), dtype=int).reshape(-1, 3)


def triangle_areas(x, tri):
    """Signed areas of the bead triangles ``tri`` (positive counter-clockwise)."""
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    u, v = b - a, c - a
    return 0.5 * (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])


def _ring_point_rows(i, point, beta):
    """Terms of a ring point as absolute coefficients: list of (bead, 2x2), with x_i's
    own coefficient; a ghost's offset from x_i is scaled by ``beta``."""
    scale = beta if point["ghost"] else 1.0
    own = np.eye(2)
    out = []
    for k, R in point["terms"]:
        out.append((k, scale * R))
        own = own - scale * R
    out.append((i, own))
    return out


def junction_map(topo, beta):
    """The junctions of every cell as a linear map of the bead positions.

    Returns (M, cell, ja, jb, ghost_edge): ``M`` (2 nJ, 2 n) sparse with ``J.ravel() = M @
    x.ravel()``; cell i's polygon edge e runs from junction ``ja[e]`` to ``jb[e]``
    (counter-clockwise), faces ring point e of bead ``cell[e]``, and ``ghost_edge[e]`` says
    that point is a ghost (a free wall). Junction j of cell i is the centroid of bead i and
    ring points j, j+1. ``beta`` is one number or one per bead (the periphery factor of the
    cell whose ghosts they are)."""
    n = topo["n"]
    beta = np.broadcast_to(np.asarray(beta, float), (n,))
    rows, cols, vals = [], [], []
    cell, ja, jb, ghost_edge = [], [], [], []
    nj = 0
    for i, ring in enumerate(topo["rings"]):
        pts = [_ring_point_rows(i, p, beta[i]) for p in ring]
        m = len(ring)
        for j in range(m):
            coeff = {}
            for k, C in [(i, np.eye(2))] + pts[j] + pts[(j + 1) % m]:
                coeff[k] = coeff.get(k, 0) + C / 3
            for k, C in coeff.items():
                for a in range(2):
                    for b in range(2):
                        if C[a, b] != 0:
                            rows.append(2 * (nj + j) + a)
                            cols.append(2 * k + b)
                            vals.append(C[a, b])
            # edge facing ring point j: from junction (j-1, j) to junction (j, j+1)
            cell.append(i)
            ja.append(nj + (j - 1) % m)
            jb.append(nj + j)
            ghost_edge.append(ring[j]["ghost"])
        nj += m
    M = sp.csr_matrix((vals, (rows, cols)), shape=(2 * nj, 2 * n))
    return M, np.array(cell), np.array(ja), np.array(jb), np.array(ghost_edge)


# --------------------------------------------------------------------------- geometry

def _edge_ends(J, x, geo):
    """Both junctions of every polygon edge, relative to the cell's own bead: the shoelace
    sums then cancel no absolute coordinates (rounding 10x smaller in a mm tissue)."""
    o = x[geo["cell"]]
    return J[geo["ja"]] - o, J[geo["jb"]] - o


def polygons(x, geo):
    """Junctions (nJ, 2), per cell polygon area (n,), chords (nE,), chord vectors."""
    J = (geo["M"] @ x.ravel()).reshape(-1, 2)
    a, b = _edge_ends(J, x, geo)
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    area = 0.5 * np.bincount(geo["cell"], cross, minlength=geo["n"])
    d = b - a
    chord = np.hypot(d[:, 0], d[:, 1])
    return J, area, chord, d


def fluid_area(area, chord, geo, mat):
    """The fluid's area: the polygon less a strip of ``lamella`` x d_p along its chords."""
    strip = geo["lamella"] * mat["pectin"]
    return area - strip * np.bincount(geo["cell"], chord, minlength=geo["n"])


def tait_pressure(A, A_f, P_T, K):
    """P = P_T + K [(A_f / A)^7 - 1] (eqn 4 at fixed fluid mass, as the MFC's fast variant)."""
    return P_T + K * ((A_f / A) ** 7 - 1)


def fluid_energy(A, A_f, P_T, K, H):
    """E = -H int_{A_f}^{A} P dA' of :func:`tait_pressure` (zero at rest area A_f)."""
    return -H * ((P_T - K) * (A - A_f) - K / 6 * A_f ** 7 * (A ** -6.0 - A_f ** -6.0))


def wall_energy(chord, rest, EA, buckle, soft=0.0):
    """Energy of one wall and its derivative in the chord: EA/(2 r) (l - r)^2 while the
    wall is stretched or compressed less than the buckling strain buckle/EA; beyond, it
    buckles and pushes with the force ``buckle`` plus ``soft`` EA/r times the further
    shortening (0: a constant, Euler-type force; energy C1-joined)."""
    k = EA / rest
    lb = rest - buckle / k                        # chord at which the wall buckles
    elastic = chord >= lb
    short = np.maximum(lb - chord, 0.0)
    e = np.where(elastic, 0.5 * k * (chord - rest) ** 2,
                 0.5 * buckle ** 2 / k + buckle * short + 0.5 * soft * k * short ** 2)
    de = np.where(elastic, k * (chord - rest), -buckle - soft * k * short)
    return e, de


def wall_stiffness(chord, rest, EA, buckle, soft=0.0):
    """The second derivative of :func:`wall_energy` in the chord: EA / r while elastic,
    ``soft`` EA / r once buckled."""
    k = EA / rest
    return np.where(chord >= rest - buckle / k, k, soft * k)


def contour(chord, rest, geo):
    """Per cell contour length: each wall's length along its folds, max(chord, rest)."""
    return np.bincount(geo["cell"], np.maximum(chord, rest), minlength=geo["n"])


# --------------------------------------------------------------------------- the state

def fresh_balance_strain(mat, geo, x0):
    """The wall strain eps of the fresh (s = 1) built lattice: the turgor P_f at the rest
    fluid area balances walls of uniform tension EA eps (virtual work of a uniform dilation
    of an interior regular cell: H P_f (2 A - w L) = T L, w the lamella strip, L the
    polygon perimeter)."""
    _, area, chord, _ = polygons(x0, geo)
    L = np.bincount(geo["cell"], chord, minlength=geo["n"])
    w = geo["lamella"] * mat["pectin"]
    i = int(np.argmax(~geo["boundary"]))   # an interior cell
    T = mat["height"] * mat["P_f"] * (2 * area[i] - w * L[i]) / L[i]
    return T / geo["wall_EA"]


def build(xy0, mat, params=None, spacing=None):
    """Everything fixed for a tissue built at ``xy0`` (n, 2): topology, the fresh fluid
    areas and wall rest lengths (from the built tissue at beta = 1, in balance at s = 1).
    ``params`` overrides :data:`DEFAULTS`."""
    p = dict(DEFAULTS, **(params or {}))
    spacing = mat["x_ref"] if spacing is None else spacing
    x0 = np.asarray(xy0, float)
    topo = topology(x0, spacing)
    M, cell, ja, jb, ghost = junction_map(topo, 1.0)
    geo = dict(topo=topo, n=topo["n"], M=M, cell=cell, ja=ja, jb=jb, ghost=ghost,
               lamella=p["lamella"], wall_EA=p["wall_EA"], buckle=p["buckle"], soft=p["soft"],
               beta_a=p["beta_a"], beta_b=p["beta_b"], x0=x0)
    geo["boundary"] = np.bincount(cell, ghost, minlength=topo["n"]) > 0
    nj, ne = M.shape[0] // 2, len(cell)
    # edge -> junction incidence, to sum the edge terms onto junctions
    geo["Sa"] = sp.csr_matrix((np.ones(ne), (ja, np.arange(ne))), shape=(nj, ne))
    geo["Sb"] = sp.csr_matrix((np.ones(ne), (jb, np.arange(ne))), shape=(nj, ne))
    _, area, chord, _ = polygons(x0, geo)
    geo["A_f0"] = fluid_area(area, chord, geo, mat)       # fresh fluid area per cell
    geo["eps"] = fresh_balance_strain(mat, geo, x0)
    geo["rest0"] = chord / (1 + geo["eps"])               # fresh rest length per wall
    nonnb = ~topo["neighbours"]
    np.fill_diagonal(nonnb, False)
    geo["pairs"] = np.argwhere(np.triu(nonnb))
    geo["triangles"] = triangles(topo, x0)
    geo["tri_area0"] = triangle_areas(x0, geo["triangles"])
    geo["mat"] = mat
    return geo


def at_level(geo, s):
    """The per-level quantities at dryness ``s``: the junction map with beta(s), fluid rest
    area s A_f0, turgor s P_f, rest lengths contracted by eqn (9), LJ radius r(s)."""
    mat = geo["mat"]
    beta = geo["beta_a"] + geo["beta_b"] * math.log(s)
    M, *_ = junction_map(geo["topo"], beta)
    return dict(geo, M=M, s=s, beta=beta, A_f=s * geo["A_f0"], P_T=s * mat["P_f"],
                rest=geo["rest0"] * float(model.perimeter_contraction(mat, s)),
                r_lj=float(model.lj_radius(mat, s)))


def energy(x, lev, gradient=True):
    """Total energy (J) of bead positions ``x`` (n, 2) at level ``lev`` (:func:`at_level`)
    and, with ``gradient``, dE/dx (n, 2) (minus the forces). A state in which some cell's
    fluid area is not positive has infinite energy (and a NaN gradient): the solvers treat
    it as a rejected step."""
    mat = lev["mat"]
    x = np.asarray(x, float)
    J, area, chord, d = polygons(x, lev)
    A = fluid_area(area, chord, lev, mat)
    if np.any(A <= 0):
        return (np.inf, np.full_like(x, np.nan)) if gradient else np.inf
    H, K = mat["height"], mat["K"]
    e_f = fluid_energy(A, lev["A_f"], lev["P_T"], K, H)
    e_w, de_w = wall_energy(chord, lev["rest"], lev["wall_EA"], lev["buckle"], lev["soft"])
    E_lj, g_lj = lj_energy(x, lev)
    E = e_f.sum() + e_w.sum() + E_lj
    if not gradient:
        return E
    # d/dJ: fluid (dE/dA = -H P), through the area and the strip; walls through chords
    dEdA = -H * tait_pressure(A, lev["A_f"], lev["P_T"], K)
    g_cell = dEdA[lev["cell"]]
    u = d / chord[:, None]
    dchord = de_w - g_cell * lev["lamella"] * mat["pectin"]
    a, b = _edge_ends(J, x, lev)
    # area = 1/2 sum (a_x b_y - a_y b_x); chord = |b - a|
    va = 0.5 * g_cell[:, None] * np.column_stack([b[:, 1], -b[:, 0]]) - dchord[:, None] * u
    vb = 0.5 * g_cell[:, None] * np.column_stack([-a[:, 1], a[:, 0]]) + dchord[:, None] * u
    gJ = lev["Sa"] @ va + lev["Sb"] @ vb
    g = (lev["M"].T @ gJ.ravel()).reshape(-1, 2) + g_lj
    return E, g


def lj_energy(x, lev):
    """LJ repulsion between beads that were not fresh neighbours (reference.py's form,
    repulsive branch only): energy and its gradient (n, 2), or (n, 3) for beads in 3-D
    (:mod:`cgms.shaped3d`, the same law)."""
    i, k = lev["pairs"][:, 0], lev["pairs"][:, 1]
    dv = x[i] - x[k]
    r = np.hypot(dv[:, 0], dv[:, 1]) if x.shape[1] == 2 else np.sqrt(np.sum(dv * dv, axis=1))
    close = r < lev["r_lj"]
    q = lev["r_lj"] / r[close]
    f0 = lev["mat"]["f0_r"]
    E = np.sum(f0 * (q ** 8 / 8 - q ** 4 / 4 + 1 / 8))
    # dE/dr = f0 (-q^8 + q^4) / r
    dEdr = f0 * (-(q ** 8) + q ** 4) / r[close]
    gp = (dEdr / r[close])[:, None] * dv[close]
    g = np.zeros_like(x)
    for c in range(x.shape[1]):
        g[:, c] = np.bincount(i[close], gp[:, c], minlength=lev["n"]) - \
            np.bincount(k[close], gp[:, c], minlength=lev["n"])
    return E, g


def lj_hessian(x, lev):
    """The exact second derivative of :func:`lj_energy` (2n, 2n, sparse CSR; 3n, 3n for
    beads in 3-D)."""
    n, dim = lev["n"], x.shape[1]
    i, kk = lev["pairs"][:, 0], lev["pairs"][:, 1]
    dv = x[i] - x[kk]
    r = np.hypot(dv[:, 0], dv[:, 1]) if dim == 2 else np.sqrt(np.sum(dv * dv, axis=1))
    close = r < lev["r_lj"]
    if not np.any(close):
        return sp.csr_matrix((dim * n, dim * n))
    i, kk, dv, r = i[close], kk[close], dv[close], r[close]
    q = lev["r_lj"] / r
    f0 = lev["mat"]["f0_r"]
    e1 = f0 * (-(q ** 8) + q ** 4) / r
    e2 = f0 * (9 * q ** 8 - 5 * q ** 4) / r ** 2
    uu = dv / r[:, None]
    B = e2[:, None, None] * uu[:, :, None] * uu[:, None, :] + \
        (e1 / r)[:, None, None] * (np.eye(dim)[None] - uu[:, :, None] * uu[:, None, :])
    rr, cc, vv = [], [], []
    for ci in range(dim):
        for ck in range(dim):
            for p, q2, sgn in ((i, i, 1), (kk, kk, 1), (i, kk, -1), (kk, i, -1)):
                rr.append(dim * p + ci)
                cc.append(dim * q2 + ck)
                vv.append(sgn * B[:, ci, ck])
    return sp.csr_matrix((np.concatenate(vv), (np.concatenate(rr), np.concatenate(cc))),
                         shape=(dim * n, dim * n))


def wall_kinds(x, lev):
    """How many walls are stretched, compressed elastically, buckled, and how many LJ
    pairs are inside their radius (to check that a test state exercises every branch)."""
    _, _, chord, _ = polygons(x, lev)
    rest = lev["rest"]
    lb = rest - lev["buckle"] * rest / lev["wall_EA"]
    i, k = lev["pairs"][:, 0], lev["pairs"][:, 1]
    r = np.linalg.norm(x[i] - x[k], axis=1)
    return dict(stretched=int(np.sum(chord > rest)),
                compressed=int(np.sum((chord <= rest) & (chord >= lb))),
                buckled=int(np.sum(chord < lb)), lj_pairs=int(np.sum(r < lev["r_lj"])))


def energy_scale(x, lev):
    """Sum of the magnitudes of the energy's terms (the scale of its rounding error)."""
    mat = lev["mat"]
    _, area, chord, _ = polygons(x, lev)
    A = fluid_area(area, chord, lev, mat)
    H, K = mat["height"], mat["K"]
    # the fluid energy's two parts, each of size H K A
    e_f = H * (abs(lev["P_T"] - K) * np.abs(A - lev["A_f"]) + K / 6 * (lev["A_f"] / A) ** 6
               * lev["A_f"] + K / 6 * lev["A_f"])
    e_w, _ = wall_energy(chord, lev["rest"], lev["wall_EA"], lev["buckle"], lev["soft"])
    return float(e_f.sum() + np.abs(e_w).sum())


def hessian(x, lev):
    """The exact second derivative of :func:`energy` (2n, 2n, sparse CSR; coordinates
    interleaved x0, y0, x1, ...): M^T (d2E/dJ2) M plus the LJ pairs. Per cell the fluid
    gives f'' gA gA^T + f' d2A/dJ2 (gA = dA_fluid/dJ, f' = -H P, f'' = 7 H K A_f^7 / A^8);
    per wall w'' u u^T + w' (I - u u^T) / l along its two junctions."""
    mat = lev["mat"]
    J, area, chord, d = polygons(x, lev)
    A = fluid_area(area, chord, lev, mat)
    H, K, n = mat["height"], mat["K"], lev["n"]
    w = lev["lamella"] * mat["pectin"]
    ja, jb, cell = lev["ja"], lev["jb"], lev["cell"]
    f1 = -H * tait_pressure(A, lev["A_f"], lev["P_T"], K)
    f2 = 7 * H * K * lev["A_f"] ** 7 / A ** 8
    _, de_w = wall_energy(chord, lev["rest"], lev["wall_EA"], lev["buckle"], lev["soft"])
    k = lev["wall_EA"] / lev["rest"]
    lb = lev["rest"] - lev["buckle"] / k
    d2w = np.where(chord >= lb, k, lev["soft"] * k)
    u = d / chord[:, None]
    a, b = _edge_ends(J, x, lev)
    rows, cols, vals = [], [], []

    def put(ji, ci, jk, ck, v):   # d2E / dJ[ji, ci] dJ[jk, ck] += v (arrays)
        rows.append(2 * ji + ci)
        cols.append(2 * jk + ck)
        vals.append(v)

    # per edge: chord (wall, minus the strip's share of the fluid) and area curvature
    dl = de_w - f1[cell] * w
    P = (np.eye(2)[None] - u[:, :, None] * u[:, None, :]) / chord[:, None, None]
    Q = d2w[:, None, None] * u[:, :, None] * u[:, None, :] + dl[:, None, None] * P
    for ci in range(2):
        for ck in range(2):
            q = Q[:, ci, ck]
            put(ja, ci, ja, ck, q)
            put(jb, ci, jb, ck, q)
            put(ja, ci, jb, ck, -q)
            put(jb, ci, ja, ck, -q)
    half = 0.5 * f1[cell]            # d2 area / da_x db_y = 1/2, da_y db_x = -1/2
    put(ja, 0, jb, 1, half)
    put(jb, 1, ja, 0, half)
    put(ja, 1, jb, 0, -half)
    put(jb, 0, ja, 1, -half)
    # per cell: the rank-one fluid term f'' gA gA^T over the cell's junctions
    ga = np.column_stack([b[:, 1], -b[:, 0]]) * 0.5 + w * u      # d A / d a of edge e
    gb = np.column_stack([-a[:, 1], a[:, 0]]) * 0.5 - w * u      # d A / d b
    nj = J.shape[0]
    gA = sp.csr_matrix((np.concatenate([ga.ravel(), gb.ravel()]),
                        (np.concatenate([np.repeat(cell, 2)] * 2),
                         np.concatenate([(2 * ja[:, None] + [0, 1]).ravel(),
                                         (2 * jb[:, None] + [0, 1]).ravel()]))),
                       shape=(n, 2 * nj))
    HJ = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                       shape=(2 * nj, 2 * nj))
    HJ = HJ + gA.T @ sp.diags(f2) @ gA
    Hx = lev["M"].T @ HJ @ lev["M"]
    Hx = Hx + lj_hessian(x, lev)
    return sp.csr_matrix(Hx)


def cell_measures(x, lev):
    """Per cell: fluid area, contour length (max(chord, rest) over its walls), elongation
    of its junction polygon (second-moment axis ratio), pressure."""
    from . import morphology
    J, area, chord, _ = polygons(x, lev)
    A = fluid_area(area, chord, lev, lev["mat"])
    perim = contour(chord, lev["rest"], lev)
    elong = np.empty(lev["n"])
    for c in range(lev["n"]):
        e = np.flatnonzero(lev["cell"] == c)
        try:
            _, _, mom = morphology._polygon_moments(J[lev["ja"][e]])
            elong[c] = morphology._axis_ratio(*mom)
        except ValueError:   # a folded polygon (inverted triangles) has no elongation
            elong[c] = np.nan
    P = tait_pressure(A, lev["A_f"], lev["P_T"], lev["mat"]["K"])
    return dict(area=A, perimeter=perim, elongation=elong, pressure=P)


# --------------------------------------------------------------------------- steady states

def relax(x, lev, ftol=1e-9, maxiter=500):
    """Steady state from ``x``: a trust-region Newton method (scipy ``trust-exact``) with
    the analytic gradient and Hessian, in units of x_ref and of x_ref times ``ftol``, run
    until the largest force component is below ``ftol`` (N). Returns (x, info): largest
    force left (N), iterations, converged, scipy's message."""
    from scipy.optimize import minimize
    L = lev["mat"]["x_ref"]
    x0 = np.asarray(x, float)
    c0 = x0.mean(axis=0)
    scale = ftol * L   # energy unit: a force ftol over x_ref

    def pos(z):
        return c0 + z.reshape(-1, 2) * L

    def fun(z):
        E, g = energy(pos(z), lev)
        return E / scale, g.ravel() * L / scale

    def hess(z):
        return hessian(pos(z), lev).toarray() * L * L / scale

    # gtol on the largest scaled component: 1 = a force of ftol
    res = minimize(fun, ((x0 - c0) / L).ravel(), jac=True, hess=hess, method="trust-exact",
                   options=dict(maxiter=maxiter, gtol=1.0, initial_trust_radius=0.02,
                                   max_trust_radius=0.2))
    xs = pos(res.x)
    fmax = float(np.max(np.abs(energy(xs, lev)[1])))
    return xs, dict(fmax=fmax, iterations=int(res.nit), converged=fmax <= ftol,
                    message=str(res.message))


def ramp(xy0, mat, levels, params=None, ftol=1e-9, kick=0.0, seed=1):
    """Steady states along a drying ramp from the built tissue ``xy0``: each level starts
    from the previous one's state (the first from ``xy0``), optionally kicked by up to
    ``kick`` (m, seeded) to leave symmetric saddles. Returns the geometry and a list of
    (s, x, info)."""
    geo = build(xy0, mat, params)
    rng = np.random.default_rng(seed)
    x = np.asarray(xy0, float)
    out = []
    for s in levels:
        lev = at_level(geo, s)
        if kick and s < 1:
            x = x + rng.uniform(-kick, kick, x.shape)
        x, info = relax(x, lev, ftol)
        out.append((s, x, info))
    return geo, out
