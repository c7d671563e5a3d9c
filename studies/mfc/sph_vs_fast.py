# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states of the full SPH model against the fast variant (one pressure per cell) on
one cell or a 7-cell cluster (doc/results/mfc.md, "SPH against the fast variant").

    source build/env.sh
    /usr/bin/python3 studies/mfc/sph_vs_fast.py [cells: 1 or 7] [levels, e.g. 1,0.8]
    /usr/bin/python3 studies/mfc/sph_vs_fast.py 7 0.8,0.6,0.3 --from-fast [--kick 0.5]
    /usr/bin/python3 studies/mfc/sph_vs_fast.py 1 --ap 0.2 --kernel wendland [--path density]

Default: both models dried along the same ramp from the fresh cell(s); ``--path`` is how
SPH takes each stage (``cgms.mfc.sph.dry``: "affine", everything moved in with the
fluid, or "density", the fluid put in tension, the route before), ``--mass`` how it sets the fluid mass
("scaled", s times the fresh fill's; "water", affine only: the fast variant's water s A0
with the layer between fluid and wall, measured again once a level is reached), ``--ap`` Monaghan's
artificial pressure factor, ``--kernel`` the kernel and ``--boundary`` the wall-fluid
coupling ("dynamic": walls with their own continuity density; "adami": walls take the
fluid's pressure; any of the three: pair sph/taitwater/ap; all at their defaults LAMMPS's
sph/taitwater/morris). Per level it prints also the SPH fluid: its area
sum m/rho, the layer between it and the wall, the share of the ring it leaves void, the
mean distance to the nearest fluid particle over the spacing (pairing), the pressures (also
next to the wall) and the fast variant's EOS pressure on its own ring and on SPH's.
``--from-fast``:
the SPH model started from the fast variant's steady state of each level (every ring
filled with SPH fluid at rest, ``cgms.mfc.sph.write_state``), walls optionally kicked at
random by up to ``--kick`` um, and run ``--steps`` steps: does SPH stay there (or come
back)? Prints, per level, the cell area, perimeter and centroid of both models, their
differences (largest over the cells), the SPH fluid's pressure and the wall times."""

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from cgms.mfc import (metrics as mfc_metrics, model as mfc_model, run as mfc_run, sph as mfc_sph,
                      tissue as mfc_tissue)
from cgms import run

STEPS = 2000          # SPH steps per chunk (4 us at dt = 2 ns)
STAGE_STEPS = 4000    # SPH steps per ramp stage
TOL = 1e-4            # SPH steady: cell areas change by less than this over a chunk
SHIFT = 0.05e-6       # ... and (more than one cell) no centroid moves more than this, m


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


