# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms sensitivity``: the paper's sensitivity study (k_T, k_PA, beta)."""

from .. import pictures, study
from ..calibration import sensitivity
from .options import tissue_source_arguments
from .tissues import tissue_in_folder


def job(args):
    """The paper's section 4.4 on the 86-bead tissue (or --data): table, plot."""
    with tissue_in_folder(args, "sensitivity") as job:
        out = job.out
        print(f"cgms: sensitivity study on the {job.n}-bead tissue; results in {out}",
              flush=True)
        rows = sensitivity.run(job.data, job.mat_file, out)
        done = [r for r in rows if "failed" not in r]
        study.write_csv(done, out / "sensitivity.csv")
        failed = [r for r in rows if "failed" in r]
        if failed:
            (out / "failed.txt").write_text(
                "".join(f"{r['parameter']} x {r['factor']}: {r['failed']}\n" for r in failed))
        pictures.sensitivity(done, out / "sensitivity.png")
        sensitivity.snapshots(out, done)
        print(f"cgms: table {out}/sensitivity.csv, plots {out}/sensitivity.png and "
              f"{out}/snapshots-*.png"
              + (f", failed settings {out}/failed.txt" if failed else ""))
    return 0


def arguments(q):
    q.add_argument("--out", help="results folder (default results/sensitivity/<date-time>)")
    q.add_argument("--material", default="apple", help="material file (default apple)")
    tissue_source_arguments(q, width=1.25, what=" (default 1.25 x 1.5: the 86-bead tissue)")
