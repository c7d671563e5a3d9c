# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms dry``: dry a tissue slice in air over time (doc/drying.md).

The air (temperature, relative humidity, velocity) and the slice (thickness, tissue from
--data or --width/--height) go in; out come, in a new folder: the drying curve X/X0(t),
the drying rate, A/A0, P/P0, EL/EL0 against time and moisture, surface and core moisture
(case hardening), moisture maps, dumps for OVITO and a CSV."""

import sys
from pathlib import Path

import numpy as np

from . import drying, material, positions, study


def read_data_positions(path):
    """Bead positions (id order) of a tissue data file (:func:`cgms.positions.read_data`)
    and whether it has a ``Diameters`` section; the transport indexes beads 1..N."""
    beads = positions.read_data(path)
    if not np.array_equal(beads["ids"], np.arange(1, len(beads["ids"]) + 1)):
        raise ValueError(f"{path}: atom ids must be 1..N")
    return beads["xy"], beads["diameters"] is not None


def add_arguments(p):
    from .cli import levels
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
    p.add_argument("--data", help="tissue data file (python3 -m cgms.tissue); else a rectangle")
    p.add_argument("--width", type=float, default=2.0, help="tissue width, mm")
    p.add_argument("--height", type=float, default=2.5, help="tissue height, mm")
    p.add_argument("--out", help="results folder (default results/drying/<date-time>)")
    p.add_argument("--material", default="apple", help="mechanics material file (default apple)")
    p.add_argument("--params", default="apple-drying",
                   help="transport parameter file (default potentials/apple-drying.params)")
    p.add_argument("--set", default="", metavar="'NAME VALUE ...'",
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
                   help="re-solve the shape when a bead's dryness moved this much "
                        "(default %(default)s)")
    p.add_argument("--solver", choices=("auto", "fire", "newton", "newton+fire"),
                   default="auto",
                   help="shape solver, warm started: FIRE, Newton, or Newton for the fresh "
                        "state and FIRE after it (auto: FIRE up to 5000 beads, Newton above, "
                        "where FIRE diverges, also warm started: doc/drying.md)")
    p.add_argument("--newton-iterations", type=int, default=8,
                   help="Newton iterations per shape solve (default %(default)s)")
    p.add_argument("--maps", type=levels, default="0.9,0.7,0.5,0.3,0.1",
                   help="X/X0 levels of the moisture maps and dumps (default %(default)s)")


def _check(args):
    for name, value, lo, hi in (("--humidity", args.humidity, 0.0, 1.0),
                                ("--stop", args.stop, 0.0, 1.0)):
        if not lo <= value < hi:
            sys.exit(f"cgms dry: {name} must be in [{lo}, {hi}), got {value}")
    for name in ("velocity", "thickness", "hours", "plate_length", "dx_max", "resolve"):
        if not getattr(args, name) > 0:
            sys.exit(f"cgms dry: --{name.replace('_', '-')} must be positive, "
                     f"got {getattr(args, name)}")
    if not -20 < args.temperature < 150:
        sys.exit(f"cgms dry: --temperature {args.temperature} C is outside -20..150 C "
                 "(the air correlations' range)")
    if args.newton_iterations < 1:
        sys.exit(f"cgms dry: --newton-iterations must be at least 1, got {args.newton_iterations}")
    if args.layers < 1:
        sys.exit(f"cgms dry: --layers must be at least 1, got {args.layers}")
    if args.faces == 0 and args.no_outline:
        sys.exit("cgms dry: with --faces 0 and --no-outline no water can leave the tissue")


def job(args):
    from . import folders

    _check(args)
    params = drying.read_params(args.params)
    mat_file = material.find(args.material)
    mat = material.with_overrides(material.read(mat_file), args.set)
    data, xy, diameters = None, None, False
    if args.data:
        data = Path(args.data).resolve()
        xy, diameters = read_data_positions(data)
    with folders.claim(args.out, "drying") as out:
        return _run(args, params, mat_file, mat, out, data, xy, diameters)


def _run(args, params, mat_file, mat, out, data, xy, diameters):
    from . import plots, tissue

    if data is None:
        xy = tissue.rectangle(args.width * 1e-3, args.height * 1e-3, mat["x_ref"])
        data = out / "tissue.data"
        tissue.write_data(data, xy, 3 * mat["x_ref"], title=f"CGMS {args.width} x "
                          f"{args.height} mm tissue")
        diameters = False
    conditions = dict(temperature=args.temperature, humidity=args.humidity,
                      velocity=args.velocity, thickness=args.thickness * 1e-3,
                      plate_length=args.plate_length * 1e-3, faces=args.faces,
                      outline=not args.no_outline, heat=not args.no_heat,
                      shrink_thickness=not args.no_shrink_thickness)
    levers = dict(layers=args.layers, dx_max=args.dx_max, resolve=args.resolve)
    levels = sorted(args.maps, reverse=True)
    print(f"cgms dry: {len(xy)} beads, air {args.temperature:g} C, RH {args.humidity:g}, "
          f"{args.velocity:g} m/s; slice {args.thickness:g} mm; results in {out}", flush=True)
    solver = args.solver if args.solver != "auto" else \
        ("newton" if len(xy) > 5000 else "fire")
    mech = None if args.frozen else drying.Mechanics(
        data, mat_file, log=out / "log.lammps", overrides=args.set, diameters=diameters,
        method=solver, newton_iterations=args.newton_iterations,
        first_iterations=8 if len(xy) > 5000 else 60)
    maps = []

    def snapshot(level, row, state):
        maps.append((level, row, state))
        if mech is not None:
            mech.dump(out / f"tissue.X{level:g}.dump")
        print(f"  t = {row['t_h']:6.3f} h  X/X0 = {row['X/X0']:.3f}  A/A0 = {row['A/A0']:.3f}  "
              f"surface {row['surface_X/X0']:.3f} core {row['core_X/X0']:.3f}  "
              f"T_product {row['T_product']:.1f} C", flush=True)

    try:
        result = drying.dry(xy, params, conditions, levers, hours=args.hours, stop=args.stop,
                            mechanics=mech, snapshots=levels, on_snapshot=snapshot)
    finally:
        if mech is not None:
            mech.close()
    rows = result["rows"]
    keys = [k for k in rows[0] if k not in ("centroid", "outline")]
    study.write_csv(rows, out / "drying.csv", columns=keys)
    plots_drying(rows, out / "drying.png")
    if maps:
        plots.snapshots([(f"X/X0 = {r['X/X0']:.2f}, {r['t_h']:.2f} h", s["xy"], s["s"])
                         for _, r, s in maps], out / "moisture.png", "bead X/X0 (column mean)")
        plots.snapshots([(f"X/X0 = {r['X/X0']:.2f}", s["xy"], s["core"] - s["surface"])
                         for _, r, s in maps], out / "case-hardening.png",
                        "core - surface X/X0", cmap="magma")
    last = rows[-1]
    t_half, t_tenth = drying.drying_time(rows, 0.5), drying.drying_time(rows, 0.1)
    fmt = lambda t: "not reached" if t is None else f"{t:.2f} h"
    print(f"cgms dry: X/X0 = 0.5 after {fmt(t_half)}, 0.1 after {fmt(t_tenth)}; at the end "
          f"({last['t_h']:.2f} h) X/X0 = {last['X/X0']:.3f}, A/A0 = {last['A/A0']:.3f}, "
          f"P/P0 = {last['P/P0']:.3f}, EL/EL0 = {last['EL/EL0']:.3f}; water balance "
          f"{max(abs(r['balance']) for r in rows):.1e}; {last['solves']} shape solves, "
          f"{result['seconds']:.1f} s")
    print(f"cgms dry: table {out}/drying.csv; plots {out}/drying.png, moisture.png, "
          f"case-hardening.png" + ("" if args.frozen else f"; dumps (OVITO) {out}/tissue.X*.dump"))
    return 0


def plots_drying(rows, path):
    """Drying curve, rate, surface and core moisture, and the shape, against time and X/X0."""
    from . import plots  # noqa: F401  (selects the non-interactive backend)
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
