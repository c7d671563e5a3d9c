# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Tissue builder (python/cgms/tissue.py): the paper's bead counts, lattice geometry,
outline validation, per-bead diameters, data files and their Diameters section in LAMMPS,
and the command line. See doc/tissues.md for the derivation of the counts."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial import cKDTree

from cgmstest import APPLE, MAT, PLUGIN, ROOT, XREF, read_dump, run_lmp
from cgms import cli, model, tissue

DY = XREF * math.sqrt(3) / 2
MM = 1e-3

# The paper's rectangular tissues, W x H (mm) as the paper writes them, and their beads
# (Soft Matter 2019, section 4.4 and conclusions).
PAPER = [((1.5, 1.5), 105), ((1.5, 2.0), 149), ((1.5, 2.5), 182), ((2.0, 2.0), 203),
         ((2.0, 2.5), 248), ((20.0, 20.0), 20273)]
# The same tissues as rows x (long row / short row) with the rows along H: the unique
# split of each count into an odd number of rows alternating m and m - 1 beads that is
# consistent across the tissues sharing a side.
PAPER_SHAPES = {(1.5, 1.5): (11, 10), (1.5, 2.0): (11, 14), (1.5, 2.5): (11, 17),
                (2.0, 2.0): (15, 14), (2.0, 2.5): (15, 17), (20.0, 20.0): (153, 133)}


# --------------------------------------------------------------------------- counts

def test_material_spacing_is_the_papers():
    assert XREF == pytest.approx(150.85e-6, abs=0.01e-6)


@pytest.mark.parametrize("size, count", PAPER, ids=[f"{w}x{h}" for (w, h), _ in PAPER])
def test_paper_rule_reproduces_paper_counts(size, count):
    w, h = size
    xy = tissue.rectangle(w * MM, h * MM, XREF)
    assert len(xy) == count
    shape = tissue.rectangle_shape(w * MM, h * MM, XREF)
    assert (shape["nrows"], shape["long"], shape["short"]) == \
        PAPER_SHAPES[size] + (PAPER_SHAPES[size][1] - 1,)
    assert shape["n"] == count
    # the formula: floor(W / (x sqrt3/2)) rows along H, floor(H / x) + 1 and one fewer beads
    nrows, long = math.floor(w * MM / DY), math.floor(h * MM / XREF) + 1
    assert (nrows + 1) // 2 * long + nrows // 2 * (long - 1) == count


def test_paper_counts_fix_the_spacing():
    """The 20 mm tissue pins the lattice: 1 % more or less spacing misses the paper."""
    for f in (0.99, 1.01):
        counts = [len(tissue.rectangle(w * MM, h * MM, XREF * f)) for (w, h), _ in PAPER]
        assert counts != [n for _, n in PAPER]


def test_paper_rule_orientation():
    """Rows along y: the paper's 1.5 x 2.0 mm tissue is taller than wide (EL = vertical /
    horizontal axis > 1, the paper's major / minor), its columns 14/13 beads high."""
    xy = tissue.rectangle(1.5 * MM, 2.0 * MM, XREF)
    ext = np.ptp(xy, axis=0)
    assert ext[1] == pytest.approx(13 * XREF, rel=1e-12)
    assert ext[0] == pytest.approx(10 * DY, rel=1e-12)
    # beads inside the rectangle, centred in it
    assert xy.min() >= 0 and np.all(xy.max(axis=0) <= [1.5 * MM, 2.0 * MM])
    np.testing.assert_allclose(0.5 * (xy.min(axis=0) + xy.max(axis=0)), [0.75 * MM, 1.0 * MM])
    # rows along x: the same tissue needs W and H swapped
    assert len(tissue.rectangle(2.0 * MM, 1.5 * MM, XREF, rows_along="x")) == 149
    assert len(tissue.rectangle(1.5 * MM, 2.0 * MM, XREF, rows_along="x")) == 143


def test_other_fill_rules_do_not_match_the_paper():
    """The mismatch table of doc/tissues.md."""
    def counts(**kw):
        return [len(tissue.rectangle(w * MM, h * MM, XREF, **kw)) for (w, h), _ in PAPER]
    assert counts(rule="centres") == [120, 162, 204, 216, 272, 20482]
    assert counts(rule="centres", rows_along="x") == [120, 160, 200, 216, 270, 20482]
    assert counts(rule="centres", inset=MAT["diameter"] / 2) == [99, 138, 176, 188, 240, 20064]
    assert counts(inset=MAT["diameter"] / 2) == [85, 125, 155, 175, 217, 19857]
    assert counts(rows_along="x") == [105, 143, 181, 203, 257, 20273]
    # centres in the closed rectangle, lattice with a bead at the rectangle's centre
    centred = [len(tissue.polygon([[0, 0], [w * MM, 0], [w * MM, h * MM], [0, h * MM]], XREF,
                                  origin=(w * MM / 2, h * MM / 2), min_neighbours=0))
               for (w, h), _ in PAPER]
    assert centred == [105, 149, 181, 203, 247, 20273]


