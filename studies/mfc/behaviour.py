# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Tissue-level behaviour of a `cgms mfc` tissue folder against what the CGMS paper reports
for the MFC (doc/results/mfc.md, "Tissues"): fresh lateral widening, contraction towards the centre,
periphery shrinking less than the interior, monotone A/A0, P/P0, EL/EL0.

    /usr/bin/python3 studies/mfc/behaviour.py results/mfc/<date-time>/calibration [name] [edge]

edge: the outline's longest edge in median nearest-neighbour spacings of each state (default
the CGMS default, 1.5; the dried cells' irregular centroids need about 2, doc/mfc.md).
"""

import sys
from pathlib import Path

import numpy as np

from cgms.mfc import model as mfc_model
from cgms import morphology, positions, tissue
from cgms.tissue import MICROSCALE


def edge_of(xy, factor):
    """The outline's longest edge: ``factor`` median nearest-neighbour spacings (None: the
    CGMS default)."""
    if factor is None:
        return None
    from scipy.spatial import cKDTree
    return factor * float(np.median(cKDTree(xy).query(xy, k=2)[0][:, 1]))


def main(folder, name=None, edge=None):
    folder = Path(folder)
    p = mfc_model.parameters()
    edge = None if edge is None else float(edge)
    w, h = MICROSCALE[name or folder.name]
    built = tissue.rectangle(w * 1e-3, h * 1e-3, p["x_ref"])
    levels = sorted((float(f.stem.split(".s", 1)[1]), f) for f in folder.glob("centroids.s*.txt"))
    states = {s: positions.read_centroids(f)[1] for s, f in levels[::-1]}
    fresh = states[1.0]
    m0 = morphology.measures(built, edge_of(built, edge))
    m1 = morphology.measures(fresh, edge_of(fresh, edge))
    print(f"fresh against the built lattice: width {m1['width'] / m0['width'] - 1:+.2%}, "
          f"height {m1['height'] / m0['height'] - 1:+.2%}, area {m1['area'] / m0['area'] - 1:+.2%}")
    outline = morphology.outline(fresh, edge_of(fresh, edge))
    inner = np.setdiff1d(np.arange(len(fresh)), outline)
    centre = fresh.mean(axis=0)
    r_fresh = np.hypot(*(fresh - centre).T)
    print("   s   A/A0    P/P0    EL/EL0  mean distance to centre / fresh   local shrinkage: "
          "periphery  interior")
    for s, xy in states.items():
        m = morphology.normalise(morphology.measures(xy, edge_of(xy, edge)), m1)
        r = np.hypot(*(xy - xy.mean(axis=0)).T)
        shrink = morphology.shrinkage(xy, fresh)
        print(f"  {s:4.2f} {m['A/A0']:.4f}  {m['P/P0']:.4f}  {m['EL/EL0']:.4f}   "
              f"{r.mean() / r_fresh.mean():.4f}                            "
              f"{np.nanmean(shrink[outline]):.4f}     {np.nanmean(shrink[inner]):.4f}")


if __name__ == "__main__":
    main(*sys.argv[1:4])   # folder [tissue name, default the folder's] [edge]
