# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Measure the levers of drying inside LAMMPS (in.transport, fix cgms/transport feeding
fix cgms/fluid): the MD steps between moisture steps (``every``), and the transport alone on
the frozen fresh lattice, for the microscale tissue and (``--macro``) the 2 x 2 cm tissue.
Prints the table of doc/results/drying.md ("In LAMMPS"). Run from anywhere with the CGMS
environment (source build/env.sh):

    /usr/bin/python3 studies/drying/levers_lammps.py --every 500 2000 5000 [--outline] [--macro]
"""

import argparse
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

#: the input it runs, with its levers as -var switches
TRANSPORT = Path(__file__).resolve().parents[2] / "examples" / "drying" / "in.transport"

FROZEN = """units si
dimension 2
boundary f f p
atom_style cgms
atom_modify map array
lattice hex 1.508469e-4
region box block -4 {nx4} -4 {ny4} -0.5 0.5
create_box 1 box
region tissue block 0 {nx} 0 {ny} -0.5 0.5
create_atoms 1 region tissue
pair_style zero 2.0e-4
pair_coeff * *
neighbor 1.5e-5 bin
fix tr all cgms/transport apple-drying.params layers 10 dt 1 adapt 0.02 600 outline {outline}
variable dried equal f_tr[3]<0.1
fix halt all halt 1 v_dried > 0.5 error continue
thermo_style custom step f_tr[2] f_tr[3] f_tr[13]
thermo 1
run 100000
"""


def lmp(folder, args, script=None):
    cmd = [os.environ["CGMS_LMP"], "-log", "log.lammps", "-nocite"] + args
    if script:
        (folder / "in.frozen").write_text(script)
        cmd += ["-in", "in.frozen"]
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=folder, capture_output=True, text=True, check=True)
    return proc.stdout, time.perf_counter() - start


def rows(stdout, ncol):
    out = []
    for line in stdout.splitlines():
        words = line.split()
        if len(words) == ncol and words[0].isdigit():
            out.append([float(w) for w in words])
    return np.array(out)


def at(level, xx, yy):
    """y where the falling x first reaches level (linear between rows)."""
    for k in range(1, len(xx)):
        if xx[k] <= level <= xx[k - 1]:
            f = (xx[k - 1] - level) / (xx[k - 1] - xx[k])
            return yy[k - 1] + f * (yy[k] - yy[k - 1])
    return float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--every", type=int, nargs="*", default=[500, 2000, 5000])
    ap.add_argument("--no-micro", action="store_true", help="skip the frozen 247-bead run")
    ap.add_argument("--outline", action="store_true", help="the piece in air, not a window")
    ap.add_argument("--macro", action="store_true", help="also the frozen 2 x 2 cm tissue")
    args = ap.parse_args()
    outline = "yes" if args.outline else "no"
    print("| run | t(0.5) h | t(0.1) h | A/A0 at 0.8 | at 0.5 | at 0.35 | steps | wall s |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for every in args.every:
            out, wall = lmp(tmp, ["-in", str(TRANSPORT), "-var", "every", str(every),
                                  "-var", "rows", "1", "-var", "outline", outline])
            r = rows(out, 10)      # the drying run's rows (the relaxations print fewer)
            t, x, aa = r[:, 1], r[:, 2], r[:, 7]
            print(f"| dynamics, every {every} | {at(0.5, x, t):.3f} | {at(0.1, x, t):.3f} | "
                  f"{at(0.8, x, aa):.4f} | {at(0.5, x, aa):.4f} | {at(0.35, x, aa):.4f} | "
                  f"{len(r) - 1} | {wall:.1f} |")
        sizes = [] if args.no_micro else [("247 beads", 12.6, 9.0)]
        if args.macro:
            sizes.append(("20 273 beads", 132.3, 76.4))
        for name, nx, ny in sizes:
            script = FROZEN.format(nx=nx, ny=ny, nx4=nx + 4, ny4=ny + 4, outline=outline)
            out, wall = lmp(tmp, [], script)
            r = rows(out, 4)
            natoms = next(line.split()[1] for line in out.splitlines()
                          if line.startswith("Created") and "atoms" in line)
            print(f"| frozen, {natoms} beads | {at(0.5, r[:, 2], r[:, 1]):.3f} | "
                  f"{at(0.1, r[:, 2], r[:, 1]):.3f} | 1 | 1 | 1 | {len(r) - 1} "
                  f"(CG {r[1:, 3].mean():.0f} it/step) | {wall:.1f} |")


if __name__ == "__main__":
    main()
