# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Calibration (cgms.calibration.calibrate): eqn (2), matching references to beads,
recovery of known parameters from CGMS's own steady states, resuming, the fitted material file."""

import json
import math
import time

import numpy as np
import pytest

from cgms.calibration import calibrate, fitparams
from cgms import cli, material, morphology, pool, positions, study, superpose, tissue
from cgmstest import APPLE, MAT

# the reference parameters of the recovery test: factors on apple's values
TRUE = {"k_T": 2.0, "k_PA": 0.5, "beta": 1.05}
LEVELS = (1.0, 0.3)


@pytest.fixture(scope="module")
def tissue86(tmp_path_factory):
    """The paper's 86-bead calibration tissue (1.25 x 1.5 mm)."""
    path = tmp_path_factory.mktemp("tissue") / "tissue.data"
    xy = tissue.rectangle(1.25e-3, 1.5e-3, MAT["x_ref"])
    assert len(xy) == 86
    tissue.write_data(path, xy, 3 * MAT["x_ref"])
    return path


@pytest.fixture(scope="module")
def references(tissue86, tmp_path_factory):
    """Steady states of the 86-bead tissue at k_T x2, k_PA x0.5, beta x1.05: the fresh one
    as an 'id x y' file (rows shuffled, so matching must go by id), the dried one as the
    LAMMPS dump the run wrote."""
    folder = tmp_path_factory.mktemp("reference")
    over = (f"k_T {MAT['k_T'] * TRUE['k_T']!r} k_PA {MAT['k_PA'] * TRUE['k_PA']!r} "
            f"beta_a {MAT['beta_a'] * TRUE['beta']!r} beta_b {MAT['beta_b'] * TRUE['beta']!r}")
    runs = {s: study.relax(tissue86, APPLE, s, folder, method="quasistatic", overrides=over)
            for s in LEVELS}
    assert all(r["converged"] for r in runs.values())
    order = np.random.default_rng(3).permutation(86)
    fresh = positions.write_centroids(folder / "fresh.txt", runs[1.0]["xy"][order],
                                      ids=order + 1, comment="CGMS at k_T x2, k_PA x0.5")
    return {1.0: fresh, 0.3: folder / "tissue.s0.3.dump"}, runs


# --------------------------------------------------------------------------- eqn (2)

def test_rmsd_is_eqn_2_after_removing_the_rigid_motion():
    rng = np.random.default_rng(0)
    q = rng.uniform(0, 1e-3, (50, 2))
    d = rng.normal(0, 1e-6, q.shape)
    p = q + d
    # eqn (2): root of the mean over beads of the squared distance (not over coordinates)
    assert superpose.rmsd(p, q, "none") == pytest.approx(math.sqrt((d ** 2).sum(1).mean()))
    shifted = p + [3e-4, -2e-4]
    assert superpose.rmsd(shifted, q, "none") > 100 * superpose.rmsd(p, q, "none")
    dd = d - d.mean(0)
    assert superpose.rmsd(shifted, q) == pytest.approx(math.sqrt((dd ** 2).sum(1).mean()))
    c, s = math.cos(0.2), math.sin(0.2)
    turned = (q - q.mean(0)) @ np.array([[c, -s], [s, c]]).T + [1e-3, 5e-4]
    assert superpose.rmsd(turned, q, "translation") > 1e-5
    assert superpose.rmsd(turned, q, "rigid") < 1e-15
    with pytest.raises(ValueError, match="align must be one of"):
        superpose.rmsd(p, q, "affine")


# --------------------------------------------------------------------------- references

def write_ref(path, ids, xy):
    path.write_text("id x y\n" + "".join(f"{i} {x!r} {y!r}\n" for i, (x, y) in zip(ids, xy)))
    return path


@pytest.mark.lammps
def test_reference_with_the_wrong_bead_count_fails_clearly(tissue86, tmp_path):
    xy = positions.read_data(tissue86)["xy"]
    short = write_ref(tmp_path / "short.txt", range(1, 86), xy[:85])
    with pytest.raises(ValueError, match=r"s = 0.3 .*short.txt.* has 85 beads but the tissue "
                                         r"has 86; lacks tissue id\(s\) 86"):
        calibrate.load_references({0.3: short}, tissue86)
    long = write_ref(tmp_path / "long.txt", range(1, 88), np.vstack([xy, xy[:1] + 1e-4]))
    with pytest.raises(ValueError, match=r"has 87 beads but the tissue has 86; has id\(s\) 87 "
                                         r"that the tissue does not"):
        calibrate.load_references({1.0: long}, tissue86)
    # the fit stops before running anything
    out = tmp_path / "fit"
    good = write_ref(tmp_path / "good.txt", range(1, 87), xy)
    with pytest.raises(ValueError, match="has 85 beads"):
        calibrate.calibrate(tissue86, APPLE, {1.0: good, 0.3: short}, out, progress=False)
    assert not (out / calibrate.CACHE).exists()