def test_calibration_tissue_of_86_beads():
    """9 columns alternating 10 and 9 beads: rectangle 1.2-1.3 x 1.4-1.5 mm."""
    xy = tissue.hex_rectangle(10, 9, XREF, short_rows=True)
    assert len(xy) == 86
    for w, h in ((1.2, 1.5), (1.25, 1.5), (1.3, 1.4)):
        assert len(tissue.rectangle(w * MM, h * MM, XREF)) == 86
    a = np.sort(tissue.rectangle(1.25 * MM, 1.5 * MM, XREF), axis=0)
    b = np.sort(tissue.hex_rectangle(10, 9, XREF, short_rows=True, rows_along="y"), axis=0)
    np.testing.assert_allclose(a - a[0], b - b[0], atol=1e-15)


def test_hex_rectangle_unchanged():
    xy = tissue.hex_rectangle(3, 2, 2.0)
    h = math.sqrt(3)
    np.testing.assert_allclose(xy, [[0, 0], [2, 0], [4, 0], [1, h], [3, h], [5, h]])
    np.testing.assert_allclose(tissue.hex_rectangle(3, 2, 2.0, rows_along="y"), xy[:, ::-1])
    assert len(tissue.hex_rectangle(3, 3, 2.0, short_rows=True)) == 8
    with pytest.raises(ValueError):
        tissue.hex_rectangle(0, 3, 1.0)


# --------------------------------------------------------------------------- geometry

def neighbour_distances(xy):
    tree = cKDTree(xy)
    d, _ = tree.query(xy, k=7)
    return d[:, 1:]


@pytest.mark.parametrize("rows_along", ["x", "y"])
@pytest.mark.parametrize("build", ["rectangle", "disc", "polygon"])
def test_lattice_spacing_is_x_ref(build, rows_along):
    if build == "rectangle":
        xy = tissue.rectangle(2.0 * MM, 1.5 * MM, XREF, rows_along=rows_along)
    elif build == "disc":
        xy = tissue.disc(1.0 * MM, XREF, rows_along=rows_along)
    else:
        xy = tissue.polygon([[0, 0], [2 * MM, 0.3 * MM], [1.2 * MM, 1.8 * MM]], XREF,
                            rows_along=rows_along)
    d = neighbour_distances(xy)
    np.testing.assert_allclose(d[:, 0], XREF, rtol=1e-9)  # every bead has a neighbour at x_ref
    six = np.isclose(d, XREF, rtol=1e-9).sum(axis=1)
    assert six.max() == 6 and np.all(six >= 1)
    assert np.all(d[six == 6, 5] < XREF * (1 + 1e-9))
    # rows: the beads sharing a row coordinate are x_ref apart; the rows are x sqrt3/2 apart
    across = xy[:, 0] if rows_along == "y" else xy[:, 1]
    levels = np.unique(np.round(across / DY, 6))
    np.testing.assert_allclose(np.diff(levels), 1.0, atol=1e-6)


@pytest.mark.parametrize("radius", [1.0, 3.0, 5.0])
def test_disc_area(radius):
    r = radius * MM
    xy = tissue.disc(r, XREF)
    cell = math.sqrt(3) / 2 * XREF ** 2
    # lattice points in a disc: N cell = pi R^2 up to a boundary layer of order 2 pi R x
    assert abs(len(xy) * cell - math.pi * r * r) < 0.5 * 2 * math.pi * r * XREF
    if radius >= 5:
        assert len(xy) * cell == pytest.approx(math.pi * r * r, rel=0.01)
    assert np.all(np.hypot(*xy.T) <= r * (1 + 1e-9))
    assert np.any(np.all(xy == 0, axis=1))  # a bead at the centre
    np.testing.assert_allclose(xy.mean(axis=0), 0, atol=1e-12)  # symmetric
    moved = tissue.disc(r, XREF, centre=(1e-3, 2e-3))
    np.testing.assert_allclose(moved - [1e-3, 2e-3], xy)


