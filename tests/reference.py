# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""An independent NumPy implementation of doc/model.md, written from the
specification (not from the plugin's source), for comparison with the plugin.

All pairs are handled as dense (n, n) arrays: clear rather than fast, for the
tens to hundreds of beads the tests use."""

import numpy as np

SQRT3 = np.sqrt(3.0)


def lj_radius(s, mat):
    """r = r0 (1 + lj_slope ln s_ik) for every pair, s_ik the mean dryness (doc/model.md)."""
    s_ik = 0.5 * (s[:, None] + s[None, :])
    return mat["r0"] * (1.0 + mat["lj_slope"] * np.log(s_ik))


def shape_stiffness(s, mat):
    """k_S,i = max(k_S s_i^n, k_S_floor) per bead (n = k_S_exponent, 0 when absent: k_S
    at every s; k_S_floor 0 when absent: no floor)."""
    power = mat.get("k_S", 0.0) * np.asarray(s, float) ** mat.get("k_S_exponent", 0.0)
    return np.maximum(power, mat.get("k_S_floor", 0.0))


def shape_energy(xy, s, mat, cutoff):
    """sum_i k_S,i/2 sum_k (x_ik - xbar_i)^2 over the neighbours k of each bead i."""
    _, dist, adj = pair_geometry(xy, s, mat, cutoff)
    xbar = np.where(adj, dist, 0.0).sum(axis=1) / np.maximum(adj.sum(axis=1), 1)
    spread2 = np.where(adj, dist - xbar[:, None], 0.0) ** 2
    return 0.5 * np.sum(shape_stiffness(s, mat) * spread2.sum(axis=1))


def quasistatic_energy(xy, s, l0p, mat, cutoff):
    """The potential of the quasi-static problem without the LJ part (doc/fix_cgms_fluid.rst,
    the fix's scalar under balance): sum_i [-k_T/2 (P_i - P_f) sum_k x_ik + k_PA (l_i -
    l_d,i)^2 / (4 g_i)] with P_i = -Pi_i = s_i |Pi_f| and g_i = dl_i/dx_ik = (N_i + beta(s_i)
    max(0, 6 - N_i)) / (sqrt(3) N_i), plus the cell-shape energy; l_d,i from the turgid
    perimeter ``l0p`` (the geometry does not depend on the fluid mass)."""
    _, dist, adj = pair_geometry(xy, s, mat, cutoff)
    geo = fluid_state(xy, s, np.ones_like(s), l0p, mat, cutoff)
    n = geo["nneigh"]
    beta = mat["beta_a"] + mat["beta_b"] * np.log(s)
    g = (n + beta * np.maximum(0.0, 6.0 - n)) / (SQRT3 * n)
    press = -s * mat["Pi_f"]
    sum_x = np.where(adj, dist, 0.0).sum(axis=1)
    return (np.sum(-0.5 * mat["k_T"] * (press - mat["P_f"]) * sum_x
                   + mat["k_PA"] * (geo["perim"] - geo["ldeq"]) ** 2 / (4 * g))
            + shape_energy(xy, s, mat, cutoff))


def pair_geometry(xy, s, mat, cutoff):
    """Displacements d[i, k] = x_i - x_k, distances and the neighbour mask.
    ``cutoff`` is ("lj", factor): factor times the pair's LJ radius (the plugin's
    default), or ("fixed", metres)."""
    d = xy[:, None, :] - xy[None, :, :]
    dist = np.sqrt((d**2).sum(-1))
    kind, value = cutoff
    adj = dist < (value * lj_radius(s, mat) if kind == "lj" else value)
    np.fill_diagonal(adj, False)
    return d, dist, adj


def fluid_state(xy, s, mf, l0p, mat, cutoff, periphery=True, turgor=True, perimeter=True,
                transfer=True, implicit_dt=None):
    """Per-bead geometry (eqns 10, 11), density, pressure (eqn 4, reference state of
    doc/model.md), equilibrium perimeter (eqn 9), dm/dt (eqn 7) and the scalar c_i with
    F_T + F_PA = (c_i + c_k) n.

    With ``implicit_dt`` the rate is the one a linearised backward Euler step of length
    implicit_dt applies: eqn (7) divided by 1 + dt lambda, lambda = -d(dm/dt)/dm at fixed
    geometry (derived here by differentiating eqns (4) and (7) in m through rho = m/(hA)),
    where lambda > 0."""
    _, dist, adj = pair_geometry(xy, s, mat, cutoff)
    n = adj.sum(axis=1).astype(float)
    b_int = (np.where(adj, dist - mat["pectin"], 0.0)).sum(axis=1) / (SQRT3 * n)
    beta = mat["beta_a"] + mat["beta_b"] * np.log(s) if periphery else np.ones_like(s)
    b = b_int / 6.0 * (n + beta * np.maximum(0.0, 6.0 - n))
    area = 1.5 * SQRT3 * b**2
    perim = 6.0 * b
    rho = mf / (mat["height"] * area)
    press = s * mat["P_f"] + mat["K"] * ((rho / (s * mat["rho0"])) ** 7 - 1.0)
    ldeq = l0p * (1.0 - mat["perim_a"] / mat["perim_b"] * (1.0 - s))
    dmdt = -perim * mat["height"] * mat["L_p"] * rho * (press + s * mat["Pi_f"])
    if implicit_dt is not None:
        # d/dm of -l h L_p rho (P + Pi) with d rho/dm = rho/m, dP/drho = 7 K q^6 / rho_ref
        q = rho / (s * mat["rho0"])
        drate_dm = -perim * mat["height"] * mat["L_p"] * (rho / mf) * (
            press + s * mat["Pi_f"] + 7 * mat["K"] * q**7)
        dmdt = dmdt / (1 + implicit_dt * np.maximum(-drate_dm, 0.0))
    if not transfer:
        dmdt = np.zeros_like(dmdt)
    c = 0.5 * (turgor * mat["k_T"] * (press - mat["P_f"]) - perimeter * mat["k_PA"] * (perim - ldeq))
    return dict(nneigh=n, side=b, area=area, perim=perim, rho=rho, pressure=press, ldeq=ldeq,
                dmdt=dmdt, cgmscoef=c)


def pair_forces(xy, v, s, c, mat, cutoff, turgor=True, perimeter=True, damping=True,
                repulsion=True, attraction=True):
    """Forces on every bead (eqns 3, 8, 12-15), the LJ energy and the virial tensor
    W_ab = sum over pairs of d_a F_b (F on i from k).

    With ``mat["k_S"]`` > 0, also the cell-shape force (an extension, not in the paper):
    minus the gradient of sum_i k_S,i/2 sum_k (x_ik - xbar_i)^2, xbar_i the mean distance
    of bead i to its neighbours and k_S,i = max(k_S s_i^n, k_S_floor) (n =
    ``mat["k_S_exponent"]``, default 0). Differentiated here term by term: d/dx_ik of bead
    i's term is
    k_S,i [(x_ik - xbar_i) - (1/N_i) sum_m (x_im - xbar_i)] = k_S,i (x_ik - xbar_i), and
    x_ik also enters bead k's term, so the pair (i, k) gets
    -[k_S,i (x_ik - xbar_i) + k_S,k (x_ik - xbar_k)] n."""
    d, dist, adj = pair_geometry(xy, s, mat, cutoff)
    safe = np.where(adj, dist, 1.0)
    nvec = d / safe[:, :, None]
    F = np.zeros_like(d)
    if turgor or perimeter:
        F += (c[:, None] + c[None, :])[:, :, None] * nvec
    if mat.get("k_S", 0.0) > 0.0:
        xbar = np.where(adj, dist, 0.0).sum(axis=1) / np.maximum(adj.sum(axis=1), 1)
        k_s = shape_stiffness(s, mat)
        spread_i = k_s[:, None] * (dist - xbar[:, None])   # bead i's term, d/dx_ik
        F += -(spread_i + spread_i.T)[:, :, None] * nvec
    r = lj_radius(s, mat)
    q = r / safe
    lj = (q**8 - q**4) / safe**2
    inside = dist <= r
    energy = np.zeros_like(dist)
    if repulsion:
        F += np.where(inside, mat["f0_r"] * lj, 0.0)[:, :, None] * d
        energy += np.where(inside, mat["f0_r"] * (q**8 / 8 - q**4 / 4 + 1 / 8), 0.0)
    if attraction:
        F += np.where(~inside, mat["f0_a"] * lj, 0.0)[:, :, None] * d
        energy += np.where(~inside, mat["f0_a"] * (q**8 / 8 - q**4 / 4), -mat["f0_a"] / 8)
    if damping:
        F += -mat["k_d"] * (v[:, None, :] - v[None, :, :])
    F = np.where(adj[:, :, None], F, 0.0)
    energy = np.where(adj, energy, 0.0)
    virial = 0.5 * np.einsum("ika,ikb->ab", d, F)
    return F.sum(axis=1), 0.5 * energy.sum(), virial
