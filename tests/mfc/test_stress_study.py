# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""studies/mfc/stress.py against cases with known answers: the mean stress of a block of
a prestressed square lattice, the lamella's pair forces (zero at the pectin distance,
repulsive inside, the truss bond's Hooke force) and the flattening of an ellipse."""

import sys

import numpy as np
import pytest

from cgms.mfc import model as mfc_model
from cgmstest import ROOT

sys.path.insert(0, str(ROOT / "studies" / "mfc"))
import stress  # noqa: E402


def lattice(n, a):
    g = np.arange(n) * a
    x = np.array([(u, v) for v in g for u in g])
    idx = np.arange(n * n).reshape(n, n)
    bonds = np.vstack([np.c_[idx[:, :-1].ravel(), idx[:, 1:].ravel()],
                       np.c_[idx[:-1, :].ravel(), idx[1:, :].ravel()]])
    return x, idx, bonds


@pytest.mark.parametrize("tension", [2e-6, -3e-6])
def test_block_of_a_prestressed_lattice_has_stress_tension_over_spacing(tension):
    """Every bond of a square lattice (spacing a) pulls with the same force T: the mean
    stress of any block of whole cells is T / a along x and y, and no shear."""
    n, a, k = 9, 1e-4, 4
    x, idx, bonds = lattice(n, a)
    d = x[bonds[:, 1]] - x[bonds[:, 0]]
    f = tension * d / np.linalg.norm(d, axis=1)[:, None]    # on the first from the second
    inside = np.zeros(n * n, bool)
    inside[idx[2:2 + k, 3:3 + k].ravel()] = True
    sigma, net = stress.region_stress(x, inside, bonds[:, 0], bonds[:, 1], f, (k * a) ** 2)
    assert np.allclose(sigma, tension / a * np.eye(2), rtol=1e-12, atol=1e-15 * abs(tension) / a)
    assert np.abs(net).max() <= 1e-15 * abs(tension) * n


def test_lamella_forces_vanish_at_the_pectin_distance_and_repel_inside():
    p = mfc_model.parameters()
    dp = p["pectin"]
    x = np.array([[0.0, 0.0], [dp, 0.0], [0.0, 0.7 * dp], [3 * dp, 3 * dp], [3 * dp + 1.3 * dp, 3 * dp]])
    cell = np.array([0, 1, 2, 3, 4])
    i, j, f = stress.inter_cell_forces(x, cell, np.zeros((0, 3), np.int64), {}, p)
    pairs = {(a, b): g for a, b, g in zip(i, j, f)}
    assert np.abs(pairs[(0, 1)]).max() < 1e-12 * p["lamella_E0"] / dp
    assert pairs[(0, 2)][1] < 0          # 0.7 d_p: particle 0 pushed away from 2 (along -y)
    assert pairs[(3, 4)][0] > 0          # 1.3 d_p: attracted toward 4 (along +x)
    # the truss bond: Hooke's force with the lamella's stiffness
    bond = np.array([[2, 0, 1]])
    i, j, f = stress.inter_cell_forces(x[:2], cell[:2], bond, {2: 0.9 * dp}, p)
    assert f[0] == pytest.approx([p["lamella_k"] * 0.1 * dp, 0.0], rel=1e-12)


def test_flattening_of_an_ellipse():
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    angle = np.radians(70)
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    q = (np.c_[2.0 * np.cos(t), 1.0 * np.sin(t)] @ rot.T)[None]
    el, ang = stress.flattening(q)
    assert el[0] == pytest.approx(2.0, rel=1e-3)
    assert np.cos(2 * (ang[0] - angle)) == pytest.approx(1.0, abs=1e-9)
    S, direction = stress.order(np.array([angle, angle + np.pi]))
    assert S == pytest.approx(1.0) and direction == pytest.approx(70.0)
