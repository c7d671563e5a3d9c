# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Every doc example runs as written (issue 26, "Done when").

The examples are read from the files themselves, so an edited example is what is tested:
the Examples block of every style page (doc/*.rst, ``code-block:: LAMMPS``) and the fenced
blocks of README.md and of the guide its detail moved to, doc/using.md (LAMMPS inputs,
Python, shell), their inline ``python3 -m cgms ...`` commands, and the example of doc/python.md.

- LAMMPS blocks run in the plugin's LAMMPS. A style page's block is a list of variants
  (paragraphs; lines that define the same ID again): each paragraph runs in a fresh
  instance after the set-up it assumes (a small tissue of this file's fixture, the styles
  a style needs), with ``run 0`` after each variant; a ``minimize`` must stop on its
  tolerance. ``/path/to/cgms`` is this checkout.
- Python blocks run as written in a folder holding what they name (tissue.data, a
  trajectory), with ``potentials/`` of this checkout.
- Shell blocks whose run is too long for CI (a LAMMPS build, a venv install, the whole
  suite) are checked: the commands exist and take those options (``--help``, a cmake
  configure into a scratch folder, the script's cases).
- Inline ``python3 -m cgms`` commands are parsed by the command line's own parser.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from cgms import cli, positions, run, tissue
from cgmstest import ROOT, XREF, require_lammps

DOC = ROOT / "doc"
README = ROOT / "README.md"
#: the guide the README's detail moved to (the plugin line, dumps, your own LAMMPS, venv)
USING = DOC / "using.md"
#: the placeholder the docs use for this checkout
CHECKOUT = "/path/to/cgms"


# --------------------------------------------------------------------------- extraction

def rst_examples(path):
    """The lines of the ``code-block:: LAMMPS`` under a page's Examples heading."""
    text = Path(path).read_text()
    tail = text.split("\nExamples\n", 1)[1]
    block = tail.split(".. code-block:: LAMMPS\n", 1)[1]
    lines = []
    for line in block.splitlines()[1:]:
        if line and not line.startswith("   "):
            break
        lines.append(line[3:])
    return "\n".join(lines).strip("\n")


def fenced_blocks(path):
    """[(language, text)] of a Markdown file's fenced code blocks."""
    return [(m.group(1), m.group(2)) for m in
            re.finditer(r"^```(\w*)\n(.*?)^```", Path(path).read_text(), re.M | re.S)]


def paragraphs(text):
    return [p for p in re.split(r"\n\s*\n", text) if p.strip()]


def variants(paragraph):
    """A paragraph's alternatives: it is split before a line that defines again an ID (a
    fix, the pair style) it defined already; continued lines (&) joined."""
    out, seen = [[]], set()
    for line in paragraph.replace("&\n", " ").splitlines():
        words = line.split()
        key = tuple(words[:2]) if words and words[0] in ("fix", "pair_style") else None
        if key and key in seen:
            out.append([])
            seen.clear()
        if key:
            seen.add(key)
        out[-1].append(line)
    return out


# --------------------------------------------------------------------------- fixtures

@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A working folder with tissue.data (a 0.9 x 0.9 mm tissue, 28 beads) and this
    checkout's potentials/ (as README's Python example names them), LAMMPS finding the
    material files as after ``source build/env.sh``."""
    require_lammps()
    positions.write_data(tmp_path / "tissue.data", tissue.rectangle(0.9e-3, 0.9e-3, XREF),
                         3 * XREF)
    (tmp_path / "potentials").symlink_to(ROOT / "potentials")
    monkeypatch.setenv("LAMMPS_POTENTIALS", str(ROOT / "potentials"))
    monkeypatch.chdir(tmp_path)
    return tmp_path


def lammps(log, plugin=True):
    """A LAMMPS instance logging to ``log``; with the plugin loaded (as LAMMPS_PLUGIN_PATH
    does after ``source build/env.sh``) or bare."""
    if plugin:
        return run.open_lammps(log=log)
    from lammps import lammps as bare
    return bare(cmdargs=["-log", str(log), "-screen", "none", "-nocite"])


def run_lines(lines, log, plugin=True):
    """Run ``lines`` one by one; AssertionError naming the line LAMMPS stopped at."""
    lmp = lammps(log, plugin)
    try:
        for line in lines:
            try:
                lmp.command(line.replace(CHECKOUT, str(ROOT)))
            except Exception as err:
                errors = [x for x in Path(log).read_text().splitlines() if "ERROR" in x]
                raise AssertionError(f"{line!r}: {errors[-1] if errors else err}") from None
    finally:
        lmp.close()
    text = Path(log).read_text()
    # a minimisation in an example must end on its tolerance, not on a stalled line search
    for why in re.findall(r"Stopping criterion = (.*)", text):
        assert "tolerance" in why, f"the minimizer stopped on '{why}'"
    return text


#: the set-up a CGMS style page's example assumes: the tissue read, the styles around it
TISSUE = ["units si", "dimension 2", "boundary f f p", "atom_style cgms", "comm_modify vel yes",
          "read_data tissue.data", "neighbor 1.5e-5 bin"]
CGMS = TISSUE + ["pair_style cgms", "pair_coeff * * apple.cgms",
                 "fix fluid all cgms/fluid dryness 1.0", "fix nve all nve",
                 "fix 2d all enforce2d", "timestep 1e-7"]


def sph_setup(folder):
    """Four SPH particles of each of four types on a 4.47 um lattice (types 1-3 walls in
    the wall variant), as the fine model's cells have them."""
    lines = ["units si", "dimension 2", "boundary f f p", "atom_style sph",
             "region box block -2e-5 2e-5 -2e-5 2e-5 -1e-6 1e-6", "create_box 4 box",
             "mass * 1e-13", "neighbor 1e-6 nsq"]
    for t in range(1, 5):
        for k in range(4):
            lines.append(f"create_atoms {t} single {(k - 1.5) * 4.47e-6:.6g} "
                         f"{(t - 2.5) * 4.47e-6:.6g} 0")
    return lines + ["set group all sph/rho 1000.0", "fix 2d all enforce2d"]


def shaped_setup(folder):
    """A 23-bead tissue of the shaped model in its fresh state (cgms.shaped_data), read
    with its per-atom properties, as pair_cgms_shaped.rst describes."""
    from cgms import material, shaped_data, shaped_tensor
    mat = material.read("apple")
    geo = shaped_tensor.build(tissue.rectangle(0.75e-3, 0.75e-3, mat["x_ref"]), mat)
    shaped_data.write_data(folder / "shaped.data", geo, shaped_tensor.fresh_state(geo))
    return (["units si", "dimension 2", "boundary f f p", "atom_style atomic",
             "atom_modify map array"] + shaped_data.fix_command(geo).splitlines()
            + [shaped_data.read_command("shaped.data"), "neighbor 1.5e-5 bin"])


#: what a style page's variant needs besides the set-up, after its line (the example
#: shows the style's own lines only): here, the pair coefficients a hybrid and a new
#: pair style need for a run
AFTER = {
    "pair_style cgms cutoff/lj 1.3 damping no": ["pair_coeff * * apple.cgms"],
    "pair_style hybrid/overlay sph/taitwater/ap kernel wendland epsilon 0.2 nm/cut 1.2e-5":
        ["pair_coeff * * nm/cut 0.0 4.47e-6 8 4"],
    "pair_style sph/taitwater/ap kernel wendland epsilon 0.2 wall 1*3":
        ["pair_coeff * * 5.99e-3 150.0 6.0e-9 1.3e-5 4.47e-6"],
}

#: per style page: the set-up its example assumes (a function of the folder)
PAGES = {
    "atom_style_cgms.rst": lambda f: [],
    "pair_cgms.rst": lambda f: TISSUE + ["fix fluid all cgms/fluid dryness 1.0",
                                         "fix nve all nve", "fix 2d all enforce2d"],
    "fix_cgms_fluid.rst": lambda f: TISSUE + ["pair_style cgms", "pair_coeff * * apple.cgms",
                                              "fix nve all nve", "fix 2d all enforce2d",
                                              "timestep 1e-7"],
    "fix_cgms_transport.rst": lambda f: CGMS,
    "compute_cgms_atom.rst": lambda f: CGMS,
    "fix_mfc_pressure.rst": None,
    "fix_mfc_pressure3d.rst": None,
    "pair_sph_taitwater_ap.rst": sph_setup,
    "pair_cgms_shaped.rst": shaped_setup,
}
#: pages whose example is a Python block and a LAMMPS block run together, by their own test
RUN_ELSEWHERE = {"fix_mfc_pressure.rst": "its Python block writes the walls its LAMMPS block "
                                         "reads: run as written, on 1 and 2 ranks, by "
                                         "test_mfc_styles_errors.py::test_fix_mfc_pressure_"
                                         "example_runs_as_written",
                 "fix_mfc_pressure3d.rst": "its Python block writes the cell its LAMMPS block "
                                           "reads: run as written by test_mfc3d.py::"
                                           "test_fix_mfc_pressure3d_example_runs_as_written"}


def test_every_style_page_is_covered():
    assert sorted(p.name for p in DOC.glob("*.rst")) == sorted(PAGES)


@pytest.mark.lammps
@pytest.mark.parametrize("page", [pytest.param(
    name, marks=[pytest.mark.skip(reason=RUN_ELSEWHERE[name])] if name in RUN_ELSEWHERE
    else []) for name in sorted(PAGES)])
def test_style_page_example_runs(folder, page):
    example = rst_examples(DOC / page)
    assert example.strip(), f"{page} has no Examples block"
    setup = PAGES[page](folder)
    alternatives = [v for paragraph in paragraphs(example) for v in variants(paragraph)]
    for k, variant in enumerate(alternatives):   # each in a fresh LAMMPS
        lines = [x for line in variant for x in [line] + AFTER.get(line.strip(), [])]
        if page == "atom_style_cgms.rst":   # the page's block is the set-up itself
            lines += CGMS[len(TISSUE):]
        if not any(line.startswith(("run", "minimize")) for line in lines):
            lines.append("run 0")
        run_lines(setup + lines, folder / f"log.{k}.lammps", plugin=page != "atom_style_cgms.rst")


# --------------------------------------------------------------------------- README

def readme_blocks(language, path=README):
    return [text for lang, text in fenced_blocks(path) if lang == language]


@pytest.mark.lammps
def test_readme_lammps_inputs_run(folder):
    """The plugin line, the minimal input (as written: 100 000 steps of the fixture's 28
    beads) and the OVITO dump lines (after the minimal input's set-up, then run 0)."""
    (minimal,) = readme_blocks("")
    plugin, ovito = readme_blocks("", USING)
    run_lines(plugin.splitlines(), folder / "log.plugin.lammps", plugin=False)
    text = run_lines(minimal.splitlines(), folder / "log.minimal.lammps")
    assert "Loop time" in text
    setup = [line for line in minimal.splitlines() if not line.startswith(("run", "thermo"))]
    run_lines(setup + ovito.replace("&\n", " ").splitlines() + ["run 0"],
              folder / "log.ovito.lammps")
    header = Path("tissue.dump").read_text().splitlines()[8]
    assert header.split()[2:] == "id type x y z d_mf d_rho pressure area perim".split()


@pytest.mark.lammps
def test_readme_python_examples_run(folder):
    """The fields/run example, then the trajectory example on a trajectory that
    ``cgms.study.relax(..., method="dynamics", dump_every=N)`` writes, as the README says."""
    from cgms import study
    (first,) = readme_blocks("python")
    (trajectory,) = readme_blocks("python", USING)
    exec(compile(first, "README.md (From Python)", "exec"), {})
    study.relax("tissue.data", ROOT / "potentials" / "apple.cgms", 0.3, folder,
                method="dynamics", dump_every=2000)
    assert Path("tissue.s0.3.dump.traj").exists()
    found = {}
    exec(compile(trajectory, "README.md (frame by frame)", "exec"), found)
    assert len(found["shape"]["step"]) > 1


@pytest.mark.lammps
def test_python_guide_example_runs(folder):
    """doc/python.md's example, as written: the public face of cgms from a material file to
    a dried slice; it prints one line per result."""
    (example,) = [text for lang, text in fenced_blocks(DOC / "python.md") if lang == "python"]
    exec(compile(example, "doc/python.md", "exec"), {})
    assert (folder / "relaxed" / "tissue.s0.3.dump").exists()
    assert sorted(p.name for p in (folder / "swept").glob("level.s*.json")) == \
        ["level.s0.3.json", "level.s1.json"]


def test_readme_shell_blocks_are_commands_that_exist():
    """Too long to run here (the main job, the whole suite, a LAMMPS build, a venv
    install), so checked: the two commands are cases of ./cgms; the set-up and CMake read
    the README's variables (a configure takes longer than this whole file's budget); the
    venv commands name a pip-installable package whose module runs."""
    (commands,) = readme_blocks("sh")
    own_lammps, venv = readme_blocks("sh", USING)
    script = (ROOT / "cgms").read_text()
    for line in commands.splitlines():
        word = shlex.split(line, comments=True)
        assert word[0] == "./cgms" and re.search(rf"^\s+{word[1]}\)", script, re.M), line
    assert "cmake -S . -B build -DLAMMPS_SOURCE_DIR=" in own_lammps
    assert "LAMMPS_SOURCE_DIR" in (ROOT / "tools" / "setup.sh").read_text()
    cmake = (ROOT / "CMakeLists.txt").read_text()
    assert "LAMMPS_SOURCE_DIR" in cmake and "LAMMPS_BUILD_DIR" in cmake
    assert "pip install --no-build-isolation -e ." in venv
    import tomllib
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert project["project"]["name"] == "cgms"
    assert (ROOT / project["tool"]["setuptools"]["package-dir"][""] / "cgms"
            / "__main__.py").exists()
    proc = subprocess.run([sys.executable, "-m", "cgms", "--help"], capture_output=True,
                          text=True, env=dict(os.environ, PYTHONPATH=str(ROOT / "python")))
    assert proc.returncode == 0 and "study" in proc.stdout, proc.stderr


def inline_commands(path):
    """The ``python3 -m cgms ...`` commands in a Markdown file's inline code and blocks."""
    text = Path(path).read_text()
    spans = re.findall(r"`(python3 -m cgms[^`]*)`", text)
    spans += [line.split("#")[0] for lang, block in fenced_blocks(path) if lang == "sh"
              for line in block.replace("\\\n", " ").splitlines() if "python3 -m cgms" in line]
    return [s.split("python3 -m cgms", 1)[1].strip() for s in spans]


@pytest.mark.parametrize("doc", ["README.md", "doc/using.md", "studies/macroscale/README.md"])
def test_inline_commands_parse(doc):
    """Each command's subcommand and options exist and take the values shown."""
    found = inline_commands(ROOT / doc)
    assert found
    for command in found:
        words = shlex.split(command)
        if not words or words[0].startswith("-") or command.startswith("."):
            continue                                  # --help; python3 -m cgms.tissue
        if len(words) == 1:                           # a command named, not run
            assert words[0] in cli.COMMANDS, f"{doc}: no command {words[0]!r}"
            continue
        try:
            cli.parser().parse_args(words)
        except SystemExit as stop:
            pytest.fail(f"{doc}: 'python3 -m cgms {command}' does not parse ({stop.code})")


REPO_PATH = re.compile(r"\b(?:tests|python/cgms|src/CGMS|examples|studies|bench|tools|reference|"
                       r"potentials)/[A-Za-z0-9_./-]*[A-Za-z0-9_]\.(?:py|cpp|h|md|rst|cgms|"
                       r"params|sh|csv|json|txt)\b")


def test_paths_the_docs_name_exist():
    # files move (tests into subject folders, research scripts into studies/): a page that
    # names a file must name one a reader can open
    pages = [ROOT / "README.md", *sorted((ROOT / "doc").rglob("*.md")),
             *sorted((ROOT / "doc").glob("*.rst")), *sorted((ROOT / "examples").rglob("*.md")),
             *sorted((ROOT / "studies").rglob("*.md")), ROOT / "tests" / "README.md"]
    missing = sorted({f"{page.relative_to(ROOT)}: {path}" for page in pages
                      for path in REPO_PATH.findall(page.read_text())
                      if not (ROOT / path).exists()})
    assert not missing, "\n".join(missing)
