# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Any tissue through the command line (issue 14, item 4): study, target, sensitivity and
calibrate take --data, a LAMMPS data file from cgms.tissue (disc, polygon with a hole,
heterogeneous cells) or a list of cell centroids ('id x y', metres). The folder logic runs
with cgmstest's stand-in for study.relax (``fake``); the last tests run LAMMPS."""

import numpy as np
import pytest

from cgms import positions, tissue
from cgmstest import APPLE, MAT, XREF, run_cli


def disc_data(folder):
    path = folder / "disc.data"
    tissue.write_data(path, tissue.disc(0.5e-3, XREF), 3 * XREF)
    return path


def holed_data(folder):
    outline = np.array([[0, 0], [1.2e-3, 0], [1.2e-3, 1.0e-3], [0, 1.0e-3]])
    hole = np.array([[0.45e-3, 0.35e-3], [0.75e-3, 0.35e-3], [0.75e-3, 0.65e-3],
                     [0.45e-3, 0.65e-3]])
    path = folder / "holed.data"
    tissue.write_data(path, tissue.polygon(outline, XREF, holes=[hole]), 3 * XREF)
    return path


def heterogeneous_data(folder):
    xy = tissue.rectangle(0.8e-3, 0.8e-3, XREF)
    path = folder / "hetero.data"
    tissue.write_data(path, xy, 3 * XREF,
                      diameters=tissue.cell_diameters(len(xy), MAT["diameter"], 0.05, 1))
    return path


def centroid_list(folder, scale=1.0, ids=None):
    """The 0.8 x 0.8 mm lattice as an 'id x y' list with ids 101, 103, ... and a header."""
    xy = tissue.rectangle(0.8e-3, 0.8e-3, XREF) * scale
    ids = 101 + 2 * np.arange(len(xy)) if ids is None else ids
    path = folder / "cells.txt"
    path.write_text("# digitised cell centres, metres\nid x y\n"
                    + "".join(f"{i} {x!r} {y!r}\n" for i, (x, y) in zip(ids, xy)))
    return path, ids, xy


@pytest.mark.parametrize("build", [disc_data, holed_data, heterogeneous_data])
def test_study_runs_a_data_file(fake, capsys, build):
    source = build(fake)
    status, err, out = run_cli(capsys, "study", "--data", str(source), "--dryness", "1,0.4",
                          "--out", "d")
    assert status == 0, err
    copy, given = positions.read_data(fake / "d/tissue/tissue.data"), positions.read_data(source)
    assert np.array_equal(copy["ids"], given["ids"])
    np.testing.assert_allclose(copy["xy"], given["xy"], rtol=1e-12)
    assert (copy["diameters"] is None) == (given["diameters"] is None)
    if given["diameters"] is not None:
        np.testing.assert_allclose(copy["diameters"], given["diameters"], rtol=1e-15)
    assert f"{len(given['ids'])} beads (data file {source})" in out


def test_study_runs_a_centroid_list_keeping_its_ids(fake, capsys):
    path, ids, xy = centroid_list(fake)
    status, err, out = run_cli(capsys, "study", "--data", str(path), "--dryness", "1", "--out", "d")
    assert status == 0, err
    copy = positions.read_data(fake / "d/tissue/tissue.data")
    assert np.array_equal(copy["ids"], ids)
    np.testing.assert_allclose(copy["xy"], xy, rtol=1e-12)


def test_target_and_sensitivity_take_data(fake, capsys):
    source = disc_data(fake)
    status, err, out = run_cli(capsys, "target", "0.6", "--data", str(source), "--out", "t")
    assert status == 0, err
    assert positions.read_data(fake / "t/tissue.data")["xy"].shape == \
        positions.read_data(source)["xy"].shape
    status, err, out = run_cli(capsys, "sensitivity", "--data", str(source), "--out", "s")
    assert status == 0, err
    assert (fake / "s/sensitivity.csv").exists()


