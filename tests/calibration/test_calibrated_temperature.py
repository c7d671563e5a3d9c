# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The coarse parameters at a temperature (doc/drying.md, "The coarse parameters at a
temperature"): the committed files potentials/apple-mfc-T*.cgms load and say their
temperature; cgms.temperature reproduces them at their temperatures, interpolates ln c
linearly in 1/T between two on one side of the membrane window (computed here by hand),
and refuses a temperature across the window or outside the calibrated ones, in one line
from the CLI."""

import json
import math
import re
import sys

import numpy as np
import pytest

from cgms import cli, material, positions, study, superpose, temperature, tissue
from cgmstest import ROOT, XREF, require_lammps

sys.path.insert(0, str(ROOT / "studies" / "calibration"))
import fit  # noqa: E402

KELVIN = 273.15
# the membrane window of doc/drying.md: intact to 50 C, none left at 60 C
ONSET, GONE = 50.0, 60.0
COMMITTED = sorted((ROOT / "potentials").glob("apple-mfc-T*.cgms"))
# Tolerance: a value is c0^(1-x) c1^x against exp of the same line written another way, a
# handful of roundings each (1e-15 relative); 1e-12 leaves room for the order and nothing
# for a wrong line (a change of 1 K in one end moves the midpoint by more than 1e-4).
EXACT = 1e-12


def by_hand(T, T0, c0, T1, c1):
    """ln c linear in 1/T (kelvin) through (T0, c0) and (T1, c1)."""
    x = (1 / (T + KELVIN) - 1 / (T0 + KELVIN)) / (1 / (T1 + KELVIN) - 1 / (T0 + KELVIN))
    return math.exp(math.log(c0) + x * (math.log(c1) - math.log(c0)))


def family_in(folder, temperatures, k_T=None, header=None):
    """Files <folder>/fake-T<deg>.cgms: apple.cgms with k_T and k_PA set per temperature
    (k_T(T) given, k_PA = 2 k_T x 1e8) and a TEMPERATURE line (or ``header``)."""
    text = (ROOT / "potentials" / "apple.cgms").read_text()
    for T in temperatures:
        kT = k_T(T) if k_T else 1e-10 * (1 + T / 100)
        body = re.sub(r"^k_T .*$", f"k_T {kT!r}", text, flags=re.M)
        body = re.sub(r"^k_PA .*$", f"k_PA {2e8 * kT!r}", body, flags=re.M)
        line = header if header is not None else f"# TEMPERATURE: {T:g} C (test)"
        (folder / f"fake-T{T:g}.cgms").write_text(
            "# DATE: 2026-12-03 UNITS: si CONTRIBUTOR: test MODEL: cgms\n" + line + "\n" + body)


@pytest.fixture
def fake(tmp_path, monkeypatch):
    """A family 'fake' at 20, 40 (membranes intact), 70, 80 C (gone) in its own folder."""
    monkeypatch.setattr(material, "POTENTIALS", tmp_path)
    family_in(tmp_path, (20, 40, 70, 80))
    return tmp_path


# ----------------------------------------------------------------- the committed files

def test_committed_files_exist_one_each_side():
    """At least one calibrated temperature on each side of the membrane window."""
    temps = [temperature.temperature_of(f) for f in COMMITTED]
    assert any(t <= ONSET for t in temps) and any(t >= GONE for t in temps), temps


@pytest.mark.parametrize("path", COMMITTED, ids=lambda p: p.name)
def test_committed_file_loads_with_tag_temperature_and_range(path):
    """Each file reads by the plugin's rules, its first line carries MODEL: cgms (the pair
    style it was fitted for), its header says its temperature (the one of its name) and how
    it was made, and the levels it holds for."""
    text = path.read_text()
    first = text.splitlines()[0]
    assert first.startswith("# DATE:") and re.search(r"\bMODEL: cgms$", first)
    T = temperature.temperature_of(path)
    assert T == float(re.search(r"-T(\d+)\.cgms$", path.name).group(1))
    assert "# Made by: python3 studies/calibration/fit.py" in text
    assert study.valid_range(path) == (0.6, 1.0)
    p = material.read(path)
    for name in ("k_T", "k_PA", "beta_a", "beta_b", "turgid_ratio"):
        assert p[name] > 0


def own_header(path):
    """A file's own header: its comment lines above the start material's copied header."""
    text = " ".join(line[1:] for line in path.read_text().splitlines() if line.startswith("#"))
    return text.split("(start file header)")[0]


@pytest.mark.parametrize("path", COMMITTED, ids=lambda p: p.name)
def test_committed_file_matches_its_reference(path):
    """The reference the header names holds the fitted levels, and was made at the header's
    temperature (its setup.json; the unheated set, which has none, stands for 20 C)."""
    folder = re.search(r"References: MFC centroids in (\S+)", own_header(path)).group(1)
    folder = ROOT / folder
    setup = folder / "setup.json"
    made_at = (json.loads(setup.read_text())["parameters"].get("temperature")
               if setup.is_file() else None)
    assert (made_at if made_at is not None else 20.0) == temperature.temperature_of(path)
    for s in (1, 0.8, 0.6):
        assert (folder / f"centroids.s{s:g}.txt").is_file()


@pytest.fixture(scope="module")
def steady(tmp_path_factory):
    """The 86-bead calibration tissue's steady states with each committed file at s = 1,
    0.8, 0.6, solved as the fit solved them (FIRE, else the dynamics)."""
    require_lammps()
    folder = tmp_path_factory.mktemp("temperature")
    data = folder / "tissue.data"
    tissue.write_data(data, tissue.rectangle(1.25e-3, 1.5e-3, XREF), 3 * XREF)
    out = {}
    for path in COMMITTED:
        for s in (1.0, 0.8, 0.6):
            run, note = study.relax_or_fallback(data, path, s, folder / path.stem)
            assert run["converged"], (path.name, s, note)
            out[path, s] = run["xy"]
    return out


@pytest.mark.parametrize("path", COMMITTED, ids=lambda p: p.name)
def test_committed_file_reproduces_the_rmsd_in_its_header(steady, path):
    """The header quotes the fit's RMSD per level against its reference; a fresh run of the
    file gives it again (the file holds what was fitted, against the data committed). The
    header prints 4 digits; the steady states are solved to 1e-13 N (FIRE) or the
    dynamics' residual, far inside 1e-3 of an RMSD of microns."""
    head = own_header(path)
    folder = ROOT / re.search(r"References: MFC centroids in (\S+)", head).group(1)
    quoted = re.findall(r"([0-9.eE+-]+)\s+m\s+\([0-9.eE+-]+\s+x_ref\)\s+at\s+s\s+=\s+([0-9.]+)",
                        head)
    assert {float(s) for _, s in quoted} == {1.0, 0.8, 0.6}
    for r, s in quoted:
        ids, q = positions.read_centroids(folder / f"centroids.s{float(s):g}.txt")
        got = superpose.rmsd(steady[path, float(s)], q[np.argsort(ids)], "rigid")
        assert got == pytest.approx(float(r), rel=1e-3), s


