# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The fine-model styles used by hand (issue 26, "The fine-model styles used by hand").

fix mfc/pressure sums a cell's area over the ring of its wall particles: a group holding
part of a ring, two rings under one molecule ID, a particle without a cell (molecule ID 0),
an empty group, a ring of two particles or an open one (a bond missing) each stop with an
ERROR naming the molecule ID or particle (a part of a ring used to give an area that moves
with the origin, two rings used to be summed into one cell). pair sph/taitwater/ap refuses
a particle whose density is not a finite positive number (one used to turn every value into
NaN); LAMMPS itself refuses a NaN density or a bad mass in a data file. The Examples block of doc/fix_mfc_pressure.rst runs as
written on 1 and 2 ranks."""

import math
import re
import subprocess
import sys

import numpy as np
import pytest

from cgmstest import PLUGIN, ROOT, lammps_env, run_lmp
from mfc.test_mfc_sph import block_script

pytestmark = pytest.mark.lammps


def rings_data(rings, radius=1e-5, n=12):
    """A data file (atom_style bond) of rings, each ``(molecule ID, centre x, n, bonds)``:
    ``n`` particles counter-clockwise on a circle, consecutive atom IDs, bonded i -> next
    (the last bond closes the ring; ``bonds`` = how many of the ring's bonds, n for a
    closed ring)."""
    atoms, bonds = [], []
    for mol, cx, count, nbond in rings:
        first = len(atoms) + 1
        for k in range(count):
            phi = 2 * math.pi * k / count
            atoms.append(f"{first + k} {mol} 1 {cx + radius * math.cos(phi):.12e} "
                         f"{radius * math.sin(phi):.12e} 0.0")
        for k in range(nbond):
            bonds.append((first + k, first + (k + 1) % count))
    return "\n".join(
        ["rings", "", f"{len(atoms)} atoms", f"{len(bonds)} bonds", "1 atom types",
         "1 bond types", "", "-1e-4 2e-4 xlo xhi", "-1e-4 1e-4 ylo yhi", "-1e-6 1e-6 zlo zhi",
         "", "Masses", "", "1 1e-12", "", "Atoms # bond", ""] + atoms
        + ["", "Bonds", ""] + [f"{k + 1} 1 {i} {j}" for k, (i, j) in enumerate(bonds)]) + "\n"


def ring_script(group="all", nprocs=1, tail=""):
    return "\n".join([
        f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
        f"processors {nprocs} 1 1", "atom_style bond", "atom_modify map array",
        "read_data rings.data", "pair_style zero 3e-5", "pair_coeff * *",
        "bond_style harmonic", "bond_coeff 1 1.0 5e-6", "neighbor 2e-6 bin",
        "comm_modify cutoff 4e-5",
        "group half id 1:6", "group whole molecule 1", "group none empty",
        f"fix mfc {group} mfc/pressure height 6e-6 modulus 2e7 turgor 2e5 area 3e-10",
        "thermo_style custom step f_mfc[1] f_mfc[2]", "thermo_modify format float %.17g",
        tail or "run 0", ""])


def run_rings(folder, rings, group="all", nprocs=1, tail="", **kwargs):
    (folder / "rings.data").write_text(rings_data(rings, **kwargs))
    return run_lmp(folder, ring_script(group, nprocs, tail), nprocs=nprocs, check=False)


def error_line(proc):
    return next((r for r in proc.stdout.splitlines() if "ERROR" in r), proc.stdout[-2000:])


# which particle of a ring finds the fault first depends on the ranks: a pattern for it
PART = r"\d+"
RING_CASES = [  # rings, group, what the ERROR says (a regular expression)
    ([(1, 0, 12, 12)], "half",
     rf"cell \(molecule ID\) 1 is only partly in group half: its wall particle {PART} is, its "
     rf"ring neighbour {PART} is not; the group must hold whole rings"),
    ([(1, 0, 12, 12), (2, 5e-5, 12, 12)], "half", r"cell \(molecule ID\) 1 is only partly"),
    ([(1, 0, 12, 12), (1, 5e-5, 12, 12)], "all",
     r"molecule ID 1 holds 2 rings of wall particles; each cell needs its own molecule ID"),
    ([(1, 0, 12, 12), (1, 5e-5, 12, 12), (1, -5e-5, 12, 12)], "whole", "molecule ID 1 holds 3"),
    ([(1, 0, 12, 12), (0, 5e-5, 12, 12)], "all",
     rf"wall particle {PART} has molecule ID 0: every particle of group all needs the positive "
     r"molecule ID of its cell"),
    ([(1, 0, 12, 12)], "none", "group none is empty"),
    ([(1, 0, 2, 2)], "all", rf"wall particle {PART} has 1 bond partner\(s\) in its own cell "
     r"\(molecule ID 1\); each must be bonded to exactly its two ring neighbours, in a closed "
     r"ring of at least 3 particles"),
    ([(1, 0, 12, 11)], "all", rf"wall particle (1|12) has 1 bond partner\(s\) in its own cell"),
    ([(1, 0, 12, 12), (2, 5e-5, 12, 11)], "all",
     r"wall particle (13|24) has 1 bond partner\(s\) in its own cell \(molecule ID 2\)"),
]


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("rings, group, message", RING_CASES, ids=[
    "half-ring", "half-ring-of-two-cells", "two-rings", "three-rings", "molecule-0",
    "empty-group", "ring-of-2", "open-ring", "open-second-ring"])
def test_rings_the_fix_refuses(tmp_path, rings, group, message, nprocs):
    proc = run_rings(tmp_path, rings, group, nprocs)
    assert proc.returncode != 0
    assert re.search(message, error_line(proc)), error_line(proc)


def thermo(proc):
    rows = [r.split() for r in proc.stdout.splitlines() if re.match(r"^\s*0\s+\S+\s+\S+\s*$", r)]
    return [float(w) for w in rows[-1][1:]]


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_whole_rings_give_areas_that_do_not_move_with_the_origin(tmp_path, nprocs):
    """the control: two whole rings (the group 'whole' is ring 1 alone) are accepted, and
    translating them leaves the area. Shoelace terms x_i y_j of size |t| R cancel to R^2:
    the rounding is ~ n eps |t| / R of the area (12 * 2.2e-16 * 10), far below 1e-12."""
    rings = [(1, 0, 12, 12), (2, 5e-5, 12, 12)]
    for group, cells in (("all", 2), ("whole", 1)):
        tail = "run 0\ndisplace_atoms all move 1e-4 -3e-5 0 units box\nrun 0"
        proc = run_rings(tmp_path, rings, group, nprocs, tail)
        assert proc.returncode == 0, proc.stdout[-2000:]
        rows = [[float(w) for w in r.split()[1:]] for r in proc.stdout.splitlines()
                if re.match(r"^\s*0\s+\S+\s+\S+\s*$", r)]
        (n0, a0), (n1, a1) = rows[-2], rows[-1]
        polygon = cells * 12 / 2 * 1e-10 * math.sin(2 * math.pi / 12)
        assert n0 == n1 == cells
        assert a0 == pytest.approx(polygon, rel=1e-12)
        assert a1 == pytest.approx(a0, rel=1e-12)


# --------------------------------------------------------------------------- SPH densities

SPH_CASES = [  # how the block is spoilt, what the ERROR says
    ("rho 0", "atom 5 has density 0 at setup (step 0); every fluid particle needs a finite "
     "density > 0"),
    ("rho -0.001", "atom 5 has density -0.001 at setup"),
    ("set sph/rho 0", "atom 5 has density 0 at setup"),
    ("set sph/rho -1e-3", "atom 5 has density -0.001 at setup"),
    # LAMMPS refuses these itself
    ("rho nan", "Expected floating point parameter instead of 'nan'"),
    ("mass nan", "Expected floating point parameter instead of 'nan'"),
    ("mass 0", "Invalid mass value"),
]


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("case, message", SPH_CASES, ids=[c for c, _ in SPH_CASES])
def test_sph_refuses_a_bad_density_or_mass(tmp_path, case, message, nprocs):
    """atom 5 is a fluid particle (type 2) of the block of test_mfc_sph"""
    data, script = block_script()
    lines = data.splitlines()
    atom5 = next(k for k, r in enumerate(lines) if r.startswith("5 2 "))
    if case.startswith("rho "):
        words = lines[atom5].split()
        words[2] = case.split()[1]
        lines[atom5] = " ".join(words)
    elif case.startswith("mass "):
        lines[lines.index("2 9.6e-14")] = "2 " + case.split()[1]
    else:
        value = case.split()[2]
        script = script.replace("neighbor 1e-6 bin", f"set atom 5 sph/rho {value}\nneighbor 1e-6 bin")
    (tmp_path / "block.data").write_text("\n".join(lines) + "\n")
    proc = run_lmp(tmp_path, script, nprocs=nprocs, check=False)
    assert proc.returncode != 0
    assert message in error_line(proc), error_line(proc)


# --------------------------------------------------------------------------- the doc example

def rst_blocks(path, title="Examples"):
    """The code blocks of a section of an rst page: [(language, text)]."""
    text = (ROOT / path).read_text()
    part = text.split(f"\n{title}\n")[1]
    part = re.split(r"\n\S[^\n]*\n\"{3,}\n", part)[0]
    blocks = re.findall(r"\.\. code-block:: (\w+)\n\n((?:(?:   [^\n]*)?\n)+)", part)
    return [(lang, "\n".join(r[3:] for r in body.splitlines())) for lang, body in blocks]


def example_script(page, folder):
    """Run the one Python block of a style page's Examples in ``folder`` (it writes the
    data file) and return its one LAMMPS block with this build's plugin path."""
    blocks = rst_blocks(page)
    python = [b for lang, b in blocks if lang == "python"]
    lammps = [b for lang, b in blocks if lang == "LAMMPS"]
    assert len(python) == 1 and len(lammps) == 1
    env = lammps_env()
    env["PYTHONPATH"] = str(ROOT / "python")
    subprocess.run([sys.executable, "-c", python[0]], cwd=folder, env=env, check=True)
    script = lammps[0].replace("/path/to/cgms/build/cgmsplugin.so", PLUGIN)
    assert script != lammps[0]
    return script


