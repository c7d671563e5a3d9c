# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states of the full SPH model against the fast variant (one pressure per cell) on
one cell or a 7-cell cluster, fresh and dried along the same ramp (doc/mfc.md, table
"SPH against the fast variant").

    source build/env.sh
    /usr/bin/python3 examples/mfc/sph_vs_fast.py [cells: 1 or 7] [levels, e.g. 1,0.8]

Prints, per level, the cell area, perimeter and centroid of both models, their relative
differences, the SPH fluid's mean pressure and the wall time of each."""

import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from cgms import mfc_metrics, mfc_model, mfc_run, mfc_sph, mfc_tissue, run

STEPS = 2000          # SPH steps per chunk (4 us at dt = 2 ns)
STAGE_STEPS = 4000    # SPH steps per ramp stage
TOL = 1e-4            # SPH steady: cell areas change by less than this over a chunk


def cluster(n):
    p = mfc_model.parameters()
    if n == 1:
        return [[0.0, 0.0]]
    ring = [[p["x_ref"] * math.cos(a), p["x_ref"] * math.sin(a)]
            for a in np.arange(6) * math.pi / 3 + math.pi / 2]
    return [[0.0, 0.0]] + ring


def sph_state(lmp, p):
    rho = np.array(lmp.gather_atoms("rho", 1, 1))
    return mfc_sph.wall_positions(lmp, p), rho


def main():
    ncell = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    levels = [float(s) for s in (sys.argv[2] if len(sys.argv) > 2 else "1,0.8,0.6,0.4,0.3").split(",")]
    p = mfc_model.parameters()
    centres = cluster(ncell)
    folder = Path(tempfile.mkdtemp(prefix="mfc-sph-"))
    # the fast variant (one LAMMPS instance at a time: the plugin loads once per process)
    mfc_tissue.write_data(folder / "walls.data", centres, p)
    fast = run.open_lammps(log=folder / "fast.log")
    fast.commands_list(mfc_run.setup_commands(folder / "walls.data", p))
    results, previous = {}, None
    for s in levels:
        t = time.perf_counter()
        report = mfc_run.ramp(fast, p, previous, s, ftol=1e-11)
        results[s] = (mfc_run.positions(fast), time.perf_counter() - t, report["converged"])
        previous = s
    fast.close()
    # the SPH model along the same ramp
    mfc_sph.write_data(folder / "sph.data", centres, p)
    sph = run.open_lammps(log=folder / "sph.log")
    sph.commands_list(mfc_sph.setup_commands(folder / "sph.data", p))
    sph.commands_list(mfc_sph.level_commands(p, 1.0) + ["timestep 2e-9"])
    s_now = 1.0
    print(f"{ncell} cell(s); SPH tau = {mfc_sph.TAU:g} s; folder {folder}")
    print("   s   model   area/A0   perim/P0   centroid shift (um)   P_fluid (kPa)   seconds")
    for s in levels:
        t = time.perf_counter()
        for stage in mfc_run.stages(s_now, s, 0.05) + ([s] if s != s_now else []):
            mfc_sph.dry(sph, p, stage, s_now)
            s_now = stage
            sph.command(f"run {STAGE_STEPS}")
        area = mfc_metrics.cells(sph_state(sph, p)[0], p["n_wall"])["area"]
        steps = 0
        while True:
            sph.command(f"run {STEPS}")
            steps += STEPS
            new = mfc_metrics.cells(sph_state(sph, p)[0], p["n_wall"])["area"]
            change = np.abs(new / area - 1).max()
            area = new
            if change < TOL or steps >= 200 * STEPS:
                break
        ts = time.perf_counter() - t
        xs, rho = sph_state(sph, p)
        xf, tf, ok = results[s]
        rho_r, c0 = mfc_sph.tait(p, s)
        b = c0 * c0 * rho_r / 7
        pf = b * ((rho[len(xs):] / rho_r) ** 7 - 1) / p["height"]
        cf, cs = mfc_metrics.cells(xf, p["n_wall"]), mfc_metrics.cells(xs, p["n_wall"])
        for name, c, sec in (("fast", cf, tf), ("SPH", cs, ts)):
            pk = f"{pf.mean() / 1e3:8.1f}" if name == "SPH" else "     -  "
            print(f"  {s:4.2f}  {name:5s}  {c['area'].mean() / p['A_ref']:.4f}   "
                  f"{c['perimeter'].mean() / (math.pi * p['diameter']):.4f}   "
                  f"{np.hypot(*(c['centroid'] - np.asarray(centres)).T).max() * 1e6:8.3f}"
                  f"          {pk}      {sec:7.1f}", flush=True)
        da = np.abs(cs["area"] / cf["area"] - 1).max()
        dp = np.abs(cs["perimeter"] / cf["perimeter"] - 1).max()
        dc = np.hypot(*(cs["centroid"] - cf["centroid"]).T).max()
        print(f"        SPH vs fast: area {da:.2%}, perimeter {dp:.2%}, centroids {dc * 1e6:.3f} um "
              f"({dc / p['x_ref']:.2%} of x_ref); SPH {steps} steps to steady "
              f"(last area change {change:.1e}); fast converged {ok}", flush=True)
    sph.close()


if __name__ == "__main__":
    main()
