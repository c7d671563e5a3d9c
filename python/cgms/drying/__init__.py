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
LEVERS = dict(layers=10, dx_max=0.02, dt_first=1.0, dt_max=600.0, resolve=0.02, ftol=1e-10,
              max_iterations=20000, s_min=0.3)


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
    "GAB_C": (lambda v: v > 0, "positive"),
    "GAB_K": (lambda v: 0 < v < 1, "in (0, 1): the isotherm must stay finite up to aw = 1"),
}


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
    lattice, doc/validation.md), or Newton for the fresh state and FIRE warm started
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
        self.dryness = 1.0      # the lowest bead dryness of the last solve
        lines = run.tissue_script(Path(data).resolve(), Path(material_file).resolve(), "v_sdry",
                                  method="quasistatic" if method == "fire" else "newton",
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
                run.solve_newton(self.lmp, spacing=material.steady_spacing(self.mat, 1.0),
                                 max_iterations=self.first_iterations)
            else:
                forces = solve.LammpsForces(self.lmp)
                xy, _ = solve.newton(forces, forces.positions(),
                                     self.lmp.extract_pair("cut_global"), ftol=1e-13,
                                     max_iterations=self.newton_iterations)
                forces(xy)                          # leave LAMMPS at the solution

    def dump(self, path):
        compute, columns, names = run.dump_columns()
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


def dry(xy, params, conditions=None, levers=None, hours=4.0, stop=0.0, mechanics=None,
        snapshots=(), on_snapshot=None, transport_geometry=True, rows=None):
    """Dry the tissue whose fresh bead positions (id order) are ``xy`` for ``hours`` or
    until its X/X0 falls to ``stop``. ``mechanics``: a :class:`Mechanics` (None: the shape
    is frozen). ``snapshots``: X/X0 levels; when the tissue first reaches one,
    ``on_snapshot(level, row, state)`` is called (``state``: positions and each bead's mean,
    surface and core X/X0).
    ``transport_geometry`` False keeps the transport geometry of the fresh tissue while the
    mechanics moves (an ingredient switch, and the moisture-domain check).
    The run also ends when the tissue's X/X0 comes within :data:`EQUILIBRIUM_GAP` of the
    air's equilibrium moisture (:func:`equilibrium_ratio`), which a lower ``stop`` never
    reaches. ``rows``: a list the records are appended to as they are made, so that a
    caller keeps the records so far when the run stops with an error.
    Returns dict(rows=[...], x=node moisture, grid=..., xy=positions, balance=...,
    ended="stop", "equilibrium" or "hours", equilibrium=the air's X/X0, halved=how many
    moisture steps were halved to keep the moisture non-negative)."""
    cond = dict(CONDITIONS, **(conditions or {}))
    lev = dict(LEVERS, **(levers or {}))
    x0 = params["X0"]
    gab = (params["GAB_Xm"], params["GAB_C"], params["GAB_K"])
    kc, h = transport.air_coefficients(cond["temperature"], cond["velocity"],
                                       cond["plate_length"])
    n = len(xy)
    if mechanics is not None:
        xy = mechanics.solve(np.ones(n))          # the fresh steady state: the reference
    fresh = morphology.measures(xy)
    geo = bead_geometry(xy)
    area0 = geo["area"].copy()
    thick0 = np.full(n, cond["thickness"])
    solids = params["solids_density"] * area0 * thick0
    grid = transport.column_grid(geo, thick0, solids, lev["layers"], cond["faces"])
    x = np.full(n * lev["layers"], x0)
    water0 = transport.water(grid, x)
    s_solved = np.ones(n)
    t, dt, out_face, out_edge = 0.0, lev["dt_first"], 0.0, 0.0
    rows = [] if rows is None else rows
    pending = sorted(snapshots, reverse=True)
    start = time.perf_counter()

    def record(rate):
        mean, surf, core = transport.bead_moisture(grid, x)
        shape = morphology.normalise(morphology.measures(xy), fresh)
        w = transport.water(grid, x)
        row = {"t_h": t / 3600, "X/X0": w / water0, "rate_per_h": rate,
               "surface_X/X0": float(np.average(surf, weights=solids)) / x0,
               "core_X/X0": float(np.average(core, weights=solids)) / x0,
               "T_product": t_product, **shape,
               "out_faces_kg": out_face, "out_outline_kg": out_edge,
               "balance": (water0 - w - out_face - out_edge) / water0,
               "solves": mechanics.solves if mechanics else 0,
               "seconds": time.perf_counter() - start}
        row["case_hardening"] = row["core_X/X0"] - row["surface_X/X0"]
        rows.append(row)
        return row, dict(xy=xy, s=mean / x0, surface=surf / x0, core=core / x0)

    def temperature():
        if not cond["heat"]:
            return cond["temperature"]
        # D at the last product temperature for the surface resistance: a lag of one step
        d = transport.diffusivity(x, t_product, params["D_ref"], params["T_ref"],
                                  params["D_energy"], params["D_moisture"], x0)
        return transport.product_temperature(kc, h, cond["temperature"], cond["humidity"],
                                             gab, grid, x, d, cond["outline"])

    t_product = cond["temperature"]     # the first guess temperature() starts from
    t_product = temperature()
    record(0.0)
    t_end = hours * 3600
    x_eq = equilibrium_ratio(params, cond["humidity"])
    halved = 0
    while t < t_end - 1e-9 and rows[-1]["X/X0"] > max(stop, x_eq + EQUILIBRIUM_GAP):
        dt = min(dt, t_end - t)
        t_product = temperature()
        law = transport.vapour_surface(kc, t_product, cond["temperature"], cond["humidity"],
                                       gab)

        def diff(v):
            return transport.diffusivity(v, t_product, params["D_ref"], params["T_ref"],
                                         params["D_energy"], params["D_moisture"], x0)

        before = transport.water(grid, x)
        x_new, face, edge, dt, cut = positive_step(grid, x, dt, diff, law, cond["outline"])
        halved += cut
        change = np.abs(x_new - x).max() / x0
        x = x_new
        t += dt
        out_face += face
        out_edge += edge
        rate = (before - transport.water(grid, x)) / water0 / (dt / 3600)
        dt = min(lev["dt_max"], dt * min(2.0, lev["dx_max"] / max(change, 1e-12)))
        s = np.clip(transport.bead_moisture(grid, x)[0] / x0, lev["s_min"], 1.0)
        if mechanics is not None and np.abs(s - s_solved).max() >= lev["resolve"]:
            _, surf, core = transport.bead_moisture(grid, x)
            xy = mechanics.solve(s, surf / x0, core / x0)
            s_solved = s
            if transport_geometry:
                geo = bead_geometry(xy)
                thick = thick0 * np.sqrt(geo["area"] / area0) if cond["shrink_thickness"] \
                    else thick0
                grid = transport.column_grid(geo, thick, solids, lev["layers"], cond["faces"])
        row, state = record(rate)
        while pending and row["X/X0"] <= pending[0]:
            level = pending.pop(0)
            if on_snapshot:
                on_snapshot(level, row, state)
    ended = "stop" if rows[-1]["X/X0"] <= stop else \
        "equilibrium" if rows[-1]["X/X0"] <= x_eq + EQUILIBRIUM_GAP else "hours"
    return dict(rows=rows, x=x, grid=grid, xy=xy, water0=water0, kc=kc, h=h,
                seconds=time.perf_counter() - start, ended=ended, equilibrium=x_eq,
                halved=halved)


def equilibrium_ratio(params, humidity):
    """X/X0 of a tissue in equilibrium with air of relative ``humidity``: the GAB moisture
    at aw = RH. The tissue dries towards it and never below (while it evaporates its
    surface is cooler than the air, its aw at a given X lower, so it holds more)."""
    return float(transport.gab_moisture(humidity, params["GAB_Xm"], params["GAB_C"],
                                        params["GAB_K"])) / params["X0"]


def positive_step(grid, x, dt, diff, law, outline):
    """:func:`cgms.transport.step` of at most ``dt``, halved until every node's moisture
    stays finite and non-negative: the surface law is linearised at the start of the
    step, and while the surface holds free water (aw = 1) it is a constant flux, which a
    long step draws past the water the surface nodes hold (measured with dx_max 1 and no
    heat: the faces' mean X/X0 at -0.15). Returns (x, out through faces, out through the outline, the
    step taken, how often it was halved); RuntimeError after :data:`MAX_HALVINGS`."""
    for cut in range(MAX_HALVINGS + 1):
        x_new, face, edge, _ = transport.step(grid, x, dt, diff, law, outline=outline)
        if np.all(np.isfinite(x_new)) and x_new.min() >= 0:
            return x_new, face, edge, dt, cut
        dt *= 0.5
    raise RuntimeError(f"no moisture step keeps every node's moisture finite and "
                       f"non-negative, down to {2 * dt:.3g} s")


def drying_time(rows, level):
    """Time (h) at which X/X0 first falls to ``level`` (linear between records), or None."""
    for a, b in zip(rows, rows[1:]):
        if b["X/X0"] <= level < a["X/X0"] or b["X/X0"] == level:
            f = (a["X/X0"] - level) / (a["X/X0"] - b["X/X0"])
            return a["t_h"] + f * (b["t_h"] - a["t_h"])
    return None
