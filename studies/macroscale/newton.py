# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Newton's method on the 2 x 2 cm macroscale tissue (20 273 beads), one level per call:
wall and CPU time, iterations, converged or not, largest force, the shape, and how far
each side of the tissue bends inward (cgms.morphology.side_bow, positive = inward).

    source build/env.sh
    /usr/bin/python3 studies/macroscale/newton.py --material apple --level 0.3 --out /tmp/m

Unlike ``cgms study`` it runs any level, also one outside the range a calibrated material
file says it is valid for (to measure the solver there, not to present the shape as valid).
Each level appends one JSON line to ``<out>/newton.jsonl``; the table of doc/calibration.md
("Macroscale") was made from those lines."""

import argparse
import json
import time
from pathlib import Path

from cgms import material, morphology, study, tissue

#: the paper's macroscale tissue (section 4.2), mm
SIZE = (20.0, 20.0)
#: beads within this many spacings of a side count as that side (side_bow's band)
BAND = 0.5


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--material", default="apple")
    p.add_argument("--level", type=float, required=True, help="dryness s")
    p.add_argument("--out", required=True, help="folder (kept: tissue, logs, dumps)")
    p.add_argument("--set", default="", help="material overrides, 'name value ...'")
    p.add_argument("--max-iterations", type=int, default=60,
                   help="Newton iterations at most (default 60, as cgms study)")
    p.add_argument("--start", metavar="DUMP",
                   help="start from the positions of a dump of an earlier run (its last "
                        "frame; the per-bead reference state is the material's, so this "
                        "continues that run); default: the built lattice")
    args = p.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    mat = material.with_overrides(material.read(args.material), args.set)
    data = out / "tissue.data"
    if not data.exists():
        xy = tissue.rectangle(SIZE[0] * 1e-3, SIZE[1] * 1e-3, mat["x_ref"])
        tissue.write_data(data, xy, 3 * mat["x_ref"])
    name = Path(material.find(args.material)).stem
    folder = out / f"{name}{'-' + args.set.replace(' ', '_') if args.set else ''}"
    if args.start:
        frame = morphology.read_dump(args.start)[-1]
        data = out / f"start-{Path(args.start).name}.data"
        tissue.write_data(data, frame["xy"], 3 * mat["x_ref"], ids=frame["ids"],
                          overwrite=True)
        folder = folder.with_name(folder.name + "-continued")
    cpu, wall = time.process_time(), time.perf_counter()
    r = study.relax(data, material.find(args.material), args.level, folder,
                    method="newton", overrides=args.set,
                    steady=dict(max_steps=args.max_iterations))
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    shape = morphology.measures(r["xy"])
    bows = morphology.side_bow(r["xy"], BAND * mat["x_ref"])
    row = dict(material=name, set=args.set, s=args.level, beads=len(r["xy"]),
               max_iterations=args.max_iterations, start=args.start,
               wall=wall, cpu=cpu, iterations=r["steps"], converged=r["converged"],
               fmax=r["fmax"], moisture=r["moisture"], area=shape["area"],
               perimeter=shape["perimeter"], elongation=shape["elongation"],
               bow_xref={k: v / mat["x_ref"] for k, v in bows.items()},
               valid_range=study.valid_range(material.find(args.material)))
    with open(out / "newton.jsonl", "a") as fh:
        fh.write(json.dumps(row) + "\n")
    print(json.dumps(row))


if __name__ == "__main__":
    main()
