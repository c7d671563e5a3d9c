# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Measure a finished MFC study folder's levels again with today's
:func:`cgms.mfc.metrics.summary` (e.g. after the tissue outline's longest edge changed):
from each ``state.s<s>.data`` (full precision) the cell and tissue measures are
recomputed and written over the measures of ``level.s<s>.json``; the solver's record
(iterations, forces, Newton steps, seconds) is kept as it is. The centroids and cells
files do not depend on the outline and are checked, not rewritten.

    source build/env.sh
    /usr/bin/python3 studies/mfc/remeasure.py FOLDER [FOLDER ...]
"""

import sys
from pathlib import Path

import numpy as np

from cgms import folders, positions
from cgms.mfc import metrics as mfc_metrics

sys.path.insert(0, str(Path(__file__).resolve().parent))
from stress import read_state  # noqa: E402  (the state file's reader, one copy)

#: what the measures own in a level record (the rest is the solver's)
MEASURES = ("cells", "A", "P", "EL", "ELpca", "A/A0", "P/P0", "EL/EL0", "ELpca/ELpca0",
            "cell_area", "cell_perimeter", "cell_roundness", "cell_elongation",
            "cell_compactness", "cell_area/A0", "cell_perimeter/P0")


def remeasure(folder):
    folder = Path(folder)
    n_wall = folders.read_json(folder / "setup.json")["parameters"]["n_wall"]
    records = sorted(folder.glob("level.s*.json"),
                     key=lambda p: -float(p.name[len("level.s"):-len(".json")]))
    fresh = None
    for path in records:
        name = path.name[len("level."):-len(".json")]
        xy = read_state(folder / f"state.{name}.data")[0]
        summary, cell = mfc_metrics.summary(xy, n_wall, fresh)
        if fresh is None:
            summary, cell = mfc_metrics.summary(xy, n_wall, summary)
        ids, c = positions.read_centroids(folder / f"centroids.{name}.txt")
        if np.abs(c[np.argsort(ids)] - cell["centroid"]).max() > 1e-12:
            raise SystemExit(f"{folder}: centroids.{name}.txt is not the state's")
        record = folders.read_json(path)
        record.update({k: summary[k] for k in MEASURES if k in summary})
        folders.write_json(path, record)
        fresh = fresh or summary
        print(f"{path}: A/A0 {record['A/A0']:.4f} P/P0 {record['P/P0']:.4f} "
              f"EL/EL0 {record['EL/EL0']:.4f}")


if __name__ == "__main__":
    for f in sys.argv[1:]:
        remeasure(f)
