# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""fix cgms/fluid keeps each neighbour distance for the pair only on lists of up to 2^16
entries (issue 18: on large tissues writing and re-reading them costs more memory traffic
than the pair's own square root). Both ways must give the same trajectory to the last bit.
On a tissue above that size the cell-shape energy forces the cache on the steps it is
tallied: thermo every step (cached) against thermo at the end only (not cached)."""

import numpy as np
import pytest

from cgmstest import header, make_tissue, physics, read_dump, run_lmp

pytestmark = pytest.mark.lammps


def test_trajectory_does_not_depend_on_the_distance_cache(tmp_path):
    info = make_tissue(tmp_path, ncols=160, nrows=150, jitter=0.05, seed=4, s=(0.6, 1.0),
                       vscale=1e-3)
    assert info["n"] == 24000  # about 70 000 list entries, above 2^16
    frames = {}
    for name, thermo in (("cached", 1), ("recomputed", 1000)):
        body = (f"thermo {thermo}\nthermo_style custom step pe\nrun 20\n"
                f"write_dump all custom {name}.dump id x y vx vy fx fy "
                "modify format float %.17g\n")
        run_lmp(tmp_path, header() + physics(material_overrides="k_S 0.5") + body)
        frames[name] = read_dump(tmp_path / f"{name}.dump")
    for key in ("x", "y", "vx", "vy", "fx", "fy"):
        assert np.array_equal(frames["cached"][key], frames["recomputed"][key]), key
    assert np.any(frames["cached"]["vx"] != 0.0)
