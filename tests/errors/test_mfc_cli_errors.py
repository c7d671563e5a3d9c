# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms mfc`` against tissue inputs it cannot build (adversarial pass of
2026-12-03): refused in one line, exit status 2, before any folder is made. Cell centres
closer than a cell spacing used to be refused only after the results folder and its
setup record were written; an MFC wall file (atom_style angle: id mol type x y z) had its
types read as x; a data file cut short at a line end was read as a smaller
tissue; a tissue given twice, or two data files of one name, shared a results folder."""

import numpy as np
import pytest

from cgmstest import XREF, run_cli
from cgms import positions
from cgms.mfc import model as mfc_model, tissue as mfc_tissue

TRIANGLE = np.array([[0.0, 0.0], [XREF, 0.0], [XREF / 2, XREF * 3 ** 0.5 / 2]])


def cases(tmp_path):
    close = tmp_path / "close.data"
    positions.write_data(close, TRIANGLE * 0.5, 3 * XREF, overwrite=True)
    whole = tmp_path / "whole.data"
    positions.write_data(whole, TRIANGLE, 3 * XREF, overwrite=True)
    lines = whole.read_text().splitlines()
    cut = tmp_path / "cut.data"
    cut.write_text("\n".join(lines[:-1]) + "\n")        # the last bead's line lost
    (tmp_path / "sub").mkdir()
    twin = tmp_path / "sub" / "whole.data"
    twin.write_text(whole.read_text())
    walls = tmp_path / "walls.data"       # an MFC wall file (atom_style angle) for a tissue
    mfc_tissue.write_data(walls, TRIANGLE, mfc_model.parameters())
    return [
        ([str(walls)], "its Atoms section is of atom_style angle; a tissue file is of "
                       "atom_style cgms or atomic"),
        ([str(close)], "two cell centres are 7.542e-05 m apart, closer than the cell spacing"),
        ([str(cut)], "its header declares 3 atoms, its Atoms section holds 2"),
        (["single", "single"], "tissues single and single would share the results folder"),
        ([str(whole), str(twin)], "would share the results folder whole"),
    ]


@pytest.mark.parametrize("case", range(5), ids=["walls", "close", "cut", "twice", "same-stem"])
def test_mfc_tissue_refused_before_anything_is_written(tmp_path, capsys, case):
    tissues, message = cases(tmp_path)[case]
    out = tmp_path / "out"
    status, err, _ = run_cli(capsys, "mfc", *tissues, "--dryness", "1", "--out", str(out))
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1, err
    assert lines[0].startswith("cgms mfc: ") and message in lines[0], lines[0]
    assert not out.exists()


def test_dry_refuses_a_data_file_of_another_atom_style(tmp_path, capsys):
    walls = tmp_path / "walls.data"
    mfc_tissue.write_data(walls, TRIANGLE, mfc_model.parameters())
    out = tmp_path / "out"
    status, err, _ = run_cli(capsys, "dry", "--data", str(walls), "--frozen", "--out", str(out))
    assert status == 2 and "its Atoms section is of atom_style angle" in err, err
    assert not out.exists()
