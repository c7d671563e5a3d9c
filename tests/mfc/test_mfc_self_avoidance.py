# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The MFC wall's self-avoidance holds a wall particle pressed against a bond of its own
ring: it must not slip through the gap between the bond's two particles (doc/mfc.md,
"Wall self-avoidance"). With the former default E0 = 1e-12 J the gap of a bond at its
s = 0.3 rest length gives way at 3.4e-5 N, and dried folds pressed their layers through
each other; ``SELF_E0_FOLDS`` (1e-10 J, the default now) holds 3.4e-3 N."""

import numpy as np
import pytest

from cgms.mfc import model as mfc_model, run as mfc_run, tissue as mfc_tissue
from cgms import run

#: the load on the pressed particle, N: 3 x the largest force a ramp stage of the 86-cell
#: tissue starts with (3.3e-4 N; the contact forces of folds at rest are 2-3e-5 N), above the
#: 3.4e-4 N E0 = 1e-11 J resists (doc/results/mfc.md, "Walls that passed through themselves")
LOAD = 1e-3


def pressed_through(tmp_path, p, s=0.3, load=LOAD, start=1.5e-6):
    """Particle 1 of one built cell, ``start`` (m) off the middle of a bond of its own ring
    shortened to the rest length of level ``s`` (particles 31 and 32, held), pushed towards
    it by ``load`` (N) and minimised; bonds and bending off, so the self-avoidance alone
    holds it. Returns its final height over the bond's line (m; negative: passed through)."""
    data = tmp_path / "walls.data"
    mfc_tissue.write_data(data, [[0.0, 0.0]], p, overwrite=True)
    lmp = run.open_lammps()
    try:
        lmp.commands_list(mfc_run.setup_commands(data, p))
        xy = mfc_run.positions(lmp)
        a, b = xy[30], xy[31]             # a bond of one straight side
        t = (b - a) / np.hypot(*(b - a))
        n = np.array([-t[1], t[0]])
        length = mfc_model.level(p, s)["r0_bond"]
        b = a + length * t
        mid = (a + b) / 2
        top = mid + start * n
        lmp.commands_list([
            "bond_coeff 1 0.0 4e-6", "angle_coeff 1 0.0",
            f"set atom 32 x {b[0]:.12g} y {b[1]:.12g}",
            f"set atom 1 x {top[0]:.12g} y {top[1]:.12g}",
            "group pushed id 1", "group held subtract all pushed",
            "fix hold held setforce 0 0 0",
            # the load's energy, zero on the bond's line (the minimiser needs it)
            f"variable e atom {load:.10g}*({n[0]:.12g}*(x-{mid[0]:.12g})"
            f"+{n[1]:.12g}*(y-{mid[1]:.12g}))",
            f"variable fx equal {-load * n[0]:.10g}", f"variable fy equal {-load * n[1]:.10g}",
            "fix push pushed addforce v_fx v_fy 0.0 energy v_e",
            "fix_modify push energy yes",
            *mfc_run.minimize_commands(1e-13, 20000)])
        return float((mfc_run.positions(lmp)[0] - mid) @ n)
    finally:
        lmp.close()


@pytest.mark.lammps
def test_wall_particle_pressed_on_its_own_bond_does_not_pass(tmp_path):
    p = mfc_model.parameters()     # the default holds the folds
    assert p["self_E0"] == mfc_model.SELF_E0_FOLDS
    h = pressed_through(tmp_path, p)
    # held in front of the gap, at about the distance where the repulsion carries the load
    assert 0.3e-6 < h < p["self_r0"], h


@pytest.mark.lammps
def test_former_self_avoidance_let_the_particle_through(tmp_path):
    """The check has teeth: E0 = 1e-12 J (the former default) and 1e-11 J (which still let
    the 86-cell tissue cross) let the same particle through the gap."""
    for weak in (1e-12, 1e-11):
        h = pressed_through(tmp_path, mfc_model.parameters(self_E0=weak))
        assert h < 0, (weak, h)
