# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""3-D walls that pass through themselves or through each other (cgms.mfc.crossing3d) and
the 3-D study stopping on them (doc/mfc.md, "3-D tissue")."""

from pathlib import Path

import numpy as np
import pytest

from cgmstest import working_directory

from cgms.mfc import crossing3d, model as mfc_model, run3d, study3d, tissue3d

P = mfc_model.parameters()


def pushed(x, depth):
    """The closed wall ``x`` (the unit-cube truncated octahedron) with the node at the
    centre of its +x square face pushed along -x to ``x = depth``, a little off the axis
    (a node pushed exactly along a symmetry line meets the far face on its inner edges, a
    touch the strict test does not count)."""
    y = x.copy()
    k = np.argmin(np.linalg.norm(x - [0.5, 0.0, 0.0], axis=1))
    y[k] = [depth, 0.013, 0.021]
    return y, k


def test_a_closed_wall_and_a_deep_dent_do_not_cross():
    """The built wall, the same kicked by 1 % of its edge, and a dent reaching to 0.05 of
    the cube edge short of the opposite face: no two triangles intersect."""
    x, tri = tissue3d.polyhedron(3)
    assert len(crossing3d.intersecting_triangles(x, tri)) == 0
    rng = np.random.default_rng(3)
    kicked = x + rng.uniform(-1, 1, x.shape) * 0.01 / 12
    assert len(crossing3d.intersecting_triangles(kicked, tri)) == 0
    dent, _ = pushed(x, -0.45)
    assert len(crossing3d.intersecting_triangles(dent, tri)) == 0


def test_a_wall_pushed_through_itself_is_found():
    """The same dent pushed 0.05 beyond the opposite face: the pushed node's triangles and
    the far face's intersect (only those), and the message names the cell."""
    x, tri = tissue3d.polyhedron(3)
    y, k = pushed(x, -0.55)
    pairs = crossing3d.intersecting_triangles(y, tri)
    assert len(pairs) > 0
    far = np.abs(y[tri][:, :, 0] + 0.5).max(axis=1) < 1e-12        # the -x face's triangles
    mine = (tri == k).any(axis=1)
    for i, j in pairs:
        assert (mine[i] and far[j]) or (mine[j] and far[i])
    found = crossing3d.tissue_crossings(y, tri, len(x))
    assert found["between"] == [] and found["cells"] == [1]
    assert "cell 1's wall crosses itself" in crossing3d.describe(found)


def test_tissue_crossings_tell_a_wall_through_itself_from_two_through_each_other():
    """The built 16-cell block (n = 3, its facing walls d_p apart) is clean. Cell 3's
    square-face node pushed through its own opposite face (3 um into the 9.24 um gap) is
    one cell crossing itself; cell 1 moved 12 um (> d_p) towards its neighbour across a
    hexagonal face is those two walls through each other, and neither crosses itself.
    (Moves along the block's symmetry lines are given a small sideways part: a node
    carried exactly onto another wall's edge is a touch the strict test does not count.)"""
    centres = tissue3d.block(P, 2)
    x, cell, w = tissue3d.walls(centres, P, 3)
    m, tri, a = len(w["x"]), w["tri"], w["cube"]
    clean = crossing3d.tissue_crossings(x, tri, m)
    assert clean == dict(self=[], between=[], cells=[])
    assert crossing3d.describe(clean) == ""
    y = x.copy()
    y[2 * m:3 * m] = centres[2] + pushed(w["x"] / a, -0.5 - 3e-6 / a)[0] * a
    found = crossing3d.tissue_crossings(y, tri, m)
    assert found["cells"] == [3] and found["between"] == [] and len(found["self"]) > 0
    assert all(2 * m < r[2] <= 3 * m and 2 * m < r[3] <= 3 * m for r in found["self"])
    hexagonal = np.argmin(np.linalg.norm(centres - centres[0] - a / 2, axis=1))
    y = x.copy()
    y[:m] += 12e-6 * np.ones(3) / np.sqrt(3) + [0.31e-6, -0.17e-6, 0.0]
    found = crossing3d.tissue_crossings(y, tri, m)
    assert found["self"] == [] and {r[:2] for r in found["between"]} == {(1, hexagonal + 1)}
    assert (f"1 pair of cells' walls pass through each other (1-{hexagonal + 1};"
            in crossing3d.describe(found))
    y[:m] -= 4.5e-6 * np.ones(3) / np.sqrt(3)                    # 7.5 um: inside the gap
    assert crossing3d.tissue_crossings(y, tri, m)["between"] == []
    with pytest.raises(ValueError, match="not finite"):
        crossing3d.intersecting_triangles(np.full_like(x, np.nan), tri)


def test_wall_crossing_says_where_what_is_kept_and_what_to_try():
    found = dict(self=[(4, 4, 3000, 3300)], between=[], cells=[4])
    err = study3d.WallCrossing(found, 0.55, 0.4, 0.6, [dict(s=1.0), dict(s=0.8),
                                                         dict(s=0.6)],
                               Path("/out/walls.failed.s0.55.dump"))
    text = str(err)
    assert text.startswith("s = 0.4 (on the ramp from s = 0.6, at s = 0.55): cell 4's wall "
                           "crosses itself")
    for part in ("the levels finished (s = 1, 0.8, 0.6) stay in /out",
                 "walls.failed.s0.55.dump", "gentler ramp (--stage below 0.05)", "--seed",
                 "self-avoidance"):
        assert part in text
    # walls of two cells through each other: the cure names the lamella, not the
    # self-avoidance the cells' own walls have
    found = dict(self=[], between=[(2, 5, 1200, 4100)], cells=[2, 5])
    text = str(study3d.WallCrossing(found, 0.4, 0.4, 0.6, [dict(s=1.0)],
                                    Path("/out/walls.failed.s0.4.dump")))
    assert "the lamella's repulsion" in text and "self-avoidance" not in text


