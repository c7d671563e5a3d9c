#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""What accuracy costs: every fidelity lever on the same tissue at one dryness, timed
side by side and scored against a tight reference solution.

Levers (one row each, repeated --repeats times, interleaved so machine noise hits all):
  dynamics  at the 1e-3 and 1e-4 steady-state thresholds (residual and speed), time step
            0.5x and 1x the paper's, density exact m/(hA) or the paper's rate form;
  dynamics  with an effect switched off (LJ attraction, periphery);
  fire      the quasi-static solve with LAMMPS minimize (FIRE), force tolerance 1e-13 N;
  newton    the quasi-static solve with cgms.solve, force tolerance 1e-13 N.
Reference: Newton at 1e-17 N. Error of a row: the largest bead displacement from the
reference after the best rigid superposition, in units of x_ref, and the relative
differences of tissue area, perimeter and elongation (= differences of A/A0, P/P0, EL/EL0
for a common fresh state). Rows with an effect off are scored against the full model,
so their error is the price of dropping the effect.

Outputs in --out (default /tmp/cgms-levers, never the repository): levers.csv (every
run), summary.csv (median and spread per lever), levers.png (wall time against error).

Usage (after `source build/env.sh`):
  /usr/bin/python3 bench/levers.py --width 1.5 --height 1.5 --repeats 3
"""

import argparse
import csv
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from cgms import material, morphology, run, superpose, tissue  # noqa: E402

APPLE = ROOT / "potentials" / "apple.cgms"


def levers(big):
    """(name, method, options) for every lever; ``big`` drops the tight dynamics rows
    that take hours on 20 000 beads."""
    rows = [
        ("newton", "newton", {}),
        ("fire", "quasistatic", {}),
        ("dynamics 1e-3", "dynamics", dict(steady=dict(residual=1e-3, speed=1e-3))),
        ("dynamics 1e-3 dt/2", "dynamics", dict(steady=dict(residual=1e-3, speed=1e-3), dt=5e-8)),
        ("dynamics 1e-3 rate", "dynamics",
         dict(steady=dict(residual=1e-3, speed=1e-3), fix_args="density rate")),
        ("dynamics 1e-3 no attraction", "dynamics",
         dict(steady=dict(residual=1e-3, speed=1e-3), pair_args="attraction no")),
        ("dynamics 1e-3 no periphery", "dynamics",
         dict(steady=dict(residual=1e-3, speed=1e-3), pair_args="periphery no")),
    ]
    if not big:
        rows.append(("dynamics 1e-4", "dynamics",
                     dict(steady=dict(residual=1e-4, speed=1e-4, max_steps=3000000))))
    return rows


def solve(data, s, method, options, ftol=1e-13):
    """Steady state: (positions by id, wall seconds, steps or iterations)."""
    options = dict(options)
    steady = dict(dict(every=1000, max_steps=2000000), **options.pop("steady", {}))
    lmp = run.open_lammps()
    try:
        start = time.perf_counter()
        lmp.commands_string(run.tissue_script(data, APPLE, s, method=method, steady=steady,
                                              ftol=ftol, **options))
        if method == "newton":
            info = run.solve_newton(lmp, ftol=ftol, max_iterations=200)
            steps = info["iterations"]
        else:
            steps = lmp.extract_global("ntimestep")
        seconds = time.perf_counter() - start
        return run.steady_state(lmp)["xy"], seconds, steps
    finally:
        lmp.close()


def score(xy, ref, x_ref):
    a = superpose.align(xy, ref, "rigid")  # the best rotation and shift onto ref
    ma, mb = morphology.measures(a), morphology.measures(ref)
    out = {"max_disp/x_ref": np.abs(a - ref).max() / x_ref}
    for key in ("area", "perimeter", "elongation"):
        out[f"d_{key}"] = ma[key] / mb[key] - 1
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--width", type=float, default=1.5, help="tissue width, mm")
    p.add_argument("--height", type=float, default=1.5, help="tissue height, mm")
    p.add_argument("--dryness", type=float, default=0.3)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--only", default="", help="comma-separated lever names to run")
    p.add_argument("--out", default="/tmp/cgms-levers")
    args = p.parse_args()

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    mat = material.read(APPLE)
    xy = tissue.rectangle(args.width * 1e-3, args.height * 1e-3, mat["x_ref"])
    data = out / f"tissue_{args.width:g}x{args.height:g}.data"
    tissue.write_data(data, xy, 4 * mat["x_ref"], overwrite=True)
    n = len(xy)
    print(f"{n} beads, s = {args.dryness}", flush=True)

    ref, ref_seconds, ref_its = solve(data, args.dryness, "newton", {}, ftol=1e-17)
    print(f"reference (newton, 1e-17 N): {ref_seconds:.2f} s, {ref_its} iterations", flush=True)
    chosen = levers(n > 5000)
    if args.only:
        keep = set(args.only.split(","))
        chosen = [c for c in chosen if c[0] in keep]

    rows = []
    for rep in range(args.repeats):
        for name, method, options in chosen:
            xy_l, seconds, steps = solve(data, args.dryness, method, options)
            row = dict(lever=name, beads=n, repeat=rep, seconds=seconds, steps=steps,
                       **score(xy_l, ref, mat["x_ref"]))
            rows.append(row)
            print("  ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                            for k, v in row.items()), flush=True)

    with open(out / "levers.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    summary = []
    for name, _, _ in chosen:
        sel = [r for r in rows if r["lever"] == name]
        t = np.array([r["seconds"] for r in sel])
        summary.append(dict(lever=name, beads=n, runs=len(sel), seconds_median=np.median(t),
                            seconds_min=t.min(), seconds_max=t.max(), steps=sel[0]["steps"],
                            **{k: sel[0][k] for k in ("max_disp/x_ref", "d_area", "d_perimeter",
                                                      "d_elongation")}))
    with open(out / "summary.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(summary[0]))
        w.writeheader()
        w.writerows(summary)
    plot(summary, out / "levers.png", n, args.dryness)
    print(f"results in {out}")


def plot(summary, path, n, s):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    for r in summary:
        err = max(abs(r["d_area"]), abs(r["d_perimeter"]), abs(r["d_elongation"]), 1e-12)
        # a legend, not labels: the dynamics levers land on top of each other
        ax.errorbar(r["seconds_median"], err,
                    xerr=[[r["seconds_median"] - r["seconds_min"]],
                          [r["seconds_max"] - r["seconds_median"]]], fmt="o",
                    label=r["lever"])
    ax.legend(fontsize=8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time to steady state (s)")
    ax.set_ylabel("largest relative error of A, P, EL")
    ax.set_title(f"{n} beads, s = {s}: error against Newton at 1e-17 N")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    main()