def test_committed_files_reproduced_at_their_temperatures():
    """At a calibrated temperature the values are that file's, bit for bit."""
    for path in COMMITTED:
        values, source = temperature.at_temperature(temperature.temperature_of(path))
        assert source == path
        assert values == material.read(path)


def test_committed_interpolation_is_log_linear_and_monotone():
    """Between two calibrated temperatures on one side every fitted value is the line
    ln c = a + b / T computed here, and so lies between its ends and moves one way."""
    files = temperature.calibrated()
    sides = [[t for t in files if t <= ONSET], [t for t in files if t >= GONE]]
    checked = 0
    for ts in sides:
        for T0, T1 in zip(ts, ts[1:]):
            a, b = material.read(files[T0]), material.read(files[T1])
            moved = [k for k in a if a[k] != b[k]]
            assert moved, "two calibrated files with the same values"
            grid = [T0 + (T1 - T0) * i / 20 for i in range(21)]
            runs = {k: [] for k in moved}
            for T in grid:
                values, _ = temperature.at_temperature(T)
                for k in moved:
                    assert values[k] == pytest.approx(by_hand(T, T0, a[k], T1, b[k]),
                                                      rel=EXACT)
                    runs[k].append(values[k])
                for k in set(a) - set(moved):
                    assert values[k] == a[k]
            for k, r in runs.items():
                steps = [q - p for p, q in zip(r, r[1:])]
                assert all(d >= 0 for d in steps) or all(d <= 0 for d in steps), k
            checked += 1
    assert checked >= 1, "no side has two calibrated temperatures"


def test_committed_refused_across_the_window_and_outside():
    files = list(temperature.calibrated())
    with pytest.raises(ValueError, match="across the membrane window"):
        temperature.at_temperature(55)
    with pytest.raises(ValueError, match="outside the calibrated range"):
        temperature.at_temperature(files[-1] + 1)
    with pytest.raises(ValueError, match="outside the calibrated range"):
        temperature.at_temperature(files[0] - 1)


# --------------------------------------------------------------- the interpolation logic

