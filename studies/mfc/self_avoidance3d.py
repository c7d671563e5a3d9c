# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""How much the 3-D block's dried levels depend on the walls' self-avoidance (doc/results/
mfc.md, "3-D walls that pass through themselves"): ``cgms.mfc.study3d`` on the 16-cell
block with the self-avoidance's radius R0 (m) and strength E0 (J per 3-D wall particle)
in place of the model's (d_p and the scaled 2-D E0, doc/mfc.md, "Self-avoidance").

    /usr/bin/python3 studies/mfc/self_avoidance3d.py OUT R0 [E0]

The study stops at a crossed wall as usual (printed). Compare with
``studies/mfc/compare3d.py reference/mfc3d/block2 OUT``.
"""

import sys
from pathlib import Path

from cgms.mfc import model as mfc_model, study3d, tissue3d


def main(argv):
    out, r0 = Path(argv[0]), float(argv[1])
    e0 = float(argv[2]) if len(argv) > 2 else None
    wall = tissue3d.wall

    def changed(*args, **kw):
        w = wall(*args, **kw)
        w["self_r0"] = r0
        if e0 is not None:
            w["self_E0"] = e0
        return w
    tissue3d.wall = changed
    try:
        study3d.dry(out, mfc_model.parameters("apple"), 2,
                    say=lambda m: print(m[:300], flush=True))
    except study3d.WallCrossing as err:
        print(f"stopped: {err}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
