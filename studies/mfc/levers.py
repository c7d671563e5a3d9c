# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Compare the MFC model's levers (lamella form and stiffness, bending stiffness) on a small
tissue: per level the cell measures, the tissue measures, local shrinkage of the periphery
and the interior, convergence and wall time (doc/mfc.md, decisions).

    /usr/bin/python3 studies/mfc/levers.py OUT CELLS LEVELS [key=value ...]

CELLS: 7, 19 (hexagonal clusters) or a tissue name of `cgms mfc` (calibration = 86 cells);
LEVELS: e.g. 1,0.6,0.3; key=value: MFC parameters, e.g. lamella=lj bend_factor=10
lamella_k=73.
"""

import math
import sys

import numpy as np

from cgms.mfc import model as mfc_model, study as mfc_study
from cgms import morphology, tissue
from cgms.tissue import MICROSCALE


def cluster(rings, spacing):
    """Centres of a hexagonal cluster: one cell and ``rings`` rings around it."""
    e1 = spacing * np.array([0.0, 1.0])
    e2 = spacing * np.array([math.cos(math.pi / 6), math.sin(math.pi / 6)])
    return np.array([q * e1 + r * e2 for q in range(-rings, rings + 1)
                     for r in range(-rings, rings + 1) if abs(q + r) <= rings])


def main(out, cells, levels, *options):
    over = {}
    for item in options:
        key, value = item.split("=", 1)
        over[key] = value if key == "lamella" else float(value)
    p = mfc_model.parameters(**over)
    if cells in MICROSCALE:
        w, h = MICROSCALE[cells]
        centres = tissue.rectangle(w * 1e-3, h * 1e-3, p["x_ref"])
    else:
        centres = cluster({"1": 0, "7": 1, "19": 2, "37": 3}[cells], p["x_ref"])
    levels = [float(s) for s in levels.split(",")]
    results = mfc_study.dry(centres, p, out, levels, say=lambda line: None)
    fresh = None
    print(f"{len(centres)} cells, {over}")
    built, now = (morphology.measures(np.asarray(c)) for c in
                  (centres, np.loadtxt(f"{out}/centroids.s1.txt")[:, 1:]))
    print(f"fresh against built: width {now['width'] / built['width'] - 1:+.2%}, height "
          f"{now['height'] / built['height'] - 1:+.2%}, area {now['area'] / built['area'] - 1:+.2%}")
    print("    s  cellA   cellP  round  elong   A/A0   P/P0  EL/EL0  shrink(per/int)   conv "
          " shift(um)  iters  secs")
    for r in results:
        s = r["s"]
        xy = np.loadtxt(f"{out}/centroids.s{s:g}.txt")[:, 1:] if s != 1 else None
        if fresh is None:
            fresh = np.loadtxt(f"{out}/centroids.s1.txt")[:, 1:]
            outline = morphology.outline(fresh) if len(fresh) > 3 else np.arange(len(fresh))
            inner = np.setdiff1d(np.arange(len(fresh)), outline)
        per = inn = float("nan")
        if xy is not None and len(fresh) > 3:
            shrink = morphology.shrinkage(xy, fresh)
            per, inn = np.nanmean(shrink[outline]), np.nanmean(shrink[inner])
        print(f"  {s:4.2f} {r['cell_area/A0']:.4f} {r['cell_perimeter/P0']:.4f} "
              f"{r['cell_roundness']:.3f} {r['cell_elongation']:.3f} "
              f"{r.get('A/A0', 1):.4f} {r.get('P/P0', 1):.4f} {r.get('EL/EL0', 1):.4f} "
              f"{per:.3f}/{inn:.3f}   {'yes' if r['converged'] else 'NO '}  "
              f"{r['shift'] * 1e6:8.3f}  {r['iterations']:6d} {r['seconds']:6.1f}")


if __name__ == "__main__":
    main(*sys.argv[1:])
