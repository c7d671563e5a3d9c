#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Where Newton's steps go in the shaped model's study (cgms.shaped_newton.study), and a
start searched off the saddles against the kicked one (doc/results/performance.md,
"The shaped model's study at scale").

Runs the drying ramp of ``cgms study --model shaped`` on one tissue twice, side by side:
"kicked", the study before 2026-12-03's third session (each level from the previous state
shrunk by sqrt(s / s_prev), every F kicked by up to 1e-3), and "searched", the study now
(cgms.shaped_start: each level from the previous state dilated to the stationary point of
the energy along the dilation, the cells' flattening grown; Newton's state certified by
the Hessian's inertia and, at a saddle, every cell flattened alike at its area, else
kicked, and Newton again). Prints per level the steps, factorisations, Hessians, refused steps and CPU
seconds, the table (A/A0, P/P0, EL/EL0), each state's energy and its number of negative
Hessian eigenvalues (0: a minimum), and the distance between the two states after a rigid
superposition.

    /usr/bin/python3 studies/shaped/start_search.py --size 2
    /usr/bin/python3 studies/shaped/start_search.py --size 5 --starts kicked
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
from cgms import material, morphology, shaped_newton as sn, shaped_tensor as st, tissue  # noqa

COUNTS = ("iterations", "factorisations", "hessians", "indefinite", "refused", "chord")


def negative_eigenvalues(z, lev, ftol):
    prob = sn.Problem(lev, ftol)
    _, _, lv = prob.energy(z)
    return sn.unstable_directions(prob, z, lv, sn.dof_order(st.split(z, lev["n"])[0], lev))


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
        geo, states, _ = sn.study(xy, mat, levels, ftol=args.ftol, max_iterations=args.limit,
                                  start=how)
        runs[how] = states
        print(f"[{how}] {time.process_time() - c:.1f} s CPU", flush=True)
        for s, z, info in states:
            negative = negative_eigenvalues(z, st.at_level(geo, s), args.ftol)
            print(f"  s = {s:g}: " + ", ".join(f"{k} {info[k]}" for k in COUNTS)
                  + f", saddles left {info.get('saddles', 0)}, negative eigenvalues {negative},"
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
