# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""No traceback reaches a command-line user, and each refusal names the real cause in the
CLI's own terms (issue 26, "Messages that blame the wrong cause"; doc/errors.md).

Every invocation below is a bad or odd input to `study`, `target`, `sensitivity`,
`calibrate`, `tissue`, `mfc` or `material` (`dry` has its own tests). Each must end with a non-zero
exit, one message line on stderr (argparse's usage lines aside) holding the words that
name the cause, no traceback, and no half-written folder: an input refused before a run
creates nothing, and a run LAMMPS stops leaves whole files only (no temporary file), with
the log the message names."""

import os
import shlex

import numpy as np
import pytest

from cgms import cli, positions, tissue
from cgmstest import XREF

#: LAMMPS's words that a command-line message must not use (its cures are for input
#: scripts); 'ERROR' is LAMMPS's own prefix
LAMMPS_WORDS = ("min_style", "min_modify", "dmax", "isolated allow", "pair_coeff",
                "pair_style", "timestep", "read_data", "ERROR", ".cpp")


@pytest.fixture
def files(tmp_path, monkeypatch):
    """Odd input files in tmp_path (the working directory)."""
    monkeypatch.chdir(tmp_path)
    block = tissue.rectangle(0.6e-3, 0.6e-3, XREF)
    calib = tissue.rectangle(1.25e-3, 1.5e-3, XREF)

    def centroids(name, xy, scale=1.0):
        (tmp_path / name).write_text("".join(f"{i + 1} {x * scale!r} {y * scale!r}\n"
                                             for i, (x, y) in enumerate(xy)))
    centroids("micrometres.txt", block, 1e6)
    centroids("row.txt", [(i * XREF, 0.0) for i in range(6)])
    centroids("isolated.txt", np.vstack([block, [[0.01, 0.01]]]))
    centroids("duplicate.txt", np.vstack([block, block[:1]]))
    centroids("ref86.txt", calib)
    centroids("ref86um.txt", calib, 1e6)
    (tmp_path / "nan.txt").write_text("".join(f"{i + 1} {x!r} {y!r}\n"
                                              for i, (x, y) in enumerate(block)) + "99 nan 0\n")
    (tmp_path / "empty.txt").write_text("")
    (tmp_path / "binary.dat").write_bytes(bytes(range(256)) * 4)
    (tmp_path / "no-atoms.data").write_text("title\n\n3 atoms\n\nAtoms\n\n")
    (tmp_path / "short.data").write_text("title\n\n3 atoms\n\nAtoms\n\n1 1 0 0\n")
    positions.write_data(tmp_path / "two.data", block[:2], 3 * XREF)
    (tmp_path / "folder").mkdir()
    return tmp_path


#: (command line, words of the message that name the cause). --out o names the folder
#: a command would write.
REFUSED = [
    # sizes
    ("study --width 0.2 --height 0.2 --out o", "(mm) holds 2 bead(s)"),
    ("study --width 1e-9 --height 1 --out o", "(mm) holds 0 bead(s)"),
    ("study --width 1e9 --height 1e9 --out o", "sizes are in millimetres"),
    ("study --width inf --out o", "argument --width: must be a positive number"),
    ("study --set 'pectin 1' --out o", "holds 0 bead(s) at the material's cell spacing"),
    ("target 0.6 --width 0.2 --height 0.2 --out o", "(mm) holds 2 bead(s)"),
    # --data files
    ("study --data micrometres.txt --out o", "positions must be cell centres in metres"),
    ("target 0.6 --data micrometres.txt --out o", "positions must be cell centres in metres"),
    ("study --data row.txt --out o", "collinear"),
    ("sensitivity --data row.txt --out o", "collinear"),
    ("study --data isolated.txt --out o", "the beads form 2 pieces: bead id(s) 15"),
    ("study --data nan.txt --out o", "bead id 99 has a non-finite position"),
    ("study --data duplicate.txt --out o", "beads 1 and 15 are at the same position"),
    ("study --data empty.txt --out o", "--data empty.txt: no 'id x y' lines"),
    ("study --data binary.dat --out o", "--data binary.dat: not a text file"),
    ("study --data no-atoms.data --out o", "the Atoms section is empty"),
    ("study --data short.data --out o", "expected 'id type x y z'"),
    ("study --data two.data --out o", "2 bead(s); a tissue needs at least 3"),
    ("study --data folder --out o", "--data folder: no such file"),
    ("calibrate --reference 1=ref86.txt --data row.txt --out o", "collinear"),
    # options and material
    ("study --set 'k_T' --out o", "expected 'name value' pairs"),
    ("study --set 'k_T nan' --out o", "k_T is not finite"),
    ("study --set 'k_T -1' --out o", "k_T = -1 must be > 0"),
    ("study --set 'nonsense 1' --out o", "unknown CGMS parameter 'nonsense'"),
    ("study --dryness 0 --out o", "level 0 is outside (0, 1]"),
    ("study --dryness 0.3,abc --out o", "'abc' is not a number"),
    ("study --material nosuch --out o", "material file 'nosuch' not found"),
    ("study --material folder --out o", "material file 'folder' not found"),
    ("study --material binary.dat --out o", "cannot be read"),
    ("study --material empty.txt --out o", "k_T is missing"),
    ("study --seed -5 --cv 0.1 --out o", "argument --seed: must be an integer from 0"),
    ("study --cv 0.9 --out o", "use a smaller --cv"),
    ("study --method dynamics --fallback dynamics --out o", "the dynamics has nothing to fall"),
    ("target 0.6 --method dynamics --fallback dynamics --out o", "nothing to fall back to"),
    ("target nan --out o", "argument target: must be a positive number"),
    ("sensitivity --width 0 --out o", "argument --width: must be a positive number"),
    # calibrate's references and fit options, checked before its folder is made
    ("calibrate --reference 1=nosuch.txt --out o", "--reference 1=nosuch.txt: no such file"),
    ("calibrate --reference 1=empty.txt --out o", "--reference 1=empty.txt: no 'id x y'"),
    ("calibrate --reference 1=binary.dat --out o", "--reference 1=binary.dat: not a text"),
    ("calibrate --reference 1=micrometres.txt --out o", "has 14 beads but the tissue has 86"),
    ("calibrate --reference 1=ref86um.txt --out o", "positions must be in metres"),
    ("calibrate --reference 5=ref86.txt --out o", "the level must be in (0, 1]"),
    ("calibrate --reference x=ref86.txt --out o", "the level must be a number"),
    ("calibrate --reference 1=ref86.txt --fit nonsense --out o", "unknown parameter 'nonsense'"),
    ("calibrate --reference 1=ref86.txt --fit '' --out o", "no parameter to fit"),
    ("calibrate --reference 1=ref86.txt --fit beta@0.3 --out o", "no reference at s = 0.3"),
    ("calibrate --reference 1=ref86.txt --bounds k_T=2:1 --out o", "--bounds: k_T: bounds"),
    ("calibrate --reference 1=ref86.txt --bounds k_T=1 --out o", "--bounds: bad value"),
    ("calibrate --reference 1=ref86.txt --start k_T=0 --out o", "--start: k_T: the start"),
    ("calibrate --reference 1=ref86.txt --workers 0 --out o", "must be at least 1"),
    # the tissue builder (--out is its data file)
    ("tissue rect 0 1 --out o", "width must be positive"),
    ("tissue rect 1 1 --margin -1 --out o", "margin must be positive"),
    ("tissue disc nan --out o", "radius must be positive"),
    ("tissue rect 1 1 --spacing 1e-30 --out o", "sizes are in millimetres"),
    ("tissue rect 1 1 --out folder", "Is a directory: folder"),
    ("tissue polygon nosuch.txt --out o", "No such file or directory: nosuch.txt"),
    ("tissue polygon binary.dat --out o", "binary.dat: not a text file"),
    ("tissue polygon empty.txt --out o", "polygon is empty"),
    ("tissue polygon row.txt --out o", "expected 'x y'"),
    ("tissue disc 0.01 --out o", "holds 1 bead(s)"),
    ("tissue rect 1 1 --material nosuch --out o", "material file 'nosuch' not found"),
    # the fine model
    ("mfc nosuch --out o", "unknown tissue 'nosuch'"),
    ("mfc --dryness 5 --out o", "level 5 is outside (0, 1]"),
    ("mfc --stage nan --out o", "--stage must be in [0, 1)"),
    ("mfc --newton nan --out o", "--newton must be >= 0"),
    ("mfc --stages steady --stage 0 --out o", "--stage 0 jumps (there are none)"),
    ("mfc --stages quasi --out o", "argument --stages: invalid choice: 'quasi'"),
    ("mfc --material nosuch --out o", "material file 'nosuch' not found"),
    ("mfc --temperature 150 --out o", "--temperature must be in 0 .. 100 (C"),
    ("mfc --temperature -1 --out o", "--temperature must be in 0 .. 100 (C"),
    ("mfc --temperature nan --out o", "--temperature must be in 0 .. 100 (C"),
    ("mfc --temperature warm --out o", "argument --temperature: invalid float value"),
    # the coarse parameters at a temperature
    ("material --temperature 55 --out o", "40 and 70 C, lie across the membrane window"),
    ("material --temperature 150 --out o", "150 C: outside the calibrated range"),
    ("material --temperature nan --out o", "must be a number of degrees C"),
    ("material --temperature 40 --family nosuch --out o", "no calibrated material nosuch-T"),
]

#: stops found by LAMMPS on a small tissue, each quick (before or at the first steps)
STOPPED = [
    ("study --width 0.6 --height 0.6 --dryness 0.3 --set 'lj_slope 50' --out o",
     "the material's LJ radius is not positive; --dryness levels above 0.98"),
    ("study --width 0.6 --height 0.6 --dryness 1e-300 --out o",
     "the material's LJ radius is not positive; --dryness levels above 4.283e-06"),
    ("study --width 0.6 --height 0.6 --dryness 0.3 --set 'beta_b 1' --out o",
     "periphery factor beta is not positive; --dryness levels above 0.3566"),
    ("study --width 0.6 --height 0.6 --dryness 0.3 --set 'lj_slope 0.3' --out o",
     "keeps its neighbours only down to s = 0.421, with little room to move); --start "
     "previous"),
    ("study --width 0.6 --height 0.6 --dryness 0.3 --set 'k_S 1e6' --method dynamics --out o",
     "k_S = 1e+06 N/m is too stiff for the dynamics' time step"),
]


def invoke(capfd, line):
    """(status, message lines, stderr) of ``python3 -m cgms <line>``, run in this process
    (capfd also catches what LAMMPS writes to the file descriptors)."""
    try:
        status = cli.main(shlex.split(line))
    except SystemExit as stop:
        status = stop.code
    err = capfd.readouterr().err
    # argparse's usage block comes before its one 'error:' line
    lines = [x for x in err.splitlines() if x.strip() and not x.startswith(("usage:", " "))]
    return status, lines, err


def temporary_files(folder):
    return [p for p in folder.rglob("*") if p.name.endswith((".tmp", ".new"))]


@pytest.mark.parametrize("line, cause", REFUSED, ids=[c[0] for c in REFUSED])
def test_refused_in_one_line_naming_the_cause(files, capfd, line, cause):
    before = sorted(p.name for p in files.iterdir())
    status, lines, err = invoke(capfd, line)
    assert "Traceback" not in err
    # a bad option or input file, refused before anything runs: status 2 in every command
    assert status == 2 and len(lines) == 1, (status, err)
    assert cause in lines[0], lines[0]
    assert not [w for w in LAMMPS_WORDS if w in lines[0]], lines[0]
    assert sorted(p.name for p in files.iterdir()) == before   # nothing created


@pytest.mark.lammps
@pytest.mark.parametrize("line, cause", STOPPED, ids=[c[0] for c in STOPPED])
def test_lammps_stops_in_one_line_in_cli_terms(files, capfd, line, cause):
    status, lines, err = invoke(capfd, line)
    assert "Traceback" not in err
    assert status == 1 and len(lines) == 1, err
    assert cause in lines[0], lines[0]
    assert not [w for w in LAMMPS_WORDS if w in lines[0]], lines[0]
    log = lines[0].rsplit("(LAMMPS log: ", 1)[1].rstrip(")")
    assert os.path.exists(log)                      # the log it names holds LAMMPS's line
    assert not temporary_files(files / "o")
    assert not list((files / "o").rglob("level.*"))  # no result for the level
