# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A wall ring the cell measures cannot take (adversarial pass of 2026-12-03).

A ``cgms mfc`` level whose walls passed through each other ended with the one line "cgms
mfc: math domain error" (a square root of a negative second moment), and a crossed ring of
positive net area was measured without a word (its shoelace area is not the cell's). Now
the ring is refused by name: the cell, the level (and the ramp stage it was met at), what
is kept and what to try; the finished levels stay, and a resume with a level in between
continues from them."""

import math
import re
import warnings

import numpy as np
import pytest

from cgmstest import run_cli

from cgms.mfc import metrics as mfc_metrics, run as mfc_run


def circle(n=12, r=1e-5, centre=(0.0, 0.0)):
    t = 2 * math.pi * np.arange(n) / n
    return np.column_stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)])


def test_crossed_inverted_and_flat_rings_are_named():
    good = circle()
    crossed = good.copy()
    crossed[[2, 7]] = crossed[[7, 2]]   # net area still positive: used to be measured
    with pytest.raises(mfc_metrics.RingError, match=r"cell 2's wall ring crosses itself "
                       r"\(its wall segment from particle 14 on crosses"):
        mfc_metrics.cells(np.concatenate([good, crossed]), 12)
    with pytest.raises(mfc_metrics.RingError, match="cell 1's wall ring encloses no positive"):
        mfc_metrics.cells(good[::-1], 12)
    flat = np.column_stack([np.linspace(0, 1e-5, 12), np.zeros(12)])
    with pytest.raises(mfc_metrics.RingError, match="cell 1's wall ring"):
        mfc_metrics.cells(flat, 12)
    nan = good.copy()
    nan[4, 0] = math.nan
    with pytest.raises(mfc_metrics.RingError, match="not finite"):
        mfc_metrics.cells(nan, 12)
    # a sound ring, non-convex too, is measured as before
    star = circle(12) * np.where(np.arange(12) % 2, 0.5, 1.0)[:, None]
    assert mfc_metrics.crossing(star) is None
    assert mfc_metrics.cells(star, 12)["area"][0] > 0


def flip_particle(lmp, atom=3):
    """Move wall particle ``atom`` to beyond the far side of its (single, centred) cell."""
    lmp.commands_list([f"group flipped id {atom}", "variable fx atom -1.5*x",
                       "variable fy atom -1.5*y", "set group flipped x v_fx y v_fy"])


@pytest.mark.lammps
@pytest.mark.parametrize("where", ["level", "ramp"])
def test_mfc_level_with_a_crossed_ring_names_cell_and_level_and_keeps_the_rest(
        tmp_path, capsys, monkeypatch, where):
    out = tmp_path / "study"
    args = ["mfc", "single", "--out", str(out), "--ftol", "1e-9"]
    if where == "level":   # the ring crosses once the level's solve is done
        ramp = mfc_run.ramp

        def crossing_ramp(lmp, p, s_from, s_to, **kwargs):
            report = ramp(lmp, p, s_from, s_to, **kwargs)
            if s_to < 1:
                flip_particle(lmp)
            return report
        monkeypatch.setattr(mfc_run, "ramp", crossing_ramp)
        said = r"s = 0\.8: cell 1's wall ring crosses itself"
    else:                  # ... or on the ramp, at a stage between the levels
        levers = mfc_run.level_commands

        def crossing_levers(p, s, fix_id="mfc"):
            flip = ["group flipped id 3", "variable fx atom -1.5*x", "variable fy atom -1.5*y",
                    "set group flipped x v_fx y v_fy"] if abs(s - 0.9) < 1e-9 else []
            return levers(p, s, fix_id) + flip
        monkeypatch.setattr(mfc_run, "level_commands", crossing_levers)
        said = r"s = 0\.8 \(on the ramp from s = 1, at s = 0\.9\): cell 1's wall ring crosses"
    status, err, _ = run_cli(capsys, *args, "--dryness", "1,0.8")
    assert status == 1 and len(err.strip().splitlines()) == 1, err
    assert "math domain" not in err
    assert err.startswith("cgms mfc: ") and re.search(said, err), err
    assert "the levels finished (s = 1) stay in" in err and "--resume" in err, err
    assert "--self-E0 above this run's" in err, err   # the lever that holds pressed folds apart
    folder = out / "single"
    assert (folder / "level.s1.json").exists() and not (folder / "level.s0.8.json").exists()
    assert (folder / "walls.failed.s0.8.dump").exists()
    # the cure it names: a level in between, resumed from the finished fresh level
    monkeypatch.undo()
    with warnings.catch_warnings():     # a one-cell resume used to warn from NumPy
        warnings.simplefilter("error")
        status, err, stdout = run_cli(capsys, *args, "--dryness", "1,0.9,0.8", "--resume")
    assert status == 0 and err == "", err
    assert (folder / "level.s0.8.json").exists()
