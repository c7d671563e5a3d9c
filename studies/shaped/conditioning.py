# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Is the shaped model better conditioned than the paper's? (issue 27, "Cost"). At its
steady state on the bench's 105-bead tissue (1.5 x 1.5 mm), per level: the smallest
non-rigid and the largest eigenvalue of the Hessian of each model's potential and their
ratio.

- The paper's model: the potential of doc/model.md ("Potential energy", pressures held at
  -Pi, plus LJ), its steady state from ``pair_style cgms`` + ``fix cgms/fluid balance yes``
  by Newton's method (``cgms.run.solve_newton``, as ``cgms study --method newton``); its
  Hessian minus the central difference of the LAMMPS forces (step ``--step`` x_ref per
  coordinate, 1e-4 unless given), symmetrised.
- The shaped tensor model: its drying ramp 1, 0.8, 0.6, 0.4, 0.3 (``cgms.shaped_tensor.ramp``
  with ``cgms.shaped_newton.newton``, each level from the previous one) and its exact
  ``hessian``, with the
  F block in the variables the LAMMPS style's minimiser moves, y = dof_scale F (dof_scale
  the power of two nearest x_ref, so d2E/dy2 = d2E/dF2 / dof_scale^2), so both Hessians
  are in N/m.

The three smallest eigenvalues in magnitude (two translations and a rotation) are rigid
and left out. Needs ``source build/env.sh``. Run from the repository root (about a minute):

    /usr/bin/python3 studies/shaped/conditioning.py [--levels 1,0.6,0.3]
"""

import argparse
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "python"))

from cgms import material, model, positions, run, shaped_tensor as st, solve, tissue  # noqa: E402

BEST = {"soft": 0.002, "kg_ratio": 1.0, "strip": "contour", "lamella": 0.391, "void": 0.063,
        "iso": 1.0, "beta_b": 0.04}
RIGID = 3


def spectrum(H):
    """(smallest non-rigid, largest eigenvalue, the three rigid ones) of a symmetric H."""
    ev = np.linalg.eigvalsh(0.5 * (H + H.T))
    rigid = np.argsort(np.abs(ev))[:RIGID]
    rest = np.delete(ev, rigid)
    return rest.min(), rest.max(), ev[rigid]


def paper(xy, s, folder, mat, step):
    """The paper model's Hessian (N/m) at its steady state at dryness s."""
    data = folder / "cgms.data"
    positions.write_data(data, xy, 4 * mat["x_ref"], overwrite=True)
    lmp = run.open_lammps(log=str(folder / f"log.paper.{s:g}.lammps"))
    try:
        lmp.commands_string(run.tissue_script(data, material.find("apple"), s,
                                              method="newton"))
        info = run.solve_newton(lmp, spacing=model.steady_spacing(mat, s))
        forces = solve.LammpsForces(lmp)
        x = forces.positions()
        n = len(x)
        H = np.empty((2 * n, 2 * n))
        for k in range(2 * n):
            e = np.zeros(2 * n)
            e[k] = step
            fp = forces(x + e.reshape(n, 2))[1].ravel()
            fm = forces(x - e.reshape(n, 2))[1].ravel()
            H[:, k] = -(fp - fm) / (2 * step)
        forces(x)
    finally:
        lmp.close()
    return H, info


def shaped(xy, levels, mat):
    """{s: (Hessian (N/m, F scaled as the LAMMPS style does), solver info)} of the shaped
    tensor model's steady states along the ramp 1, 0.8, 0.6, 0.4, 0.3 (cgms.shaped_tensor.
    ramp with Newton's method, each level from the previous one, kicked) at ``levels``."""
    from cgms import shaped_newton
    ramp = sorted(set(levels) | {1.0, 0.8, 0.6, 0.4, 0.3}, reverse=True)
    geo, states = st.ramp(xy, mat, ramp, BEST, solver=shaped_newton.newton)
    n = geo["n"]
    dof_scale = 2.0 ** round(math.log2(mat["x_ref"]))
    out = {}
    for s, z, info in states:
        if s not in levels:
            continue
        H = st.hessian(z, st.at_level(geo, s)).toarray()
        scale = np.concatenate([np.ones(2 * n), np.full(len(z) - 2 * n, 1 / dof_scale)])
        out[s] = (scale[:, None] * H * scale[None, :], info)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--levels", default="1,0.6,0.3")
    ap.add_argument("--size", type=float, default=1.5, help="tissue side (mm)")
    ap.add_argument("--step", type=float, default=1e-4,
                    help="difference step of the paper's Hessian (x_ref)")
    args = ap.parse_args(argv)
    mat = material.read("apple")
    xy = tissue.rectangle(args.size * 1e-3, args.size * 1e-3, mat["x_ref"])
    print(f"{len(xy)} beads; dof_scale {2.0 ** round(math.log2(mat['x_ref'])):.6g} m")
    print("| s | model | smallest non-rigid (N/m) | largest (N/m) | ratio | rigid (N/m) | "
          "solver |")
    print("|---|---|---|---|---|---|---|")
    levels = [float(v) for v in args.levels.split(",")]
    shaped_states = shaped(xy, levels, mat)
    with tempfile.TemporaryDirectory() as tmp:
        for s in levels:
            H, info = paper(xy, s, Path(tmp), mat, args.step * mat["x_ref"])
            lo, hi, rigid = spectrum(H)
            print(f"| {s:g} | paper | {lo:.4g} | {hi:.4g} | {hi / lo:.4g} | "
                  f"{np.abs(rigid).max():.2g} | Newton {info['iterations']} iterations, "
                  f"fmax {info['fmax']:.1e} N |", flush=True)
            H, info = shaped_states[s]
            lo, hi, rigid = spectrum(H)
            m = 2 * len(xy)    # the largest of the bead block and of the (scaled) F block
            hx, hF = np.linalg.eigvalsh(H[:m, :m])[-1], np.linalg.eigvalsh(H[m:, m:])[-1]
            print(f"| {s:g} | shaped | {lo:.4g} | {hi:.4g} | {hi / lo:.4g} | "
                  f"{np.abs(rigid).max():.2g} | Newton {info['iterations']} iterations, "
                  f"fmax {info['fmax']:.1e} N; largest of the x block {hx:.4g}, of the F "
                  f"block {hF:.4g} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
