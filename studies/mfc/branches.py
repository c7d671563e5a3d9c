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


def same_functional(folders):
    """None if every folder's ``setup.json`` holds one tissue (its centres) and one set of
    parameters, so that their energies are of one functional; else what differs."""
    setups = {}
    for label, folder in folders:
        path = Path(folder) / "setup.json"
        if not path.is_file():
            return f"{folder} has no setup.json: not a tissue folder of cgms mfc"
        setup = json.loads(path.read_text())
        setups[label] = (setup.get("centres_sha256"), setup.get("parameters"))
    (first, a), *rest = setups.items()
    for label, b in rest:
        if b[0] != a[0]:
            return f"{first} and {label} are of different tissues (cell centres)"
        if b[1] != a[1]:
            return (f"{first} and {label} were made with different parameters, so their "
                    "energies are of different functionals")
    return None


def main(argv=None):
    args = argv if argv is not None else sys.argv[1:]
    if not args or any("=" not in a for a in args):
        sys.exit("usage: branches.py LABEL=FOLDER [LABEL=FOLDER ...] (tissue folders of "
                 "cgms mfc --out)")
    folders = [tuple(a.split("=", 1)) for a in args]
    differ = same_functional(folders)
    if differ:
        sys.exit(f"branches.py: {differ}; compare studies of one tissue and parameters")
    studies = [(label, levels(folder)) for label, folder in folders]
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
