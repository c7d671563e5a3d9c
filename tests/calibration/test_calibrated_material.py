# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""potentials/apple-mfc.cgms, apple calibrated against the fine-scale (MFC) reference
(doc/calibration.md): read by the plugin and by Python alike, the plugin's forces with it
against the independent NumPy oracle, its header says how it was made, and it reproduces
the fit: on the 86-bead tissue it is closer to the MFC centroids than the paper's values,
by the RMSD its header records."""

import re

import numpy as np
import pytest

from cgms import positions, study, superpose, tissue
from cgmstest import APPLE, ROOT, XREF, forces_with_material, make_tissue, require_lammps

MFC_MATERIAL = ROOT / "potentials" / "apple-mfc.cgms"
MFC_REFERENCE = ROOT / "reference" / "mfc" / "calibration"
DT = 1e-9   # s


def reference_levels():
    files = sorted(MFC_REFERENCE.glob("centroids.s*.txt"))
    return {float(f.name[len("centroids.s"):-len(".txt")]): f for f in files}


def header_text():
    """The file's own header: its comment lines up to the start material's header, which a
    fit copies below it ('(start file header)') with that fit's own RMSD."""
    text = " ".join(line[1:] for line in MFC_MATERIAL.read_text().splitlines()
                    if line.startswith("#"))
    return text.split("(start file header)")[0]


def fitted_levels():
    """The levels the header says were fitted ('... centroids at s = 1, 0.8, 0.6 on ...')."""
    found = re.search(r"centroids\s+at\s+s\s+=\s+([0-9., ]+?)\s+on\s+the", header_text())
    assert found, "the header names the fitted levels"
    return {float(w) for w in found.group(1).replace(",", " ").split()}


def test_header_says_how_it_was_made():
    text = MFC_MATERIAL.read_text()
    head = [line for line in text.splitlines() if line.startswith("#")]
    assert head[0].startswith("# DATE:") and "UNITS: si" in head[0]
    joined = " ".join(head)
    for needed in ("studies/calibration/fit.py", "commit", "reference/mfc/calibration", "RMSD"):
        assert needed in joined, needed
    # every level the header quotes has its reference centroids in the repository
    assert fitted_levels() <= set(reference_levels())


def test_python_and_plugin_read_the_same_file(tmp_path):
    """The plugin's per-bead state and forces with apple-mfc.cgms equal the NumPy oracle's
    with the values cgms.material reads from it (so both read the same numbers)."""
    require_lammps()
    make_tissue(tmp_path, jitter=0.06, seed=11, s=(0.3, 1.0), vscale=1e-3)
    # a time step inside the stability limit of its turgor force (k_T is 300 x apple's):
    # the fix refuses 1e-7 s
    f, want, apple = forces_with_material(tmp_path, MFC_MATERIAL, dt=DT)
    assert np.max(np.abs(f - want)) <= 1e-10 * np.max(np.abs(want))
    # and the file is not apple: the same configuration gives other forces with apple
    assert np.max(np.abs(f - apple)) > 1e-3 * np.max(np.abs(want))


@pytest.fixture(scope="module")
def rmsds(tmp_path_factory):
    """RMSD (eqn 2, rigid motion removed) of the 86-bead tissue's steady states against the
    committed MFC centroids, per level, with apple and with apple-mfc."""
    require_lammps()
    folder = tmp_path_factory.mktemp("mfc-fit")
    data = folder / "tissue.data"
    tissue.write_data(data, tissue.rectangle(1.25e-3, 1.5e-3, XREF), 3 * XREF)
    out = {}
    for name, mat in (("apple", APPLE), ("apple-mfc", MFC_MATERIAL)):
        for s, path in reference_levels().items():
            if s not in fitted_levels():
                continue
            ids, q = positions.read_centroids(path)
            q = q[np.argsort(ids)]
            run, note = study.relax_or_fallback(data, mat, s, folder / name)
            assert run["converged"], (name, s, note)
            out[name, s] = superpose.rmsd(run["xy"], q, "rigid")
    return out


def test_calibrated_is_closer_to_the_mfc_than_the_paper(rmsds):
    levels = fitted_levels()
    assert len(levels) >= 2
    total = {name: sum(rmsds[name, s] ** 2 for s in levels) for name in ("apple", "apple-mfc")}
    assert total["apple-mfc"] < 0.5 * total["apple"], total
    for s in levels:
        if s < 1:
            assert rmsds["apple-mfc", s] < rmsds["apple", s], s


def test_calibrated_reproduces_the_rmsd_in_its_header(rmsds):
    """The header quotes the fit's RMSD per level ('<r> m (<r/x_ref> x_ref) at s = <s>'); a
    fresh run of the file gives it again (the file holds what was fitted)."""
    quoted = re.findall(r"([0-9.eE+-]+)\s+m\s+\([0-9.eE+-]+\s+x_ref\)\s+at\s+s\s+=\s+([0-9.]+)",
                        header_text())
    assert {float(s) for _, s in quoted} == fitted_levels()
    for r, s in quoted:
        assert rmsds["apple-mfc", float(s)] == pytest.approx(float(r), rel=1e-3), s


def test_cgms_study_reaches_the_fitted_states_with_the_fallback(tmp_path, capsys, monkeypatch):
    """``cgms study --fallback dynamics`` on the 86-bead tissue: FIRE stops at s = 0.6 and
    0.3 with this file (a bead leaves the cutoff, or the tissue folds), the dynamics solves
    those levels, the table says so, and the states are the fit's (the RMSD against the MFC
    that the header quotes). (A level outside a file's VALID FOR range is named and not run:
    tests/cli/test_cli.py.)"""
    require_lammps()
    from cgmstest import run_cli
    monkeypatch.chdir(tmp_path)
    status, err, out = run_cli(capsys, "study", "--material", str(MFC_MATERIAL), "--width",
                               "1.25", "--height", "1.5", "--dryness", "1,0.6,0.3",
                               "--fallback", "dynamics", "--out", "d")
    assert status == 0, err
    assert "not run" not in out
    marked = [line.split()[2] for line in out.splitlines()
              if line.split()[-3:] == ["yes", "dynamics", "(fallback)"]]
    assert marked == ["0.60", "0.30"], out
    folder = tmp_path / "d" / "tissue"
    quoted = dict((float(s), float(r)) for r, s in re.findall(
        r"([0-9.eE+-]+)\s+m\s+\([0-9.eE+-]+\s+x_ref\)\s+at\s+s\s+=\s+([0-9.]+)", header_text()))
    for s in (0.6, 0.3):
        ids, q = positions.read_centroids(MFC_REFERENCE / f"centroids.s{s:g}.txt")
        xy = np.load(folder / f"level.s{s:g}.npy")
        assert superpose.rmsd(xy, q[np.argsort(ids)], "rigid") == \
            pytest.approx(quoted[s], rel=1e-3), s