def run_example(folder, nprocs):
    """The Examples of doc/fix_mfc_pressure.rst: the Python block writes the data file, the
    LAMMPS block (its plugin path made this build's) minimises it. Returns the force
    tolerance, the largest force component left and the wall positions by atom ID."""
    script = example_script("doc/fix_mfc_pressure.rst", folder)
    ftol = float(re.search(r"^minimize\s+\S+\s+(\S+)", script, re.M).group(1))
    script += ("\nwrite_dump all custom walls.dump id x y modify sort id format float %.17g\n"
               'print "FMAX $(fmax:%.17g)"\n')
    proc = run_lmp(folder, script, nprocs=nprocs)
    assert "linesearch alpha is zero" not in proc.stdout
    fmax = float(re.search(r"^FMAX (\S+)", proc.stdout, re.M).group(1))
    rows = (folder / "walls.dump").read_text().splitlines()[9:]
    return ftol, fmax, np.array([[float(w) for w in r.split()[1:]] for r in rows])


def test_fix_mfc_pressure_example_runs_as_written(tmp_path):
    """The minimiser reaches the example's force tolerance (it used to stop at once on a
    failed line search with a large force left)."""
    ftol, fmax, _ = run_example(tmp_path, 1)
    assert fmax < ftol


@pytest.mark.mpi
def test_fix_mfc_pressure_example_runs_on_two_ranks(tmp_path):
    """On 2 ranks (it used to stop with "Bond atoms missing") it reaches the tolerance too,
    at the serial run's state. Both stop with every force component below ftol = 1e-10 N,
    so they differ by about 2 ftol / k at most, k the softest stiffness of the walls against
    a deformation: bending, k_b / b^2 = 3.5e-11 J / (4.7 um)^2 = 1.6 N/m, so 1.3e-10 m.
    Rigid motions cost nothing, but the forces of every style sum to zero and so does their
    torque, so neither run drifts beyond round-off. Checked: 1e-9 m."""
    (tmp_path / "1").mkdir()
    (tmp_path / "2").mkdir()
    ftol, fmax1, xy1 = run_example(tmp_path / "1", 1)
    _, fmax2, xy2 = run_example(tmp_path / "2", 2)
    assert fmax1 < ftol and fmax2 < ftol
    assert np.abs(xy1 - xy2).max() < 1e-9


