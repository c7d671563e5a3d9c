# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Which dried shape each of several MFC studies of one tissue reached: per level they
share, each study's tissue measures and its total energy (``level.s<s>.json``: LAMMPS's pe
with the fluid's energy, the same functional for every study of the tissue, so the lower
energy is the more stable of two steady states). Used for the long tissue's two branches
(doc/mfc.md, "How well the dried levels are determined"). Reads folders; instant.

    /usr/bin/python3 studies/mfc/branches.py LABEL=FOLDER [LABEL=FOLDER ...]

FOLDER is a tissue folder of ``cgms mfc --out`` (or of reference/mfc).
"""

import json
import sys
from pathlib import Path

KEYS = ("A/A0", "P/P0", "EL/EL0", "ELpca/ELpca0", "cell_elongation")


def levels(folder):
    """{s: record} of a study folder's level.s<s>.json files."""
    return {float(f.name[len("level.s"):-len(".json")]): json.loads(f.read_text())
            for f in Path(folder).glob("level.s*.json")}


def main(argv=None):
    args = argv if argv is not None else sys.argv[1:]
    studies = [(a.split("=", 1)[0], levels(a.split("=", 1)[1])) for a in args]
    common = sorted(set.intersection(*(set(r) for _, r in studies)), reverse=True)
    print("| s | study | " + " | ".join(KEYS) + " | energy (J) | largest force (N) |")
    print("|---|---|" + "---|" * (len(KEYS) + 2))
    for s in common:
        for label, recs in studies:
            r = recs[s]
            print(f"| {s:g} | {label} | " + " | ".join(f"{r[k]:.4f}" for k in KEYS)
                  + f" | {r['energy']:.5e} | {r['fmax']:.1e} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
