#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Where Newton's steps go in the shaped model's study (cgms.shaped_newton.study), and a
start searched off the saddles tried against the kicked one (doc/results/performance.md,
"The shaped model's study at scale").

Runs the drying ramp of ``cgms study --model shaped`` on one tissue twice, side by side:
"kicked", the study as it is (each level from the previous state shrunk by
sqrt(s / s_prev), every F kicked by up to 1e-3), and "searched": each level from the
previous state (1) dilated isotropically to the stationary point of the energy along the
dilation, (2) where the cells are flattened, its flattening grown to the stationary point
along it, then Newton; where Newton stops on a saddle (the inertia of the Hessian at the
converged state has negative eigenvalues) a uniform flattening of every cell is tried (a
scan of amplitudes and axes; taken if its energy is lower), else the F are kicked, and
Newton again. Prints per level the steps, factorisations, Hessians, refused steps and CPU
seconds, the table (A/A0, P/P0, EL/EL0), each state's energy and its number of negative
Hessian eigenvalues (0: a minimum), and the distance between the two states after a rigid
superposition.

    /usr/bin/python3 studies/shaped/start_search.py --size 2
    /usr/bin/python3 studies/shaped/start_search.py --size 5 --starts kicked
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
from cgms import material, morphology, shaped_newton as sn, shaped_tensor as st, tissue  # noqa

DEVIATORIC = (np.array([[1.0, 0.0], [0.0, -1.0]]), np.array([[0.0, 1.0], [1.0, 0.0]]))
COUNTS = ("iterations", "factorisations", "hessians", "indefinite", "refused", "chord")


def stationary(slope, a, step, tol):
    """A root of ``slope`` (dE/dt along a path, scaled as Problem's gradient) from ``a``:
    ``a`` when |slope(a)| <= 1; else steps doubling downhill until the sign changes
    (halving where the energy is infinite), then Brent's method. None without a bracket."""
    from scipy.optimize import brentq
    da = slope(a)
    if not np.isfinite(da):
        return None
    if abs(da) <= 1.0:
        return a
    step = math.copysign(abs(step), -da)
    for _ in range(40):
        b = a + step
        db = slope(b)
        if not np.isfinite(db):
            step *= 0.5
            continue
        if (db > 0) != (da > 0):
            return brentq(slope, min(a, b), max(a, b), xtol=tol)
        a, da, step = b, db, 2 * step
    return None


def slope_along(prob, z, dz):
    dy = dz / prob.unit
    return lambda t: float(prob.energy(z + t * dz)[1] @ dy)


def flattened(z, n):
    F = st.split(z, n)[1]
    dev = np.linalg.norm(st._deviatoric(F)[0], axis=(1, 2))
    return bool(np.median(dev / np.sqrt(np.abs(np.linalg.det(F)))) > 1e-3)


def searched_start(z, lev, ftol):
    """Dilated to the stationary point, then (flattened cells) the flattening grown."""
    prob = sn.Problem(lev, ftol)
    x, F = st.split(z, prob.n)
    centred = st.join(np.broadcast_to(x.mean(axis=0), x.shape), np.zeros_like(F))
    t = stationary(slope_along(prob, centred, z - centred), 1.0, 0.02, 1e-6)
    if t is not None:
        z = centred + t * (z - centred)
    if flattened(z, prob.n):
        x, F = st.split(z, prob.n)
        dz = st.join(np.zeros_like(x), st._deviatoric(F)[0])
        m = stationary(slope_along(prob, z, dz), 0.0, 0.05, 1e-6)
        if m is not None:
            z = z + m * dz
    return z


def uniform_flattening(z, prob):
    """Every F_i -> G F_i, G = I + m (cos 2a D1 + sin 2a D2): the lowest energy of m in
    0.025 .. 0.3 along x, then of six axes at that m; None if not below z's energy."""
    x, F = st.split(z, prob.n)

    def moved(m, a):
        G = np.eye(2) + m * (math.cos(2 * a) * DEVIATORIC[0] + math.sin(2 * a) * DEVIATORIC[1])
        return st.join(x, np.einsum("ab,nbc->nac", G, F))
    E0 = prob.energy(z)[0]
    ms = np.arange(1, 13) * 0.025
    m = ms[int(np.argmin([prob.energy(moved(m, 0.0))[0] for m in ms]))]
    axes = np.radians(np.arange(0, 180, 30))
    E = [prob.energy(moved(m, a))[0] for a in axes]
    k = int(np.argmin(E))
    return moved(m, axes[k]) if E[k] < E0 else None


