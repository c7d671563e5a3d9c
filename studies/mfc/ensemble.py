# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""An MFC reference ensemble of one tissue: the mean and the spread, level by level, of
several ``cgms mfc`` runs that differ only in the ramp's kick seed (``--seed``; the dried
levels land on neighbouring minima that the seed alone moves: doc/mfc.md).

    /usr/bin/python3 studies/mfc/ensemble.py OUT MEMBER [MEMBER ...]

Each MEMBER is a tissue folder of ``cgms mfc`` (``centroids.s<s>.txt``, ``level.s<s>.json``);
only the levels every member has are used. Writes into OUT:

- ``measures.csv``: per level and measure the member count, mean, sample standard deviation
  (ddof 1), min, max and the members' values in the order given. Tissue measures from the
  cell centroids' outline (:func:`cgms.morphology.measures`), each member normalised by its
  own s = 1 state: ``A/A0``, ``P/P0``, ``EL/EL0`` (the paper's), ``ELpca/ELpca0`` (second
  moments), at the outline's longest edge 2.0 median spacings (as doc/results/validation.md) and
  2.5 (suffix ``@2.5``; the default 1.5 of ``level.s<s>.json`` drops cells at s = 0.3 and
  counts holes); cell means from the
  records: ``cell_area/A0``, ``cell_perimeter/P0``, ``cell_roundness``,
  ``cell_elongation``; ``rmsd_to_mean_um``, each member's centroid RMSD from the mean
  (rigid motion removed); ``pairwise_rmsd_um``, that of every pair of members; and
  ``floor_um``, the spread sigma per centroid, sqrt(mean pairwise RMSD^2 / 2), the RMSD a
  deterministic model cannot beat against one member (doc/results/calibration.md, "The floor").
- ``centroids.s<s>.txt``: the mean centroids after superposition (the reference format,
  cell id = bead id, in the first member's frame): each member moved by the best rigid
  motion (:func:`cgms.superpose.align`) onto the mean, the mean recomputed, until it stops
  moving (generalised Procrustes).
- ``spread.s<s>.txt``: per cell the RMS and the largest distance of the members' centroids
  from the mean (um).
"""

import csv
import json
import sys
from pathlib import Path

import numpy as np

from cgms import morphology, positions, superpose

OUTLINES = ((2.0, ""), (2.5, "@2.5"))   # longest outline edge / median spacing, suffix
TISSUE = ("A/A0", "P/P0", "EL/EL0", "ELpca/ELpca0")
CELL = ("cell_area/A0", "cell_perimeter/P0", "cell_roundness", "cell_elongation")


def centroids(folder, name):
    ids, xy = positions.read_centroids(Path(folder) / f"centroids.{name}.txt")
    return np.asarray(xy, float)[np.argsort(ids)]


def levels(folder):
    return {float(f.name[len("centroids.s"):-len(".txt")])
            for f in Path(folder).glob("centroids.s*.txt")}


def tissue_measures(xy, fresh):
    """The tissue measures of ``xy`` normalised by those of ``fresh``, at each outline."""
    out = {}
    for factor, suffix in OUTLINES:
        def measure(q):
            return morphology.measures(q, morphology.default_max_edge(q) * factor / 1.5)
        norm = morphology.normalise(measure(xy), measure(fresh))
        out.update({k + suffix: norm[k] for k in TISSUE})
    return out


def mean_shape(shapes, tol=1e-12, rounds=100):
    """Generalised Procrustes: the mean of ``shapes`` each rigidly superposed on it, and the
    superposed shapes. Starts from the first shape; stops when the mean moves less than
    ``tol`` times its size."""
    mean = shapes[0]
    size = np.ptp(mean, axis=0).max()
    for _ in range(rounds):
        moved = [superpose.align(q, mean, "rigid") for q in shapes]
        new = np.mean(moved, axis=0)
        if np.abs(new - mean).max() < tol * size:
            return new, moved
        mean = new
    raise RuntimeError(f"the mean shape did not settle in {rounds} rounds")


def stats(values):
    v = np.asarray(values, float)
    return dict(n=len(v), mean=v.mean(), std=v.std(ddof=1) if len(v) > 1 else 0.0,
                min=v.min(), max=v.max(), values=" ".join(f"{x:.6g}" for x in v))


def main(out, members):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    common = sorted(set.intersection(*(levels(m) for m in members)), reverse=True)
    if 1.0 not in common:
        sys.exit("ensemble.py: every member needs its fresh level s = 1")
    fresh = [centroids(m, "s1") for m in members]
    rows = []
    for s in common:
        name = f"s{s:g}"
        xy = [centroids(m, name) for m in members]
        per = [tissue_measures(q, f) for q, f in zip(xy, fresh)]
        records = [json.loads((Path(m) / f"level.{name}.json").read_text()) for m in members]
        for key in per[0]:
            rows.append(dict(s=s, measure=key, **stats([p[key] for p in per])))
        for key in CELL:
            rows.append(dict(s=s, measure=key, **stats([r[key] for r in records])))
        mean, moved = mean_shape(xy)
        d = np.stack([np.hypot(*(q - mean).T) for q in moved])   # members x cells
        rows.append(dict(s=s, measure="rmsd_to_mean_um",
                         **stats(np.sqrt(np.mean(d ** 2, axis=1)) * 1e6)))
        pairs = [superpose.rmsd(xy[i], xy[j], "rigid") * 1e6
                 for i in range(len(xy)) for j in range(i + 1, len(xy))]
        rows.append(dict(s=s, measure="pairwise_rmsd_um", **stats(pairs)))
        # two draws from minima of spread sigma lie sqrt(2) sigma apart (doc/calibration.md,
        # "The floor"): the RMSD a deterministic model cannot beat against one member
        floor = float(np.sqrt(np.mean(np.square(pairs)) / 2))
        rows.append(dict(s=s, measure="floor_um", n=len(pairs), mean=floor, std="", min="",
                         max="", values=""))
        label = ", ".join(str(m) for m in members)
        positions.write_centroids(out / f"centroids.{name}.txt", mean, overwrite=True,
                                  comment=f"MFC ensemble mean centroids at s = {s:g}, "
                                          f"{len(members)} members (studies/mfc/ensemble.py): "
                                          f"{label}")
        spread = np.column_stack([np.arange(1, d.shape[1] + 1), np.sqrt(np.mean(d ** 2, axis=0))
                                  * 1e6, d.max(axis=0) * 1e6])
        np.savetxt(out / f"spread.{name}.txt", spread, fmt=["%d", "%.4f", "%.4f"],
                   header=f"MFC ensemble at s = {s:g}, {len(members)} members: per cell the RMS "
                          "and largest distance (um) of the members' centroids from the mean "
                          "(rigid motion removed)\nid rms_um max_um")
    with open(out / "measures.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["s", "measure", "n", "mean", "std", "min", "max",
                                           "values"])
        w.writeheader()
        for r in rows:
            w.writerow({k: f"{v:.6g}" if isinstance(v, float) else v for k, v in r.items()})
    return rows


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__.split("\n\n")[1])
    main(sys.argv[1], sys.argv[2:])
