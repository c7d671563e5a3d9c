# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The model's formulas, written once (doc/model.md): the reference cell, the periphery
factor beta(s), the virtual-cell geometry, the Tait law, the mass transfer, the pair
coefficient and the quasi-static energy, the steady state of a bead (perimeter, spacing,
density, moisture) and the time-step limits of the damping and the cell-shape stiffness.
The plugin's twin is ``src/CGMS/cgms_laws.h``; ``tests/plugin/test_laws.py`` holds the two equal.

Every function takes a material dict (:func:`cgms.material.read`) and plain numbers or
NumPy arrays. ``tests/reference.py`` repeats the force and update formulas on purpose, as
an independent oracle; everything else in the package and the tests uses this module."""

import math

import numpy as np


def reference_cell(diameter, pectin):
    """The reference cell of a bead of cell ``diameter`` (doc/model.md): the regular hexagon
    of the cell's area ``A_ref`` (side ``b_ref``, perimeter ``l_ref``) and the lattice
    spacing ``x_ref`` = sqrt(3) b_ref + pectin. Works on arrays of diameters."""
    area = np.pi * np.asarray(diameter, float) ** 2 / 4
    side = np.sqrt(2 * area / (3 * math.sqrt(3)))
    return dict(A_ref=area, b_ref=side, l_ref=6 * side, x_ref=math.sqrt(3) * side + pectin)


def beta(mat, s):
    """Periphery factor beta(s) = beta_a + beta_b ln s."""
    return mat["beta_a"] + mat["beta_b"] * np.log(s)


def sides(nneigh, beta_s):
    """N + beta max(0, 6 - N): the virtual hexagon's perimeter in units of b_int (eqn 11)."""
    nn = np.asarray(nneigh, float)
    return nn + beta_s * np.maximum(0, 6 - nn)


def cell_side(nneigh, sum_r, beta_s, pectin, b_ref):
    """The side b of eqns (10)-(11) of a bead with ``nneigh`` neighbours at summed centre
    distance ``sum_r``: b_int = (sum_r - N d_p) / (sqrt(3) N), b = b_int / 6 (N + beta
    max(0, 6 - N)); ``b_ref`` for a bead without neighbours."""
    nn = np.asarray(nneigh, float)
    safe = np.where(nn > 0, nn, 1.0)
    b = (np.asarray(sum_r, float) - safe * pectin) / (math.sqrt(3) * safe) / 6 * sides(safe, beta_s)
    return np.where(nn > 0, b, b_ref)


def perimeter_gradient(nneigh, beta_s):
    """g_i = dl_i/dx_ik = (N + beta max(0, 6 - N)) / (sqrt(3) N) (doc/model.md, Potential
    energy)."""
    return sides(nneigh, beta_s) / (math.sqrt(3) * np.asarray(nneigh, float))


def tait_pressure(q, P_ref, K):
    """The Tait law P = P_ref + K (q^7 - 1), q the density over its reference (eqn 4)."""
    return P_ref + K * (np.asarray(q, float) ** 7 - 1)


def tait_density(P, P_ref, K, rho_ref):
    """The density of pressure ``P`` in the Tait law: rho_ref (1 + (P - P_ref) / K)^(1/7)."""
    return rho_ref * (1 + (np.asarray(P, float) - P_ref) / K) ** (1 / 7)


def mass_rate(perimeter, height, L_p, rho, P, Pi):
    """Eqn (7): dm_f/dt = -l h L_p rho (P + Pi), membrane area l h."""
    return -perimeter * height * L_p * rho * (P + Pi)


def transfer_rate(L_p, perimeter, area, P, Pi, K, q):
    """lambda = -d(dm_f/dt)/dm_f = L_p (l / A) (P + Pi + 7 K q^7) of the linearised backward
    Euler step of the mass transfer (doc/model.md, Fluid phase)."""
    return L_p * perimeter / area * (P + Pi + 7 * K * np.asarray(q, float) ** 7)


def pair_coefficient(k_T, k_PA, P_f, P, perimeter, l_d):
    """c_i = (k_T (P - P_f) - k_PA (l - l_d)) / 2, the turgor and perimeter forces' per-bead
    coefficient (eqns 3, 8)."""
    return 0.5 * (k_T * (P - P_f) - k_PA * (perimeter - l_d))


def quasi_static_energy(k_T, k_PA, P_f, P, sum_r, perimeter, l_d, g):
    """A bead's potential with its pressure held (doc/model.md, Potential energy):
    -k_T/2 (P - P_f) sum_k x_ik + k_PA (l - l_d)^2 / (4 g)."""
    return -0.5 * k_T * (P - P_f) * sum_r + k_PA * (perimeter - l_d) ** 2 / (4 * g)


def shape_stiffness(mat, s):
    """k_S(s) = max(k_S s^n, k_S_floor), exactly k_S when n = 0 (doc/model.md, Shear and the
    cell-shape stiffness)."""
    n = mat.get("k_S_exponent", 0.0)
    if n == 0:
        return mat["k_S"] + 0 * np.asarray(s, float)
    return np.maximum(mat["k_S"] * np.asarray(s, float) ** n, mat.get("k_S_floor", 0.0))


def turgor_omega2(k_T, K, q, mass, sum_gap):
    """omega^2 = 56 k_T K q^7 / (m sum_k (x_ik - d_p)) of the turgor-density coupling."""
    return 56 * k_T * K * np.asarray(q, float) ** 7 / (mass * sum_gap)


