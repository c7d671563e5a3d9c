# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Moisture transport in a drying tissue slice: plain functions on arrays (doc/drying.md).

The 2-D tissue is a slice of thickness ``L``. Each bead carries a column of its tissue
across the thickness, cut into ``layers`` nodes (the per-bead thickness sub-model: the
surface and the core of a column hold different moisture). The unknown is the dry-basis
moisture ``X`` (kg water / kg dry solid) of every node; a node's dry solid ``S`` never
changes, so its water is ``S X`` and water is conserved node by node.

Water moves by Fick's law in ``X`` (the form the drying literature fits ``D_eff`` with):
between the same layer of neighbouring beads through their shared face, between the
layers of a column, and out through the slice faces and the tissue outline into air,
at a rate ``k_c (rho_v,surface - rho_v,air)``, the surface vapour density following from
the sorption isotherm (GAB) at the product temperature. The Euler step (:func:`step`) is
backward Euler with the surface law and ``D`` linearised at the start of the step
(unconditionally stable; one sparse solve): what leaves the tissue in it is exactly the
linearised surface flow the matrix holds, so the water balance closes to rounding. A
moisture step (:func:`extrapolated_step`, as ``fix cgms/transport`` steps) is the
Richardson extrapolation of three Euler steps, second order in the step length.

