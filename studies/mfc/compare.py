# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""How far two sets of MFC centroids of one tissue lie apart, level by level (doc/mfc.md,
"Newton"): the RMSD of the cell centroids (eqn 2 of the CGMS paper, as calibrate measures
it: after the best translation, and after the best rigid motion), the largest distance,
and the tissue measures A/A0, P/P0, EL/EL0 of each set with the outline of 2.0 median
spacings (the default 1.5 drops triangles at s = 0.3).

    /usr/bin/python3 studies/mfc/compare.py reference/mfc/calibration <folder>/calibration
"""

import sys
from pathlib import Path

import numpy as np

from cgms import morphology, positions, superpose


def centroids(folder, name):
    ids, xy = positions.read_centroids(Path(folder) / f"centroids.{name}.txt")
    return np.asarray(xy, float)[np.argsort(ids)]


def measures(xy):
    m = morphology.measures(xy, morphology.default_max_edge(xy, morphology.FINE_EDGE_FACTOR))
    return np.array([m["area"], m["perimeter"], m["elongation"]])


def main(old, new):
    names = sorted((f.stem.split(".", 1)[1] for f in Path(new).glob("centroids.s*.txt")),
                   key=lambda n: -float(n[1:]))
    fresh = [measures(centroids(f, "s1")) for f in (old, new)]
    print("| s | RMSD, translation removed (um) | RMSD, rigid motion removed (um) | largest "
          "distance (um) | A/A0 old / new | P/P0 old / new | EL/EL0 old / new |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        a, b = centroids(old, name), centroids(new, name)
        moved = np.hypot(*(superpose.align(a, b, "rigid") - b).T).max()
        ma, mb = measures(a) / fresh[0], measures(b) / fresh[1]
        print(f"| {name[1:]} | {superpose.rmsd(a, b, 'translation') * 1e6:.2f} | "
              f"{superpose.rmsd(a, b, 'rigid') * 1e6:.2f} | {moved * 1e6:.2f} | "
              + " | ".join(f"{x:.4f} / {y:.4f}" for x, y in zip(ma, mb)) + " |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