def test_polygon_of_a_rectangle_is_the_centres_rule():
    sq = np.array([[0, 0], [2.0, 0], [2.0, 1.5], [0, 1.5]]) * MM
    for rows_along in ("x", "y"):
        ref = tissue.rectangle(2.0 * MM, 1.5 * MM, XREF, rule="centres", rows_along=rows_along)
        for v in (sq, sq[::-1], np.vstack([sq, sq[:1]])):  # ccw, cw, explicitly closed
            xy = tissue.polygon(v, XREF, rows_along=rows_along)
            assert len(xy) == len(ref)
            a, b = (np.array(sorted(map(tuple, p - p.min(axis=0)))) for p in (xy, ref))
            np.testing.assert_allclose(a, b, atol=1e-15)


def test_polygon_points_on_the_outline_count():
    # a rectangle whose corners and edges carry lattice points (rows along x)
    r = np.array([[0, 0], [2 * XREF, 0], [2 * XREF, 2 * DY], [0, 2 * DY]])
    assert len(tissue.polygon(r, XREF, rows_along="x")) == 3 + 2 + 3
    assert len(tissue.polygon(r[::-1], XREF, rows_along="x")) == 8


def test_polygon_drops_isolated_beads():
    """The sharp corner at the origin holds a bead whose nearest lattice neighbour is
    outside: kept with min_neighbours=0, dropped by default (it would have no neighbour)."""
    tri = np.array([[0, 0], [2.0, 0.3], [1.2, 1.8]]) * MM
    every = tissue.polygon(tri, XREF, rows_along="x", min_neighbours=0)
    kept = tissue.polygon(tri, XREF, rows_along="x")
    assert len(every) == len(kept) + 1
    assert np.any(np.all(every == 0, axis=1)) and not np.any(np.all(kept == 0, axis=1))
    assert neighbour_distances(every)[:, 0].max() > 1.5 * XREF
    assert neighbour_distances(kept)[:, 0].max() == pytest.approx(XREF, rel=1e-9)
    two = tissue.polygon(tri, XREF, rows_along="x", min_neighbours=2)
    assert np.all((np.isclose(neighbour_distances(two), XREF, rtol=1e-9)).sum(axis=1) >= 2)


def test_polygon_hole():
    sq = np.array([[0, 0], [1.5, 0], [1.5, 1.5], [0, 1.5]]) * MM
    hole = np.array([[0.5, 0.5], [1.0, 0.5], [1.0, 1.0], [0.5, 1.0]]) * MM
    full = tissue.polygon(sq, XREF)
    holed = tissue.polygon(sq, XREF, holes=[hole])
    from matplotlib.path import Path as MplPath
    gone = MplPath(hole).contains_points(full)
    assert 0 < gone.sum() and len(holed) == len(full) - gone.sum()
    with pytest.raises(ValueError, match="meets"):
        tissue.polygon(sq, XREF, holes=[hole * 2])
    with pytest.raises(ValueError, match="overlap|meets"):
        tissue.polygon(sq, XREF, holes=[hole, hole + 0.1 * MM])


@pytest.mark.parametrize("vertices, message", [
    ([], "empty"),
    (np.zeros((0, 2)), "empty"),
    ([[0, 0], [1, 0]], "at least 3"),
    ([[0, 0], [1, 0], [0, 0]], "at least 3"),
    ([[0, 0], [1, 1], [1, 0], [0, 1]], "self-intersecting"),  # bow tie
    ([[np.cos(t), np.sin(t)] for t in np.arange(5) * 4 * np.pi / 5], "self-intersecting"),
    ([[0, 0], [2, 0], [2, 2], [1, 0], [0, 2]], "self-intersecting"),  # vertex on an edge
    ([[0, 0], [2, 0], [1, 0], [1, 1]], "fold back"),
    ([[0, 0], [1, 0], [2, 0]], "no area"),
    ([[0, 0], [0, 0], [1, 0], [0, 1]], "coincide"),
    ([[0, 0], [1, np.nan], [0, 1]], "finite"),
    ([1, 2, 3], r"\(m, 2\)"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], r"\(m, 2\)"),
])
def test_polygon_validation(vertices, message):
    v = np.asarray(vertices, float)
    with pytest.raises(ValueError, match=message):
        tissue.polygon(v * MM if v.ndim == 2 else v, XREF)


