# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""CGMS steady states of the microscale tissues, solved as the calibration solves them.

    python3 studies/calibration/steady.py --material apple-mfc --out OUT [--levels 1,0.8,0.6]
        [--tissues calibration,1.5x1.5,...]

Writes ``OUT/<tissue>/level.s<s>.npy`` (bead positions, m), the layout compare.py reads
from a ``cgms main`` folder. With ``--equal-moisture`` the state stored as level s is the
one whose water content is s times that of the tissue's own fresh (s = 1) steady state,
i.e. the MFC's level s (its fluid mass is s times the fresh one): the dryness s0 that
reaches it is found by Brent's method (xtol 1e-4) and printed. Each steady state is the quasi-static solve, and where FIRE
stops (a bead pushed out of its neighbours' cutoff by a long minimiser step) or reaches
its limit, the dynamics at dt = 5e-8 s (cgms.study.relax_or_fallback, as cgms.calibration.calibrate
does). ``cgms main`` has no fallback: with a material fitted to the MFC, FIRE stops at
s = 0.6 on the 86-bead tissue where the dynamics reaches a steady state.
"""

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from cgms import material, study, tissue
from cgms.tissue import MICROSCALE


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--material", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--levels", default="1,0.8,0.6")
    ap.add_argument("--tissues", default=",".join(MICROSCALE))
    ap.add_argument("--equal-moisture", action="store_true",
                    help="level s = the state holding s times the fresh state's water")
    args = ap.parse_args(argv)
    path = material.find(args.material)
    x_ref = material.read(path)["x_ref"]
    levels = [float(w) for w in args.levels.split(",")]
    for name in args.tissues.split(","):
        if name not in MICROSCALE:
            sys.exit(f"steady.py: unknown tissue {name!r} (one of {', '.join(MICROSCALE)})")
        folder = Path(args.out) / name
        folder.mkdir(parents=True, exist_ok=True)
        w, h = MICROSCALE[name]
        data = folder / "tissue.data"
        if not data.exists():
            tissue.write_data(data, tissue.rectangle(w * 1e-3, h * 1e-3, x_ref), 3 * x_ref)
        def solve(s):
            return study.relax_or_fallback(data, str(path), s,
                                           folder / f"s0-{s:.6f}" if args.equal_moisture
                                           else folder / study.level_name(s))
        fresh = None
        for s in levels:
            target = folder / f"level.{study.level_name(s)}.npy"
            if target.exists():
                continue
            if args.equal_moisture and s < 1:
                fresh = fresh or solve(1.0)[0]["moisture"]
                s0 = brentq(lambda u: solve(round(u, 6))[0]["moisture"] - s * fresh, s, 1.0,
                            xtol=1e-4)
                run, note = solve(round(s0, 6))
                print(f"steady.py: {name}: water s x fresh = {s:g} x {fresh:.4f} at s0 = "
                      f"{s0:.4f}", flush=True)
            else:
                run, note = solve(s)
            np.save(target, run["xy"])
            print(f"steady.py: {name} s = {s:g}: {run['method']}"
                  f"{' (' + note[:60] + ')' if note else ''}, X/X0 {run['moisture']:.4f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
