# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The one harness of the CGMS tests: tissues, input scripts, running LAMMPS with the
plugin (``lmp -in`` serially or under mpirun, or the ``lammps`` Python module), the checks
every dynamics case must pass, and the ``slow`` marker.

Without a built LAMMPS (``CGMS_LMP``, ``CGMS_PLUGIN`` unset) every helper that runs it
skips its test with the reason, so the pure-Python tests run alone;
``CGMS_REQUIRE_LAMMPS=1`` (set by ``./cgms test``) turns that skip into a failure."""

import contextlib
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from cgms import cli, material, model, positions, study, tissue  # noqa: E402

LMP = os.environ.get("CGMS_LMP", "")
PLUGIN = os.environ.get("CGMS_PLUGIN", "")
APPLE = str(ROOT / "potentials" / "apple.cgms")
MAT = material.read(APPLE)
XREF = MAT["x_ref"]
CUTOFF = ("lj", 1.35)  # the plugin's default: 1.35 times the pair's LJ radius

# the tests load the plugin explicitly; an inherited autoload path would load it twice
os.environ.pop("LAMMPS_PLUGIN_PATH", None)


def lammps_missing():
    """Why LAMMPS cannot run here ("" if it can)."""
    missing = [v for v in ("CGMS_LMP", "CGMS_PLUGIN") if not os.environ.get(v)]
    if missing:
        return (f"{', '.join(missing)} not set: LAMMPS and the plugin are not built "
                "(./cgms test builds them and sets the environment)")
    if not Path(PLUGIN).exists():
        return f"the plugin {PLUGIN} does not exist: run ./cgms setup"
    return ""


def require_lammps():
    """Skip the calling test when LAMMPS is not built (fail under CGMS_REQUIRE_LAMMPS=1)."""
    reason = lammps_missing()
    if reason:
        if os.environ.get("CGMS_REQUIRE_LAMMPS"):
            pytest.fail(reason, pytrace=False)
        pytest.skip(reason)


def slow(test):
    """A long variant: marked ``slow`` and skipped unless CGMS_SLOW is set
    (``CGMS_SLOW=1 ./cgms test -m slow``)."""
    return pytest.mark.slow(pytest.mark.skipif(
        not os.environ.get("CGMS_SLOW"), reason="long variant: CGMS_SLOW=1 pytest -m slow")(test))


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


def two_blocks():
    """``(block, apart)``: a sound hexagonal tissue (0.6 x 0.6 mm) and two copies of it 3
    spacings apart, a tissue in two pieces that no pair links."""
    block = tissue.rectangle(0.6e-3, 0.6e-3, XREF)
    return block, np.vstack([block, block + [np.ptp(block[:, 0]) + 3 * XREF, 0.0]])


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


def run_lmp(folder, script, nprocs=1, check=True, timeout=600, env=None):
    """Run ``script`` with lmp in ``folder`` (serially or with mpirun -np N), with the
    environment variables ``env`` added."""
    require_lammps()
    folder = Path(folder)
    (folder / "in.test").write_text(script)
    cmd = [LMP, "-in", "in.test", "-log", "log.lammps", "-nocite"]
    if nprocs > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(nprocs)] + cmd
    proc = subprocess.run(cmd, cwd=folder, env={**lammps_env(), **(env or {})},
                          capture_output=True, text=True,
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
    require_lammps()
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


def forces_with_material(folder, material_file, dt=1e-7):
    """``run 0`` of the tissue in ``folder`` (``tissue.data``) with ``material_file``: the
    plugin's forces, those of the NumPy oracle (``tests/reference.py``) with the values
    ``cgms.material`` reads from the file, and the oracle's with apple.cgms on the same
    configuration (so a test can tell the file from apple), all in id order. The time step
    ``dt`` must lie inside the file's stability limits (the fix refuses others)."""
    import reference
    lammps = pytest.importorskip("lammps", reason="no LAMMPS Python module (./cgms setup)")
    mat = material.read(material_file)
    lmp = new_lammps()
    try:
        with working_directory(folder):
            lmp.commands_string(header() + physics().replace(APPLE, str(material_file))
                                .replace("timestep 1e-7", f"timestep {dt}"))
            lmp.command("run 0")
        n = lmp.extract_global("nlocal")
        order = np.argsort(np.array(lmp.numpy.extract_atom("id")[:n]))
        x = np.array(lmp.numpy.extract_atom("x")[:n, :2])[order]
        v = np.array(lmp.numpy.extract_atom("v")[:n, :2])[order]
        f = np.array(lmp.numpy.extract_atom("f")[:n, :2])[order]
        cg = np.array(lmp.numpy.extract_fix("fl", lammps.LMP_STYLE_ATOM,
                                            lammps.LMP_TYPE_ARRAY))[:n][order]
    finally:
        lmp.close()
    dryness, mf, l0p = cg[:, 1], cg[:, 4], cg[:, 7]   # columns: doc/fix_cgms_fluid.rst

    def oracle(mat):
        fluid = reference.fluid_state(x, dryness, mf, l0p, mat, CUTOFF, implicit_dt=dt)
        return reference.pair_forces(x, v, dryness, fluid["cgmscoef"], mat, CUTOFF)[0]

    return f, oracle(mat), oracle(material.read(APPLE))