def from_fast(folder, p, s, walls, colour, pressure, steps, kick):
    """SPH started from the fast variant's steady state ``walls`` at level s; prints the
    state every 4 000 steps (pairing shows as nearest fluid neighbours much closer than
    the lattice spacing). Returns the SPH walls, fluid pressures, filled fluid area per
    cell and seconds."""
    t = time.perf_counter()
    state = mfc_sph.write_state(folder / f"sph.s{s}.data", walls, colour, p, s, pressure)
    sph = run.open_lammps(log=folder / f"sph.s{s}.log")
    sph.commands_list(mfc_sph.setup_commands(folder / f"sph.s{s}.data", p))
    sph.commands_list(mfc_sph.level_commands(p, s, mf=state["fluid_mass"]) + ["timestep 2e-9"])
    if kick:
        sph.command(f"displace_atoms wall random {kick * 1e-6:.6g} {kick * 1e-6:.6g} 0 7 units box")
    cf = mfc_metrics.cells(walls, p["n_wall"])
    nw, dx = len(walls), p["fluid_spacing"] * math.sqrt(s)
    done = 0
    while done < steps:
        sph.command(f"run {STAGE_STEPS}")
        done += STAGE_STEPS
        xy, rho = sph_state(sph, p)
        cs = mfc_metrics.cells(xy, p["n_wall"])
        pf = mfc_sph.pressure(p, s, rho[nw:])
        x = mfc_run.positions(sph)[nw:]
        near = cKDTree(x).query(x, 2)[0][:, 1]
        print(f"    {done:6d} steps: area {np.abs(cs['area'] / cf['area'] - 1).max():.4%}, "
              f"perimeter {np.abs(cs['perimeter'] / cf['perimeter'] - 1).max():.4%}, "
              f"centroid {np.hypot(*(cs['centroid'] - cf['centroid']).T).max() * 1e6:.3f} um; "
              f"fluid P {pf.mean() / 1e3:.1f} +- {pf.std() / 1e3:.1f} kPa, "
              f"nearest fluid neighbour {near.mean() / dx:.2f} dx", flush=True)
    sph.close()
    return xy, pf, state["fluid_area"], time.perf_counter() - t


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cells", nargs="?", type=int, default=1, choices=(1, 7))
    parser.add_argument("levels", nargs="?", default="1,0.8,0.6,0.4,0.3")
    parser.add_argument("--from-fast", action="store_true")
    parser.add_argument("--steps", type=int, default=60000)
    parser.add_argument("--kick", type=float, default=0.0, help="um")
    parser.add_argument("--path", choices=mfc_sph.PATHS, default="affine")
    parser.add_argument("--mass", choices=mfc_sph.MASSES, default="scaled",
                        help="fluid mass per level (water: affine path only)")
    parser.add_argument("--ap", type=float, default=0.0, help="artificial pressure epsilon")
    parser.add_argument("--kernel", choices=("lucy", "wendland"), default="lucy")
    parser.add_argument("--boundary", choices=mfc_sph.BOUNDARIES, default="dynamic",
                        help="wall-fluid coupling (adami: walls take the fluid's pressure)")
    parser.add_argument("--chunks", type=int, default=200,
                        help="most chunks of %d SPH steps per level" % STEPS)
    args = parser.parse_args()
    if args.mass == "water" and args.path != "affine":
        parser.error("--mass water needs --path affine")
    ncell, levels = args.cells, [float(s) for s in args.levels.split(",")]
    p = mfc_model.parameters(sph_ap=args.ap, sph_kernel=args.kernel,
                             sph_boundary=args.boundary)
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
        pressure = np.array([fast.numpy.extract_fix("mfc", 0, 2, c, 1) for c in range(ncell)])
        results[s] = (mfc_run.positions(fast), time.perf_counter() - t, report["converged"],
                      pressure)
        previous = s
    colour = np.array(fast.gather_atoms("type", 0, 1)) - 1
    fast.close()
    if args.from_fast:
        print(f"{ncell} cell(s), SPH from the fast steady states, kick {args.kick} um; "
              f"folder {folder}")
        for s in levels:
            xf, tf, ok, pfast = results[s]
            print(f"  s = {s}: fast converged {ok} ({tf:.1f} s), fluid P "
                  f"{pfast.min() / 1e3:.1f} to {pfast.max() / 1e3:.1f} kPa", flush=True)
            xs, pf, fluid, ts = from_fast(folder, p, s, xf, colour, pfast, args.steps, args.kick)
            cf, cs = mfc_metrics.cells(xf, p["n_wall"]), mfc_metrics.cells(xs, p["n_wall"])
            print(f"  s = {s}: fast area/A0 {cf['area'].mean() / p['A_ref']:.4f}, SPH "
                  f"{cs['area'].mean() / p['A_ref']:.4f}; SPH fluid filled / ring "
                  f"{(fluid / cf['area']).mean():.3f}; {ts:.0f} s", flush=True)
        return
    # the SPH model along the same ramp
    mfc_sph.write_data(folder / "sph.data", centres, p)
    sph = run.open_lammps(log=folder / "sph.log")
    sph.commands_list(mfc_sph.setup_commands(folder / "sph.data", p))
    sph.commands_list(mfc_sph.level_commands(p, 1.0) + ["timestep 2e-9"])
    s_now = 1.0
    print(f"{ncell} cell(s); SPH tau = {mfc_sph.TAU:g} s, {' '.join(mfc_sph.fluid_style(p))}, "
          f"path {args.path}, mass {args.mass}; folder {folder}")
    print("   s   model   area/A0   perim/P0   centroid shift (um)   P_fluid (kPa)   seconds")
    for s in levels:
        t = time.perf_counter()
        for stage in mfc_run.stages(s_now, s, 0.05) + ([s] if s != s_now else []):
            mfc_sph.dry(sph, p, stage, s_now, path=args.path, mass=args.mass)
            s_now = stage
            sph.command(f"run {STAGE_STEPS}")
        if args.mass == "water":
            # the layer carried through the last stage, measured again; the fresh fill's
            # after it has relaxed (as built, its ring encloses exactly A0)
            if s == 1.0:
                sph.command(f"run {STAGE_STEPS}")
            mfc_sph.dry(sph, p, s, s, mass="water")
            sph.command(f"run {STAGE_STEPS}")
        cells = mfc_metrics.cells(sph_state(sph, p)[0], p["n_wall"])
        steps = 0
        while True:
            sph.command(f"run {STEPS}")
            steps += STEPS
            new = mfc_metrics.cells(sph_state(sph, p)[0], p["n_wall"])
            change = np.abs(new["area"] / cells["area"] - 1).max()
            shift = np.hypot(*(new["centroid"] - cells["centroid"]).T).max()
            cells = new
            # a single cell's centroid drifts with its fluid's noise; a cluster's must settle
            if (change < TOL and (ncell == 1 or shift < SHIFT)) or steps >= args.chunks * STEPS:
                break
        ts = time.perf_counter() - t
        fl = mfc_sph.fluid_state(sph, p, s)
        xs = fl["walls"]
        xf, tf, ok, _ = results[s]
        cf, cs = mfc_metrics.cells(xf, p["n_wall"]), mfc_metrics.cells(xs, p["n_wall"])
        for name, c, sec in (("fast", cf, tf), ("SPH", cs, ts)):
            pk = f"{fl['pressure'].mean() / 1e3:8.1f}" if name == "SPH" else "     -  "
            print(f"  {s:4.2f}  {name:5s}  {c['area'].mean() / p['A_ref']:.4f}   "
                  f"{c['perimeter'].mean() / (math.pi * p['diameter']):.4f}   "
                  f"{np.hypot(*(c['centroid'] - np.asarray(centres)).T).max() * 1e6:8.3f}"
                  f"          {pk}      {sec:7.1f}", flush=True)
        da = np.abs(cs["area"] / cf["area"] - 1).max()
        dp = np.abs(cs["perimeter"] / cf["perimeter"] - 1).max()
        dc = np.hypot(*(cs["centroid"] - cf["centroid"]).T).max()
        print(f"        SPH vs fast: area {da:.2%}, perimeter {dp:.2%}, centroids {dc * 1e6:.3f} um "
              f"({dc / p['x_ref']:.2%} of x_ref); SPH {steps} steps to steady "
              f"(last chunk: area change {change:.1e}, centroid shift {shift * 1e6:.3f} um); "
              f"fast converged {ok}", flush=True)
        print(f"        SPH fluid: area/A0 {fl['fluid'].mean() / p['A_ref']:.4f}, layer "
              f"{fl['layer'].mean() * 1e6:.2f} um, void {fl['void'].max():.2%}, nearest "
              f"neighbour {fl['nearest'].min():.2f} spacings, P {fl['pressure'].mean() / 1e3:.1f}"
              f" +- {fl['pressure_sd'].mean() / 1e3:.1f} kPa, walls "
              f"{fl['wall_pressure'].mean() / 1e3:.1f} kPa, within h of the wall "
              f"{fl['near_wall_pressure'].mean() / 1e3:.1f} kPa", flush=True)
        # the fast variant's EOS, P_T + K[(A_f/A)^7 - 1], on its own ring and on SPH's
        eos = [mfc_sph.pressure(p, s, p["rho0"] * p["height"]
                                * mfc_model.level(p, s)["fluid_area"] / c["area"]).mean()
               for c in (cf, cs)]
        print(f"        fast EOS pressure: on the fast ring {eos[0] / 1e3:.2f} kPa, on the SPH "
              f"ring {eos[1] / 1e3:.1f} kPa", flush=True)
    sph.close()


if __name__ == "__main__":
    main()