@pytest.mark.lammps
def test_reference_with_the_wrong_ids_fails_clearly(tissue86, tmp_path):
    xy = positions.read_data(tissue86)["xy"]
    ids = np.arange(1, 87)
    ids[40] = 200
    other = write_ref(tmp_path / "other.txt", ids, xy)
    with pytest.raises(ValueError, match=r"lacks tissue id\(s\) 41; has id\(s\) 200 that the "
                                         r"tissue does not \(tissue ids 1..86\)"):
        calibrate.load_references({1.0: other}, tissue86)
    ids[40] = 40
    twice = write_ref(tmp_path / "twice.txt", ids, xy)
    with pytest.raises(ValueError, match=r"repeated id\(s\) 40"):
        calibrate.load_references({1.0: twice}, tissue86)
    # arrays: ids 1..n implied, so only the count can be wrong
    with pytest.raises(ValueError, match="has 80 beads but the tissue has 86"):
        calibrate.load_references({1.0: xy[:80]}, tissue86)
    # a dump whose ids are shifted by one
    dump = tmp_path / "shifted.dump"
    rows = "".join(f"{i + 2} 1 {x!r} {y!r} 0\n" for i, (x, y) in enumerate(xy))
    dump.write_text("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n86\nITEM: BOX BOUNDS ss ss pp\n"
                    "-1 1\n-1 1\n-1 1\nITEM: ATOMS id type x y z\n" + rows)
    with pytest.raises(ValueError, match=r"shifted.dump.* lacks tissue id\(s\) 1; has id\(s\) "
                                         r"87 that the tissue does not"):
        calibrate.load_references({0.3: dump}, tissue86)
    bad = tmp_path / "bad.txt"
    bad.write_text("# centroids\n1 0.1 0.2\n2 0.3\n")
    with pytest.raises(ValueError, match=r"bad.txt line 3: expected 'id x y'"):
        positions.read_centroids(bad)
    micro = write_ref(tmp_path / "um.txt", range(1, 87), xy * 1e6)
    with pytest.raises(ValueError, match="must be in metres"):
        calibrate.calibrate(tissue86, APPLE, {1.0: micro}, tmp_path / "fit", progress=False)


def test_parameter_names_and_the_material_they_stand_for():
    mat = material.read(APPLE)
    with pytest.raises(ValueError, match="unknown parameter 'k_X'"):
        fitparams.parse_parameters(["k_X"], mat, LEVELS)
    with pytest.raises(ValueError, match="'beta' scales beta_a and beta_b together"):
        fitparams.parse_parameters(["beta", "beta_b"], mat, LEVELS)
    with pytest.raises(ValueError, match="no reference at s = 0.5"):
        fitparams.parse_parameters(["beta@0.5"], mat, LEVELS)
    with pytest.raises(ValueError, match="bounds given for parameter"):
        fitparams.parse_parameters(["k_T"], mat, LEVELS, bounds={"k_PA": (0.5, 2)})
    params = fitparams.parse_parameters(["k_PA", "beta@*"], mat, LEVELS)
    assert [p.name for p in params] == ["k_PA", "beta@1", "beta@0.3"]
    assert params[2].start == pytest.approx(1.0311 + 0.1088 * math.log(0.3))
    values = [3.0, 1.1, 0.95]
    assert fitparams.overrides(params, values, mat, 0.3) == "k_PA 3.0 beta_a 0.95 beta_b 0.0"
    assert fitparams.overrides(params, values, mat, 1.0) == "k_PA 3.0 beta_a 1.1 beta_b 0.0"
    # per-level betas -> the law a + b ln s through them
    fitted = fitparams.fitted_material(params, values, mat, LEVELS)
    assert fitted["k_PA"] == 3.0 and fitted["beta_a"] == pytest.approx(1.1)
    assert fitted["beta_b"] == pytest.approx((1.1 - 0.95) / -math.log(0.3))


