# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""An experiment beside cgms.shaped: the same cells, fluid and walls, but with free
junctions (a vertex model) instead of junctions slaved to the beads, to test whether
cells that can flatten inside an ordered tissue follow the MFC further. The cell's
position is its polygon's area centroid. L-BFGS with the analytic gradient.

    python3 studies/shaped/vertex.py [--tissue calibration] [--params JSON]
"""

import argparse
import sys
import time

import numpy as np
import scipy.sparse as sp
from scipy.optimize import minimize

import table
from cgms import model, morphology, shaped, superpose


def vertex_geometry(geo):
    """Unique junctions of the built tissue (shared by the cells that meet there) and the
    0/1 map from them to every cell's own junction list."""
    J0 = (geo["M"] @ geo["x0"].ravel()).reshape(-1, 2)
    key = np.round(J0 / (1e-6 * geo["mat"]["x_ref"])).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    n_u = len(first)
    S = sp.csr_matrix((np.ones(len(J0)), (np.arange(len(J0)), inverse)),
                      shape=(len(J0), n_u))
    return J0[first], S


def energy(U, lev, S):
    mat = lev["mat"]
    J = S @ U
    cell, ja, jb, n = lev["cell"], lev["ja"], lev["jb"], lev["n"]
    nvert = np.bincount(cell, minlength=n)
    o = np.column_stack([np.bincount(cell, J[ja][:, c], minlength=n) for c in range(2)]) \
        / nvert[:, None]
    a, b = J[ja] - o[cell], J[jb] - o[cell]
    area = 0.5 * np.bincount(cell, a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], minlength=n)
    d = b - a
    chord = np.hypot(d[:, 0], d[:, 1])
    A = shaped.fluid_area(area, chord, lev, mat)
    if np.any(A <= 0):
        return np.inf, np.full(U.size, np.nan)
    H, K = mat["height"], mat["K"]
    E = shaped.fluid_energy(A, lev["A_f"], lev["P_T"], K, H).sum()
    e_w, de_w = shaped.wall_energy(chord, lev["rest"], lev["wall_EA"], lev["buckle"],
                                   lev["soft"])
    E += e_w.sum()
    g_cell = -H * shaped.tait_pressure(A, lev["A_f"], lev["P_T"], K)[cell]
    u = d / chord[:, None]
    dchord = de_w - g_cell * lev["lamella"] * mat["pectin"]
    va = 0.5 * g_cell[:, None] * np.column_stack([b[:, 1], -b[:, 0]]) - dchord[:, None] * u
    vb = 0.5 * g_cell[:, None] * np.column_stack([-a[:, 1], a[:, 0]]) + dchord[:, None] * u
    gJ = lev["Sa"] @ va + lev["Sb"] @ vb
    if lev.get("bend", 0.0) > 0:
        e_b, g_b = bending(J, lev)
        E += e_b
        gJ = gJ + g_b
    return E, (S.T @ gJ).ravel()


def bending(J, lev):
    """Wall bending concentrated at the junctions: per cell and junction
    EI / (2 bend l) (theta - pi/3)^2, theta the polygon's turning angle there and l the
    wall's fresh rest length (``bend`` the length over which the turning spreads, in walls);
    returns the energy and its gradient on the per-cell junctions."""
    ja, jb = lev["ja"], lev["jb"]
    # edges e (into junction jb[e]) and f (out of it) of the same cell: next edge in order
    nxt = lev["next_edge"]
    e1 = J[jb] - J[ja]
    e2 = J[jb[nxt]] - J[ja[nxt]]
    theta = np.arctan2(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0],
                       e1[:, 0] * e2[:, 0] + e1[:, 1] * e2[:, 1])
    k = lev["EI"] / (lev["bend"] * lev["rest0"])
    dth = theta - np.pi / 3
    E = float(np.sum(0.5 * k * dth ** 2))
    c = (k * dth)[:, None]
    de1 = -np.column_stack([-e1[:, 1], e1[:, 0]]) / np.sum(e1 * e1, axis=1)[:, None]
    de2 = np.column_stack([-e2[:, 1], e2[:, 0]]) / np.sum(e2 * e2, axis=1)[:, None]
    nj = J.shape[0]
    g = np.zeros((nj, 2))
    for col in range(2):
        g[:, col] += np.bincount(ja, -c[:, 0] * de1[:, col], minlength=nj)
        g[:, col] += np.bincount(jb, c[:, 0] * (de1[:, col] - de2[:, col]), minlength=nj)
        g[:, col] += np.bincount(jb[nxt], c[:, 0] * de2[:, col], minlength=nj)
    return E, g


