# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The gap between the MFC's cells, measured (doc/results/shaped-results.md, "The gap between the
cells"): per interior cell, its share of the centroid network (a third of each Delaunay
triangle of the fresh centroids it is a corner of, the same triangles at every level)
less its wall polygon's area, in units of its fresh share; and that gap over the cell's
perimeter ratio P/P0 (a strip along the walls keeps gap / (P/P0) constant). Also the
local deformation of the centroid network (least-squares F of each interior cell's six
bonds): its stretch ratio, the orientation order of its long axes |<exp(2i theta)>| and
its correlation with the cell's own elongation.

    python3 studies/shaped/gap.py [--tissues calibration,...]

Prints one row per tissue and level; a few seconds.
"""

import argparse
import sys
from collections import Counter
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay

ROOT = Path(__file__).resolve().parents[2]
LEVELS = ("0.8", "0.6", "0.4", "0.3")


def load(tissue, s, root=ROOT / "reference" / "mfc"):
    """Cell centroids (n, 2), wall-polygon areas, perimeters and elongations at level s."""
    t = np.genfromtxt(root / tissue / f"cells.s{s}.csv", delimiter=",", names=True)
    return np.column_stack([t["x"], t["y"]]), t["area"], t["perimeter"], t["elongation"]


def network(xy0, longest=1.5):
    """The fresh centroids' Delaunay triangles with no edge over ``longest`` median edges,
    and which cells are interior (on no edge used by a single triangle)."""
    tri = Delaunay(xy0).simplices
    edge = np.stack([np.linalg.norm(xy0[tri[:, i]] - xy0[tri[:, (i + 1) % 3]], axis=1)
                     for i in range(3)], 1)
    tri = tri[edge.max(axis=1) < longest * np.median(edge)]
    count = Counter(tuple(sorted((t[i], t[(i + 1) % 3]))) for t in tri for i in range(3))
    rim = {v for e, c in count.items() if c == 1 for v in e}
    return tri, np.array([i not in rim for i in range(len(xy0))])


def shares(xy, tri):
    """Each cell's third of the signed areas of the triangles it is a corner of."""
    a, b = xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]
    area = 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    out = np.zeros(len(xy))
    for k in range(3):
        np.add.at(out, tri[:, k], area / 3)
    return out


def local_deformation(xy0, xy, tri, interior):
    """Per interior cell with six bonds: stretch ratio and long-axis angle of the
    least-squares F mapping its fresh bonds onto its current ones."""
    nb = [set() for _ in xy0]
    for t in tri:
        for i in range(3):
            a, b = t[i], t[(i + 1) % 3]
            nb[a].add(b)
            nb[b].add(a)
    ratio, angle, cells = [], [], []
    for i in np.flatnonzero(interior):
        k = sorted(nb[i])
        if len(k) < 6:
            continue
        F = np.linalg.lstsq(xy0[k] - xy0[i], xy[k] - xy[i], rcond=None)[0].T
        U, S, _ = np.linalg.svd(F)
        ratio.append(S[0] / S[1])
        angle.append(np.arctan2(U[1, 0], U[0, 0]))
        cells.append(i)
    return np.array(ratio), np.array(angle), np.array(cells)


def rows(tissue):
    xy0, A0, P0, _ = load(tissue, "1")
    tri, interior = network(xy0)
    sh0 = shares(xy0, tri)
    gap0 = np.mean(1 - A0[interior] / sh0[interior])
    out = [dict(tissue=tissue, s=1.0, gap=gap0, per_perimeter=gap0)]
    for s in LEVELS:
        xy, A, P, el = load(tissue, s)
        gap = np.mean((shares(xy, tri)[interior] - A[interior]) / sh0[interior])
        pr = np.mean(P[interior] / P0[interior])
        ratio, angle, cells = local_deformation(xy0, xy, tri, interior)
        out.append(dict(tissue=tissue, s=float(s), gap=gap, per_perimeter=gap / pr,
                        stretch=ratio.mean(), order=abs(np.mean(np.exp(2j * angle))),
                        elongation=el[cells].mean(),
                        correlation=np.corrcoef(ratio, el[cells])[0, 1]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tissues", default="calibration,1.5x1.5,1.5x2.0,1.5x2.5,2.0x2.0,"
                    "2.0x2.5,potato-calibration")
    args = ap.parse_args(argv)
    print("| tissue | s | gap / fresh share | gap / (P/P0) | network stretch ratio "
          "| orientation order | cell elongation | correlation |")
    print("|---|---|---|---|---|---|---|---|")
    for name in args.tissues.split(","):
        for r in rows(name):
            extra = ("| - | - | - | - |" if r["s"] == 1 else
                     f"| {r['stretch']:.3f} | {r['order']:.2f} | {r['elongation']:.2f} "
                     f"| {r['correlation']:+.2f} |")
            print(f"| {name} | {r['s']:g} | {r['gap']:.4f} | {r['per_perimeter']:.4f} "
                  + extra)
    return 0


if __name__ == "__main__":
    sys.exit(main())