# --------------------------------------------------------------------------- dynamics cases

COLUMNS = ["nneigh", "pressure", "area", "perim", "ldeq", "mf", "mf0", "dryness"]
THERMO = ["step", "atoms", "residual", "moisture", "speed", "kinetic", "nmin", "nmax", "pmax"]
DT = 1e-7


def pair_cutoff(si, sk):
    """The default cutoff of a pair, 1.35 r(s_ik) (pair_style cgms cutoff/lj 1.35)."""
    return CUTOFF[1] * model.lj_radius(MAT, 0.5 * (np.asarray(si) + np.asarray(sk)))


class Run:
    """One LAMMPS run of a tissue: thermo rows (``THERMO`` plus extra columns), the final
    per-bead state (``end``: x, y, vx, vy and ``COLUMNS``), the error line, the wall time."""

    def __init__(self, folder, proc, columns, wall):
        self.folder, self.proc, self.wall = Path(folder), proc, wall
        self.error = next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")
        rows = []
        for line in proc.stdout.splitlines():
            words = line.split()
            if len(words) == len(columns) and words[0].isdigit():
                try:
                    rows.append([float(w) for w in words])
                except ValueError:
                    pass
        self.thermo = {c: np.array([r[k] for r in rows]) for k, c in enumerate(columns)}
        self.end = None
        if proc.returncode == 0 and (self.folder / "end.dump").exists():
            raw = read_dump(self.folder / "end.dump")
            self.end = {name: raw[f"c_c[{k + 1}]"] for k, name in enumerate(COLUMNS)}
            self.end.update({c: raw[c] for c in ("id", "x", "y", "vx", "vy")})

    @property
    def xy(self):
        return np.column_stack([self.end["x"], self.end["y"]])

    @property
    def moisture(self):
        return float(self.end["mf"].sum() / self.end["mf0"].sum())

    def last(self, name):
        return float(self.thermo[name][-1])

    def tail(self):
        return self.proc.stdout[-3000:] + self.proc.stderr[-2000:]


