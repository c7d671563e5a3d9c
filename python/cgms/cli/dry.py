# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms dry``: dry a tissue slice in air over time (doc/drying.md).

The air (temperature, relative humidity, velocity) and the slice (thickness, tissue from
--data or --width/--height) go in; out come, in a new folder: the drying curve X/X0(t),
the drying rate, A/A0, P/P0, EL/EL0 against time and moisture, surface and core moisture
(case hardening), moisture maps, dumps for OVITO and a CSV."""

import math
import sys
from contextlib import ExitStack
from pathlib import Path

import numpy as np

from .. import drying, folders, material, morphology, parallel, positions, study, tissue


#: the longest drying the command runs: a moisture step is at most 10 min
#: (drying.LEVERS dt_max), so 1000 h are at most 6000 steps; a run whose --stop lies
#: below the air's equilibrium ends at that equilibrium instead (drying.EQUILIBRIUM_GAP)
MAX_HOURS = 1000.0
#: the most nodes across the half thickness (doc/drying.md measures up to 80)
MAX_LAYERS = 200
#: the thinnest node across the thickness: the column solve nears singular below it
#: (measured on 33 beads: 5 um nodes, 0.4 s per moisture step; 1.9 um, 2 s, CG failing)
MIN_NODE_DEPTH = 5e-6
#: the options that are numbers: (test, rule); each must also be finite
RULES = {
    "temperature": (lambda v: -20 < v < 150, "in -20..150 C (the air correlations' range)"),
    "humidity": (lambda v: 0 <= v < 1, "in [0, 1)"),
    "stop": (lambda v: 0 <= v < 1, "in [0, 1)"),
    "velocity": (lambda v: v > 0, "positive"),
    "thickness": (lambda v: v > 0, "positive"),
    "hours": (lambda v: 0 < v <= MAX_HOURS,
              f"positive and at most {MAX_HOURS:g} (6000 moisture steps of at most 10 min)"),
    "plate_length": (lambda v: v > 0, "positive"),
    "width": (lambda v: v > 0, "positive"),
    "height": (lambda v: v > 0, "positive"),
    "dx_max": (lambda v: 0 < v <= 1, "in (0, 1] (the largest change of a node's X/X0 in "
                                     "one moisture step)"),
    "resolve": (lambda v: v > 0, "positive"),
    "layers": (lambda v: 1 <= v <= MAX_LAYERS, f"1 to {MAX_LAYERS}"),
    "newton_iterations": (lambda v: v >= 1, "at least 1"),
}
#: the files a run may write, in the order they are listed
OUTPUTS = ("drying.csv", "drying.png", "moisture.png", "case-hardening.png", "tissue.data",
           "log.lammps")


def add_arguments(p):
    from .options import levels, material_overrides
    p.add_argument("--temperature", type=float, default=70.0, help="air temperature, C")
    p.add_argument("--humidity", type=float, default=0.1,
                   help="air relative humidity, 0-1 (default 0.1)")
    p.add_argument("--velocity", type=float, default=1.5, help="air velocity, m/s")
    p.add_argument("--thickness", type=float, default=2.0, help="slice thickness, mm")
    p.add_argument("--hours", type=float, default=4.0, help="drying time to simulate, h")
    p.add_argument("--stop", type=float, default=0.1,
                   help="stop earlier when the tissue's X/X0 reaches this (default 0.1)")
    p.add_argument("--plate-length", type=float, default=40.0,
                   help="length of the slice along the air flow, mm (Sherwood correlation; "
                        "default 40)")
    p.add_argument("--data", help="tissue file instead of --width/--height: a LAMMPS data file "
                                  "(python3 -m cgms.tissue, or write_data) or cell centroids, "
                                  "one 'id x y' line each, in metres; ids 1..N")
    p.add_argument("--width", type=float, default=2.0, help="tissue width, mm")
    p.add_argument("--height", type=float, default=2.5, help="tissue height, mm")
    p.add_argument("--out", help="results folder (default results/drying/<date-time>)")
    p.add_argument("--material", default="apple", help="mechanics material file (default apple)")
    p.add_argument("--params", default="apple-drying",
                   help="transport parameter file (default potentials/apple-drying.params)")
    p.add_argument("--set", default="", metavar="'NAME VALUE ...'", type=material_overrides,
                   help="mechanics material parameters that replace the file's")
    p.add_argument("--faces", type=int, choices=(0, 1, 2), default=2,
                   help="slice faces in air (2: both, 1: one, on a tray; 0: none)")
    p.add_argument("--no-outline", action="store_true",
                   help="no drying through the tissue outline (a window of a larger slice)")
    p.add_argument("--no-heat", action="store_true",
                   help="product at the air temperature (no evaporative cooling)")
    p.add_argument("--no-shrink-thickness", action="store_true",
                   help="keep the slice thickness while the cells shrink in plane")
    p.add_argument("--frozen", action="store_true",
                   help="mechanics off: the tissue keeps its fresh shape")
    p.add_argument("--layers", type=int, default=drying.LEVERS["layers"],
                   help="nodes across the half thickness (default %(default)s)")
    p.add_argument("--dx-max", type=float, default=drying.LEVERS["dx_max"],
                   help="largest change of a node's X/X0 per moisture step (default %(default)s)")
    p.add_argument("--resolve", type=float, default=drying.LEVERS["resolve"],
                   help="re-solve the shape when the beads' dryness moved this much on "
                        "average (default %(default)s)")
    p.add_argument("--solver", choices=("auto", "fire", "newton", "newton+fire"),
                   default="auto",
                   help="shape solver, warm started: FIRE, Newton, or Newton for the fresh "
                        "state and FIRE after it (auto: FIRE up to 5000 beads, Newton above, "
                        "where FIRE diverges, also warm started: doc/drying.md)")
    p.add_argument("--newton-iterations", type=int, default=8,
                   help="Newton iterations per shape solve (default %(default)s)")
    p.add_argument("--maps", type=levels, default="0.9,0.7,0.5,0.3,0.1",
                   help="X/X0 levels of the moisture maps and dumps (default %(default)s)")


def _usage(text):
    from .options import UsageError
    return UsageError(text)


def _check(args, mat):
    """Every number option against :data:`RULES`, and the combinations that cannot dry
    (``mat``: the material, whose cell spacing bounds the thickness)."""
    for name, (test, rule) in RULES.items():
        value = getattr(args, name)
        if not (math.isfinite(value) and test(value)):
            raise _usage(f"--{name.replace('_', '-')} must be {rule}, got {value:g}")
    re = drying.transport.reynolds(args.temperature, args.velocity, args.plate_length * 1e-3)
    if not drying.transport.REYNOLDS[0] <= re <= drying.transport.REYNOLDS[1]:
        raise _usage(f"--velocity {args.velocity:g} m/s over --plate-length "
                     f"{args.plate_length:g} mm gives a Reynolds number of {re:.3g}, outside "
                     f"{drying.transport.REYNOLDS[0]:g} to {drying.transport.REYNOLDS[1]:g}, "
                     "the range of the flat-plate correlations of the air-side coefficients: "
                     "give another velocity or plate length")
    if args.thickness * 1e-3 < mat["x_ref"]:
        raise _usage(f"--thickness must be at least one cell, the material's spacing x_ref = "
                     f"{mat['x_ref'] * 1e3:.3g} mm, got {args.thickness:g}")
    depth = args.thickness * 1e-3 / (2 if args.faces == 2 else 1) / args.layers
    if depth < MIN_NODE_DEPTH:
        raise _usage(f"--layers {args.layers} cut the {args.thickness:g} mm slice into nodes "
                     f"{depth * 1e6:.2g} um deep, below {MIN_NODE_DEPTH * 1e6:g} um: use at "
                     "most " + f"{int(args.layers * depth / MIN_NODE_DEPTH)} layers")
    if args.faces == 0 and args.no_outline:
        raise _usage("with --faces 0 and --no-outline no water can leave the tissue")
    if args.out and Path(args.out).is_dir() and \
            any(p.name != folders.LOCK for p in Path(args.out).iterdir()):
        raise _usage(f"--out {args.out} exists and is not empty; choose another --out (dry "
                     "always starts a new run)")


def _tissue(args, mat):
    """The tissue of --data or --width x --height (a dict as tissues.file_tissue's), checked
    before anything is written: enough beads, positions in metres, ids 1..N, every bead
    with a neighbour (moisture must move in and out of it) and an outline with an area."""
    from . import tissues
    from .options import UsageError

    if args.data:
        what = f"--data {args.data}"
        try:
            t = tissues.file_tissue(args.data, mat)
        except UsageError:
            raise
        except ValueError as err:      # the readers' messages name the file, not always
            raise _usage(str(err) if str(args.data) in str(err) else f"{what}: {err}") \
                from None
        if not np.array_equal(t["ids"], np.arange(1, len(t["ids"]) + 1)):
            raise _usage(f"{what}: atom ids must be 1..N")
        if positions.is_data_file(args.data) and any(
                line.split("#")[0].split() == ["CGMS"]
                for line in Path(args.data).read_text().splitlines()[1:]):
            t["note"] = (f"cgms dry: {what}: its CGMS section (the fluid state LAMMPS's "
                         "write_data keeps) is not read: the drying starts from the fresh "
                         "tissue at these positions, as cgms study does")
    else:
        what = f"--width {args.width:g} --height {args.height:g}"
        room = args.width * args.height * 1e-6 / (tissue.ROW_PITCH * mat["x_ref"] ** 2)
        if room > tissues.MAX_CLI_BEADS:
            raise _usage(f"{what}: room for about {room:.3g} beads (limit "
                         f"{tissues.MAX_CLI_BEADS:g}); sizes are in millimetres")
        try:
            t = tissues.rectangle_tissue(args.width, args.height, mat)
        except ValueError:
            t = dict(xy=np.zeros((0, 2)))
        if len(t["xy"]) < tissue.MIN_BEADS:
            raise _usage(f"{what}: the rectangle holds {len(t['xy'])} bead(s) at the "
                         f"material's spacing x_ref = {mat['x_ref'] * 1e6:.2f} um; a tissue "
                         f"needs at least {tissue.MIN_BEADS}")
    try:
        drying.bead_geometry(t["xy"])
        morphology.measures(t["xy"])
    except ValueError as err:
        raise _usage(f"{what}: {err}") from None
    return t


def _mechanics_range(args, mat_file):
    """The lowest dryness the mechanics is solved at: drying.LEVERS' s_min, or higher where
    the material file's header says it is valid for less (``VALID FOR lo <= s <= hi``, as
    cgms study honours it), and the line that says so ('' if none)."""
    lo, hi = study.valid_range(mat_file)
    if args.frozen or lo <= drying.LEVERS["s_min"] and hi >= 1:
        return drying.LEVERS["s_min"], ""
    why = f"{mat_file.name} is valid for {lo:g} <= s <= {hi:g} only (its header)"
    if hi < 1:
        raise _usage(f"--material {args.material}: {why}; dry starts from the fresh tissue, "
                     "s = 1 (--frozen dries without the mechanics)")
    return lo, (f"cgms dry: {why}: a bead drier than s = {lo:g} keeps the shape of "
                f"s = {lo:g} (the shape is held there, as below s = "
                f"{drying.LEVERS['s_min']:g} for every material)")


def job(args):
    from .errors import failure
    try:
        world = parallel.world(lambda err: failure(err, args))
        return _job(args, world)
    except parallel.Stopped as stop:        # printed once, by process 0
        return stop.status
    except KeyboardInterrupt:
        print("cgms dry: interrupted before the drying began; nothing to keep",
              file=sys.stderr)
        return 130


def _job(args, world):
    """Under mpirun (``world``: doc/drying.md, Limits) every process checks the options
    and reads the inputs, and none goes on unless all could; process 0 alone then claims
    the folder and writes the tissue, and tells the others where."""
    mat_file, mat, params, s_min, valid_note, t = world.together(lambda: _inputs(args))
    with ExitStack() as stack:
        def claim():
            if world.rank > 0:
                return None
            out = stack.enter_context(folders.claim(args.out, "drying", resumable=False))
            from .tissues import write_tissue
            return out, write_tissue(out, t, mat)

        out, data = world.first(world.together(claim))
        status = world.together(lambda: _run(args, params, mat_file, out, data, t, s_min,
                                             valid_note, world))
        # the run's own stops are alike on every process, a file process 0 failed to
        # write is not: the worst status, on all
        return status if world.comm is None else max(world.comm.allgather(status))


def _inputs(args):
    """The options checked and the inputs read: (material file, material, transport
    parameters, lowest dryness of the mechanics, its note, tissue)."""
    mat_file = material.find(args.material)
    mat = material.with_overrides(material.read(mat_file), args.set)
    _check(args, mat)
    params = drying.read_params(args.params)
    s_min, valid_note = _mechanics_range(args, mat_file)
    return mat_file, mat, params, s_min, valid_note, _tissue(args, mat)


def _run(args, params, mat_file, out, data, t, s_min, valid_note, world):
    from .. import pictures

    xy = t["xy"]
    conditions = dict(temperature=args.temperature, humidity=args.humidity,
                      velocity=args.velocity, thickness=args.thickness * 1e-3,
                      plate_length=args.plate_length * 1e-3, faces=args.faces,
                      outline=not args.no_outline, heat=not args.no_heat,
                      shrink_thickness=not args.no_shrink_thickness)
    levers = dict(layers=args.layers, dx_max=args.dx_max, resolve=args.resolve, s_min=s_min)
    levels = sorted(args.maps, reverse=True)
    edge = "sealed (--no-outline: a window of a larger slice)" if args.no_outline else \
        "in air (a piece; --no-outline for a window of a larger slice)"
    print(f"cgms dry: {len(xy)} beads, air {args.temperature:g} C, RH {args.humidity:g}, "
          f"{args.velocity:g} m/s; slice {args.thickness:g} mm, {args.faces} face(s) in air, "
          f"outline {edge}; results in {out}", flush=True)
    for note in (valid_note, t.get("note")):
        if note:
            print(note, flush=True)
    x_eq = drying.equilibrium_ratio(params, args.humidity)
    if args.stop <= x_eq + drying.EQUILIBRIUM_GAP:
        print(f"cgms dry: air of RH {args.humidity:g} holds the tissue at X/X0 >= {x_eq:.3f} "
              f"(its GAB equilibrium): --stop {args.stop:g} is never reached; the run ends "
              "at that equilibrium or after --hours", flush=True)
    solver = args.solver if args.solver != "auto" else \
        ("newton" if len(xy) > 5000 else "fire")
    maps, rows, mech = [], [], None

    def snapshot(level, row, state):
        maps.append((level, row, state))
        if mech is not None:
            mech.dump(out / f"tissue.X{level:g}.dump", state["surface"], state["core"])
        print(f"  t = {row['t_h']:6.3f} h  X/X0 = {row['X/X0']:.3f}  A/A0 = {row['A/A0']:.3f}  "
              f"surface {row['surface_X/X0']:.3f} core {row['core_X/X0']:.3f}  "
              f"T_product {row['T_product']:.1f} C", flush=True)

    result, stopped, status = None, "", 0
    try:
        if not args.frozen:
            mech = drying.Mechanics(
                data, mat_file, log=out / "log.lammps", overrides=args.set,
                diameters=t["diameters"] is not None, method=solver,
                newton_iterations=args.newton_iterations,
                first_iterations=8 if len(xy) > 5000 else 60)
        result = drying.dry(xy, params, conditions, levers, hours=args.hours, stop=args.stop,
                            mechanics=mech, snapshots=levels, on_snapshot=snapshot, rows=rows)
    except study.LammpsError as err:
        # FIRE, warm started, can fling a bead out where Newton holds (potato-mfc.cgms:
        # a bead at 2e4 m at s = 0.79, "Too many neighbor bins"; Newton dries it to 0.1)
        hint = "; --solver newton solves the shape by Newton's method instead" \
            if solver == "fire" else ""
        stopped, status = (f"LAMMPS stopped the shape solve at s = {err.dryness:.3g}: "
                           f"{err.reason} (log: {err.log}{hint})"), 1
    except (RuntimeError, ValueError) as err:
        stopped, status = str(err), 1
    except KeyboardInterrupt:
        stopped, status = "interrupted", 130
    finally:
        if mech is not None:
            mech.close()
    if world.rank > 0:          # process 0 writes the files and speaks
        return status
    if rows:
        keys = [k for k in rows[0] if k not in ("centroid", "outline")]
        study.write_csv(rows, out / "drying.csv", columns=keys)
        plots_drying(rows, out / "drying.png")
    if maps:
        pictures.snapshots([dict(title=f"X/X0 = {r['X/X0']:.2f}, {r['t_h']:.2f} h",
                                 xy=s["xy"], values=s["s"], fresh_xy=None)
                            for _, r, s in maps], out / "moisture.png", "bead X/X0 (column mean)")
        pictures.snapshots([dict(title=f"X/X0 = {r['X/X0']:.2f}", xy=s["xy"],
                                 values=s["core"] - s["surface"], fresh_xy=None)
                            for _, r, s in maps], out / "case-hardening.png",
                           "core - surface X/X0", cmap="magma")
    if stopped:
        when = (f"at t = {rows[-1]['t_h']:.3f} h (X/X0 = {rows[-1]['X/X0']:.3f}); the results "
                f"up to then: {written(out)}") if rows else \
            f"before the drying began; written: {written(out)}"
        print(f"cgms dry: {stopped} {when}; dry does not resume: run again with a new --out",
              file=sys.stderr)
        return status
    report(result, args, x_eq)
    print(f"cgms dry: results: {written(out)}")
    return 0


def report(result, args, x_eq):
    """The summary lines of a finished run: the drying times, the final state, and why it
    ended where --stop was not reached."""
    rows = result["rows"]
    last = rows[-1]
    t_half, t_tenth = drying.drying_time(rows, 0.5), drying.drying_time(rows, 0.1)
    fmt = lambda t: "not reached" if t is None else f"after {t:.2f} h"
    print(f"cgms dry: X/X0 = 0.5 {fmt(t_half)}, 0.1 {fmt(t_tenth)}; at the end "
          f"({last['t_h']:.2f} h) X/X0 = {last['X/X0']:.3f}, A/A0 = {last['A/A0']:.3f}, "
          f"P/P0 = {last['P/P0']:.3f}, EL/EL0 = {last['EL/EL0']:.3f}; water balance "
          f"{max(abs(r['balance']) for r in rows):.1e}; {last['solves']} shape solves, "
          f"{result['seconds']:.1f} s")
    if result["ended"] == "equilibrium":
        print(f"cgms dry: the tissue came within {drying.EQUILIBRIUM_GAP:g} of its equilibrium "
              f"with the air (X/X0 = {x_eq:.3f} at RH {args.humidity:g}) and dries no further; "
              f"--stop {args.stop:g} lies below it")
    if result["halved"]:
        print(f"cgms dry: {result['halved']} moisture step(s) were halved to keep every "
              f"node's moisture non-negative (--dx-max {args.dx_max:g} lets steps grow "
              "longer than the surface water lasts)")


def written(out):
    """The files of a run that exist, as one phrase."""
    names = [name for name in OUTPUTS if (out / name).exists()]
    dumps = sorted(out.glob("tissue.X*.dump"))
    return f"{out}/ " + ", ".join(names) + \
        (f"; dumps (OVITO) {', '.join(p.name for p in dumps)}" if dumps else "")


def plots_drying(rows, path):
    """Drying curve, rate, surface and core moisture, and the shape, against time and X/X0."""
    from .. import pictures  # noqa: F401  (selects the non-interactive backend)
    import matplotlib.pyplot as plt

    t = np.array([r["t_h"] for r in rows])
    x = np.array([r["X/X0"] for r in rows])
    fig, ax = plt.subplots(2, 3, figsize=(12, 6.5), constrained_layout=True)
    ax[0, 0].plot(t, x, label="tissue")
    ax[0, 0].plot(t, [r["surface_X/X0"] for r in rows], "--", label="faces (surface layer)")
    ax[0, 0].plot(t, [r["core_X/X0"] for r in rows], ":", label="core (mid-plane layer)")
    ax[0, 0].set(xlabel="t (h)", ylabel="X/X0", title="drying curve")
    ax[0, 0].legend(fontsize=7)
    ax[0, 1].plot(t[1:], [r["rate_per_h"] for r in rows[1:]])
    ax[0, 1].set(xlabel="t (h)", ylabel="-d(X/X0)/dt (1/h)", title="drying rate")
    ax[0, 2].plot(x[1:], [r["rate_per_h"] for r in rows[1:]])
    ax[0, 2].set(xlabel="X/X0", ylabel="-d(X/X0)/dt (1/h)", title="drying rate")
    ax[0, 2].invert_xaxis()
    for key in ("A/A0", "P/P0", "EL/EL0"):
        ax[1, 0].plot(t, [r[key] for r in rows], label=key)
        ax[1, 1].plot(x, [r[key] for r in rows], label=key)
    ax[1, 0].set(xlabel="t (h)", title="shape")
    ax[1, 1].set(xlabel="X/X0", title="shape")
    ax[1, 1].invert_xaxis()
    ax[1, 0].legend(fontsize=7)
    ax[1, 2].plot(t, [r["case_hardening"] for r in rows], label="core - surface X/X0")
    ax[1, 2].plot(t, [r["T_product"] / 100 for r in rows], label="T_product / 100 C")
    ax[1, 2].set(xlabel="t (h)", title="case hardening, product temperature")
    ax[1, 2].legend(fontsize=7)
    for a in ax.ravel():
        a.grid(alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