def centroids(U, lev, S):
    J = S @ U
    out = np.empty((lev["n"], 2))
    for c in range(lev["n"]):
        out[c] = morphology._polygon_moments(J[lev["ja"][lev["cell"] == c]])[1]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tissue", default="calibration")
    ap.add_argument("--params", default='{"buckle": 8.6e-7, "soft": 0.0}')
    ap.add_argument("--levels", default="1,0.8,0.6,0.4,0.3")
    ap.add_argument("--bend", type=float, default=0.0, help="junction bending: the length "
                    "(in walls) over which a junction's turning spreads; 0: none. The "
                    "buckled walls then push with their Euler load pi^2 EI / r^2")
    args = ap.parse_args(argv)
    params = table.given_params(shaped, args.params)
    mat, xy, geo = table.geometry(args.tissue, params)
    U, S = vertex_geometry(geo)
    # the edge after each edge in its cell's polygon (ja of the next = jb of this)
    start = {(c, a): e for e, (c, a) in enumerate(zip(geo["cell"], geo["ja"]))}
    next_edge = np.array([start[(c, b)] for c, b in zip(geo["cell"], geo["jb"])])
    EI = (660.0 if mat["diameter"] > 175e-6 else 330.0) * 1e-12 * mat["height"] / 12
    L = mat["x_ref"]
    rng = np.random.default_rng(1)
    ref0 = table.mfc(args.tissue, 1.0)
    out = []
    for s in (float(v) for v in args.levels.split(",")):
        lev = shaped.at_level(geo, s)
        lev.update(next_edge=next_edge, EI=EI, bend=args.bend)
        if args.bend > 0:
            lev["buckle"] = np.pi ** 2 * EI / lev["rest"] ** 2
        t0 = time.time()
        U = U + (rng.uniform(-1e-7, 1e-7, U.shape) if s < 1 else 0)
        c0 = U.mean(axis=0)
        scale = 1e-9 * L

        def fun(z):
            E, g = energy(c0 + z.reshape(-1, 2) * L, lev, S)
            return E / scale, g * L / scale

        res = minimize(fun, ((U - c0) / L).ravel(), jac=True, method="L-BFGS-B",
                       options=dict(maxiter=30000, maxfun=60000, maxcor=50, gtol=1.0,
                                    ftol=0.0))
        U = c0 + res.x.reshape(-1, 2) * L
        fmax = float(np.abs(energy(U, lev, S)[1]).max())
        x = centroids(U, lev, S)
        if s == 1.0:
            m0, x1 = table.measures(x), x
        got = morphology.normalise(table.measures(x), m0)
        J = S @ U
        el = []
        for c in range(lev["n"]):
            _, _, mom = morphology._polygon_moments(J[lev["ja"][lev["cell"] == c]])
            el.append(morphology._axis_ratio(*mom))
        line = (f"| {s:g} | {got['A/A0']:.4f} | {got['P/P0']:.4f} | {got['EL/EL0']:.4f} | "
                f"{np.mean(el):.2f} | {fmax:.1e} | {res.nit} | {time.time() - t0:.1f} |")
        ref = table.mfc(args.tissue, s)
        if ref is not None:
            want = morphology.normalise(table.measures(ref[0]), table.measures(ref0[0]))
            line += (" " + " / ".join(f"{100 * (got[k] / want[k] - 1):+.2f} %"
                                      for k in table.KEYS)
                     + f" | {superpose.rmsd(x, ref[0], 'rigid') * 1e6:.1f} |")
        print(line, flush=True)
        out.append((s, x))
    return 0


if __name__ == "__main__":
    sys.exit(main())
