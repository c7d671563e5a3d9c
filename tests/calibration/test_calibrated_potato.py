# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""potentials/potato.cgms (the second tissue) and its MFC-calibrated form potato-mfc.cgms:
every value sourced, read by the plugin and by Python alike (the plugin's forces against
the independent NumPy oracle), and a steady state of the 86-bead potato tissue that holds
the moisture the analytic steady state of potato's cell gives (not apple's)."""

from pathlib import Path

import numpy as np
import pytest

from cgms import material, model, study, tissue
from cgmstest import APPLE, ROOT, forces_with_material, require_lammps

POTATO = ROOT / "potentials" / "potato.cgms"
POTATO_MFC = ROOT / "potentials" / "potato-mfc.cgms"
FILES = [p for p in (POTATO, POTATO_MFC) if p.exists()]


def potato_tissue(folder, mat, jitter=0.06, seed=5, s=(0.3, 1.0), vscale=1e-3):
    """A jittered hexagonal patch at the material's own spacing, with per-bead dryness and
    velocities in ``state.in`` (as cgmstest.make_tissue does for apple)."""
    rng = np.random.default_rng(seed)
    x_ref = mat["x_ref"]
    xy = tissue.hex_rectangle(7, 8, x_ref) + rng.uniform(-jitter, jitter, (56, 2)) * x_ref
    sv = rng.uniform(*s, len(xy))
    v = rng.normal(0.0, vscale, xy.shape)
    tissue.write_data(Path(folder) / "tissue.data", xy, 4 * x_ref, overwrite=True)
    (Path(folder) / "state.in").write_text("".join(
        f"set atom {i + 1} d_s {sv[i]:.17g} vx {v[i, 0]:.17g} vy {v[i, 1]:.17g}\n"
        for i in range(len(xy))))


def test_every_value_has_its_source():
    """Each parameter line of potato.cgms carries a comment, and the ones that differ from
    apple's name a source or say they are a decision; the file is potato's, not apple's."""
    apple = material.read(APPLE)
    potato = material.read(POTATO)
    lines = [raw for raw in POTATO.read_text().splitlines()
             if raw.split("#", 1)[0].split()]
    assert len(lines) == sum(1 for k in material.PARAMETERS if k in potato and k != "r0")
    for raw in lines:
        name, _ = raw.split("#", 1)[0].split()
        assert "#" in raw and raw.split("#", 1)[1].strip(), name
    changed = {"diameter", "perim_a", "P_f", "Pi_f", "solid_ratio"}
    assert {k for k in material.PARAMETERS if k in potato and k != "r0"
            and potato[k] != apple.get(k)} == changed
    text = POTATO.read_text()
    words = " ".join(line.lstrip("# ") for line in text.splitlines())
    for source in ("Konstankiewicz et al. 2002", "Wang and Brennan 1995", "Bland and Tanner 1985",
                   "Kleinkopf et al. 1987"):
        assert source in words, source
    # the perimeter law's slope is the ideal-shrinkage line the comment derives
    v = lambda s: (0.798 * s + 0.202 / 1.5) / (0.798 + 0.202 / 1.5)   # noqa: E731
    slope = (1 - v(0.3) ** (1 / 3)) / 0.7
    assert potato["perim_a"] / potato["perim_b"] == pytest.approx(slope, rel=0.01)
    assert potato["solid_ratio"] == pytest.approx(20.2 / 79.8, rel=2e-3)


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_python_and_plugin_read_the_same_file(tmp_path, path):
    """The plugin's per-bead state and forces with the file equal the NumPy oracle's with
    the values cgms.material reads from it; and they are not apple's forces."""
    require_lammps()
    mat = material.read(path)
    potato_tissue(tmp_path, mat)
    f, want, apple = forces_with_material(tmp_path, path)
    assert np.max(np.abs(f - want)) <= 1e-10 * np.max(np.abs(want))
    assert np.max(np.abs(f - apple)) > 1e-3 * np.max(np.abs(want))


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_the_86_bead_potato_tissue_dries_to_potatos_steady_state(tmp_path, path):
    """On the 86-bead calibration tissue at potato's spacing the steady state at s = 1 and
    0.8 is quasi-static and holds the moisture X/X0 of the analytic uniform steady state of
    potato's cell (cgms.model.steady_moisture), which apple's cell does not give."""
    require_lammps()
    mat = material.read(path)
    apple = material.read(APPLE)
    scale = mat["x_ref"] / apple["x_ref"]
    xy = tissue.rectangle(1.25e-3 * scale, 1.5e-3 * scale, mat["x_ref"])
    assert len(xy) == 86
    data = tmp_path / "tissue.data"
    tissue.write_data(data, xy, 3 * mat["x_ref"])
    for s in (1.0, 0.8):
        run = study.relax(data, str(path), s, tmp_path / f"s{s:g}", method="quasistatic")
        assert run["converged"], s
        want = model.steady_moisture(mat, s)
        assert run["moisture"] == pytest.approx(want, rel=1e-3), s
    assert abs(model.steady_moisture(apple, 0.8) - want) > 0.01 * want


def header_levels_and_rmsd():
    """{s: RMSD (m)} as potato-mfc.cgms's own header quotes them ('<r> m (<r/x_ref> x_ref)
    at s = <s>'), not the start material's header that a fit copies below it ('(start file
    header)')."""
    import re
    head = " ".join(line[1:] for line in POTATO_MFC.read_text().splitlines()
                    if line.startswith("#")).split("(start file header)")[0]
    quoted = re.findall(r"([0-9.eE+-]+)\s+m\s+\([0-9.eE+-]+\s+x_ref\)\s+at\s+s\s+=\s+([0-9.]+)",
                        head)
    return {float(s): float(r) for r, s in quoted}


@pytest.mark.skipif(not POTATO_MFC.exists(), reason="no potato-mfc.cgms yet")
def test_potato_mfc_reproduces_its_fit_and_beats_the_start(tmp_path):
    """On the 86-bead potato tissue, potato-mfc.cgms gives the RMSD against the committed
    MFC centroids (reference/mfc/potato-calibration) that its header quotes, at every level
    it names, and is closer to them than the uncalibrated potato.cgms."""
    from cgms import positions, superpose
    require_lammps()
    quoted = header_levels_and_rmsd()
    assert set(quoted) == {1.0, 0.8, 0.6}
    mat = material.read(POTATO_MFC)
    scale = mat["x_ref"] / material.read(APPLE)["x_ref"]
    data = tmp_path / "tissue.data"
    tissue.write_data(data, tissue.rectangle(1.25e-3 * scale, 1.5e-3 * scale, mat["x_ref"]),
                      3 * mat["x_ref"])
    folder = ROOT / "reference" / "mfc" / "potato-calibration"
    total = {}
    for name, path in (("start", POTATO), ("fitted", POTATO_MFC)):
        total[name] = 0.0
        for s, r in quoted.items():
            ids, q = positions.read_centroids(folder / f"centroids.s{s:g}.txt")
            run, note = study.relax_or_fallback(data, str(path), s, tmp_path / name / f"{s:g}")
            assert run["converged"], (name, s, note)
            got = superpose.rmsd(run["xy"], q[np.argsort(ids)], "rigid")
            total[name] += got ** 2
            if name == "fitted":
                assert got == pytest.approx(r, rel=1e-3), s
    assert total["fitted"] < 0.25 * total["start"], total
