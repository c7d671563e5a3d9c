# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Where the shaped model's near-affine tissue stops being a minimum: a fine drying ramp
(steps of 0.05) on one tissue, with the lowest non-rigid eigenvalue of the exact Hessian,
the smallest bead-triangle area over s times its fresh area (the MFC's centroids keep it
at 0.72 or more down to s = 0.3), the number of inverted triangles and the wall states.

    python3 studies/shaped/stability.py [--tissue calibration] [--params JSON]
"""

import argparse
import sys
import time

import numpy as np

import table
from cgms import shaped


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tissue", default="calibration")
    ap.add_argument("--params", default="{}")
    ap.add_argument("--kick", type=float, default=1e-7, help="seeded kick before each "
                    "level (m), to leave a saddle")
    args = ap.parse_args(argv)
    params = table.given_params(shaped, args.params)
    mat, xy, geo = table.geometry(args.tissue, params)
    x = xy
    rng = np.random.default_rng(1)
    a0 = geo["tri_area0"]
    print("| s | lowest non-rigid eigenvalue (N/m) | smallest triangle / (s fresh) | inverted "
          "| walls stretched / buckled | largest force (N) | seconds |")
    print("|---|---|---|---|---|---|---|")
    for s in np.round(np.arange(1.0, 0.249, -0.05), 2):
        lev = shaped.at_level(geo, s)
        t0 = time.time()
        if s < 1:
            x = x + rng.uniform(-args.kick, args.kick, x.shape)
        x, info = shaped.relax(x, lev)
        ev = np.linalg.eigvalsh(shaped.hessian(x, lev).toarray())[3]
        z = shaped.triangle_areas(x, geo["triangles"]) / (s * a0)
        k = shaped.wall_kinds(x, lev)
        print(f"| {s:g} | {ev:.3g} | {z.min():.3f} | {int(np.sum(z < 0))} | "
              f"{k['stretched']} / {k['buckled']} | {info['fmax']:.1e} | "
              f"{time.time() - t0:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
