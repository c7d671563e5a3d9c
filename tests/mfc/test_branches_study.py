# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""studies/mfc/branches.py compares energies only of one functional: studies of one
tissue (cell centres) and one set of parameters; the drying path and the seed may differ."""

import json
import sys

import pytest

from cgmstest import ROOT

sys.path.insert(0, str(ROOT / "studies" / "mfc"))
import branches  # noqa: E402


def study(folder, sha="c0ffee", parameters=None, **solver):
    folder.mkdir()
    (folder / "setup.json").write_text(json.dumps(dict(
        centres_sha256=sha, parameters=parameters or dict(E=1.0), **solver)))
    (folder / "level.s0.8.json").write_text(json.dumps(
        {**{k: 1.0 for k in branches.KEYS}, "energy": -1.0, "fmax": 1e-12}))
    return str(folder)


def test_branches_refuses_energies_of_different_functionals(tmp_path, capsys):
    a = study(tmp_path / "a")
    b = study(tmp_path / "b", steady_stages=True, seed=3)
    assert branches.main([f"chunk={a}", f"steady={b}"]) == 0
    assert "| 0.8 | steady |" in capsys.readouterr().out
    for name, kw, cause in (("c", dict(sha="beef"), "different tissues"),
                            ("d", dict(parameters=dict(E=2.0)), "different parameters")):
        other = study(tmp_path / name, **kw)
        with pytest.raises(SystemExit, match=cause):
            branches.main([f"a={a}", f"x={other}"])
    with pytest.raises(SystemExit, match="no setup.json"):
        branches.main([f"a={a}", f"x={tmp_path / 'none'}"])
    with pytest.raises(SystemExit, match="usage"):
        branches.main([a])
