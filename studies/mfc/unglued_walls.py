# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Is the wall contraction of the unglued walls what makes the periphery shrink more?
(doc/results/mfc.md, "The periphery".) From a study folder with the lamella set in the fresh
tissue (``lamella.data``, ``lamella.txt``), dry along the ramp to s = 0.6 and 0.3 with
the ring bonds that have no lamella bond at either end (the outer walls and the opened
three-cell corners) kept at their fresh rest length (``unglued``) or, for comparison, with
every wall contracting (``all``); print the local shrinkage of the outline cells and the
inner ones, their cell areas and A/A0, P/P0 (outline of 2.0 median spacings).

    source build/env.sh
    /usr/bin/python3 studies/mfc/unglued_walls.py <study folder> <scratch prefix> [unglued|all]

About 3-5 min for 19 cells."""

import sys
import time

import numpy as np

from cgms.mfc import metrics as mfc_metrics, model as mfc_model, run as mfc_run
from cgms import morphology, run


def edge(xy):
    return morphology.default_max_edge(xy, morphology.FINE_EDGE_FACTOR)


def retype_unglued(lines):
    """The data file's lines with the unglued ring bonds (type 1, no bond of type > 1 at
    either end) given a new bond type; returns the lines, that type and their count."""
    types = next(k for k, line in enumerate(lines) if line.endswith("bond types"))
    new = int(lines[types].split()[0]) + 1
    first = lines.index("Bonds") + 2
    last = first
    while last < len(lines) and lines[last].strip():
        last += 1
    bonds = np.array([[int(v) for v in lines[k].split()] for k in range(first, last)])
    glued = set(bonds[bonds[:, 1] > 1][:, 2:].ravel())
    unglued = (bonds[:, 1] == 1) & np.array([a not in glued and b not in glued
                                             for a, b in bonds[:, 2:]])
    bonds[unglued, 1] = new
    out = list(lines)
    out[types] = f"{new} bond types"
    out[first:last] = [" ".join(map(str, b)) for b in bonds]
    return out, new, int(unglued.sum()), int((bonds[:, 1] == 1).sum() + unglued.sum())


def main(folder, prefix, mode="unglued"):
    p = mfc_model.parameters()
    rest = np.loadtxt(f"{folder}/lamella.txt", ndmin=2).reshape(-1, 2)[:, 1]
    lines = open(f"{folder}/lamella.data").read().split("\n")
    new = None
    if mode == "unglued":
        lines, new, count, ring = retype_unglued(lines)
        print(f"{count} of {ring} ring bonds unglued: kept at the fresh rest length")
    data = f"{prefix}.{mode}.data"
    with open(data, "x") as f:      # never overwrite
        f.write("\n".join(lines))
    lmp = run.open_lammps(log="none")
    lmp.commands_list(mfc_run.setup_commands(data, p, rest=rest))
    if new:   # mfc_run.level_commands sets type 1 per level; this type keeps its fresh length
        lmp.command(f"bond_coeff {new} {p['k_bond'] / 2:.10g} {p['r0_bond']:.10g}")
    fresh = mfc_metrics.cells(mfc_run.positions(lmp), p["n_wall"])
    cen0 = fresh["centroid"]
    outline = np.zeros(len(cen0), bool)
    outline[morphology.outline(cen0, edge(cen0))] = True
    m0 = morphology.measures(cen0, edge(cen0))
    previous = 1.0
    for s in (0.6, 0.3):
        t = time.perf_counter()
        report = mfc_run.ramp(lmp, p, previous, s, max_iterations=30000)
        previous = s
        c = mfc_metrics.cells(mfc_run.positions(lmp), p["n_wall"])
        shrink = morphology.shrinkage(c["centroid"], cen0, edge(cen0))
        area = c["area"] / fresh["area"]
        m = morphology.measures(c["centroid"], edge(c["centroid"]))
        print(f"{mode}, s = {s}: local shrinkage outline / inner {np.nanmean(shrink[outline]):.3f}"
              f" / {np.nanmean(shrink[~outline]):.3f}; cell area / fresh "
              f"{area[outline].mean():.4f} / {area[~outline].mean():.4f}; A/A0 "
              f"{m['area'] / m0['area']:.4f}, P/P0 {m['perimeter'] / m0['perimeter']:.4f}; "
              f"converged {report['converged']} after {report['iterations']} iterations, "
              f"{time.perf_counter() - t:.0f} s", flush=True)
    lmp.close()


if __name__ == "__main__":
    main(*sys.argv[1:])