def test_size_validation():
    for args in [(0, 1e-3, XREF), (1e-3, -1e-3, XREF), (1e-3, 1e-3, 0), (1e-3, 1e-3, np.nan),
                 (np.inf, 1e-3, XREF)]:
        with pytest.raises(ValueError, match="positive"):
            tissue.rectangle(*args)
    with pytest.raises(ValueError, match="no row"):
        tissue.rectangle(0.1 * MM, 1 * MM, XREF)  # narrower than one row pitch
    with pytest.raises(ValueError, match="radius"):
        tissue.disc(-1e-3, XREF)
    with pytest.raises(ValueError, match="spacing"):
        tissue.polygon([[0, 0], [1, 0], [0, 1]], -1.0)
    with pytest.raises(ValueError, match="no lattice point"):
        tissue.polygon(np.array([[0.3, 0.2], [0.4, 0.3], [0.2, 0.3]]) * XREF, XREF)
    with pytest.raises(ValueError, match="rows_along"):
        tissue.rectangle(1e-3, 1e-3, XREF, rows_along="z")
    with pytest.raises(ValueError, match="rule"):
        tissue.rectangle(1e-3, 1e-3, XREF, rule="outline")


# --------------------------------------------------------------------------- diameters

@pytest.mark.parametrize("dist", ["lognormal", "normal"])
def test_cell_diameters_statistics(dist):
    d = tissue.cell_diameters(200_000, 150e-6, 0.1, seed=1, dist=dist)
    assert d.mean() == pytest.approx(150e-6, rel=2e-3)
    assert d.std() / d.mean() == pytest.approx(0.1, rel=0.02)
    np.testing.assert_array_equal(d, tissue.cell_diameters(200_000, 150e-6, 0.1, 1, dist=dist))
    assert not np.array_equal(d, tissue.cell_diameters(200_000, 150e-6, 0.1, 2, dist=dist))


def test_cell_diameters_clipping_and_edge_cases():
    d = tissue.cell_diameters(50_000, 150e-6, 0.5, seed=3, dist="normal")
    assert d.min() == pytest.approx(75e-6) and np.all(d > 0)  # clipped at 0.5 mean
    d = tissue.cell_diameters(50_000, 150e-6, 0.5, seed=3, lower=0.8, upper=1.2)
    assert d.min() == pytest.approx(120e-6) and d.max() == pytest.approx(180e-6)
    np.testing.assert_array_equal(tissue.cell_diameters(4, 150e-6, 0.0), 150e-6)
    for bad in (dict(n=0), dict(mean=0), dict(cv=-0.1), dict(dist="uniform"), dict(lower=0)):
        kw = dict(n=10, mean=150e-6, cv=0.1, seed=0) | bad
        with pytest.raises(ValueError):
            tissue.cell_diameters(**kw)


# --------------------------------------------------------------------------- data files

def test_write_data_never_overwrites(tmp_path):
    path = tmp_path / "tissue.data"
    path.write_text("the user's work\n")
    xy = tissue.hex_rectangle(3, 3, XREF)
    with pytest.raises(FileExistsError, match="overwrite=True"):
        tissue.write_data(path, xy, 3 * XREF)
    assert path.read_text() == "the user's work\n"
    assert tissue.write_data(path, xy, 3 * XREF, overwrite=True) == 9
    assert "9 atoms" in path.read_text()
    assert tissue.write_data(tmp_path / "new.data", xy, 3 * XREF) == 9


def test_write_data_sections(tmp_path):
    xy = tissue.hex_rectangle(3, 2, XREF)
    d = tissue.cell_diameters(len(xy), 150e-6, 0.1, seed=4)
    tissue.write_data(tmp_path / "a.data", xy, 3 * XREF, title="two\nlines", diameters=d)
    lines = (tmp_path / "a.data").read_text().splitlines()
    assert lines[0] == "two lines"
    k = lines.index("Diameters")
    rows = [line.split() for line in lines[k + 2:]]
    assert [int(r[0]) for r in rows] == list(range(1, 7))
    np.testing.assert_array_equal([float(r[1]) for r in rows], d)  # exact round trip
    with pytest.raises(ValueError, match="diameters"):
        tissue.write_data(tmp_path / "b.data", xy, 3 * XREF, diameters=d[:-1])
    with pytest.raises(ValueError, match="positive"):
        tissue.write_data(tmp_path / "c.data", xy, 3 * XREF, diameters=-d)
    with pytest.raises(ValueError, match="margin"):
        tissue.write_data(tmp_path / "d.data", xy, 0.0)
    assert not (tmp_path / "b.data").exists() and not (tmp_path / "d.data").exists()


