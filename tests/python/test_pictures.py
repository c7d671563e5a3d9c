# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""cgms.pictures: the cell polygons against lattice geometry, the fresh outline over a dried
tissue, and the pictures of a real (small) study folder."""

import math

import numpy as np
import pytest

from cgmstest import APPLE, MAT, XREF
from cgms import morphology, pictures, study, tissue


def polygon_area(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def turned(xy, angle):
    c, s = math.cos(angle), math.sin(angle)
    return xy @ np.array([[c, s], [-s, c]])


@pytest.fixture
def lattice():
    """A fresh 86-bead lattice turned by 0.3 rad, with the number of first-shell neighbours
    of each bead."""
    xy = turned(tissue.rectangle(1.25e-3, 1.5e-3, XREF), 0.3)
    d = np.hypot(*(xy[:, None] - xy[None]).transpose(2, 0, 1))
    return xy, ((d > 0) & (d < 1.1 * XREF)).sum(axis=1)


def test_voronoi_cells_of_a_lattice(lattice):
    xy, neighbours = lattice
    cells = pictures.voronoi_cells(xy)
    assert len(cells) == len(xy)
    areas = np.array([polygon_area(c) for c in cells])
    inner = neighbours == 6
    # the Voronoi cell of a hexagonal lattice of spacing x: a hexagon of area sqrt(3)/2 x^2
    np.testing.assert_allclose(areas[inner], math.sqrt(3) / 2 * XREF**2, rtol=1e-9)
    # edge cells lose their outer part to the disc of 0.6 x: smaller than the disc, larger
    # than an inner cell's half
    disc = 24 / 2 * math.sin(2 * math.pi / 24) * (pictures.CLIP_RADIUS * XREF) ** 2
    assert np.all(areas[~inner] < disc) and np.all(areas[~inner] > 0.5 * areas[inner][0])
    # each cell holds its bead and no other
    for k, cell in enumerate(cells):
        d = np.hypot(*(xy - cell.mean(axis=0)).T)
        assert np.argmin(d) == k


def test_hexagons_have_the_side_and_face_the_neighbours(lattice):
    xy, neighbours = lattice
    assert pictures.lattice_angle(xy) % (math.pi / 3) == pytest.approx(
        (0.3 + math.pi / 2) % (math.pi / 3), abs=1e-9)    # rows along y, turned by 0.3
    side = np.linspace(0.9, 1.0, len(xy)) * MAT["b_ref"]
    cells = pictures.hexagon_cells(xy, side)
    areas = np.array([polygon_area(c) for c in cells])
    np.testing.assert_allclose(areas, 1.5 * math.sqrt(3) * side**2, rtol=1e-12)
    # a wall midpoint lies on every bond, at the apothem sqrt(3)/2 b: flat walls face the
    # neighbours, so reference cells across a bond are d_p apart
    k = int(np.flatnonzero(neighbours == 6)[0])
    mids = (cells[k] + np.roll(cells[k], -1, axis=0)) / 2 - xy[k]
    bonds = xy[np.hypot(*(xy - xy[k]).T) < 1.1 * XREF] - xy[k]
    bonds = bonds[np.hypot(*bonds.T) > 0]
    for b in bonds:
        unit = b / np.hypot(*b)
        assert np.max(mids @ unit) == pytest.approx(math.sqrt(3) / 2 * side[k], rel=1e-12)


def test_fresh_outline_drawn_over_the_dried_tissue(lattice):
    import matplotlib.pyplot as plt

    fresh, _ = lattice
    dried = 0.8 * fresh + np.array([3e-4, -2e-4])    # shrunk and moved
    fig, ax = plt.subplots()
    values = np.arange(len(fresh), dtype=float)
    coll = pictures.draw_tissue(ax, dried, values, fresh_xy=fresh)
    np.testing.assert_array_equal(coll.get_array(), values)
    solid, dashed = ax.lines
    assert dashed.get_linestyle() == "--"
    # the dashed line is the fresh outline (through its peripheral beads), moved onto the
    # dried one's centroid: the same polygon as the fresh tissue's, in mm
    loop = morphology.outline(fresh)
    here = np.column_stack(dashed.get_data()) / 1e3
    shift = np.subtract(morphology.measures(dried)["centroid"],
                        morphology.measures(fresh)["centroid"])
    np.testing.assert_allclose(here[:-1], fresh[loop] + shift, rtol=0, atol=1e-15)
    np.testing.assert_allclose(polygon_area(here[:-1]), morphology.measures(fresh)["area"],
                               rtol=1e-12)
    np.testing.assert_allclose(np.column_stack(solid.get_data())[:-1] / 1e3,
                               dried[morphology.outline(dried)], rtol=1e-12)
    plt.close(fig)


def test_hexagon_cells_need_the_side(lattice):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match="needs the per-bead side"):
        pictures.draw_tissue(ax, lattice[0], np.zeros(len(lattice[0])), cells="hexagon")
    plt.close(fig)


def test_pictures_of_a_study_folder(tmp_path):
    """Two tissues at two levels, solved quasi-statically by LAMMPS with the plugin: every
    picture is written, and a level whose dump does not match its positions is refused."""
    from matplotlib.image import imread

    for name, (w, h) in {"small": (0.8, 0.8), "tall": (0.8, 1.2)}.items():
        folder = tmp_path / name
        folder.mkdir()
        xy = tissue.rectangle(w * 1e-3, h * 1e-3, XREF)
        tissue.write_data(folder / "tissue.data", xy, 3 * XREF)
        study.sweep(folder / "tissue.data", APPLE, folder, levels=(1.0, 0.4), progress=False,
                    method="quasistatic")
    written = pictures.study_pictures(tmp_path, field="pressure")
    names = sorted(str(p.relative_to(tmp_path)) for p in written)
    assert names == ["curves-all.png", "small/cells-pressure.png", "small/cells-shrinkage.png",
                     "tall/cells-pressure.png", "tall/cells-shrinkage.png"]
    for path in written:
        image = imread(path)
        assert image.shape[0] > 300 and image.shape[1] > 600
        assert image[..., :3].std() > 0.05    # not blank
    with pytest.raises(FileNotFoundError, match="no study results"):
        pictures.study_pictures(tmp_path / "small" / "nothing")
    moved = tmp_path / "small" / "level.s0.4.npy"
    np.save(moved, np.load(moved) + 1e-6)
    with pytest.raises(ValueError, match="does not hold the positions"):
        pictures.study_pictures(tmp_path)