@pytest.mark.parametrize("make,args,message", [
    (lambda f: centroid_list(f, scale=1e3)[0], [], "positions must be cell centres in metres"),
    (lambda f: centroid_list(f, ids=np.full(30, 7))[0], [], "an id is given twice"),
    (lambda f: f / "none.data", [], "no such file"),
    (heterogeneous_data, ["--cv", "0.1"], "has a Diameters section: leave out --cv"),
    (lambda f: (f / "two.txt").write_text("1 0 0\n2 1.5e-4 0\n") and f / "two.txt", [],
     "2 bead(s); a tissue needs at least 3"),
])
def test_bad_data_is_refused_before_anything_is_made(fake, capsys, make, args, message):
    source = make(fake)
    status, err, out = run_cli(capsys, "study", "--data", str(source), *args, "--out", "d")
    assert status == 2 and message in err, err
    assert not (fake / "d").exists()


def test_data_file_read_errors_name_the_line(tmp_path):
    path = tmp_path / "bad.data"
    path.write_text("title\n\n3 atoms\n\nAtoms # cgms\n\n1 1 0 0 0\n2 1 x 0 0\n3 1 1 1 0\n")
    with pytest.raises(ValueError, match=r"bad.data line 8: expected 'id type x y z'"):
        positions.read_data(path)
    path.write_text("title\n\n2 atoms\n\nAtoms # cgms\n\n1 1 0 0 0\n1 1 1 0 0\n")
    with pytest.raises(ValueError, match="atom id 1 given twice"):
        positions.read_data(path)
    path.write_text("title\n\n2 atoms\n\nAtoms\n\n1 1 0 0 0\n2 1 1 0 0\n\nDiameters\n\n1 1e-4\n")
    with pytest.raises(ValueError, match=r"no diameter for atom id\(s\) \[2\]"):
        positions.read_data(path)


def test_data_file_round_trip(tmp_path):
    """write_data -> read_data: ids, positions and diameters back exactly (the writer's
    12 significant digits for positions)."""
    xy = tissue.hex_rectangle(4, 3, XREF) + 1e-3
    d = tissue.cell_diameters(len(xy), MAT["diameter"], 0.1, 2)
    ids = np.arange(len(xy)) * 3 + 5
    positions.write_data(tmp_path / "t.data", xy, 3 * XREF, diameters=d, ids=ids)
    back = positions.read_data(tmp_path / "t.data")
    assert np.array_equal(back["ids"], ids)
    np.testing.assert_allclose(back["xy"], xy, rtol=1e-11)
    np.testing.assert_array_equal(back["diameters"], d)


# --------------------------------------------------------------------------- with LAMMPS

@pytest.mark.lammps
def test_study_of_a_holed_polygon_in_lammps(tmp_path, capsys, monkeypatch):
    """The real thing on a holed polygon: fresh and dried levels, smaller when dried
    (Newton: FIRE stalls on this tissue at s = 0.4, 2e6 iterations without converging)."""
    monkeypatch.chdir(tmp_path)
    source = holed_data(tmp_path)
    status, err, out = run_cli(capsys, "study", "--data", str(source), "--dryness", "1,0.4",
                               "--method", "newton", "--out", "d")
    assert status == 0, err
    rows = [line.split() for line in out.splitlines() if line.split()[:1] == ["tissue"]
            and line.split()[1].isdigit()]
    assert len(rows) == 2 and rows[1][1] == "66", out
    assert float(rows[1][4]) < 0.9 and rows[1][8:] == ["yes", "Newton"], out


@pytest.mark.lammps
def test_calibrate_takes_a_centroid_list(tmp_path, capsys, monkeypatch):
    """calibrate --data cells.txt: beads keep the list's ids, so a reference written with
    those ids matches; the reference is the tissue's own steady state, so the fit starts
    (and stays) at apple's values with an RMSD near zero."""
    from cgms import study
    monkeypatch.chdir(tmp_path)
    path, ids, _ = centroid_list(tmp_path)
    data = tmp_path / "as.data"
    positions.write_data(data, positions.read_centroids(path)[1], 3 * XREF, ids=ids)
    fresh = study.relax(data, APPLE, 1.0, tmp_path / "ref", method="quasistatic")
    positions.write_centroids(tmp_path / "ref1.txt", fresh["xy"], ids=np.sort(ids))
    status, err, out = run_cli(capsys, "calibrate", "--data", str(path), "--reference",
                               "1=ref1.txt", "--fit", "k_PA", "--max-evaluations", "3",
                               "--workers", "1", "--out", "c")
    assert status == 0, err
    assert f"({len(ids)} beads)" in out and "RMSD" in out