@pytest.mark.lammps
def test_study_stops_at_walls_through_each_other(tmp_path):
    """At n = 2 (27 um edges) the LJ, acting between particles only, does not hold the
    facing walls of the two-cell block apart (doc/mfc.md, "Mesh"): the fresh level stops,
    its walls dumped, no level recorded; the command line says so in one line."""
    out = tmp_path / "coarse"
    with pytest.raises(study3d.WallCrossing, match=r"^s = 1: 1 pair of cells' walls pass "
                                                   r"through each other \(1-2;") as err:
        study3d.dry(out, P, cubes=1, n=2, levels=(1.0, 0.8), say=lambda *a: None)
    assert err.value.s == 1.0 and "no level finished" in str(err.value)
    dump = (out / "walls.failed.s1.dump").read_text().splitlines()
    assert dump[3] == str(2 * 146) and not list(out.glob("level.*.json"))
    with pytest.raises(SystemExit, match=r"^cgms mfc3d: s = 1: .*pass through each other"):
        study3d.main([str(tmp_path / "cli"), "--cubes", "1", "--subdivision", "2",
                      "--levels", "1"])
    with pytest.raises(SystemExit, match=r"^cgms mfc3d: --stage must be in \(0, 0.5\], got 0$"):
        study3d.main([str(tmp_path / "stage"), "--stage", "0"])
    assert not (tmp_path / "stage").exists()


def dried_in_one_step(folder, self_E0=None):
    """One free cell of the study's wall (n = 5, 902 particles) kicked and minimised at
    s = 0.3 straight from its built state: the fluid's rest volume drops to 0.3 at once and
    the wall, pulled in, folds deeply. ``self_E0`` replaces the self-avoidance's strength
    (0: none). Returns the positions and the wall."""
    x, cell, w = tissue3d.write_data(folder / "cell.data", [(0.0, 0.0, 0.0)], P,
                                     overwrite=True)
    if self_E0 is not None:
        w["self_E0"] = self_E0
    with working_directory(folder):
        lmp = study3d.open_lammps("cell.data", w)
        try:
            run3d.kick(lmp, 1e-7, 3)
            r = run3d.relax(lmp, P, w, 0.3, max_iterations=4000)
            x = run3d.positions(lmp)
        finally:
            lmp.close()
    assert r["converged"]
    return x, w


@pytest.mark.lammps
def test_self_avoidance_keeps_a_folding_wall_from_passing_through_itself(tmp_path):
    """Without the self-avoidance the cell's folds pass through each other (measured: 70
    intersecting triangle pairs); with it (radius d_p, bonded pairs spared) no two triangles
    intersect, and the closest unbonded pair lies inside the radius (the repulsion is what
    holds the fold) but farther apart than two of its longest bonds' corners are when the
    bonds cross at their middles, l_max / sqrt(2) (measured 7.87 um against 6.17 um). The
    study's wall at s = 0.3 rest lengths is not touched where flat: its closest unbonded
    pair (a square face's diagonal) lies beyond d_p."""
    x, w = dried_in_one_step(tmp_path, self_E0=0.0)
    assert len(crossing3d.tissue_crossings(x, w["tri"], len(w["x"]))["self"]) > 0
    x, w = dried_in_one_step(tmp_path)
    assert crossing3d.tissue_crossings(x, w["tri"], len(w["x"])) == dict(self=[], between=[],
                                                                         cells=[])
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    d[w["edges"][:, 0], w["edges"][:, 1]] = d[w["edges"][:, 1], w["edges"][:, 0]] = np.inf
    np.fill_diagonal(d, np.inf)
    e = w["edges"]
    l_max = np.linalg.norm(x[e[:, 1]] - x[e[:, 0]], axis=1).max()
    assert l_max / np.sqrt(2) < d.min() < w["self_r0"]
    flat = w["x"] * (1 - w["stretch"]) * mfc_model.level(P, 0.3)["contraction"]
    far = np.linalg.norm(flat[:, None] - flat[None], axis=2)
    far[e[:, 0], e[:, 1]] = far[e[:, 1], e[:, 0]] = np.inf
    np.fill_diagonal(far, np.inf)
    assert far.min() > w["self_r0"]


def test_cells_are_coloured_so_no_two_glued_walls_share_a_colour(tmp_path):
    """The self-avoidance acts within one atom type: every lamella pair of the 16- and
    54-cell blocks joins two colours; lamella bonds between cells of one colour are
    refused, naming them."""
    for cubes in (2, 3):
        centres = tissue3d.block(P, cubes)
        x, cell, w = tissue3d.walls(centres, P, 2)
        colour = tissue3d.colours(centres, P)
        assert set(colour) == {0, 1, 2, 3}
        pairs = tissue3d.lamella_pairs(x, cell, w, P)
        assert len(pairs) and np.all(colour[cell[pairs[:, 0]]] != colour[cell[pairs[:, 1]]])
    centres = tissue3d.block(P, 2)
    same = np.nonzero(tissue3d.colours(centres, P) == tissue3d.colours(centres, P)[0])[0][1]
    m = len(tissue3d.wall(P, 2)["x"])    # particles per cell
    with pytest.raises(ValueError, match=f"cells 1 and {same + 1} are glued but have one "
                                         "colour"):
        tissue3d.write_data(tmp_path / "bad.data", centres, P, n=2,
                            lamella=(np.array([[0, same * m]]), [3], [8e-6]))