@pytest.mark.lammps
def test_diameters_section_in_lammps(tmp_path):
    """The Diameters section read by fix property/atom (defined before the box exists)
    sets each bead's reference cell: mf0 = rho0 h pi D^2 / 4, l0p = turgid_ratio 6 b."""
    xy = tissue.rectangle(0.8 * MM, 0.9 * MM, XREF)
    d = tissue.cell_diameters(len(xy), MAT["diameter"], 0.15, seed=7)
    tissue.write_data(tmp_path / "tissue.data", xy, 3 * XREF, diameters=d)
    script = "\n".join([
        f"plugin load {PLUGIN}",
        "units si", "dimension 2", "boundary f f p",
        "atom_style cgms", "atom_modify map array", "comm_modify vel yes",
        "fix diam all property/atom d_diameter",
        "read_data tissue.data fix diam NULL Diameters",
        "neighbor 1.5e-5 bin",
        "variable d atom d_diameter",
        "pair_style cgms",
        f"pair_coeff * * {APPLE}",
        "fix fl all cgms/fluid dryness 1.0 diameter v_d",
        "fix nve all nve", "fix e2 all enforce2d", "timestep 1e-8",
        "compute p all property/atom mf0 l0p d_diameter",
        "dump 1 all custom 1 out.dump id c_p[1] c_p[2] c_p[3]",
        "dump_modify 1 sort id format float %.17g",
        "run 0",
    ]) + "\n"
    run_lmp(tmp_path, script)
    out = read_dump(tmp_path / "out.dump")
    assert len(out["id"]) == len(xy)
    np.testing.assert_allclose(out["c_p[3]"], d, rtol=1e-15)
    cell = model.reference_cell(d, MAT["pectin"])
    np.testing.assert_allclose(out["c_p[1]"], MAT["rho0"] * MAT["height"] * cell["A_ref"],
                               rtol=1e-12)
    np.testing.assert_allclose(out["c_p[2]"], MAT["turgid_ratio"] * cell["l_ref"], rtol=1e-12)


# --------------------------------------------------------------------------- command line

def test_cli_rect_disc_polygon(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert cli.tissue.tissue_main(["rect", "1.5", "2.0"]) == 0
    assert capsys.readouterr().out.startswith("149 beads -> tissue.data")
    assert "149 atoms" in (tmp_path / "tissue.data").read_text()
    before = (tmp_path / "tissue.data").read_text()
    assert cli.tissue.tissue_main(["rect", "1.5", "1.5"]) == 2  # exists: not replaced
    assert "--force" in capsys.readouterr().err
    assert (tmp_path / "tissue.data").read_text() == before
    assert cli.tissue.tissue_main(["rect", "1.5", "1.5", "--force", "--cv", "0.1", "--seed",
                                   "1"]) == 0
    assert capsys.readouterr().out.startswith("105 beads")
    text = (tmp_path / "tissue.data").read_text()
    assert "105 atoms" in text and "\nDiameters\n" in text
    assert cli.tissue.tissue_main(["disc", "1", "--out", "disc.data"]) == 0
    assert capsys.readouterr().out.startswith(f"{len(tissue.disc(1e-3, XREF))} beads")
    (tmp_path / "tri.txt").write_text("# metres\n0 0\n1.5e-3 0\n\n0 1.5e-3\n")
    assert cli.tissue.tissue_main(["polygon", "tri.txt", "--out", "tri.data"]) == 0
    n = len(tissue.polygon([[0, 0], [1.5e-3, 0], [0, 1.5e-3]], XREF))
    assert capsys.readouterr().out.startswith(f"{n} beads")
    (tmp_path / "bow.txt").write_text("0 0\n1e-3 1e-3\n1e-3 0\n0 1e-3\n")
    assert cli.tissue.tissue_main(["polygon", "bow.txt", "--out", "bow.data"]) == 2
    assert "self-intersecting" in capsys.readouterr().err
    (tmp_path / "mm.txt").write_text("0 0\n1500 0\n0 1500\n")  # millimetres by mistake
    assert cli.tissue.tissue_main(["polygon", "mm.txt", "--out", "mm.data"]) == 2
    assert "metres" in capsys.readouterr().err
    assert cli.tissue.tissue_main(["rect", "0", "1", "--out", "zero.data"]) == 2
    assert not any((tmp_path / f).exists() for f in ("bow.data", "mm.data", "zero.data"))


def test_cli_as_module(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), env.get("PYTHONPATH", "")])
    proc = subprocess.run([sys.executable, "-m", "cgms.tissue", "rect", "1.5", "1.5",
                           "--out", "t.data"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("105 beads") and proc.stderr == ""
    help_ = subprocess.run([sys.executable, "-m", "cgms.tissue", "rect", "--help"], env=env,
                           capture_output=True, text=True, timeout=120)
    assert "mm" in help_.stdout and help_.returncode == 0
