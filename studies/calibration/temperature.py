# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The coarse parameters at a temperature, checked (doc/results/drying.md, "The coarse
parameters at a temperature"). From the repository root, after ``source build/env.sh``:

    python3 studies/calibration/temperature.py --out OUT \\
        --material T20=potentials/apple-mfc-T20.cgms --material T80=... \\
        --reference T20=reference/mfc/calibration --reference T80=... [--levels 1,0.8,0.6]

For each material, the CGMS steady states of the 86-bead calibration tissue at the levels
(as the fit solves them: FIRE, else the dynamics; ``cgms.study.relax_or_fallback``), and
for each pair (material, reference) the RMSD of eqn (2), rigid motion removed, per level
the reference has:
the cross table that says whether a material fitted at one temperature is worse at
another than that temperature's own fit. Also each reference's and each material's tissue
shape (A/A0, P/P0, EL/EL0; the outline's longest edge 2.0 x the median bead spacing, which
holds the dried MFC tissue whole: reference/mfc/README.md). Prints tables and writes
``OUT/temperature.json``.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from cgms import folders, material, morphology, positions, study, superpose, tissue

sys.path.insert(0, str(Path(__file__).resolve().parent))
from potato import calibration_tissue  # noqa: E402  (the 86-cell tissue of any material)

EDGE = 2.0   # the outline's longest edge, times the median nearest-neighbour distance


def shape(xy):
    xy = np.asarray(xy, float)
    return morphology.measures(xy, max_edge=EDGE * morphology.spacing(xy))


def shapes(by_level):
    """{level: {A/A0, P/P0, EL/EL0}} of {level: positions}, against the level s = 1."""
    fresh = shape(by_level[1.0])
    return {s: morphology.normalise(shape(xy), fresh) for s, xy in by_level.items()}


def pairs(text, what):
    out = {}
    for item in text:
        name, _, value = item.partition("=")
        if not value:
            sys.exit(f"temperature.py: --{what} {item}: expected NAME=PATH")
        out[name] = value
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--material", action="append", required=True, help="NAME=FILE")
    ap.add_argument("--reference", action="append", required=True, help="NAME=MFC folder")
    ap.add_argument("--levels", default="1,0.8,0.6")
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    levels = [float(w) for w in args.levels.split(",")]
    if 1.0 not in levels:
        sys.exit("temperature.py: --levels must hold 1 (the shapes are against it)")
    mats, refs = pairs(args.material, "material"), pairs(args.reference, "reference")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    data = out / "tissue.data"
    if not data.exists():
        tissue.write_data(data, calibration_tissue("apple"),
                          3 * material.read("apple")["x_ref"])
    reference = {}
    for name, folder in refs.items():
        reference[name] = {}
        for s in levels:   # a level the reference lacks is left out of its columns
            path = Path(folder) / f"centroids.s{s:g}.txt"
            if path.is_file():
                ids, xy = positions.read_centroids(path)
                reference[name][s] = xy[np.argsort(ids)]
    steady, methods = {}, {}
    for name, path in mats.items():
        steady[name], methods[name] = {}, {}
        for s in levels:
            run, note = study.relax_or_fallback(data, str(material.find(path)), s,
                                                out / name / study.level_name(s))
            steady[name][s] = np.asarray(run["xy"])
            methods[name][s] = run.get("method", "") + (" (fallback)" if note else "")
    x_ref = material.read("apple")["x_ref"]
    rmsd = {m: {r: {s: superpose.rmsd(steady[m][s], reference[r][s], "rigid")
                    for s in reference[r]} for r in refs} for m in mats}
    result = dict(levels=levels, materials=mats, references=refs, methods=methods,
                  rmsd_um={m: {r: {f"{s:g}": v * 1e6 for s, v in row.items()}
                               for r, row in rr.items()} for m, rr in rmsd.items()},
                  reference_shape={r: {f"{s:g}": v for s, v in shapes(reference[r]).items()}
                                   for r in refs},
                  cgms_shape={m: {f"{s:g}": v for s, v in shapes(steady[m]).items()}
                              for m in mats},
                  x_ref=x_ref, edge=EDGE)
    folders.write_json(out / "temperature.json", result)
    print("RMSD (um, rigid removed) of each material's steady states against each reference, "
          "s = " + " / ".join(f"{s:g}" for s in levels))
    print("| material | " + " | ".join(refs) + " |")
    for m in mats:
        print(f"| {m} | " + " | ".join(" / ".join(f"{rmsd[m][r][s] * 1e6:.2f}"
                                                  if s in rmsd[m][r] else "-" for s in levels)
                                     for r in refs) + " |")
    print("\nshape (A/A0, P/P0, EL/EL0) at s = " + ", ".join(f"{s:g}" for s in levels if s < 1))
    for kind, table in (("MFC", result["reference_shape"]), ("CGMS", result["cgms_shape"])):
        for name, row in table.items():
            print(f"| {kind} {name} | " + " | ".join(
                f"{row[f'{s:g}']['A/A0']:.4f}, {row[f'{s:g}']['P/P0']:.4f}, "
                f"{row[f'{s:g}']['EL/EL0']:.4f}" if f"{s:g}" in row else "-"
                for s in levels if s < 1) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