Units: SI; temperatures in degrees Celsius at the interface of these functions.
"""

import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import brentq
from scipy.spatial import cKDTree


R_GAS = 8.314462618        # J/(mol K)
M_WATER = 0.018015         # kg/mol
M_AIR = 0.028965           # kg/mol
KELVIN = 273.15
P_ATM = 101325.0           # Pa

# --------------------------------------------------------------------- air and water


def saturation_pressure(t_c):
    """Saturation vapour pressure of water (Pa) at ``t_c`` (deg C), over water: the Arden
    Buck equation with Buck's 1996 coefficients (Buck Research CR-1A manual), a revision of
    Buck (1981), J. Appl. Meteorol. 20, 1527. Against the IAPWS-95 values (Wagner and
    Pruss 2002, J. Phys. Chem. Ref. Data 31, 387) it is within 0.05 % from 0 to 70 C and
    0.11 % low at 100 C."""
    t_c = np.asarray(t_c, float)
    return 611.21 * np.exp((18.678 - t_c / 234.5) * (t_c / (257.14 + t_c)))


def vapour_density(p_v, t_c):
    """Water vapour density (kg/m^3) of partial pressure ``p_v`` (Pa) at ``t_c`` (ideal gas)."""
    return p_v * M_WATER / (R_GAS * (np.asarray(t_c, float) + KELVIN))


def latent_heat(t_c):
    """Latent heat of vaporisation of water (J/kg), linear fit 0-100 C (2501 kJ/kg at 0 C,
    2257 kJ/kg at 100 C; Rogers and Yau 1989, A Short Course in Cloud Physics)."""
    return 2.501e6 - 2.44e3 * np.asarray(t_c, float)


def air_properties(t_c, pressure=P_ATM):
    """Dry-air properties at ``t_c`` (deg C), a dict: density, viscosity (Sutherland),
    kinematic viscosity, heat capacity, conductivity, diffusivity of water vapour in air
    (Marrero and Mason 1972, J. Phys. Chem. Ref. Data 1, 3: D = 1.87e-10 T^2.072 / p[atm]
    m^2/s, 280-450 K), Prandtl and Schmidt numbers."""
    t = t_c + KELVIN
    rho = pressure * M_AIR / (R_GAS * t)
    mu = 1.716e-5 * (t / 273.15) ** 1.5 * (273.15 + 110.4) / (t + 110.4)
    cp = 1007.0
    k = 0.0241 * (t / 273.15) ** 0.81   # fit to tabulated air conductivity, 0-100 C (+-1 %)
    dva = 1.87e-10 * t ** 2.072 / (pressure / P_ATM)
    nu = mu / rho
    return dict(rho=rho, mu=mu, nu=nu, cp=cp, k=k, D_va=dva, Pr=mu * cp / k, Sc=nu / dva)


def sherwood_flat_plate(reynolds, schmidt):
    """Mean Sherwood number of a flat plate in parallel flow (Incropera, DeWitt, Bergman and
    Lavine 2007, Fundamentals of Heat and Mass Transfer, 6th ed., eqs 7.34 and 7.41 by the
    heat-mass analogy): laminar 0.664 Re^1/2 Sc^1/3 below Re = 5e5, mixed above."""
    re = np.asarray(reynolds, float)
    lam = 0.664 * np.sqrt(re) * schmidt ** (1 / 3)
    mixed = (0.037 * re ** 0.8 - 871.0) * schmidt ** (1 / 3)
    return np.where(re < 5e5, lam, mixed)


#: the Reynolds numbers the flat-plate Sherwood correlations hold for: a boundary layer
#: needs Re >> 1, the mixed correlation ends at 1e8 (fix cgms/transport's RE_MIN, RE_MAX)
REYNOLDS = (1.0, 1e8)


def reynolds(t_c, velocity, length, pressure=P_ATM):
    """Reynolds number of air at ``t_c`` (C) and ``velocity`` (m/s) over ``length`` (m)."""
    return velocity * length / air_properties(t_c, pressure)["nu"]


def air_coefficients(t_c, velocity, length, pressure=P_ATM):
    """Convective mass- and heat-transfer coefficients of a slice of flow length ``length``
    (m) in air at ``t_c`` and ``velocity`` (m/s): (k_c m/s, h W/(m^2 K)). The heat
    coefficient follows from k_c by the Chilton-Colburn analogy, h = k_c rho c_p Le^(2/3)
    (Incropera et al. 2007, eq. 6.92)."""
    air = air_properties(t_c, pressure)
    re = reynolds(t_c, velocity, length, pressure)
    kc = float(sherwood_flat_plate(re, air["Sc"])) * air["D_va"] / length
    lewis = air["Sc"] / air["Pr"]
    return kc, kc * air["rho"] * air["cp"] * lewis ** (2 / 3)


# ------------------------------------------------------------------------- material


def gab_moisture(aw, xm, c, k):
    """Equilibrium dry-basis moisture of the GAB isotherm at water activity ``aw``."""
    aw = np.asarray(aw, float)
    return xm * c * k * aw / ((1 - k * aw) * (1 - k * aw + c * k * aw))


def gab_activity(x, xm, c, k):
    """Water activity and its derivative d aw / dX at dry-basis moisture ``x`` (the GAB
    isotherm inverted: a quadratic in y = K aw). Above the moisture of aw = 1 the water is
    free: aw = 1, derivative 0."""
    x = np.maximum(np.asarray(x, float), 1e-12)
    # x (c - 1) y^2 - (x (c - 2) - xm c) y - x = 0, the root in (0, 1/k]
    a = x * (c - 1)
    b = -(x * (c - 2) - xm * c)
    disc = np.sqrt(b * b + 4 * a * x)
    y = np.where(np.abs(a) > 1e-300, (-b + disc) / (2 * np.where(a == 0, 1, a)), x / np.where(b == 0, 1, b))
    aw = y / k
    # dX/daw of the GAB form, for the derivative
    u = 1 - k * aw
    w = 1 - k * aw + c * k * aw
    dxda = xm * c * k * (u * w + aw * k * w - aw * u * k * (c - 1)) / (u * w) ** 2
    free = aw >= 1.0
    return np.where(free, 1.0, aw), np.where(free, 0.0, 1.0 / dxda)


def diffusivity(x, t_c, d_ref, t_ref_c, energy, b=0.0, x0=1.0):
    """Effective moisture diffusivity (m^2/s): Arrhenius in temperature about ``t_ref_c``
    with activation ``energy`` (J/mol), times exp(b (X/X0 - 1)) for its moisture
    dependence (b = 0: constant, as the slope-method fits of the literature report it)."""
    arrhenius = math.exp(-energy / R_GAS * (1 / (t_c + KELVIN) - 1 / (t_ref_c + KELVIN)))
    return d_ref * arrhenius * np.exp(b * (np.asarray(x, float) / x0 - 1))


# ------------------------------------------------------------------------- geometry


#: a bead whose widest angular gap between neighbours exceeds this is on the outline: on a
#: hexagonal lattice an interior bead's gaps are 60 deg, a concave corner's open gap 120,
#: a straight edge's 180 and a convex corner's 240; 100 deg lies between 60 and 120 with
#: 40 deg to spare for the shear of a shrunken tissue on the side of the interior gaps,
#: which are the many
OPEN_GAP = math.radians(100.0)
#: passes of the [1, 2, 1] / 4 smoothing along the outline: 8 passes are a Gaussian of
#: 2 beads (variance 8 / 2)
OUTLINE_PASSES = 8


def outline_edge(xy, pairs, spacing, passes=OUTLINE_PASSES, offset=True):
    """Length of the tissue outline each bead exposes to air (m), found from every bead's
    own neighbours (the construction ``fix cgms/transport`` makes in LAMMPS, one to one):

    - the neighbours of a bead sorted by angle; the widest gap between two successive
      ones, if wider than :data:`OPEN_GAP`, is open to air. Its two bounding neighbours
      are the bead's neighbours along the outline polygon (on a lattice they are those of
      :func:`cgms.morphology.outline`); half of each of the two edges is its share;
    - the polygon smoothed ``passes`` times, each vertex to (prev + 2 self + next) / 4:
      the staircase of a lattice outline is 10 % longer than the curve it follows, and
      stays so however small the beads (measured on discs, doc/drying.md);
    - offset outwards by half a spacing: each bead adds a/2 times the turning angle of
      the smoothed polygon at it (pi a over a closed outline).

    ``passes`` = 0 and ``offset`` False give the shares of the plain polygon. A bead the
    outline passes twice (a bridge one bead wide) counts its widest gap only."""
    xy = np.asarray(xy, float)
    n = len(xy)
    i = np.concatenate([pairs[:, 0], pairs[:, 1]])
    j = np.concatenate([pairs[:, 1], pairs[:, 0]])
    d = xy[j] - xy[i]
    angle = np.arctan2(d[:, 1], d[:, 0])
    order = np.lexsort((angle, i))
    i, j, angle = i[order], j[order], angle[order]
    start = np.searchsorted(i, np.arange(n))
    count = np.bincount(i, minlength=n)
    # the gap from each neighbour to the next one counter-clockwise (the last wraps)
    following = np.arange(len(i)) + 1
    last = start + count - 1
    following[last] = start
    gap = angle[following] - angle
    gap[last] += 2 * np.pi
    widest = np.full(n, -1.0)
    np.maximum.at(widest, i, gap)
    at = np.nonzero(gap == widest[i])[0]
    at = at[np.unique(i[at], return_index=True)[1]]          # the first widest per bead
    sel = widest[i[at]] > OPEN_GAP
    ring = i[at][sel]
    prev = np.full(n, -1)
    nxt = np.full(n, -1)
    # walking the outline counter-clockwise (tissue on the left, air on the right), the
    # neighbour where the open gap starts (counter-clockwise) comes before the bead, the
    # one where it ends after it
    prev[ring] = j[at[sel]]
    nxt[ring] = j[following[at[sel]]]
    shift = np.zeros_like(xy)
    for _ in range(passes):
        p = xy + shift
        new = np.zeros_like(xy)
        new[ring] = 0.25 * (p[prev[ring]] + 2 * p[ring] + p[nxt[ring]]) - xy[ring]
        shift = new
    p = xy + shift
    back = p[ring] - p[prev[ring]]
    ahead = p[nxt[ring]] - p[ring]
    cross = back[:, 0] * ahead[:, 1] - back[:, 1] * ahead[:, 0]
    dot = np.sum(back * ahead, axis=1)
    # the tip of a one-bead chain turns back: +pi (the outline goes round it)
    turn = np.where((cross == 0) & (dot < 0), np.pi, np.arctan2(cross, dot))
    edge = np.zeros(n)
    edge[ring] = 0.5 * (np.hypot(*back.T) + np.hypot(*ahead.T))
    if offset:
        edge[ring] += 0.5 * np.asarray(spacing)[ring] * turn
    return np.maximum(edge, 0.0)     # a sharp concave corner cannot take in air


def bead_geometry(xy, cutoff):
    """In-plane finite-volume geometry of the beads at positions ``xy`` (n, 2), as a dict:

    - ``pairs`` (m, 2): neighbours (centre distance below ``cutoff``), ``dist`` their
      distance (the path length), ``face`` the length of the face they share: a bead
      owns the hexagonal Voronoi cell of its lattice, whose face is dist / sqrt(3);
    - ``area`` (n,): (sqrt 3 / 2) a^2, a the bead's mean neighbour distance;
    - ``edge`` (n,): length of the tissue outline a bead exposes to air
      (:func:`outline_edge`);
    - ``spacing`` (n,): the mean neighbour distance a."""
    xy = np.asarray(xy, float)
    n = len(xy)
    pairs = cKDTree(xy).query_pairs(cutoff, output_type="ndarray")
    dist = np.linalg.norm(xy[pairs[:, 0]] - xy[pairs[:, 1]], axis=1)
    count = np.bincount(pairs.ravel(), minlength=n)
    if np.any(count == 0):
        raise ValueError(f"{np.sum(count == 0)} bead(s) have no neighbour within the cutoff "
                         f"{cutoff:.4g} m: moisture cannot move in or out of them")
    total = np.bincount(pairs[:, 0], dist, n) + np.bincount(pairs[:, 1], dist, n)
    a = total / count
    area = 0.5 * math.sqrt(3) * a * a
    return dict(pairs=pairs, dist=dist, face=dist / math.sqrt(3), area=area,
                edge=outline_edge(xy, pairs, a), spacing=a)


# ------------------------------------------------------------------------- the grid


def column_grid(geometry, thickness, solids, layers, faces=2):
    """Nodes of the thickness sub-model. ``thickness`` (n,) of every bead's column (m),
    ``solids`` (n,) its dry solid mass (kg, whole column), ``layers`` nodes across the
    modelled depth. ``faces`` = 2: both slice faces in air, the mid-plane is a symmetry
    plane and only half the column is modelled (``multiplicity`` 2); 1: one face in air,
    the other sealed; 0: no face exchange. Node index = bead * layers + layer; layer 0
    touches the face."""
    if faces not in (0, 1, 2):
        raise ValueError(f"faces must be 0, 1 or 2, got {faces}")
    if layers < 1:
        raise ValueError(f"layers must be at least 1, got {layers}")
    mult = 2 if faces == 2 else 1
    depth = np.asarray(thickness, float) / mult
    return dict(geometry=geometry, layers=layers, faces=faces, multiplicity=mult,
                dz=depth / layers, solids=np.repeat(np.asarray(solids, float) / mult / layers,
                                                    layers),
                solid_density=np.asarray(solids, float) / (geometry["area"] * thickness))


def _series(g, alpha):
    """Share of the surface law that reaches a node through a half-cell conductance ``g``
    (per unit area): the surface value eliminated from N = alpha X_s + beta and
    N = g (X - X_s)."""
    return g / (g + alpha)


def surface_nodes(grid, d, outline=True):
    """The nodes that exchange with air: a list of (node indices, surface area m^2, half-cell
    conductance per unit area kg/(m^2 s) per unit X, on a slice face?), first the faces
    (layer 0 of every column), then the outline (every layer of the outline beads)."""
    geo, nl = grid["geometry"], grid["layers"]
    n = len(geo["area"])
    rho_s, dz = grid["solid_density"], grid["dz"]
    parts = []
    if grid["faces"]:
        top = np.arange(n) * nl
        parts.append((top, geo["area"], d[top] * rho_s / (0.5 * dz), True))
    if outline:
        beads = np.nonzero(geo["edge"] > 0)[0]
        for j in range(nl):
            idx = beads * nl + j
            parts.append((idx, geo["edge"][beads] * dz[beads],
                          d[idx] * rho_s[beads] / (0.5 * geo["spacing"][beads]), False))
    return parts


def step(grid, x, dt, diff, surface, outline=True):
    """One linearised backward Euler step of length ``dt`` (s) from node moisture ``x``
    (first order in ``dt``; :func:`extrapolated_step` combines three).

    ``diff(x)``: diffusivity at node moisture (m^2/s). ``surface(x)``: the surface law
    linearised at node moisture, (alpha, beta) per unit area, N = alpha X + beta (kg/m^2/s).
    ``outline``: exchange through the tissue outline too. Returns (new x, water out through
    the faces, water out through the outline), both in kg of the whole column, and a
    dict of per-node face fluxes for reports."""
    geo, nl = grid["geometry"], grid["layers"]
    n = len(geo["area"])
    rho_s = grid["solid_density"]
    dz = grid["dz"]
    d = diff(x)
    rows, cols, vals = [], [], []

    def couple(i, j, g):
        rows.extend([i, j, i, j])
        cols.extend([i, j, j, i])
        vals.extend([g, g, -g, -g])

    layer = np.arange(nl)
    # in-plane: the same layer of two neighbouring beads
    p, q = geo["pairs"][:, 0], geo["pairs"][:, 1]
    for j in layer:
        ip, iq = p * nl + j, q * nl + j
        dm = 0.5 * (d[ip] + d[iq])
        g = dm * 0.5 * (rho_s[p] + rho_s[q]) * geo["face"] * 0.5 * (dz[p] + dz[q]) / geo["dist"]
        couple(ip, iq, g)
    # across the thickness: layers j and j+1 of a column
    for j in layer[:-1]:
        beads = np.arange(n)
        ia, ib = beads * nl + j, beads * nl + j + 1
        g = 0.5 * (d[ia] + d[ib]) * rho_s * geo["area"] / dz
        couple(ia, ib, g)
    lap = sp.csr_matrix((np.concatenate([np.atleast_1d(v) for v in vals]),
                         (np.concatenate([np.atleast_1d(r) for r in rows]),
                          np.concatenate([np.atleast_1d(c) for c in cols]))),
                        shape=(n * nl, n * nl))
    alpha, beta = surface(x)
    # surface terms: flow = c1 x + c0 per node (kg/s)
    c1 = np.zeros(n * nl)
    c0 = np.zeros(n * nl)
    c1_face = np.zeros(n * nl)
    c0_face = np.zeros(n * nl)
    for idx, area, g, on_face in surface_nodes(grid, d, outline):
        share = _series(g, alpha[idx]) * area
        np.add.at(c1, idx, share * alpha[idx])
        np.add.at(c0, idx, share * beta[idx])
        if on_face:
            c1_face[idx] += share * alpha[idx]
            c0_face[idx] += share * beta[idx]
    mass = grid["solids"]
    matrix = (sp.diags(mass / dt + c1) + lap).tocsr()
    x_new = solve(matrix, mass / dt * x - c0, nl)
    flow = c1 * x_new + c0
    flow_face = c1_face * x_new + c0_face
    mult = grid["multiplicity"]
    out_face = mult * dt * flow_face.sum()
    out_edge = mult * dt * (flow.sum() - flow_face.sum())
    return x_new, out_face, out_edge, dict(face_flux=flow_face)


def extrapolated_step(grid, x, dt, coefficients, outline=True):
    """One moisture step of length ``dt`` (s) from node moisture ``x``, second order in
    ``dt``: the Richardson extrapolation of :func:`step`, twice the result of two steps of
    ``dt/2`` minus that of one of ``dt``. Each Euler step is first order with an error
    expansion in its length, so the combination cancels the first-order term; its
    amplification of a decaying mode, 2/(1 + z/2)^2 - 1/(1 + z) (z = rate times dt), goes
    to 0 as z grows (L-stable) and is never below -0.04. The water out is combined alike,
    so the balance closes as each Euler step's does.

    ``coefficients(x)`` gives (diff, surface) of :func:`step` at node moisture ``x`` (the
    product temperature solved there): at ``x`` for the whole step and the first half,
    at the midpoint for the second. Returns (new x, water out through the faces, through
    the outline, the midpoint x) (kg; ``fix cgms/transport`` move)."""
    diff, law = coefficients(x)
    whole, face_w, edge_w, _ = step(grid, x, dt, diff, law, outline)
    mid, face_1, edge_1, _ = step(grid, x, 0.5 * dt, diff, law, outline)
    diff, law = coefficients(mid)
    end, face_2, edge_2, _ = step(grid, mid, 0.5 * dt, diff, law, outline)
    return (2 * end - whole, 2 * (face_1 + face_2) - face_w, 2 * (edge_1 + edge_2) - edge_w,
            mid)


def _columns(matrix, layers):
    """A solver of the column blocks of ``matrix`` (the couplings within each bead's
    column: one symmetric tridiagonal matrix per bead), by the Thomas algorithm on all
    columns at once."""
    n = matrix.shape[0] // layers
    diag = matrix.diagonal().reshape(n, layers)
    off = matrix.diagonal(1)[np.arange(n * layers - 1) % layers != layers - 1] \
        .reshape(n, layers - 1) if layers > 1 else np.zeros((n, 0))
    piv = np.empty_like(diag)        # LDL^T: pivots and multipliers
    mul = np.empty_like(off)
    piv[:, 0] = diag[:, 0]
    for j in range(1, layers):
        mul[:, j - 1] = off[:, j - 1] / piv[:, j - 1]
        piv[:, j] = diag[:, j] - mul[:, j - 1] * off[:, j - 1]

    def apply(rhs):
        y = np.array(rhs, float).reshape(n, layers)
        for j in range(1, layers):
            y[:, j] -= mul[:, j - 1] * y[:, j - 1]
        y /= piv
        for j in range(layers - 2, -1, -1):
            y[:, j] -= mul[:, j] * y[:, j + 1]
        return y.ravel()
    return apply


def solve(matrix, rhs, layers, rtol=1e-14):
    """Solve the symmetric positive definite system of :func:`step`: conjugate gradients
    preconditioned by the columns (:func:`_columns`). A direct LU of the whole matrix
    fills in like a 3-D problem: on 248 beads x 40 layers it took 0.30 s, this 0.03 s, to
    the same answer (1e-14). Falls back to the direct solve if CG does not converge."""
    columns = _columns(matrix, layers)
    pre = spla.LinearOperator(matrix.shape, columns)
    x, info = spla.cg(matrix, rhs, x0=columns(rhs), M=pre, tol=rtol, atol=0.0, maxiter=2000)
    if info != 0:
        x = spla.splu(matrix.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                      options=dict(SymmetricMode=True)).solve(rhs)
    return x


def water(grid, x):
    """Water in the tissue (kg), whole columns."""
    return grid["multiplicity"] * float(grid["solids"] @ x)


def bead_moisture(grid, x):
    """Column-mean dry-basis moisture of every bead, and its surface (layer 0) and core
    (last layer) values."""
    nl = grid["layers"]
    cols = x.reshape(-1, nl)
    return cols.mean(axis=1), cols[:, 0], cols[:, -1]


# --------------------------------------------------------------------- surface laws


def linear_surface(h_x, x_eq=0.0):
    """Surface law N = h_x (X - x_eq) (kg/m^2/s, h_x per unit X): Crank's convective
    boundary condition, -D rho_s dX/dn = h rho_s (X - X_eq), with h_x = h rho_s."""
    def law(x):
        return np.full_like(x, h_x), np.full_like(x, -h_x * x_eq)
    return law


def vapour_surface(kc, t_product, t_air, humidity, gab):
    """Surface law N = k_c (aw(X) rho_sat(T_p) - RH rho_sat(T_air)), linearised in X at the
    node moisture; ``gab`` = (Xm, C, K)."""
    rho_sat_p = float(vapour_density(saturation_pressure(t_product), t_product))
    rho_air = float(humidity * vapour_density(saturation_pressure(t_air), t_air))

    def law(x):
        aw, slope = gab_activity(x, *gab)
        alpha = kc * rho_sat_p * slope
        beta = kc * (rho_sat_p * (aw - slope * x) - rho_air)
        return alpha, beta
    return law


#: the coldest product temperature (deg C) :func:`product_temperature` looks for: the
#: saturation pressure is over liquid water, and the model has no freezing
T_PRODUCT_MIN = -20.0


def product_temperature(kc, h, t_air, humidity, gab, grid, x, diffusivity, outline=True):
    """Quasi-steady product temperature (deg C): the heat the air brings to every surface
    that exchanges with it, h (T_air - T_p), equals the heat of the water that evaporates
    there at T_p, the surface law of :func:`vapour_surface` through the same half-cell
    resistance as in :func:`step`, at node moisture ``x``, with the diffusivity
    ``diffusivity(x, T_p)`` (m^2/s per node) at T_p itself: so T_p is a function of the
    moisture alone, as the second order of :func:`extrapolated_step` needs (D taken at
    the last step's T_p instead lagged a step behind: 2.7 % off in X/X0 at the default
    steps of the 248-bead window, doc/results/drying.md). A thin slice follows it within
    minutes (its time constant rho c_p L / 2h is about 2 min for 2 mm), so its heat
    capacity is left out. Returns T_air when nothing evaporates."""
    # the half-cell conductances per unit D: surface_nodes's with D = 1
    parts = surface_nodes(grid, np.ones_like(x), outline)
    if not parts:
        return float(t_air)
    idx = np.concatenate([p[0] for p in parts])
    area = np.concatenate([p[1] for p in parts])
    g1 = np.concatenate([p[2] for p in parts])
    xs = x[idx]

    def balance(tp):
        g = g1 * diffusivity(xs, tp)
        alpha, beta = vapour_surface(kc, tp, t_air, humidity, gab)(xs)
        evap = np.sum(area * _series(g, alpha) * (alpha * xs + beta))
        return h * (t_air - tp) * area.sum() - latent_heat(tp) * evap

    if balance(t_air) >= 0:
        return float(t_air)
    if balance(T_PRODUCT_MIN) < 0:
        raise ValueError(f"air at {t_air:g} C and RH {humidity:g} would cool the wet product "
                         f"below {T_PRODUCT_MIN:g} C by evaporation, and the model has no "
                         "freezing: warmer or more humid air")
    return float(brentq(balance, T_PRODUCT_MIN, t_air, xtol=1e-6))