#: pair_style cgms's default cutoff/lj (src/CGMS/pair_cgms.cpp, CUTOFF_FACTOR): a pair's
#: cutoff is this times its LJ radius
CUTOFF_LJ = 1.35


def lj_radius(mat, s):
    """LJ radius r(s) = r0 (1 + lj_slope ln s) of a pair of mean dryness ``s``."""
    return mat["r0"] * (1 + mat["lj_slope"] * np.log(s))


def hexagon_area(perimeter):
    """Area of the regular hexagon of ``perimeter``."""
    return 1.5 * math.sqrt(3) * (np.asarray(perimeter, float) / 6) ** 2


def fresh_perimeter(mat, diameter=None):
    """l0' = turgid_ratio l_ref of a cell of ``diameter`` (default the material's)."""
    d = mat["diameter"] if diameter is None else diameter
    return mat["turgid_ratio"] * reference_cell(d, mat["pectin"])["l_ref"]


def perimeter_contraction(mat, s):
    """l_d / l0' = 1 - (a/b)(1 - s): the perimeter law (eqn 9) as a fraction of the fresh
    perimeter (the MFC scales its wall rest lengths by it too)."""
    return 1 - mat["perim_a"] / mat["perim_b"] * (1 - np.asarray(s, float))


def equilibrium_perimeter(mat, s, diameter=None):
    """l_d = l0' [1 - (a/b)(1 - s)], the perimeter that the moisture level prescribes
    (eqn 9)."""
    return fresh_perimeter(mat, diameter) * perimeter_contraction(mat, s)


def steady_perimeter(mat, s, diameter=None, k_T=None, k_PA=None):
    """A bead's perimeter at steady state: with P = -s Pi_f (mass balance, eqn 7) every
    bead's pair coefficient vanishes, so l* = l_d - (k_T / k_PA)(P_f + s Pi_f), whatever
    the shape of the tissue (doc/results/validation.md, hard cases). ``k_T``, ``k_PA`` replace the
    material's."""
    k_T = mat["k_T"] if k_T is None else k_T
    k_PA = mat["k_PA"] if k_PA is None else k_PA
    s = np.asarray(s, float)
    return equilibrium_perimeter(mat, s, diameter) - k_T / k_PA * (mat["P_f"] + s * mat["Pi_f"])


def steady_spacing(mat, s):
    """Centre distance of two inner beads (6 neighbours) of a uniform tissue at steady
    state at dryness ``s``: an inner bead's perimeter is l = 2 sqrt(3) (x - d_p)."""
    return float(steady_perimeter(mat, s)) / (2 * math.sqrt(3)) + mat["pectin"]


def balance_density(mat, s):
    """Fluid density at which the Tait pressure P = s P_f + K ((rho / (s rho0))^7 - 1)
    balances the osmotic potential: P = -s Pi_f."""
    s = np.asarray(s, float)
    return s * mat["rho0"] * (1 - s * (mat["Pi_f"] + mat["P_f"]) / mat["K"]) ** (1 / 7)


def steady_moisture(mat, s, diameter=None, **coefficients):
    """X/X0 of a tissue at steady state whose beads have dryness ``s`` (a number or one
    per bead) and cell ``diameter``: sum rho h A(l*) over sum of the fresh fluid masses."""
    d = mat["diameter"] if diameter is None else diameter
    s = np.broadcast_to(np.asarray(s, float), np.shape(d) or np.shape(s))
    mf = balance_density(mat, s) * mat["height"] * hexagon_area(
        steady_perimeter(mat, s, d, **coefficients))
    mf0 = mat["rho0"] * mat["height"] * reference_cell(np.broadcast_to(d, s.shape),
                                                       mat["pectin"])["A_ref"]
    return float(np.sum(mf) / np.sum(mf0))


def fresh_mass(mat, diameter=None):
    """The default inertial mass of a bead: fluid and solid mass of the fresh cell,
    (1 + solid_ratio) rho0 h A_ref."""
    d = mat["diameter"] if diameter is None else diameter
    area = reference_cell(d, mat["pectin"])["A_ref"]
    return (1 + mat["solid_ratio"]) * mat["rho0"] * mat["height"] * area


def damping_dt_limit(mass, nneigh, k_d):
    """Stability limit of the relative-velocity damping: 2 m / (1.5 N k_d)."""
    return 2 * np.asarray(mass, float) / (1.5 * np.asarray(nneigh, float) * k_d)


def shape_dt_limit(mass, nneigh, k_S):
    """Stability limit of the cell-shape stiffness k_S (about 2 k_S per pair):
    sqrt(m / (2 k_S N))."""
    return np.sqrt(np.asarray(mass, float) / (2 * k_S * np.asarray(nneigh, float)))


def turgor_dt_limit(mat, mass, nneigh, side, rho, s):
    """Stability limit 2 / omega of the turgor-density coupling (doc/fix_cgms_fluid.rst):
    omega^2 = 56 k_T K (rho / (s rho0))^7 / (m sum_k x_ik), sum_k x_ik of a bead with N
    neighbours and cell side b."""
    nn = np.asarray(nneigh, float)
    sum_gap = math.sqrt(3) * nn * 6 * side / sides(nn, beta(mat, s))
    return 2 / np.sqrt(turgor_omega2(mat["k_T"], mat["K"], rho / (s * mat["rho0"]), mass,
                                     sum_gap))