def test_material_file_is_new_and_reads_back(tmp_path):
    path = material.write(tmp_path / "fit.cgms", APPLE, {"k_T": 2.5e-10}, "a note")
    text = path.read_text()
    assert text.startswith("# DATE: ") and "UNITS: si" in text.splitlines()[0]
    assert "a note" in text and "fitted (start 1e-10)" in text
    assert material.read(path)["k_T"] == 2.5e-10
    assert material.read(path)["k_PA"] == MAT["k_PA"]
    with pytest.raises(FileExistsError, match="exists"):
        material.write(path, APPLE, {"k_T": 3e-10})
    assert material.read(path)["k_T"] == 2.5e-10



def test_material_file_is_whole_or_absent(tmp_path, monkeypatch):
    """A disk that fills while the fitted file is written leaves no half file behind
    (a later calibrate would read it as a material)."""
    import os

    def full_disk(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(OSError, match="No space"):
        material.write(tmp_path / "fit.cgms", APPLE, {"k_T": 2.5e-10})
    assert list(tmp_path.iterdir()) == []

def test_command_line_rejects_bad_arguments(capsys):
    assert cli.main(["calibrate", "--reference", "fresh.txt"]) == 2
    assert "expected LEVEL=FILE" in capsys.readouterr().err
    assert cli.main(["calibrate", "--reference", "1=a.txt", "--start", "k_T"]) == 2
    assert "expected name=value" in capsys.readouterr().err


# --------------------------------------------------------------------------- recovery

@pytest.mark.lammps
def test_fit_recovers_known_parameters_and_resumes(tissue86, references, tmp_path):
    """The issue's test: references from CGMS at k_T x2, k_PA x0.5, beta x1.05 (s = 1 and
    0.3); fitted from apple's values, every parameter within 2 %. Then the fit is cut
    short (half of its cached steady states dropped, the last line broken) and run again
    in the same folder: it reuses the cache, runs only what was lost, and lands on the
    same values."""
    refs, runs = references
    out = tmp_path / "fit"
    lines = []
    t0 = time.perf_counter()
    result = calibrate.calibrate(tissue86, APPLE, refs, out, parameters=["k_T", "k_PA", "beta"],
                                 progress=lines.append)
    seconds = time.perf_counter() - t0
    print(f"\nrecovery: {result['evaluations']} evaluations, {result['jacobians']} Jacobians, "
          f"{result['runs']} steady states ({result['fallbacks']} by the fallback), "
          f"{seconds:.1f} s; factors {result['factors']}; RMSD/x_ref {result['rmsd_x_ref']}")
    assert result["success"], result["message"]
    for name, true in TRUE.items():
        assert result["factors"][name] == pytest.approx(true, rel=0.02), name
    assert max(result["rmsd_x_ref"].values()) < 1e-4
    assert min(result["rmsd_start"].values()) > 1e-2 * MAT["x_ref"]
    assert result["moisture"][0.3] == pytest.approx(runs[0.3]["moisture"], abs=1e-4)
    assert len(lines) >= result["evaluations"] and "RMSD/x_ref" in lines[0]
    # outputs: material file (fitted values), result.json, one folder per evaluation
    fitted = material.read(result["material_file"])
    assert fitted["k_T"] == pytest.approx(MAT["k_T"] * TRUE["k_T"], rel=0.02)
    assert fitted["beta_b"] == pytest.approx(MAT["beta_b"] * TRUE["beta"], rel=0.02)
    assert fitted["k_d"] == MAT["k_d"]
    saved = json.loads((out / "result.json").read_text())
    assert saved["parameters"] == result["parameters"]
    assert len(list((out / "runs").iterdir())) >= result["evaluations"]

    # resume after an interruption
    cache = out / calibrate.CACHE
    records = cache.read_text().splitlines()
    keep = len(records) // 2
    cache.write_text("\n".join(records[:keep]) + "\n" + records[keep][:40])
    again = calibrate.calibrate(tissue86, APPLE, refs, out, parameters=["k_T", "k_PA", "beta"],
                                progress=False)
    assert again["parameters"] == result["parameters"]
    assert again["runs"] == len(records) - keep and again["reused"] == keep
    assert again["steady_states"] == result["steady_states"] == len(records)
    assert again["material_file"] != result["material_file"]   # the first one is kept
    # a finished fit run again runs nothing
    third = calibrate.calibrate(tissue86, APPLE, refs, out, parameters=["k_T", "k_PA", "beta"],
                                progress=False, material_out=False)
    assert third["runs"] == 0 and third["reused"] == len(records)
    assert third["parameters"] == result["parameters"]


@pytest.mark.lammps
def test_cache_of_another_setup_is_refused(tissue86, tmp_path):
    out = tmp_path / "fit"
    out.mkdir()
    (out / pool.SETUP).write_text(json.dumps({"data_sha256": "0"}))
    xy = positions.read_data(tissue86)["xy"]
    with pytest.raises(ValueError, match="another setup"):
        calibrate.calibrate(tissue86, APPLE, {1.0: xy}, out, progress=False)


@pytest.mark.lammps
def test_reference_dump_is_read_by_id(references):
    refs, runs = references
    frame = morphology.read_dump(refs[0.3])[-1]
    ids, xy = positions.read_centroids(refs[0.3])
    assert np.array_equal(ids, frame["ids"]) and np.allclose(xy, runs[0.3]["xy"], atol=1e-12)
    ids, xy = positions.read_centroids(refs[1.0])
    assert np.array_equal(calibrate.match(ids, xy, np.arange(1, 87)), runs[1.0]["xy"])


@pytest.mark.lammps
def test_fit_per_level_beta_against_a_moved_reference(tissue86, references, tmp_path):
    """beta at each level (beta@*) with k_T and k_PA, against references given in another
    frame (turned by 10 degrees and shifted): with align="rigid" the frame does not matter,
    and the law a + b ln s through the two betas is apple's x1.05."""
    _, runs = references
    c, s = math.cos(math.radians(10)), math.sin(math.radians(10))
    moved = {lvl: r["xy"] @ np.array([[c, -s], [s, c]]).T + [2e-3, -1e-3]
             for lvl, r in runs.items()}
    result = calibrate.calibrate(tissue86, APPLE, moved, tmp_path / "fit",
                                 parameters=["k_T", "k_PA", "beta@*"], align_mode="rigid",
                                 progress=False)
    print(f"\nper-level beta, rigid: {result['evaluations']} evaluations, "
          f"{result['jacobians']} Jacobians, {result['runs']} steady states "
          f"({result['fallbacks']} by the fallback), {result['seconds']:.1f} s; "
          f"factors {result['factors']}")
    assert result["success"], result["message"]
    assert result["factors"]["k_T"] == pytest.approx(TRUE["k_T"], rel=0.02)
    assert result["factors"]["k_PA"] == pytest.approx(TRUE["k_PA"], rel=0.02)
    for lvl in LEVELS:
        assert result["factors"][f"beta@{lvl:g}"] == pytest.approx(TRUE["beta"], rel=0.02)
    assert result["material"]["beta_a"] == pytest.approx(MAT["beta_a"] * TRUE["beta"], rel=0.02)
    assert result["material"]["beta_b"] == pytest.approx(MAT["beta_b"] * TRUE["beta"], rel=0.02)
    assert max(result["rmsd_x_ref"].values()) < 1e-4


def test_centroid_distance_slope_of_a_lattice_shrunk_by_the_paper_s_law():
    """A lattice scaled about any point by 1 + c ln s at each level, then turned and moved,
    gives back c (every neighbour distance has the ratio 1 + c ln s) and the ratios."""
    lattice = tissue.rectangle(1.25e-3, 1.5e-3, 150e-6)
    c, levels = 0.31, (0.8, 0.5, 0.3)
    turn = np.array([[math.cos(0.4), -math.sin(0.4)], [math.sin(0.4), math.cos(0.4)]])
    dried = {s: (lattice - lattice[5]) * (1 + c * math.log(s)) @ turn.T + [2e-3, -1e-3]
             for s in levels}
    slope, ratio = calibrate.centroid_distance_slope(lattice, dried)
    assert slope == pytest.approx(c, rel=1e-12)
    for s in levels:
        assert ratio[s] == pytest.approx(1 + c * math.log(s), rel=1e-12)


def test_centroid_distance_slope_averages_over_the_fresh_neighbour_pairs():
    """A level stretched along x only: the ratio is the mean over the fresh first-shell
    pairs (brute force here) of stretched over fresh length; second-shell pairs excluded."""
    lattice = tissue.rectangle(1.25e-3, 1.5e-3, 150e-6)
    squeezed = lattice * [0.7, 1.0]
    lengths = [(np.linalg.norm(squeezed[a] - squeezed[b]), np.linalg.norm(lattice[a] - lattice[b]))
               for a in range(len(lattice)) for b in range(a)
               if np.linalg.norm(lattice[a] - lattice[b]) < 1.3 * 150e-6]
    expected = np.mean([d / d0 for d, d0 in lengths])
    slope, ratio = calibrate.centroid_distance_slope(lattice, {0.5: squeezed})
    assert ratio[0.5] == pytest.approx(expected, rel=1e-12)
    assert slope == pytest.approx((expected - 1) / math.log(0.5), rel=1e-12)
