#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Cost per bead-step of two or more builds of the plugin side by side, and of lj/cut.

run_bench.py times one plugin against lj/cut in one LAMMPS process. Two builds of the
plugin cannot share a process (their styles have the same names), so this driver runs
each case as its own LAMMPS process, interleaved: for every repeat, each plugin on
bench/in.cgms, then lj/cut on bench/in.ljcut, on the same beads. Per run: loop time and
its CPU share (LAMMPS's "% CPU use"), so the loop's CPU time per bead-step; the ratio
to the lj/cut run of the same repeat; medians over repeats with [min-max].

  /usr/bin/python3 bench/compare_plugins.py --size 340x300 --steps 200 --repeats 5 \\
      --plugin before=/path/a/cgmsplugin.so --plugin after=build/cgmsplugin.so
"""

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import run_bench as rb
from cgms import material


def one_run(args, out, label, case, variables, rep):
    log = out / f"{label}.{rep}.log"
    cmd = rb.lmp_command(args, 1) + ["-in", str(rb.HERE / f"in.{case}"), "-log", str(log),
                                     "-screen", "none"]
    for k, v in variables.items():
        cmd += ["-var", k, v]
    subprocess.run(cmd, env=rb.child_env(), cwd=out, check=True)
    text = log.read_text()
    rec = rb.parse_log("BENCH-RUN x\n" + text)["x"]
    bs = rec["atoms"] * rec["steps"]
    return dict(wall=1e9 * rec["loop"] / bs, cpu=1e9 * rec["loop"] * rec["cpu_share"] / bs,
                share=rec["cpu_share"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plugin", action="append", required=True, metavar="LABEL=PATH")
    ap.add_argument("--size", type=rb.parse_size, default=(340, 300))
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--spacing", type=float, default=0.8786, help="lattice spacing, x_ref")
    ap.add_argument("--out", type=Path, default=Path("/tmp/cgms-compare"))
    ap.add_argument("--lmp", default=os.environ.get("CGMS_LMP"))
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--material", default="apple")
    ap.add_argument("--dryness", type=float, default=0.3)
    ap.add_argument("--skin", type=float, default=1.5e-5)
    ap.add_argument("--dt", type=float, default=1e-7)
    ap.add_argument("--lj-epsilon", type=float, default=1e-9)
    args = ap.parse_args()
    plugins = dict(p.split("=", 1) for p in args.plugin)
    args.out.mkdir(parents=True, exist_ok=True)
    mat = material.read(args.material)
    spacing = args.spacing * mat["x_ref"]
    n, data_a, data_b = rb.write_tissue(args.out, *args.size, spacing, mat["x_ref"])
    rows = {label: [] for label in [*plugins, "lj/cut"]}
    load = [os.getloadavg()[0]]
    t0 = time.time()
    for rep in range(args.repeats):
        for label, path in plugins.items():
            common = rb.case_vars(args, mat, Path(path).resolve(), spacing)
            common.update(data=str(data_a), steps=str(args.steps))
            rows[label].append(one_run(args, args.out, label, "cgms", common, rep))
        common = rb.case_vars(args, mat, Path(next(iter(plugins.values()))).resolve(), spacing)
        common.update(data=str(data_b), steps=str(args.steps))
        rows["lj/cut"].append(one_run(args, args.out, "ljcut", "ljcut", common, rep))
        load.append(os.getloadavg()[0])
    print(f"{n} beads, {args.steps} steps, {args.repeats} interleaved repeats, "
          f"{time.time() - t0:.0f} s; load average (1 min) {min(load):.1f}-{max(load):.1f}")
    print("| case | ns per bead-step, wall | CPU | CPU share | ratio to lj/cut, wall | CPU |")
    print("|---|---|---|---|---|---|")
    med = lambda v: f"{statistics.median(v):.1f}"
    span = lambda v: f"{statistics.median(v):.2f} [{min(v):.2f}-{max(v):.2f}]"
    for label, runs in rows.items():
        ratio = [[r[k] / b[k] for r, b in zip(runs, rows["lj/cut"])] for k in ("wall", "cpu")]
        share = statistics.median([r["share"] for r in runs])
        print(f"| {label} | {med([r['wall'] for r in runs])} | {med([r['cpu'] for r in runs])} | "
              f"{share:.2f} | {span(ratio[0])} | {span(ratio[1])} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
