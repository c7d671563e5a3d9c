# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Time-domain drying: moisture transport (:mod:`cgms.transport`) coupled to the
quasi-static mechanics of the tissue (doc/drying.md).

Two time scales: the mechanics relaxes in milliseconds, drying takes hours. The moisture
advances with its own implicit step; the beads are kept at the steady state of the
current moisture field: every bead's dryness is its column's mean X/X0, and LAMMPS
(``fix cgms/fluid`` with ``minimize balance``, FIRE) re-solves the shape, warm started
from the last one, whenever some bead's dryness has moved by ``resolve`` since the last
solve. The shape feeds back into the transport: neighbour distances, shared faces, cell
areas, the outline and (``shrink_thickness``) the column thickness.

Accuracy levers (doc/drying.md measures them): ``dx_max`` (largest change of any node's
X/X0 in one moisture step; sets the step), ``layers`` (nodes across the half thickness),
``resolve`` (dryness change that triggers a mechanics solve), ``ftol`` (FIRE force
tolerance).
"""

import math
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .. import material, model, morphology, run, study
from . import transport

CONDITIONS = dict(temperature=70.0, humidity=0.1, velocity=1.5, thickness=2e-3,
                  plate_length=0.04, faces=2, outline=True, heat=True, shrink_thickness=True)
#: ``trigger`` "mean": a shape solve when the beads' mean |change of dryness| since the
#: last reaches ``resolve`` (248-bead piece: 31 solves, A/A0 and EL/EL0 within 0.0022 of
#: solving at nearly every step; "max", the most-changed bead: 49 solves, 0.0020)
LEVERS = dict(layers=10, dx_max=0.02, dt_first=1.0, dt_max=600.0, resolve=0.02, ftol=1e-10,
              max_iterations=20000, s_min=0.3, trigger="mean")


#: what the transport needs of each parameter of a ``.params`` file (test, rule): a NaN,
#: a negative moisture or density, or a GAB K of 1 or more (the isotherm's moisture is
#: infinite at aw = 1/K) would run on into NaN or negative moisture
PARAM_RULES = {
    "X0": (lambda v: v > 0, "positive (kg water / kg dry solid)"),
    "solids_density": (lambda v: v > 0, "positive (kg/m^3)"),
    "D_ref": (lambda v: v > 0, "positive (m^2/s)"),
    "T_ref": (lambda v: v > -transport.KELVIN, "above absolute zero (C)"),
    "D_energy": (lambda v: v >= 0, ">= 0 (J/mol)"),
    "D_moisture": (lambda v: True, "a number"),
    "GAB_Xm": (lambda v: v > 0, "positive"),
    "GAB_C": (lambda v: v > 1, "above 1 (as fix cgms/transport requires)"),
    "GAB_K": (lambda v: 0 < v < 1, "in (0, 1): the isotherm must stay finite up to aw = 1"),
}


#: a warm Newton solve (Mechanics) takes at most this many iterations per Jacobian it
#: may build (``newton_iterations``): the steps of a kept matrix cost one force
#: evaluation each
REUSED_PER_JACOBIAN = 8

#: the ordering of the warm Newton solves' factorisations (:func:`cgms.solve.newton`):
#: the geometric one factorises 1.6-1.9 times faster on 20 273 beads, where the
#: factorisations took 74 % of a drying run's time (doc/results/performance.md,
#: 2026-12-03); the fresh state keeps the minimum-degree ordering of cgms study
ORDERING = "geometric"

#: the run ends when the tissue's X/X0 is this close to the equilibrium moisture of the
#: air (:func:`equilibrium_ratio`), which it nears ever more slowly and never passes: a
#: --stop below it is never reached (1e-3: the precision of the X/X0 the CLI prints)
EQUILIBRIUM_GAP = 1e-3
#: how often :func:`positive_step` halves a moisture step before it gives up (2^-60 of
#: the step: far below any step that could matter)
MAX_HALVINGS = 60


def read_params(name="apple-drying"):
    """Transport parameters of a ``potentials/*.params`` file as a dict of floats, checked
    against :data:`PARAM_RULES` (ValueError names the file, the line or the value)."""
    path = Path(name)
    if not path.is_file():
        path = material.POTENTIALS / (name if name.endswith(".params") else f"{name}.params")
    if not path.is_file():
        raise FileNotFoundError(f"drying parameter file {name!r} not found "
                                f"(looked in {material.POTENTIALS})")
    params = {}
    try:
        text = path.read_text()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None
    for lineno, raw in enumerate(text.splitlines(), 1):
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) != 2:
            raise ValueError(f"{path} line {lineno}: expected 'name value', got {raw.strip()!r}")
        if words[0] in params:
            raise ValueError(f"{path} line {lineno}: {words[0]} given twice")
        if words[0] not in PARAM_RULES:   # a misspelt name would be dropped unread
            raise ValueError(f"{path} line {lineno}: unknown parameter {words[0]!r} (known: "
                             f"{' '.join(PARAM_RULES)})")
        try:
            params[words[0]] = float(words[1])
        except ValueError:
            raise ValueError(f"{path} line {lineno}: value {words[1]!r} of {words[0]} is not "
                             "a number") from None
    missing = set(PARAM_RULES) - set(params)
    if missing:
        raise ValueError(f"{path}: missing {', '.join(sorted(missing))}")
    for name, (test, rule) in PARAM_RULES.items():
        if not (math.isfinite(params[name]) and test(params[name])):
            raise ValueError(f"{path}: {name} = {params[name]:g} must be {rule}")
    return params


def bead_geometry(xy):
    """:func:`cgms.transport.bead_geometry` of the beads at ``xy``, neighbours within
    pair_style cgms's cutoff factor (:data:`cgms.model.CUTOFF_LJ`) times the current
    median spacing: the nearest shell of the lattice, not the second at sqrt(3)
    spacings."""
    return transport.bead_geometry(xy, model.CUTOFF_LJ * morphology.spacing(xy))


class Mechanics:
    """The tissue in LAMMPS, held at the steady state of a per-bead dryness field:
    ``fix cgms/fluid dryness v_sdry`` (an atom-style variable on a per-atom property),
    solved with the pressures at balance and warm started from the last shape, by FIRE
    (``method="fire"``: ``minimize`` to the force tolerance ``ftol``) or by Newton's method
    (``method="newton"``, :func:`cgms.solve.newton`, at most ``newton_iterations``
    iterations per solve: FIRE diverges on the 20 273-bead tissue started from the
    lattice, doc/results/validation.md), or Newton for the fresh state and FIRE warm started
    after it (``method="newton+fire"``). ``first_iterations`` bounds the Newton solve of
    the fresh state (the reference of A/A0), which starts from the lattice."""

    def __init__(self, data, material_file, log="none", ftol=1e-10, max_iterations=20000,
                 overrides="", diameters=False, method="fire", newton_iterations=8, first_iterations=60):
        if method not in ("fire", "newton", "newton+fire"):
            raise ValueError(f"method must be 'fire', 'newton' or 'newton+fire', not {method!r}")
        self.log = log
        self.lmp = run.open_lammps(log=log)
        self.ftol, self.max_iterations, self.method = ftol, max_iterations, method
        self.newton_iterations, self.first_iterations = newton_iterations, first_iterations
        self.mat = material.with_overrides(material.read(material_file), overrides)
        self.solves = 0
        self.seconds = 0.0
        self.factor = {}        # Newton's kept matrix (cgms.solve.newton)
        self.info = {}          # the report of the last Newton solve
        self.dryness = 1.0      # the lowest bead dryness of the last solve
        fire = method == "fire"
        # the pressures held at balance in runs too (FIRE holds them so in its solves):
        # the moisture steps of dry() are runs of one MD step, which then change nothing
        # of the mechanics' state
        lines = run.tissue_script(Path(data).resolve(), Path(material_file).resolve(), "v_sdry",
                                  method="quasistatic" if fire else "newton",
                                  fix_args="balance yes" if fire else "",
                                  overrides=overrides, diameters=diameters).splitlines()
        # the solves are ours; the per-bead fields go in before the fix that reads them
        lines = [ln for ln in lines
                 if not ln.startswith(("minimize", "min_style", "min_modify", "run 0"))]
        at = next(k for k, ln in enumerate(lines) if ln.startswith("pair_style"))
        lines[at:at] = ["fix sdry all property/atom d_sdry d_xsurf d_xcore",
                        "variable sdry atom d_sdry"]
        lines += run.FIRE_SETTINGS
        with self._stops(1.0):
            self.lmp.commands_string("\n".join(lines) + "\n")
        self.n = self.lmp.get_natoms()

    @contextmanager
    def _stops(self, dryness):
        """LAMMPS's stops (a plain Exception, its message cut at about 100 characters) as
        :class:`cgms.study.LammpsError` with LAMMPS's whole ERROR line from the log;
        ``dryness``: the lowest bead dryness of the solve."""
        try:
            yield
        except Exception as err:
            # LAMMPS raises a plain Exception (MPIAbortException under MPI); the Python
            # solvers' own errors (cgms.solve) are not LAMMPS's and pass as they are
            if type(err) is not Exception and not type(err).__module__.startswith("lammps"):
                raise
            raise study.LammpsError(dryness, study.lammps_reason(err, self.log),
                                    self.log) from err

    def _set(self, name, values):
        nlocal = self.lmp.extract_global("nlocal")
        ids = np.array(self.lmp.numpy.extract_atom("id")[:nlocal])
        field = self.lmp.numpy.extract_atom(name)
        field[:nlocal] = np.asarray(values, float)[ids - 1]

    def solve(self, s, surface=None, core=None):
        """Positions (id order) of the steady state at dryness ``s`` (id order)."""
        start = time.perf_counter()
        self.dryness = float(np.min(s))
        with self._stops(self.dryness):
            self._solve(s, surface, core)
            # a minimiser or Newton ends on a folded tissue, or one in pieces, without a
            # word (cgms.run.folded; cgms study checks every level alike)
            broken = run.folded(self.lmp)
        if broken:
            raise study.LammpsError(self.dryness, broken, self.log)
        self.solves += 1
        self.seconds += time.perf_counter() - start
        # gathered in id order on every process (collective), so the moisture loop, which
        # every process runs alike, works under mpirun too
        x = np.ctypeslib.as_array(self.lmp.gather_atoms("x", 1, 3)).reshape(-1, 3)
        return x[:, :2].copy()

    def _solve(self, s, surface, core):
        self._set("d_sdry", s)
        self._set("d_xsurf", s if surface is None else surface)
        self._set("d_xcore", s if core is None else core)
        if self.method == "fire" or (self.method == "newton+fire" and self.solves > 0):
            self.lmp.command(f"minimize 0.0 {self.ftol} {self.max_iterations} "
                             f"{10 * self.max_iterations}")
        else:
            from .. import solve
            self.lmp.command("run 0 post no")       # the fix takes the new dryness at setup
            if self.solves == 0:
                # the fresh state from the lattice: swell it to the steady spacing first
                # and converge it (run.solve_newton, as cgms study does): it is the
                # reference of A/A0, and a reference left short of its minimum lets the
                # later, warm-started solves keep swelling (A/A0 of 1.008 at X/X0 = 0.95
                # measured with 3 iterations)
                self.info = run.solve_newton(
                    self.lmp, spacing=material.steady_spacing(self.mat, 1.0),
                    max_iterations=self.first_iterations, factor=self.factor)
            else:
                # the matrix of the last Jacobian is kept across the warm solves: the
                # shape changes little between them, and a step of the kept one costs
                # one force evaluation instead of a Jacobian's hundred
                forces = solve.LammpsForces(self.lmp)
                xy, self.info = solve.newton(
                    forces, forces.positions(), self.lmp.extract_pair("cut_global"),
                    ftol=1e-13, max_iterations=REUSED_PER_JACOBIAN * self.newton_iterations,
                    factor=self.factor, max_jacobians=self.newton_iterations,
                    ordering=ORDERING)
                forces(xy)                          # leave LAMMPS at the solution

    def dump(self, path, surface=None, core=None):
        """The tissue to ``path`` for OVITO, with each bead's ``surface`` and ``core``
        X/X0 (id order; default: those of the last solve) as ``d_xsurf``, ``d_xcore``."""
        compute, columns, names = run.dump_columns()
        if surface is not None:
            self._set("d_xsurf", surface)
            self._set("d_xcore", core)
        with self._stops(self.dryness):
            self.lmp.command(f"write_dump all custom {path} {columns} d_xsurf d_xcore "
                             f"modify sort id {names}")

    def close(self, finalize=False):
        """Close LAMMPS; ``finalize`` also ends MPI (the last call of a script run under
        mpirun)."""
        if finalize:
            self.lmp.finalize()
        else:
            self.lmp.close()


#: the transport fix's ID in the LAMMPS instance of :func:`dry`
FIX = "tr"
#: its global outputs (doc/fix_cgms_transport.rst, Output), by name
OUT = dict(t_s=0, t_h=1, ratio=2, rate=3, out_face=4, out_edge=5, balance=6, surface=7,
           core=8, T_product=10, dt_next=11, halved=15)


class TransportError(RuntimeError):
    """A stop of ``fix cgms/transport`` (its whole ERROR line): an input the moisture
    transport cannot take, or a step it cannot solve."""

    def __init__(self, line):
        super().__init__(f"the moisture transport stopped: {line}")
        self.line = line


class Transport:
    """``fix cgms/transport`` (the moisture engine, doc/fix_cgms_transport.rst) in a
    LAMMPS instance: the mechanics' own (``lmp``), or, for a frozen shape, one of its own
    holding the beads at ``xy`` and nothing else. ``keywords``: the fix's keywords for the
    conditions and levers of :func:`dry`. The fix is defined on the fresh state (its
    columns take their area from it), and again, with the same ID, after each shape
    solve with the neighbour cutoff of the new shape (it continues its columns, clock and
    balance)."""

    def __init__(self, xy, params_file, keywords, lmp=None, log="none"):
        self.own = lmp is None
        self.file, self.keywords, self.log = params_file, keywords, log
        self.cutoff = model.CUTOFF_LJ * morphology.spacing(xy)
        if self.own:
            self.lmp = run.open_lammps(log=log)
            self._beads(np.asarray(xy, float))
        else:
            self.lmp = lmp
            # the ghost beads must reach the transport's cutoff (the fresh one, the
            # largest: the tissue shrinks); the moisture steps move nothing
            self.lmp.commands_string(f"comm_modify cutoff {2 * self.cutoff!r}\n"
                                     "unfix nve\n")
        self.n = self.lmp.get_natoms()
        self.define(xy)                  # the columns start at X0 on this shape

    def _beads(self, xy):
        lo, hi = xy.min(axis=0) - 2 * self.cutoff, xy.max(axis=0) + 2 * self.cutoff
        self.lmp.commands_string("\n".join([
            "units si", "dimension 2", "boundary s s p", "atom_style atomic",
            "atom_modify map array",
            f"region box block {lo[0]!r} {hi[0]!r} {lo[1]!r} {hi[1]!r} -0.5 0.5",
            "create_box 1 box", "mass 1 1.0", f"neighbor {0.1 * self.cutoff!r} bin",
            f"comm_modify cutoff {2 * self.cutoff!r}", "thermo_style custom step",
            "thermo 0"]) + "\n")
        n = len(xy)
        x = np.zeros((n, 3))
        x[:, :2] = xy
        self.lmp.create_atoms(n, list(range(1, n + 1)), [1] * n, x.ravel().tolist())

    def define(self, xy):
        """The fix (again) with the neighbour cutoff of the shape ``xy``: pair_style
        cgms's factor times its median spacing, the nearest shell of the lattice."""
        self.cutoff = model.CUTOFF_LJ * morphology.spacing(xy)
        with self._stops():
            self.lmp.command(f"fix {FIX} all cgms/transport {self.file} {self.keywords} "
                             f"cutoff {self.cutoff!r}")
            self.lmp.command("run 0 post no")        # its setup: the outputs of its state

    @contextmanager
    def _stops(self):
        """The fix's stops (LAMMPS raises a plain Exception, its message cut at about 100
        characters) as a :class:`TransportError` with LAMMPS's whole ERROR line from the
        log (``log``: the instance's log file)."""
        try:
            yield
        except Exception as err:
            if type(err) is not Exception and not type(err).__module__.startswith("lammps"):
                raise
            raise TransportError(study.lammps_reason(err, self.log)) from err

    def move(self, xy=None):
        """One moisture step; ``xy``: the beads' new positions (frozen transport: moved
        there first)."""
        if xy is not None and self.own:
            x = np.ctypeslib.as_array(self.lmp.gather_atoms("x", 1, 3)).reshape(-1, 3)
            x[:, :2] = xy
            self.lmp.scatter_atoms("x", 1, 3, np.ctypeslib.as_ctypes(x.ravel()))
        with self._stops():
            self.lmp.command("run 1 post no")

    def vector(self):
        """The fix's global outputs (all 16, as doc/fix_cgms_transport.rst numbers them)."""
        return [self.lmp.extract_fix(FIX, 0, 1, k) for k in range(16)]

    def beads(self):
        """Each bead's (dryness for the mechanics, mean, surface, core X/X0), id order."""
        data = self.lmp.gather(f"f_{FIX}", 1, 4)
        return np.ctypeslib.as_array(data).reshape(self.n, 4).copy()

    def close(self):
        if self.own:
            self.lmp.close()


def fix_keywords(cond, lev, hours):
    """The keywords of ``fix cgms/transport`` for the conditions and levers of :func:`dry`
    (every one of them maps onto a keyword)."""
    yes = lambda flag: "yes" if flag else "no"
    return (f"temperature {cond['temperature']!r} humidity {cond['humidity']!r} "
            f"velocity {cond['velocity']!r} plate {cond['plate_length']!r} "
            f"thickness {cond['thickness']!r} faces {cond['faces']} "
            f"outline {yes(cond['outline'])} heat {yes(cond['heat'])} "
            f"shrink {yes(cond['shrink_thickness'])} layers {lev['layers']} "
            f"dt {lev['dt_first']!r} adapt {lev['dx_max']!r} {lev['dt_max']!r} "
            f"smin {lev['s_min']!r} until {hours * 3600.0!r} every 1")


def write_params(params, folder):
    """``params`` (:func:`read_params`) as a parameter file the fix reads, every value
    to the last bit."""
    path = Path(folder) / "drying.params"
    path.write_text("".join(f"{k} {params[k]!r}\n" for k in PARAM_RULES))
    return path


def resolve_due(s, s_solved, resolve, trigger):
    """Whether the dryness ``s`` has moved far enough from that of the last shape solve:
    by ``resolve`` in the tissue's mean of |change| (``trigger="mean"``) or at its
    most-changed bead (``"max"``)."""
    change = np.abs(s - s_solved)
    return (change.mean() if trigger == "mean" else change.max()) >= resolve


def dry(xy, params, conditions=None, levers=None, hours=4.0, stop=0.0, mechanics=None,
        snapshots=(), on_snapshot=None, rows=None):
    """Dry the tissue whose fresh bead positions (id order) are ``xy`` for ``hours`` or
    until its X/X0 falls to ``stop``, by ``fix cgms/transport`` (:class:`Transport`).
    ``mechanics``: a :class:`Mechanics` (None: the shape is frozen); the fix runs in its
    LAMMPS instance, and a shape solve follows whenever the dryness has moved by
    ``resolve`` (:func:`resolve_due`). ``snapshots``: X/X0 levels; when the tissue first
    reaches one, ``on_snapshot(level, row, state)`` is called (``state``: positions and
    each bead's mean, surface and core X/X0).
    The run also ends when the tissue's X/X0 comes within :data:`EQUILIBRIUM_GAP` of the
    air's equilibrium moisture (:func:`equilibrium_ratio`), which a lower ``stop`` never
    reaches. ``rows``: a list the records are appended to as they are made, so that a
    caller keeps the records so far when the run stops with an error.
    Returns dict(rows=[...], xy=positions, seconds=..., ended="stop", "equilibrium" or
    "hours", equilibrium=the air's X/X0, halved=how many moisture steps were halved to
    keep the moisture non-negative, transport=the per-bead outputs at the end)."""
    import tempfile

    cond = dict(CONDITIONS, **(conditions or {}))
    lev = dict(LEVERS, **(levers or {}))
    start = time.perf_counter()
    fresh_xy = np.asarray(xy, float)
    if mechanics is not None:
        xy = mechanics.solve(np.ones(len(fresh_xy)))    # the fresh steady state: the reference
    fresh = morphology.measures(xy)
    shape = morphology.normalise(fresh, fresh)
    rows = [] if rows is None else rows
    pending = sorted(snapshots, reverse=True)
    x_eq = equilibrium_ratio(params, cond["humidity"])
    halved = 0
    with tempfile.TemporaryDirectory(prefix="cgms-dry-") as folder:
        engine = Transport(xy, write_params(params, folder), fix_keywords(cond, lev, hours),
                           lmp=mechanics.lmp if mechanics else None,
                           log=mechanics.log if mechanics else Path(folder) / "log.lammps")
        try:
            def record():
                v = engine.vector()
                row = {"t_h": v[OUT["t_h"]], "X/X0": v[OUT["ratio"]],
                       "rate_per_h": v[OUT["rate"]], "surface_X/X0": v[OUT["surface"]],
                       "core_X/X0": v[OUT["core"]], "T_product": v[OUT["T_product"]],
                       **shape, "out_faces_kg": v[OUT["out_face"]],
                       "out_outline_kg": v[OUT["out_edge"]], "balance": v[OUT["balance"]],
                       "solves": mechanics.solves if mechanics else 0,
                       "seconds": time.perf_counter() - start}
                row["case_hardening"] = row["core_X/X0"] - row["surface_X/X0"]
                rows.append(row)
                return row, v

            row, v = record()
            beads = engine.beads()
            s_solved = beads[:, 0]
            t_end = hours * 3600
            while v[OUT["t_s"]] < t_end - 1e-9 and row["X/X0"] > max(stop, x_eq + EQUILIBRIUM_GAP):
                engine.move()
                beads = engine.beads()
                if mechanics is not None and resolve_due(beads[:, 0], s_solved, lev["resolve"],
                                                         lev["trigger"]):
                    xy = mechanics.solve(beads[:, 0], beads[:, 2], beads[:, 3])
                    s_solved = beads[:, 0]
                    shape = morphology.normalise(morphology.measures(xy), fresh)
                    engine.define(xy)
                row, v = record()
                halved += int(v[OUT["halved"]] > 0)
                while pending and row["X/X0"] <= pending[0]:
                    level = pending.pop(0)
                    if on_snapshot:
                        on_snapshot(level, row, dict(xy=xy, s=beads[:, 1], surface=beads[:, 2],
                                                     core=beads[:, 3]))
        finally:
            engine.close()
    ended = "stop" if rows[-1]["X/X0"] <= stop else \
        "equilibrium" if rows[-1]["X/X0"] <= x_eq + EQUILIBRIUM_GAP else "hours"
    return dict(rows=rows, xy=xy, seconds=time.perf_counter() - start, ended=ended,
                equilibrium=x_eq, halved=halved, transport=beads)


def equilibrium_ratio(params, humidity):
    """X/X0 of a tissue in equilibrium with air of relative ``humidity``: the GAB moisture
    at aw = RH. The tissue dries towards it and never below (while it evaporates its
    surface is cooler than the air, its aw at a given X lower, so it holds more)."""
    return float(transport.gab_moisture(humidity, params["GAB_Xm"], params["GAB_C"],
                                        params["GAB_K"])) / params["X0"]


def drying_time(rows, level):
    """Time (h) at which X/X0 first falls to ``level`` (linear between records), or None."""
    for a, b in zip(rows, rows[1:]):
        if b["X/X0"] <= level < a["X/X0"] or b["X/X0"] == level:
            f = (a["X/X0"] - level) / (a["X/X0"] - b["X/X0"])
            return a["t_h"] + f * (b["t_h"] - a["t_h"])
    return None