def add(info, more):
    for key in COUNTS + ("evaluations",):
        more[key] += info[key]
    more["seconds"] = {k: v + info["seconds"][k] for k, v in more["seconds"].items()}
    return more


def searched_level(z, lev, ftol, limit):
    z, info = sn.newton(searched_start(z, lev, ftol), lev, ftol, limit, certify=True)
    rng = np.random.default_rng(1)
    saddles = 0
    while info["negative"] and info["iterations"] < limit:
        saddles += 1
        z1 = uniform_flattening(z, sn.Problem(lev, ftol)) if saddles == 1 else None
        if z1 is None:
            x, F = st.split(z, lev["n"])
            z1 = st.join(x, F + rng.uniform(-1e-3, 1e-3, F.shape) * math.sqrt(lev["s"]))
        z, more = sn.newton(z1, lev, ftol, limit - info["iterations"], certify=True)
        info = add(info, more)
    info["saddles"] = saddles
    return z, info


def run(xy, mat, levels, how, ftol, limit):
    """(geometry, [(s, z, info)]) of the ramp started ``how``."""
    p = dict(sn.PAIR_DEFAULTS)
    if how == "kicked":
        def solver(z, lev, tol):
            c = time.process_time()
            z, info = sn.newton(z, lev, tol, limit, certify=True)
            info.update(cpu=time.process_time() - c, saddles=0)
            return z, info
        return st.ramp(xy, mat, levels, p, ftol=ftol, local=True, solver=solver)
    geo = st.build(xy, mat, p, local=True)
    z, out = st.fresh_state(geo), []
    for s in levels:
        c = time.process_time()
        z, info = searched_level(z, st.at_level(geo, s), ftol, limit)
        info["cpu"] = time.process_time() - c
        out.append((s, z, info))
    return geo, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=2.0, help="tissue side (mm)")
    ap.add_argument("--levels", default="1,0.8,0.6,0.4,0.3")
    ap.add_argument("--starts", default="kicked,searched")
    ap.add_argument("--ftol", type=float, default=1e-9)
    ap.add_argument("--limit", type=int, default=1000, help="Newton steps per level")
    args = ap.parse_args(argv)
    mat = material.read("apple")
    xy = tissue.rectangle(args.size * 1e-3, args.size * 1e-3, mat["x_ref"])
    levels = [float(v) for v in args.levels.split(",")]
    starts = args.starts.split(",")
    print(f"{len(xy)} beads, levels {levels}", flush=True)
    runs = {}
    for how in starts:
        c = time.process_time()
        geo, states = run(xy, mat, levels, how, args.ftol, args.limit)
        runs[how] = states
        print(f"[{how}] {time.process_time() - c:.1f} s CPU", flush=True)
        for s, z, info in states:
            print(f"  s = {s:g}: " + ", ".join(f"{k} {info[k]}" for k in COUNTS)
                  + f", saddles {info['saddles']}, negative eigenvalues {info['negative']},"
                  f" largest force {info['fmax']:.1e} N, {info['cpu']:.1f} s CPU", flush=True)
    n = geo["n"]
    print("\n   s  | " + " | ".join(f"{h}: A/A0 P/P0 EL/EL0 energy (J)" for h in starts))
    shapes = {h: [morphology.measures(st.split(z, n)[0]) for _, z, _ in runs[h]] for h in starts}
    for i, s in enumerate(levels):
        line = f"  {s:4.2f}"
        for h in starts:
            m = morphology.normalise(shapes[h][i], shapes[h][0])
            z = runs[h][i][1]
            lev = sn.with_near_pairs(st.split(z, n)[0], st.at_level(geo, s))
            line += (f" | {m['A/A0']:.6f} {m['P/P0']:.6f} {m['EL/EL0']:.6f} "
                     f"{st.energy(z, lev, gradient=False):.12e}")
        if len(starts) == 2:
            a, b = runs[starts[0]][i][1], runs[starts[1]][i][1]
            b = st.align(b, a)
            line += f" | bead distance {np.linalg.norm((st.split(a, n)[0] - st.split(b, n)[0]) / mat['x_ref']):.1e} x_ref"
        print(line)


if __name__ == "__main__":
    main()
