# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Measure the accuracy levers of ``python3 -m cgms dry`` (cgms.drying.dry) on the 248-bead
tissue (2.0 x 2.5 mm) at 70 C, 10 % RH, 1.5 m/s, 2 mm, with the parameters of
potentials/apple-drying.params, and print the two tables of doc/results/drying.md ("Accuracy
levers"): the transport levers (``layers``, ``dx_max``) with the shape frozen, and the
shape solves (``resolve``, FIRE or Newton) with the outline in air. Run with the CGMS
environment (source build/env.sh); about 5 minutes on one core:

    /usr/bin/python3 studies/drying/levers_python.py [--no-transport] [--no-shape]
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from cgms import drying, material, tissue

TRANSPORT_ROWS = [(5, 0.02), (10, 0.02), (20, 0.02), (40, 0.02), (10, 0.05), (10, 0.01),
                  (10, 0.005)]
#: (solver, resolve, Newton iterations per warm solve)
SHAPE_ROWS = [("fire", 0.005, None), ("fire", 0.01, None), ("fire", 0.02, None),
              ("fire", 0.05, None), ("fire", 0.1, None), ("newton", 0.02, 8),
              ("newton", 0.05, 3)]
LEVELS = (0.8, 0.5, 0.3)


def tissue_xy():
    mat = material.read("apple")
    return tissue.rectangle(2.0e-3, 2.5e-3, mat["x_ref"]), mat


def at(rows, key, level):
    """``key`` where X/X0 falls to ``level`` (linear between records)."""
    x = np.array([r["X/X0"] for r in rows])
    y = np.array([r[key] for r in rows])
    return float(np.interp(-level, -x, y))


def transport_table(params):
    xy, _ = tissue_xy()
    print(f"{len(xy)} beads, 70 C, shape frozen; time (h) to X/X0 = 0.5 and 0.1:\n")
    print("| layers | dx_max | steps | window 0.5 / 0.1 | piece 0.5 / 0.1 |")
    print("|---|---|---|---|---|")
    for layers, dx in TRANSPORT_ROWS:
        cells, steps = [], 0
        for outline in (False, True):
            rows = drying.dry(xy, params, dict(outline=outline),
                              dict(layers=layers, dx_max=dx), hours=10, stop=0.099)["rows"]
            if not outline:
                steps = len(rows) - 1
            cells.append(f"{drying.drying_time(rows, 0.5):.3f} / "
                         f"{drying.drying_time(rows, 0.1):.3f}")
        print(f"| {layers} | {dx} | {steps} | {cells[0]} | {cells[1]} |", flush=True)


def shape_table(params):
    xy, mat = tissue_xy()
    print(f"\nShape solves, {len(xy)} beads, outline in air, 10 layers, dx_max 0.02; A/A0, "
          f"EL/EL0 at X/X0 = {', '.join(map(str, LEVELS))}; dev: the largest difference from "
          "the first row:\n")
    print("| solver | resolve | solves | wall | " +
          " | ".join(f"A/A0, EL/EL0 at {lev}" for lev in LEVELS) + " | dev |")
    print("|---|---|---|---|" + "---|" * len(LEVELS) + "---|")
    first = None
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "tissue.data"
        tissue.write_data(data, xy, 3 * mat["x_ref"])
        for solver, resolve, iterations in SHAPE_ROWS:
            start = time.perf_counter()
            mech = drying.Mechanics(data, material.find("apple"), method=solver,
                                    newton_iterations=iterations or 8)
            try:
                rows = drying.dry(xy, params, dict(outline=True), dict(resolve=resolve),
                                  hours=10, stop=0.099, mechanics=mech)["rows"]
            finally:
                mech.close()
            wall = time.perf_counter() - start
            values = np.array([[at(rows, k, lev) for k in ("A/A0", "EL/EL0")]
                               for lev in LEVELS])
            first = values if first is None else first
            dev = np.abs(values - first).max()
            name = "FIRE" if solver == "fire" else f"Newton, {iterations} iterations"
            print(f"| {name} | {resolve} | {rows[-1]['solves']} | {wall:.0f} s | " +
                  " | ".join(f"{a:.4f}, {e:.4f}" for a, e in values) +
                  f" | {'-' if dev == 0 else f'{dev:.4f}'} |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--no-transport", action="store_true", help="skip the frozen table")
    ap.add_argument("--no-shape", action="store_true", help="skip the shape-solve table")
    args = ap.parse_args()
    params = drying.read_params()
    print(f"D_ref {params['D_ref']:.3g} m^2/s at {params['T_ref']:g} C, D_energy "
          f"{params['D_energy'] / 1e3:.1f} kJ/mol, D_moisture {params['D_moisture']:g}\n")
    if not args.no_transport:
        transport_table(params)
    if not args.no_shape:
        shape_table(params)


if __name__ == "__main__":
    main()
