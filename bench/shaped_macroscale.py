#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""pair_style cgms/shaped on the paper's macroscale tissue (20 x 20 mm, 20 273 beads) at one
level: the tissue's per-atom data by cgms.shaped_data.per_bead of the local build
(shaped_tensor.build(local=True): no (n, n) arrays), written with a kicked start at s (as shaped_tensor.ramp: beads
and F shrunk by sqrt(s), F kicked by 1e-3), then ``minimize`` (cg, line forcezero) to a
force tolerance or an iteration budget; the final state goes to <out>/final.dump (id, x,
y, F at full precision; studies/shaped/newton_check.py compares it with
cgms.shaped_newton). Prints the build time, the minimisation's iterations, force
evaluations, loop time and the largest force left.

Outputs go to --out (default /tmp/cgms-shaped-macro), never into the repository.

Usage (after ``source build/env.sh``):
  /usr/bin/python3 bench/shaped_macroscale.py --dryness 0.6 --ftol 1e-9 --maxiter 20000
"""

import argparse
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "python"))

from cgms import material, shaped_data, shaped_tensor, tissue  # noqa: E402
from shaped_cost import BEST  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=20.0, help="tissue side (mm)")
    ap.add_argument("--dryness", type=float, default=0.6)
    ap.add_argument("--ftol", type=float, default=1e-9)
    ap.add_argument("--maxiter", type=int, default=20000)
    ap.add_argument("--nprocs", type=int, default=1)
    ap.add_argument("--line", default="forcezero", choices=["forcezero", "quadratic", "backtrack"],
                    help="the minimiser's line search (min_modify line)")
    ap.add_argument("--out", type=Path, default=Path("/tmp/cgms-shaped-macro"))
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    mat = material.read("apple")
    L, s = mat["x_ref"], args.dryness
    xy = tissue.rectangle(args.size * 1e-3, args.size * 1e-3, L)
    t = time.time()
    b = dict(shaped_data.per_bead(shaped_tensor.build(xy, mat, local=True)), n=len(xy))
    build = time.time() - t
    rng = np.random.default_rng(1)
    c = xy.mean(axis=0)
    F = math.sqrt(s) * (np.eye(2) + rng.uniform(-1e-3, 1e-3, (len(xy), 2, 2)))
    z = np.concatenate([(c + (xy - c) * math.sqrt(s)).ravel(), F.ravel()])
    shaped_data.write_data(args.out / "macro.data", b, z, overwrite=True)
    text = "\n".join([
        f"plugin load {os.environ['CGMS_PLUGIN']}", "units si", "dimension 2",
        "boundary f f p", "atom_style atomic", "atom_modify map array",
        shaped_data.fix_command(b), shaped_data.read_command("macro.data"),
        "neighbor 1.5e-5 bin", "neigh_modify every 1 delay 0 check yes",
        shaped_data.pair_style(s, BEST), f"pair_coeff * * {material.find('apple')}",
        "min_style cg", f"min_modify dmax 1e-6 norm max line {args.line}", "thermo 1000",
        f"minimize 0 {args.ftol} {args.maxiter} {10 * args.maxiter}",
        "write_dump all custom final.dump id x y "
        + " ".join(f"d2_shaped_F[{k}]" for k in range(1, 5))
        + " modify sort id format float %.17g", ""])
    (args.out / "in.macro").write_text(text)
    cmd = [os.environ["CGMS_LMP"], "-in", "in.macro", "-log", "log.lammps", "-nocite",
           "-screen", "none"]
    if args.nprocs > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(args.nprocs)] + cmd
    t = time.time()
    subprocess.run(cmd, cwd=args.out, check=True)
    wall = time.time() - t
    log = (args.out / "log.lammps").read_text()
    print(f"beads {len(xy)}, per-atom data built in {build:.1f} s")
    for key in ("Stopping criterion", "Iterations, force evaluations", "Force max component",
                "Loop time"):
        print(re.findall(rf"^\s*{key}.*$", log, re.M)[-1].strip())
    print(f"wall time of the LAMMPS process {wall:.1f} s")


if __name__ == "__main__":
    main()
