#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""cgms.shaped_newton against pair_style cgms/shaped + cg at one level: the state that
``bench/shaped_macroscale.py`` leaves in <out>/final.dump (run it first, same --size and
--dryness) and Newton's from the same kicked start. Compares what does not depend on the
mirror-image choice of the cells' flattening (bead positions after a rigid superposition,
each F's singular values and determinant) against the bound (|g1| + |g2|) / lambda, lambda
the smallest eigenvalue of the scaled Hessian at Newton's state with the rigid motions
left out (sparse shift-invert), as tests/shaped/test_shaped_minimize does.

    /usr/bin/python3 studies/shaped/newton_check.py --size 5 --dryness 0.6 \\
        --dump /tmp/cgms-shaped-macro/final.dump
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spla

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "tests"))
from cgms import material, shaped_newton as sn, shaped_tensor as st, tissue  # noqa: E402
from cgmstest import read_dump  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=5.0, help="tissue side (mm)")
    ap.add_argument("--dryness", type=float, default=0.6)
    ap.add_argument("--ftol", type=float, default=1e-9)
    ap.add_argument("--dump", type=Path, required=True)
    args = ap.parse_args(argv)
    mat = material.read("apple")
    L, s = mat["x_ref"], args.dryness
    xy = tissue.rectangle(args.size * 1e-3, args.size * 1e-3, L)
    geo = st.build(xy, mat, sn.PAIR_DEFAULTS, local=True)
    lev = st.at_level(geo, s)
    n = geo["n"]
    rng = np.random.default_rng(1)        # the start of bench/shaped_macroscale.py
    c = xy.mean(axis=0)
    F = math.sqrt(s) * (np.eye(2) + rng.uniform(-1e-3, 1e-3, (n, 2, 2)))
    z0 = np.concatenate([(c + (xy - c) * math.sqrt(s)).ravel(), F.ravel()])
    t, cpu = time.time(), time.process_time()
    z_nt, info = sn.newton(z0, lev, args.ftol, max_iterations=2000)
    print(f"Newton: {info['iterations']} steps, {info['factorisations']} factorisations, "
          f"largest force {info['fmax']:.2e} N, {time.time() - t:.1f} s wall, "
          f"{time.process_time() - cpu:.1f} s CPU, {info['status']}")
    d = read_dump(args.dump)
    z_lmp = st.align(st.join(np.c_[d["x"], d["y"]],
                             np.stack([d[f"d2_shaped_F[{k}]"] for k in range(1, 5)], axis=1)),
                     z_nt)
    prob = sn.Problem(lev, args.ftol)
    g_nt, lv = prob.energy(z_nt)[1:]
    g_lmp = prob.energy(z_lmp)[1]
    H = prob.hessian(z_nt, lv)
    # scaled gradients are in units of ftol; the Hessian in ftol per unit step
    w = spla.eigsh(H, k=6, sigma=-1.0, which="LM", return_eigenvectors=False)
    w = np.sort(w)
    lam = w[3]                             # the three rigid motions below it
    bound = (np.linalg.norm(g_nt) + np.linalg.norm(g_lmp)) / lam
    x_nt, F_nt = st.split(z_nt, n)
    x_lmp, F_lmp = st.split(z_lmp, n)
    dx = np.linalg.norm((x_nt - x_lmp) / L)
    dsv = np.linalg.norm(np.linalg.svd(F_nt, compute_uv=False)
                         - np.linalg.svd(F_lmp, compute_uv=False))
    ddet = np.linalg.norm(np.linalg.det(F_nt) - np.linalg.det(F_lmp))
    print(f"smallest eigenvalues (scaled) {w}; lambda {lam:.3e}; largest force LAMMPS "
          f"{np.abs(g_lmp).max() * args.ftol:.2e} N")
    print(f"|dx| / x_ref {dx:.2e}, |d sv(F)| {dsv:.2e}, |d det F| {ddet:.2e}; bound {bound:.2e}"
          f" ({'within' if max(dx, dsv) <= bound else 'OUTSIDE'})")
    E = [prob.energy(z)[0] * prob.scale for z in (z_nt, z_lmp)]
    print(f"energy Newton {E[0]:.12e} J, LAMMPS {E[1]:.12e} J")


if __name__ == "__main__":
    main()
