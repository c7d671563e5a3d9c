"""Helpers shared by the CGMS tests: tissues, input scripts, running LAMMPS with the
plugin (``lmp -in`` serially or under mpirun, or the ``lammps`` Python module)."""

import contextlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from cgms import material, tissue  # noqa: E402

LMP = os.environ.get("CGMS_LMP", "")
PLUGIN = os.environ.get("CGMS_PLUGIN", "")
APPLE = str(ROOT / "potentials" / "apple.cgms")
MAT = material.read(APPLE)
XREF = MAT["x_ref"]
CUTOFF = ("lj", 1.35)  # the plugin's default: 1.35 times the pair's LJ radius

# the tests load the plugin explicitly; an inherited autoload path would load it twice
os.environ.pop("LAMMPS_PLUGIN_PATH", None)


def lammps_env():
    env = dict(os.environ)
    env.pop("LAMMPS_PLUGIN_PATH", None)
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env["OMP_NUM_THREADS"] = "1"
    return env


def make_tissue(folder, ncols=9, nrows=10, jitter=0.05, seed=0, s=1.0, vscale=0.0, drift=(0, 0),
                margin=4.0):
    """A jittered hexagonal patch written to ``folder/tissue.data`` plus ``folder/state.in``,
    an include file that sets per-bead dryness (property d_s) and velocities.
    ``s`` is a number or a (lo, hi) range drawn uniformly per bead."""
    rng = np.random.default_rng(seed)
    xy = tissue.hex_rectangle(ncols, nrows, XREF)
    xy = xy + rng.uniform(-jitter, jitter, xy.shape) * XREF
    n = len(xy)
    sv = rng.uniform(*s, n) if isinstance(s, tuple) else np.full(n, float(s))
    v = rng.normal(0.0, vscale, (n, 2)) + np.asarray(drift, float) if vscale or any(drift) \
        else np.zeros((n, 2))
    folder = Path(folder)
    tissue.write_data(folder / "tissue.data", xy, margin * XREF, overwrite=True)
    lines = [f"set atom {i + 1} d_s {sv[i]:.17g} vx {v[i, 0]:.17g} vy {v[i, 1]:.17g}"
             for i in range(n)]
    (folder / "state.in").write_text("\n".join(lines) + "\n")
    return dict(xy=xy, s=sv, v=v, n=n)


def header(data="tissue.data", newton="on", plugin=True, processors=None):
    """Commands up to and including read_data, with the per-bead state include."""
    return "\n".join([
        f"plugin load {PLUGIN}" if plugin else "",
        "units si",
        "dimension 2",
        "boundary f f p",
        f"newton {newton}",
        f"processors {processors} 1 1" if processors else "",
        "atom_style cgms",
        "atom_modify map array sort 0 0",
        "comm_modify vel yes",
        f"read_data {data}",
        "neighbor 1.5e-5 bin",
        "neigh_modify every 1 delay 0 check yes",
        "fix sprop all property/atom d_s",
        "include state.in",
        "variable s atom d_s",
    ]) + "\n"


def physics(pair_args="", fix_args="", material_overrides=""):
    return "\n".join([
        f"pair_style cgms {pair_args}",
        f"pair_coeff * * {APPLE} {material_overrides}",
        f"fix fl all cgms/fluid dryness v_s {fix_args}",
        "fix nve all nve",
        "fix e2 all enforce2d",
        "timestep 1e-7",
    ]) + "\n"


def run_lmp(folder, script, nprocs=1, check=True, timeout=600):
    """Run ``script`` with lmp in ``folder`` (serially or with mpirun -np N)."""
    folder = Path(folder)
    (folder / "in.test").write_text(script)
    cmd = [LMP, "-in", "in.test", "-log", "log.lammps", "-nocite"]
    if nprocs > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(nprocs)] + cmd
    proc = subprocess.run(cmd, cwd=folder, env=lammps_env(), capture_output=True, text=True,
                          timeout=timeout, stdin=subprocess.DEVNULL)
    if check and proc.returncode != 0:
        raise AssertionError(f"lmp failed ({proc.returncode}):\n{proc.stdout[-4000:]}\n"
                             f"{proc.stderr[-4000:]}")
    return proc


def read_dump(path):
    """Last frame of a text dump as {column: array sorted by id}."""
    lines = Path(path).read_text().splitlines()
    start = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    cols = lines[start].split()[2:]
    data = np.array([[float(w) for w in line.split()] for line in lines[start + 1:]])
    data = data[np.argsort(data[:, cols.index("id")])]
    return {c: data[:, k] for k, c in enumerate(cols)}


def new_lammps():
    """A serial lammps Python instance with the CGMS plugin loaded."""
    from lammps import lammps
    lmp = lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    lmp.command(f"plugin load {PLUGIN}")
    return lmp


@contextlib.contextmanager
def working_directory(folder):
    """Run a Python LAMMPS session's relative paths inside ``folder``."""
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(cwd)
