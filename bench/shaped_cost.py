#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Cost of one force evaluation per bead: pair_style cgms/shaped against pair_style cgms.

One LAMMPS process runs both cases on the same built tissue, one after the other
(separated by ``clear``): A, the paper's model, ``pair_style cgms`` + ``fix cgms/fluid``
in dynamics (``run N``: one force evaluation per step, the fix's passes inside the pair's
compute); B, the shaped model, ``pair_style cgms/shaped`` under ``minimize`` (min_style cg,
line forcezero) from a kicked state at the same dryness. Timing: LAMMPS's Pair time over
beads x force evaluations (A: steps + 1 set-up, B: the force evaluations the minimiser
reports + its set-up ones, counted from callgrind's calls when it runs). With
``--callgrind`` the process runs under ``valgrind --tool=callgrind`` and the instructions
(Ir, inclusive) of PairCGMS::compute and PairCGMSShaped::compute are divided by their
calls and the beads.

Outputs go to --out (default /tmp/cgms-shaped-bench), never into the repository.

Usage (after ``source build/env.sh``):
  /usr/bin/python3 bench/shaped_cost.py --size 1.5 --steps 200
  /usr/bin/python3 bench/shaped_cost.py --size 1.5 --steps 50 --callgrind
"""

import argparse
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "python"))

from cgms import material, positions, shaped_data, shaped_tensor as st, tissue  # noqa: E402

BEST = {"soft": 0.002, "kg_ratio": 1.0, "strip": "contour", "lamella": 0.391, "void": 0.063,
        "iso": 1.0, "beta_b": 0.04}


def inputs(out, size, steps, s):
    mat = material.read("apple")
    L = mat["x_ref"]
    xy = tissue.rectangle(size * 1e-3, size * 1e-3, L)
    geo = st.build(xy, mat, BEST)
    x, F = st.split(st.fresh_state(geo), geo["n"])
    c = x.mean(axis=0)
    rng = np.random.default_rng(1)
    F = math.sqrt(s) * (F + rng.uniform(-1e-3, 1e-3, F.shape))
    shaped_data.write_data(out / "shaped.data", geo, st.join(c + (x - c) * math.sqrt(s), F),
                           overwrite=True)
    positions.write_data(out / "cgms.data", xy, 4 * L, overwrite=True)
    apple = material.find("apple")
    plugin = os.environ["CGMS_PLUGIN"]
    text = f"""plugin load {plugin}
units si
dimension 2
boundary f f p
atom_style cgms
atom_modify map array sort 0 0
comm_modify vel yes
read_data cgms.data
neighbor 1.5e-5 bin
neigh_modify every 1 delay 0 check yes
pair_style cgms
pair_coeff * * {apple}
fix fl all cgms/fluid dryness {s}
fix nve all nve
fix e2 all enforce2d
timestep 1e-7
run {steps}
clear
plugin load {plugin}
units si
dimension 2
boundary f f p
atom_style atomic
atom_modify map array sort 0 0
{shaped_data.fix_command(geo)}
{shaped_data.read_command("shaped.data")}
neighbor 1.5e-5 bin
neigh_modify every 1 delay 0 check yes
{shaped_data.pair_style(s, BEST)}
pair_coeff * * {apple}
min_style cg
min_modify dmax 1e-6 norm max line forcezero
minimize 0 0 {steps} {10 * steps}
"""
    (out / "in.bench").write_text(text)
    return geo["n"]


def pair_times(log):
    """[(Pair seconds, steps or force evaluations)] of every run in the log."""
    text = log.read_text()
    pair = [float(m) for m in re.findall(r"^Pair\s*\|\s*([0-9.eE+-]+)", text, re.M)]
    steps = [int(m) for m in re.findall(r"for (\d+) steps with", text)]
    evals = [int(m) for m in re.findall(r"Iterations, force evaluations = \d+ (\d+)", text)]
    return pair, steps, evals


def callgrind_calls(path, names):
    """{name: (inclusive Ir, calls)} from a callgrind output file (the calls are summed
    over the call sites, cfn= lines naming the function, compressed or not)."""
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(path)],
                         capture_output=True, text=True).stdout
    ids, calls = {}, dict.fromkeys(names, 0)
    current = None
    for line in path.read_text(errors="replace").splitlines():
        m = re.match(r"c?fn=\((\d+)\)(?: (.*))?", line)
        if m:
            if m.group(2):
                ids[m.group(1)] = m.group(2)
            current = ids.get(m.group(1)) if line.startswith("cfn=") else None
        elif line.startswith("calls=") and current:
            for name in names:
                if current.startswith(name + "("):
                    calls[name] += int(line.split("=")[1].split()[0])
            current = None
    out = {}
    for name in names:
        ir = [int(x.split()[0].replace(",", "")) for x in ann.splitlines()
              if f":{name}(int, int)" in x]
        out[name] = (max(ir, default=0), calls[name])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=1.5, help="tissue side (mm)")
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--dryness", type=float, default=0.6)
    ap.add_argument("--callgrind", action="store_true")
    ap.add_argument("--out", type=Path, default=Path("/tmp/cgms-shaped-bench"))
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    n = inputs(args.out, args.size, args.steps, args.dryness)
    lmp = [os.environ["CGMS_LMP"], "-in", "in.bench", "-log", "log.lammps", "-nocite",
           "-screen", "none"]
    if args.callgrind:
        lmp = ["valgrind", "--tool=callgrind", "--callgrind-out-file=callgrind.out"] + lmp
    subprocess.run(lmp, cwd=args.out, check=True)
    pair, steps, evals = pair_times(args.out / "log.lammps")
    print(f"beads {n}")
    print(f"A pair cgms: {steps[0]} steps, Pair {pair[0]:.4g} s, "
          f"{pair[0] / (n * (steps[0] + 1)) * 1e9:.1f} ns per bead and force evaluation")
    print(f"B pair cgms/shaped: {evals[0]} force evaluations (+1 set-up), Pair {pair[1]:.4g} s, "
          f"{pair[1] / (n * (evals[0] + 1)) * 1e9:.1f} ns per bead and force evaluation")
    if args.callgrind:
        res = callgrind_calls(args.out / "callgrind.out",
                              ["LAMMPS_NS::PairCGMS::compute", "LAMMPS_NS::PairCGMSShaped::compute"])
        for name, (ir, calls) in res.items():
            print(f"{name}: Ir {ir} in {calls} calls: {ir / max(calls, 1) / n:.1f} Ir per bead "
                  "and force evaluation")


if __name__ == "__main__":
    main()
