# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Along the k_T/k_PA ridge of apple-mfc.cgms: k_T and k_PA both divided by a factor (their
ratio, what the MFC reference pins down, kept; every other value of the file kept). Per
factor, tissue and level: does FIRE reach the steady state at the given time step, which
solve gave it, how long it took, and the centroid RMSD (eqn 2, rigid motion removed)
against the MFC reference and against the installed file's own state.

    source build/env.sh
    /usr/bin/python3 studies/calibration/ridge.py --factors 1,10,100 --dt 5e-8 --out /tmp/ridge

Writes ``<out>/ridge.csv`` (one row per factor, tissue, level) and prints a summary per
factor. Each steady state: FIRE at ``--dt``, and where it stops or does not converge the
dynamics (cgms.study.relax_or_fallback, at the same dt). doc/results/calibration.md, "A smaller
k_T on the ridge", has the results."""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from cgms import material, positions, study, superpose, tissue
from cgms.tissue import MICROSCALE

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "reference" / "mfc"


def reference(name, s):
    """The MFC centroids of a tissue at level s, in id order (None if not there)."""
    path = REFERENCE / name / f"centroids.{study.level_name(s)}.txt"
    if not path.exists():
        return None
    ids, q = positions.read_centroids(path)
    return q[np.argsort(ids)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--material", default="apple-mfc")
    ap.add_argument("--factors", default="1,10,100")
    ap.add_argument("--levels", default="1,0.8,0.6")
    ap.add_argument("--tissues", default=",".join(MICROSCALE))
    ap.add_argument("--dt", type=float, default=5e-8, help="time step of FIRE (and dynamics)")
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    path = material.find(args.material)
    mat = material.read(path)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    base = {}
    for f in (float(w) for w in args.factors.split(",")):
        overrides = f"k_T {mat['k_T'] / f!r} k_PA {mat['k_PA'] / f!r}"
        for name in args.tissues.split(","):
            w, h = MICROSCALE[name]
            folder = out / f"f{f:g}" / name
            folder.mkdir(parents=True, exist_ok=True)
            data = folder / "tissue.data"
            tissue.write_data(data, tissue.rectangle(w * 1e-3, h * 1e-3, mat["x_ref"]),
                              3 * mat["x_ref"])
            for s in (float(w) for w in args.levels.split(",")):
                start = time.perf_counter()
                run, note = study.relax_or_fallback(data, str(path), s,
                                                    folder / study.level_name(s),
                                                    dt=args.dt, overrides=overrides)
                q = reference(name, s)
                if f == 1:
                    base[name, s] = run["xy"]
                row = dict(factor=f, k_T=mat["k_T"] / f, k_PA=mat["k_PA"] / f, tissue=name,
                           s=s, solved_by="FIRE" if not note else "dynamics",
                           converged=run["converged"], moisture=run["moisture"],
                           seconds=time.perf_counter() - start,
                           rmsd_mfc_um=superpose.rmsd(run["xy"], q, "rigid") * 1e6
                           if q is not None else "",
                           rmsd_installed_um=superpose.rmsd(run["xy"], base[name, s], "rigid")
                           * 1e6 if (name, s) in base else "",
                           why=note[:120])
                rows.append(row)
                um = ", ".join(f"{key[5:-3]} {row[key]:.3f} um" for key in
                               ("rmsd_mfc_um", "rmsd_installed_um") if row[key] != "")
                print(f"ridge.py: x1/{f:g} {name} s = {s:g}: {row['solved_by']}, "
                      f"{row['seconds']:.1f} s; RMSD {um}", flush=True)
    study.write_csv(rows, out / "ridge.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