# ------------------------------------------------ adversarial pass of 2026-12-03

MORE_CASES = [  # what follows the fix, what the ERROR says
    # a fluid area far above the ring's: (A_f / A)^7 overflowed to an inf pressure, silently
    ("fix mfc all mfc/pressure height 6e-6 modulus 2e7 turgor 2e5 area 1e300\nrun 0",
     r"cell 1 on step 0: its fluid of rest area 1e\+300 m\^2 in a ring of area \S+ m\^2 gives "
     r"a pressure of inf Pa"),
    # a second fix on the same particles: every cell's fluid pushed twice, silently
    ("fix mfc2 all mfc/pressure height 6e-6 modulus 2e7 turgor 1e5 area 3e-10\nrun 0",
     r"Fix mfc/pressure mfc: fix mfc2 holds wall particles of group all too"),
    # one ring particle deleted: the message blamed the ghost region alone
    ("run 0\ngroup one id 3\ndelete_atoms group one bond yes\nrun 0",
     r"bond partner 3 of wall particle (2|4) is missing: it was deleted \(a ring needs every "
     r"particle: delete whole cells"),
]


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
@pytest.mark.parametrize("tail, message", MORE_CASES, ids=["overflow", "twice", "deleted"])
def test_fix_mfc_pressure_refuses_overflow_twice_and_deleted(tmp_path, tail, message, nprocs):
    proc = run_rings(tmp_path, [(1, 0, 12, 12), (2, 5e-5, 12, 12)], "all", nprocs, tail)
    assert proc.returncode != 0
    assert re.search(message, error_line(proc)), error_line(proc)
    assert not re.search(r"\binf\b", proc.stdout.split("ERROR")[0].split("Step")[-1])


def test_fix_mfc_pressure_keeps_separate_fixes_and_whole_cell_deletion(tmp_path):
    """The controls: two fixes on separate cells, and a whole cell deleted with its bonds."""
    tail = ("unfix mfc\nfix a whole mfc/pressure height 6e-6 modulus 2e7 turgor 2e5 area 3e-10\n"
            "group other molecule 2\n"
            "fix b other mfc/pressure height 6e-6 modulus 2e7 turgor 1e5 area 3e-10\n"
            "thermo_style custom step f_a[1] f_b[1]\nrun 0\n"
            "delete_atoms group other bond yes\nrun 0")
    proc = run_rings(tmp_path, [(1, 0, 12, 12), (2, 5e-5, 12, 12)], "all", 1, tail)
    assert proc.returncode == 0, error_line(proc)
    rows = [r.split() for r in proc.stdout.splitlines() if re.match(r"^\s*0\s+1\s+[01]\s*$", r)]
    assert [r[1:] for r in rows] == [["1", "1"], ["1", "0"]], proc.stdout[-1500:]
