# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Markdown tables of a `cgms mfc` study folder: tissue-level results and cost per tissue
and level (doc/mfc.md).

    /usr/bin/python3 studies/mfc/tables.py results/mfc/<date-time> [more folders]
"""

import json
import sys
from pathlib import Path


def levels(folder):
    out = []
    for tissue in sorted(p for p in Path(folder).iterdir() if p.is_dir()):
        for f in sorted(tissue.glob("level.s*.json"), key=lambda f: -float(f.stem[7:])):
            r = json.loads(f.read_text())
            r["tissue"] = tissue.name
            out.append(r)
    return out


def main(folders):
    rows = [r for f in folders for r in levels(f)]
    print("| tissue | cells | s | A/A0 | P/P0 | EL/EL0 | cell area / fresh | cell perimeter / fresh "
          "| cell roundness | cell elongation |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['tissue']} | {r['cells']} | {r['s']:g} | {r['A/A0']:.4f} | {r['P/P0']:.4f} | "
              f"{r['EL/EL0']:.4f} | {r['cell_area/A0']:.4f} | {r['cell_perimeter/P0']:.4f} | "
              f"{r['cell_roundness']:.3f} | {r['cell_elongation']:.3f} |")
    print()
    print("| tissue | wall particles | s | iterations | largest force (N) | last-chunk centroid "
          "shift (um) | converged | seconds |")
    print("|---|---|---|---|---|---|---|---|")
    total = {}
    for r in rows:
        total[r["tissue"]] = total.get(r["tissue"], 0.0) + r["seconds"]
        print(f"| {r['tissue']} | {r['particles']} | {r['s']:g} | {r['iterations']} | "
              f"{r['fmax']:.1e} | {r['shift'] * 1e6:.4f} | {'yes' if r['converged'] else 'NO'} | "
              f"{r['seconds']:.0f} |")
    print()
    for name, sec in total.items():
        print(f"- {name}: {sec / 60:.1f} min for its levels")


if __name__ == "__main__":
    main(sys.argv[1:])
