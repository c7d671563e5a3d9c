# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Why the periphery of an MFC tissue shrinks more than its interior (doc/mfc.md, "The
periphery"): from a study folder's wall dumps, per level, the local area shrinkage of the
outline cells and the rest (cgms.morphology.shrinkage on the centroids, outline of 2.0
median spacings), their own polygon areas, their size along and across the radial
direction (from the tissue centre) against fresh, and the centroid spacings of
interior-interior, outline-interior and outline-outline neighbours against fresh.

    source build/env.sh
    /usr/bin/python3 studies/mfc/periphery.py results/mfc/<date-time>/calibration"""

import sys

import numpy as np

from cgms.mfc import metrics as mfc_metrics, model as mfc_model
from cgms import morphology


def edge(xy):
    return morphology.default_max_edge(xy, morphology.FINE_EDGE_FACTOR)


def load(folder, s, n_wall):
    xy = morphology.read_dump(f"{folder}/walls.s{s}.dump")[-1]["xy"]
    return xy.reshape(-1, n_wall, 2), mfc_metrics.cells(xy, n_wall)


def sizes(rings, centroids, radial):
    """RMS extent of each wall ring along ``radial`` and across it."""
    q = rings - centroids[:, None, :]
    along = np.einsum("cnk,ck->cn", q, radial)
    across = np.einsum("cnk,ck->cn", q, np.c_[-radial[:, 1], radial[:, 0]])
    return along.std(axis=1), across.std(axis=1)


def main(folder, *levels):
    levels = levels or ("0.8", "0.6", "0.4", "0.3")
    n_wall = mfc_model.parameters()["n_wall"]
    rings0, c0 = load(folder, "1", n_wall)
    cen0 = c0["centroid"]
    out = np.zeros(len(cen0), bool)
    out[morphology.outline(cen0, edge(cen0))] = True
    radial = cen0 - cen0.mean(axis=0)
    radial /= np.hypot(*radial.T)[:, None]
    along0, across0 = sizes(rings0, cen0, radial)
    tri = morphology.triangles(cen0, edge(cen0))
    pairs = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]),
                              axis=1), axis=0)
    kind = out[pairs].sum(axis=1)       # 0 interior-interior, 1 outline-interior, 2 outline-outline
    length0 = np.hypot(*(cen0[pairs[:, 0]] - cen0[pairs[:, 1]]).T)
    print(f"{out.sum()} outline cells, {(~out).sum()} interior; values outline / interior")
    for s in levels:
        rings, c = load(folder, s, n_wall)
        cen = c["centroid"]
        shrink = morphology.shrinkage(cen, cen0, edge(cen0))
        area = c["area"] / c0["area"]
        along, across = sizes(rings, cen, radial)
        along, across = along / along0, across / across0
        length = np.hypot(*(cen[pairs[:, 0]] - cen[pairs[:, 1]]).T) / length0
        print(f"s = {s}: local shrinkage {np.nanmean(shrink[out]):.3f} / "
              f"{np.nanmean(shrink[~out]):.3f}; cell area / fresh {area[out].mean():.4f} / "
              f"{area[~out].mean():.4f}; radial size / fresh {along[out].mean():.3f} / "
              f"{along[~out].mean():.3f}; tangential {across[out].mean():.3f} / "
              f"{across[~out].mean():.3f}; centroid spacing / fresh: interior-interior "
              f"{length[kind == 0].mean():.3f}, outline-interior {length[kind == 1].mean():.3f}, "
              f"outline-outline {length[kind == 2].mean():.3f}")


if __name__ == "__main__":
    main(sys.argv[1], *sys.argv[2:])
