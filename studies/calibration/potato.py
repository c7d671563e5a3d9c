# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The second tissue: potato through the chain MFC parameters -> MFC reference -> CGMS fit
(doc/calibration.md, "Potato"). From the repository root, after ``source build/env.sh``:

    python3 studies/calibration/potato.py mfc --out OUT [--levels 1,0.8] [--resume]
    python3 studies/calibration/fit.py --material potato --mfc OUT/calibration ...

``mfc`` dries the 86-cell calibration tissue of potato (the apple layout scaled by the
ratio of lattice spacings, so cell i is bead i of the same 86-bead CGMS tissue) in the
fine-scale model with potato's shared values from potentials/potato.cgms and the MFC
values below, and writes the reference centroids to OUT/calibration (the format of
reference/mfc/). Each level takes minutes; run the dried ones with ``--resume``.
"""

import argparse
import sys
from datetime import datetime
from pathlib import Path

from cgms import material, tissue
from cgms.mfc import model as mfc_model, run as mfc_run, study as mfc_study

#: the MFC values potato changes (the rest are mfc_model.MFC's):
#: - wall_Et: the wall is given the same turgid strain as apple's MFC wall (4.5 %:
#:   eps = P_f D / (2 E t)), a decision, for lack of a measured potato wall modulus:
#:   E t = 3e5 Pa x 200e-6 m / (2 x 0.0455) = 660 N/m, i.e. E = 0.66 GPa for the
#:   1 um wall below. No potato wall modulus was found; single cultured tomato cells
#:   give E = 2.3 +- 0.2 GPa (Wang, Wang and Thomas 2004, Ann. Bot. 93, 443-453), which
#:   with a 1 um wall would be E t = 2300 N/m and a turgid strain of 1.3 %.
#: - wall_thickness: potato parenchyma walls thicken to 0.8-1.36 um at maturity, about
#:   1 um in Russet Burbank (Am. Potato J., "Cell wall thickness during growth of domestic
#:   and foreign potato cultivars", doi 10.1007/BF02851771; abstract).
POTATO_MFC = dict(wall_Et=660.0, wall_thickness=1.0e-6)

#: the apple calibration tissue (mm), cgms.tissue.MICROSCALE["calibration"]
APPLE_CALIBRATION = (1.25e-3, 1.5e-3)


def parameters():
    """The MFC parameters of potato."""
    return mfc_model.parameters("potato", **POTATO_MFC)


def calibration_tissue(name="potato"):
    """Bead (= cell) centres of the 86-cell calibration tissue of a material: apple's
    rectangle scaled by x_ref / x_ref(apple), so that the lattice, the bead count and the
    ids are apple's."""
    x_ref = material.read(name)["x_ref"]
    scale = x_ref / material.read("apple")["x_ref"]
    w, h = APPLE_CALIBRATION
    return tissue.rectangle(w * scale, h * scale, x_ref)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=["mfc", "tissue"],
                    help="mfc: the MFC reference; tissue: write the CGMS data file only")
    ap.add_argument("--out", required=True)
    ap.add_argument("--levels", default="1,0.8,0.6")
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--stages", choices=("steady", "chunk"), default="steady",
                    help="the drying path: quasi-static (default) or chunked, as "
                         "python3 -m cgms mfc --stages")
    args = ap.parse_args(argv)
    out = Path(args.out)
    xy = calibration_tissue()
    if args.what == "tissue":
        x_ref = material.read("potato")["x_ref"]
        tissue.write_data(out, xy, 3 * x_ref)
        print(f"potato.py: {len(xy)} beads -> {out}")
        return 0
    folder = out / "calibration"
    if folder.exists() and not args.resume:
        sys.exit(f"potato.py: {folder} exists; pass --resume to continue it")
    levels = [float(w) for w in args.levels.split(",")]
    p = parameters()
    print(f"potato.py: MFC of potato, {len(xy)} cells, turgid wall strain "
          f"{100 * p['strain_turgid']:.2f} %, levels {levels}", flush=True)
    steady = args.stages == "steady"
    rows = mfc_study.dry(xy, p, folder, levels, steady_stages=steady,
                         stage=mfc_run.REFERENCE_PATH["stage"] if steady else
                         mfc_run.DEFAULTS["stage"],
                         say=lambda line: print(line, flush=True))
    mfc_study.write_table(rows, folder / f"summary-{datetime.now():%H%M%S}.csv")
    for r in rows:
        print(f"  s {r['s']:.2f}  A/A0 {r['A/A0']:.4f}  P/P0 {r['P/P0']:.4f}  "
              f"EL/EL0 {r['EL/EL0']:.4f}  cell A/A0 {r['cell_area/A0']:.4f}  "
              f"{'converged' if r['converged'] else 'NOT converged'}  {r['seconds']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