def run_tissue(folder, xy, dryness="1.0", steps=100000, dt=DT, every=None, pre="",
               pair_args="", fix_args="", coefficients="", after="", diameters=None,
               nprocs=1, margin=5.0, extra_thermo=(), dumps=""):
    """Write ``xy`` as a data file and run it. ``dryness``: a number or v_name (``pre``
    defines variables); ``after``: commands after the first run (a second stage, written
    before the final dump); ``coefficients``: pair_coeff overrides."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    tissue.write_data(folder / "tissue.data", xy, margin * XREF, overwrite=True,
                      diameters=diameters)
    every = every or max(steps // 20, 1)
    if diameters is not None:
        read = ["fix diam all property/atom d_diameter",
                "read_data tissue.data fix diam NULL Diameters",
                "variable diameter atom d_diameter"]
        fix_args = f"diameter v_diameter {fix_args}"
    else:
        read = ["read_data tissue.data"]
    thermo = THERMO + [name for name, _ in extra_thermo]
    lines = [
        f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
        f"processors {nprocs} 1 1" if nprocs > 1 else "",
        "atom_style cgms", "atom_modify map array sort 0 0", "comm_modify vel yes",
        *read,
        "neighbor 1.5e-5 bin", "neigh_modify every 1 delay 0 check yes",
        pre,
        f"pair_style cgms {pair_args}", f"pair_coeff * * {APPLE} {coefficients}",
        f"fix fl all cgms/fluid dryness {dryness} {fix_args}",
        "fix nve all nve", "fix e2 all enforce2d", f"timestep {dt}",
        "compute c all property/atom " + " ".join(COLUMNS),
        "compute nmin all reduce min c_c[1]", "compute nmax all reduce max c_c[1]",
        "compute pmax all reduce max c_c[2]",
        *[f"variable {name} equal {expr}" for name, expr in extra_thermo],
        "thermo_style custom step atoms f_fl[1] f_fl[2] f_fl[3] f_fl[4] c_nmin c_nmax c_pmax "
        + " ".join(f"v_{name}" for name, _ in extra_thermo),
        "thermo_modify norm no lost error format float %.12g",
        f"thermo {every}",
        dumps,
        f"run {steps}",
        after,
        "write_dump all custom end.dump id x y vx vy c_c[*] modify sort id format float %.17g",
    ]
    start = time.perf_counter()
    proc = run_lmp(folder, "\n".join(lines) + "\n", nprocs=nprocs, check=False)
    return Run(folder, proc, thermo, time.perf_counter() - start)


def healthy(run, residual=1e-3, max_neighbours=6, decay=0.1):
    """The conditions every case must meet (module docstring)."""
    assert run.proc.returncode == 0, f"LAMMPS stopped: {run.error}\n{run.tail()}"
    assert run.end is not None
    th = run.thermo
    assert len(th["step"]) >= 2, run.tail()
    for name, values in list(th.items()) + list(run.end.items()):
        assert np.all(np.isfinite(values)), f"non-finite {name}"
    n = len(run.end["id"])
    assert np.all(th["atoms"] == n), "beads were lost"
    # no bead has left the tissue: recount the neighbours within each pair's cutoff
    xy, s = run.xy, run.end["dryness"]
    if n > 1:
        pairs = cKDTree(xy).query_pairs(1.35 * MAT["r0"] * 1.000001, output_type="ndarray")
        d = np.hypot(*(xy[pairs[:, 0]] - xy[pairs[:, 1]]).T)
        pairs = pairs[d < pair_cutoff(s[pairs[:, 0]], s[pairs[:, 1]])]
        degree = np.bincount(pairs.ravel(), minlength=n)
        assert degree.min() >= 1, f"bead {int(run.end['id'][degree.argmin()])} has no neighbour"
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        pieces = connected_components(graph, directed=False)[0]
        assert pieces == 1, f"the tissue fell apart into {pieces} pieces"
        np.testing.assert_array_equal(run.end["nneigh"], degree)
    # no bead was ever captured by a neighbour shell it does not belong to
    assert th["nmax"].max() <= max_neighbours, f"a bead had {th['nmax'].max():.0f} neighbours"
    # the pressures balance the osmotic potential
    assert th["residual"][-1] < residual, f"residual {th['residual'][-1]:.3g}"
    assert th["residual"][-1] < 1e-2 * max(th["residual"][0], residual)
    # bounded kinetic energy: no bead moves 1 % of a cell per step, and the motion decays
    dt = float(run.proc.stdout.split("Time step     :")[1].split()[0])
    assert th["speed"].max() < 0.01 * XREF / dt, f"speed {th['speed'].max():.3g} m/s"
    if decay:
        assert th["kinetic"][-1] <= decay * th["kinetic"].max()


def assert_steady_perimeters(run, rtol=1e-2, xtol=3e-4, diameter=None,
                             **coefficients):
    """Each bead's perimeter is l*_i (relative tolerance ``rtol``) and X/X0 the derived
    value (``xtol``) (:func:`cgms.model.steady_perimeter`, test_hard_cases.py). The
    moisture converges fast; single perimeters approach l* with the slow creep (2e-3 to
    5e-3 off after 1e5 steps, 5e-4 after 5e5)."""
    s = run.end["dryness"]
    want = model.steady_perimeter(MAT, s, diameter, **coefficients)
    worst = np.abs(run.end["perim"] / want - 1).max()
    assert worst < rtol, f"a bead's perimeter is {worst:.3g} off l*"
    x_pred = model.steady_moisture(MAT, s, diameter, **coefficients)
    assert run.moisture == pytest.approx(x_pred, rel=xtol)
    assert run.last("moisture") == pytest.approx(run.moisture, rel=1e-8)


# --------------------------------------------------------------------------- command line

def reached(s):
    """The stand-in's X/X0 at dryness s: rising, above s for s > 0.5 (like CGMS, where
    s = 0.85 reaches 0.87), 1.1 at s = 1."""
    return 1.1 * s ** 1.2


def fake_relax(data, material_file, dryness, out, **kwargs):
    """study.relax without LAMMPS: the tissue shrunk by a factor of s, and its dump."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    d = positions.read_data(data)
    xy = d["xy"] * (0.7 + 0.3 * dryness)
    name = study.level_name(dryness)
    lines = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(len(xy)),
             "ITEM: BOX BOUNDS ss ss pp", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id x y pressure"]
    lines += [f"{i} {x!r} {y!r} {1e5 * dryness!r}" for i, (x, y) in zip(d["ids"], xy)]
    (out / f"tissue.{name}.dump").write_text("\n".join(lines) + "\n")
    (out / f"log.{name}.lammps").write_text(f"options {kwargs}\n")
    return dict(xy=xy, moisture=reached(dryness), residual=0.0, speed=0.0, kinetic=0.0,
                steps=10, dryness=dryness, seconds=0.0, method=kwargs.get("method", "dynamics"),
                converged=True)


def run_cli(capsys, *args):
    """(exit status, stderr, stdout) of ``python3 -m cgms args``; argparse's exit counts."""
    try:
        status = cli.main(list(args))
    except SystemExit as stop:
        status = stop.code
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return status, err, out


def run_then_dump(steps, restart=None):
    """The end of a test input: ``steps`` steps (with ``restart`` written halfway, so that
    a run read back from it can be compared), then every atom's state at full precision
    in final.dump."""
    lines = ([f"run {steps // 2}", f"write_restart {restart}", f"run {steps - steps // 2}"]
             if restart else [f"run {steps}"])
    return lines + ["write_dump all custom final.dump id mol x y z vx vy vz fx fy fz "
                    "modify sort id format float %.17g"]
