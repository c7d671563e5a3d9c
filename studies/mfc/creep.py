# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The creep of a dried level (doc/results/mfc.md, "The creep of the dried levels"): carry on
minimising a stored steady state of a study folder, chunk by chunk, and print what each
chunk moves (centroids, with and without the best rigid motion; the outer 30 % of the
cells against the rest), the tissue measures A/A0, P/P0, EL/EL0 (outline of 2.0 median
spacings), the energy; at the end a geometric fit of the per-chunk changes and the
remaining change it extrapolates to.

    source build/env.sh
    /usr/bin/python3 studies/mfc/creep.py results/mfc/<date-time>/calibration 0.6 [chunks]

The folder needs ``state.s<s>.data``, ``lamella.txt`` and ``centroids.s1.txt`` (a study
with the lamella set in the fresh tissue)."""

import sys
import time

import numpy as np

from cgms.mfc import metrics as mfc_metrics, model as mfc_model, run as mfc_run
from cgms import morphology, run

CHUNK = 2000   # iterations, as mfc_run.relax


def measures(xy):
    m = morphology.measures(xy, morphology.default_max_edge(xy, morphology.FINE_EDGE_FACTOR))
    return np.array([m["area"], m["perimeter"], m["elongation"]])


def main(folder, s, chunks=12):
    p = mfc_model.parameters()
    rest = np.loadtxt(f"{folder}/lamella.txt", ndmin=2).reshape(-1, 2)[:, 1]
    lmp = run.open_lammps(log="none")
    lmp.commands_list(mfc_run.setup_commands(f"{folder}/state.s{s:g}.data", p, rest=rest))
    lmp.commands_list(mfc_run.level_commands(p, s))
    fresh = measures(np.loadtxt(f"{folder}/centroids.s1.txt")[:, 1:])

    def centroids():
        return mfc_metrics.cells(mfc_run.positions(lmp), p["n_wall"])["centroid"]

    c0 = centroids()
    r = np.hypot(*(c0 - c0.mean(axis=0)).T)
    outer = r > np.percentile(r, 70)
    rows = [np.r_[measures(c0) / fresh, 0.0, 0.0]]
    lmp.commands_list(mfc_run.minimize_commands(1e-10, 0))
    energy = [lmp.get_thermo("pe")]
    print(f"start: A/A0 {rows[0][0]:.4f}  P/P0 {rows[0][1]:.4f}  EL/EL0 {rows[0][2]:.4f}")
    style = "cg"
    for k in range(chunks):
        t = time.perf_counter()
        before = lmp.extract_global("ntimestep")
        lmp.commands_list(mfc_run.minimize_commands(1e-10, CHUNK, style=style))
        fmax = lmp.get_thermo("fmax")
        stalled = lmp.extract_global("ntimestep") - before < CHUNK and fmax > 1e-10
        style = "fire" if stalled else "cg"     # as mfc_run.relax
        c1 = centroids()
        d = np.hypot(*(c1 - c0).T)
        a, b = c0 - c0.mean(axis=0), c1 - c1.mean(axis=0)
        u, _, vt = np.linalg.svd(a.T @ b)
        nonrigid = np.hypot(*(b - a @ (u @ vt)).T)
        rows.append(np.r_[measures(c1) / fresh, d.max(), d.mean()])
        energy.append(lmp.get_thermo("pe"))
        print(f"chunk {k + 1}: centroids moved max {d.max() * 1e6:.2f} um (without rigid "
              f"motion {nonrigid.max() * 1e6:.2f}), mean {d.mean() * 1e6:.2f} um (outer 30 % "
              f"{d[outer].mean() * 1e6:.2f}, inner {d[~outer].mean() * 1e6:.2f}); A/A0 "
              f"{rows[-1][0]:.4f}  P/P0 {rows[-1][1]:.4f}  EL/EL0 {rows[-1][2]:.4f}; energy "
              f"{energy[-1]:.6e} J; fmax {fmax:.1e} N; {time.perf_counter() - t:.0f} s",
              flush=True)
        c0 = c1
    lmp.close()
    rows, energy = np.array(rows), np.array(energy)
    print("over the chunks: A/A0 {:+.4f}, P/P0 {:+.4f}, EL/EL0 {:+.4f}, energy {:+.3e} J"
          .format(*(rows[-1, :3] - rows[0, :3]), energy[-1] - energy[0]))
    for name, changes in (("A/A0", np.diff(rows[:, 0])), ("P/P0", np.diff(rows[:, 1])),
                          ("EL/EL0", np.diff(rows[:, 2])), ("energy (J)", np.diff(energy)),
                          ("mean centroid shift (m)", rows[1:, 4])):
        ratio, remaining = mfc_run.remaining(changes, last=len(changes))
        print(f"{name}: per-chunk change shrinks by {ratio:.3f} a chunk; extrapolated "
              f"remaining change {remaining:.3g}")


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]), *(int(a) for a in sys.argv[3:]))