def test_interpolation_by_hand_on_a_made_family(fake):
    """On a family whose k_T is 1e-10 (1 + T/100): the ends exact, the middle the line."""
    for T in (20, 40, 70, 80):
        values, _ = temperature.at_temperature(T, "fake")
        assert values["k_T"] == 1e-10 * (1 + T / 100)
    for T, (T0, T1) in ((31.0, (20, 40)), (77.5, (70, 80))):
        values, _ = temperature.at_temperature(T, "fake")
        for k, scale in (("k_T", 1.0), ("k_PA", 2e8)):
            want = by_hand(T, T0, scale * 1e-10 * (1 + T0 / 100),
                           T1, scale * 1e-10 * (1 + T1 / 100))
            assert values[k] == pytest.approx(want, rel=EXACT)
    # a value ln-linear in 1/T is reproduced exactly between the ends
    family_in(fake, (21, 41), k_T=lambda T: 3e-11 * math.exp(-2000 / (T + KELVIN)))
    for f in fake.glob("fake-T[2478]0.cgms"):
        f.unlink()
    values, _ = temperature.at_temperature(33.3, "fake")
    assert values["k_T"] == pytest.approx(3e-11 * math.exp(-2000 / (33.3 + KELVIN)), rel=EXACT)


@pytest.mark.parametrize("T, words", [
    (45, "across the membrane window (50-60 C"),
    (55, "across the membrane window"),
    (65, "across the membrane window"),
    (10, "outside the calibrated range 20-80 C"),
    (95, "outside the calibrated range 20-80 C"),
    (float("nan"), "must be a number"),
    (float("inf"), "must be a number"),
])
def test_refusals_name_the_cause_and_the_calibrated_ones(fake, T, words):
    with pytest.raises(ValueError) as err:
        temperature.at_temperature(T, "fake")
    assert words in str(err.value)
    if math.isfinite(T):
        assert "20, 40 C (membranes intact); 70, 80 C (membranes gone)" in str(err.value)


def test_a_file_inside_the_window_or_without_temperature_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(material, "POTENTIALS", tmp_path)
    family_in(tmp_path, (20, 55))
    with pytest.raises(ValueError, match="calibrated at 55 C, inside the membrane window"):
        temperature.calibrated("fake")
    (tmp_path / "fake-T55.cgms").unlink()
    family_in(tmp_path, (40,), header="# no temperature here")
    with pytest.raises(ValueError, match="no '# TEMPERATURE: <T> C' line"):
        temperature.calibrated("fake")
    with pytest.raises(ValueError, match="no calibrated material nothing-T"):
        temperature.calibrated("nothing")


def test_written_file_reads_back_and_says_its_temperature(fake):
    path = temperature.write(fake / "at33.cgms", 33, "fake")
    values, _ = temperature.at_temperature(33, "fake")
    assert material.read(path) == values
    lines = path.read_text().splitlines()
    assert "MODEL: cgms" in lines[0]
    assert lines[1].startswith("# TEMPERATURE: 33 C, fake: ln c linear in 1/T between "
                               "fake-T20.cgms (20 C) and fake-T40.cgms (40 C)")
    assert temperature.temperature_of(path) == 33.0   # not the source file's own line
    # the nearer end in 1/T (x = 0.665 of the way to 40 C) lends its other values and its
    # header, whose TEMPERATURE line no longer reads as the file's
    assert [w for w in lines if w.startswith("# (start file header) TEMPERATURE: 40 C")]
    with pytest.raises(FileExistsError):
        temperature.write(path, 33, "fake")


def test_cli_writes_and_refuses_in_one_line(fake, tmp_path, capsys):
    out = tmp_path / "at75.cgms"
    assert cli.main(["material", "--temperature", "75", "--family", "fake",
                     "--out", str(out)]) == 0
    assert temperature.temperature_of(out) == 75.0
    assert cli.main(["material", "--temperature", "55", "--family", "fake",
                     "--out", str(tmp_path / "no.cgms")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(
        "cgms material: --temperature: no coarse parameters at 55 C: the calibrated "
        "temperatures nearest it, 40 and 70 C, lie across the membrane window")
    assert not (tmp_path / "no.cgms").exists()


# ------------------------------------------------------------- fit.py's header lines

def test_fit_reads_the_reference_temperature(tmp_path):
    (tmp_path / "setup.json").write_text(
        '{"parameters": {"temperature": 70.0, "wall_factor": 0.8389, '
        '"turgor_factor": 0.0}}')
    assert fit.reference_temperature(tmp_path, None).startswith("70 C (the MFC reference")
    assert fit.reference_temperature(tmp_path, 70.0).startswith("70 C")
    with pytest.raises(SystemExit, match="was made at 70 C"):
        fit.reference_temperature(tmp_path, 40.0)
    unheated = tmp_path / "unheated"
    unheated.mkdir()
    assert fit.reference_temperature(unheated, None) is None
    assert fit.reference_temperature(unheated, 20.0).startswith("20 C (the MFC reference")
