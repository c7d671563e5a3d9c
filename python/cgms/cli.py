"""Command line: ``python3 -m cgms main`` runs the main job (the microscale study);
``study`` dries any rectangular tissue over moisture levels; ``target`` finds the initial
dryness that reaches a given moisture; ``calibrate`` fits material parameters to reference
centroid positions (eqn 2); ``sensitivity`` runs the paper's sensitivity study."""

import argparse
import os
import sys
from datetime import datetime
from pathlib import Path

import numpy as np

from . import calibrate, material, morphology, plots, study, tissue

DEFAULT_LEVELS = ",".join(f"{s:g}" for s in study.LEVELS)

# the paper's microscale tissues (width x height, mm) and the 86-bead calibration tissue
MICROSCALE = {
    "calibration": (1.25, 1.5),
    "1.5x1.5": (1.5, 1.5),
    "1.5x2.0": (1.5, 2.0),
    "1.5x2.5": (1.5, 2.5),
    "2.0x2.0": (2.0, 2.0),
    "2.0x2.5": (2.0, 2.5),
}


def new_folder(out, kind):
    """A results folder that does not hold anything yet (nothing is overwritten)."""
    out = Path(out) if out else Path("results") / kind / datetime.now().strftime("%Y%m%d-%H%M%S")
    if out.exists() and any(out.iterdir()):
        sys.exit(f"cgms: {out} exists and is not empty; choose another --out "
                 "(or --resume to continue an interrupted study there)")
    out.mkdir(parents=True, exist_ok=True)
    return out


def build(out, width_mm, height_mm, mat, cv=0.0, seed=1):
    """Write the tissue's data file (reused if it is already there) and return its info."""
    xy = tissue.rectangle(width_mm * 1e-3, height_mm * 1e-3, mat["x_ref"])
    diameters = tissue.cell_diameters(len(xy), mat["diameter"], cv, seed) if cv > 0 else None
    data = out / "tissue.data"
    if not data.exists():
        tissue.write_data(data, xy, 3 * mat["x_ref"], diameters=diameters,
                          title=f"CGMS {width_mm} x {height_mm} mm tissue")
    return dict(data=data, n=len(xy), diameters=diameters is not None)


def dry(out, name, width_mm, height_mm, mat_file, levels, args):
    """One tissue through every level: the table, the curves and the snapshots."""
    mat = material.with_overrides(material.read(mat_file), args.set)
    folder = out / name
    folder.mkdir(exist_ok=True)
    info = build(folder, width_mm, height_mm, mat, args.cv, args.seed)
    print(f"cgms: {name}: {info['n']} beads ({width_mm} x {height_mm} mm)", flush=True)
    results = study.sweep(info["data"], mat_file, folder, levels, progress=sys.stderr.isatty(),
                          diameters=info["diameters"], method=args.method,
                          overrides=args.set,
                          steady=dict(residual=args.residual, speed=args.speed,
                                      max_steps=args.max_steps))
    rows = study.table(results)
    for r in rows:
        r["tissue"] = name
        r["beads"] = info["n"]
    plots.curves(rows, folder / "curves.png", title=f"{name}: {info['n']} beads")
    fresh = results[int(np.argmax([r["dryness"] for r in results]))]
    panels_p, panels_s = [], []
    for r in results:
        frame = morphology.read_dump(folder / f"tissue.s{r['dryness']:g}.dump",
                                     columns=["pressure"], engine="numpy")[-1]
        panels_p.append((f"s = {r['dryness']:g}", frame["xy"], frame["columns"]["pressure"] / 1e3))
        panels_s.append((f"s = {r['dryness']:g}", r["xy"],
                         morphology.shrinkage(r["xy"], fresh["xy"])))
    plots.snapshots(panels_p, folder / "pressure.png", "turgor pressure (kPa)")
    plots.snapshots(panels_s, folder / "shrinkage.png", "local area shrinkage", cmap="magma")
    return rows


def print_table(rows):
    print("\n  tissue        beads     s    X/X0    A/A0    P/P0   EL/EL0  steps*  converged")
    for r in rows:
        print(f"  {r['tissue']:12s} {r['beads']:6d}  {r['s']:4.2f}  {r['X/X0']:.4f}  "
              f"{r['A/A0']:.4f}  {r['P/P0']:.4f}  {r['EL/EL0']:.4f}  {r['steps']:6d}  "
              f"{'yes' if r['converged'] else 'NO'}")
    print("  * time steps (dynamics) or minimiser iterations (quasistatic)")


def main_job(args):
    """The microscale study: the calibration tissue and the paper's five microscale
    tissues, each dried to steady state at every level."""
    out = Path(args.out) if (args.resume and args.out) else new_folder(args.out, "microscale")
    mat_file = material.find(args.material)
    levels = [float(s) for s in args.dryness.split(",")]
    print(f"cgms: microscale study, material {mat_file.name}, levels {levels}; results in {out}",
          flush=True)
    rows = []
    for name, (w, h) in MICROSCALE.items():
        rows += dry(out, name, w, h, mat_file, levels, args)
    study.write_csv(rows, out / f"summary-{datetime.now():%H%M%S}.csv")
    print_table(rows)
    print(f"\ncgms: table {out}/summary-*.csv; plots {out}/*/curves.png, pressure.png, "
          f"shrinkage.png; dumps (OVITO) {out}/*/tissue.s*.dump; logs {out}/*/log.*.lammps")
    return 0


def study_job(args):
    out = Path(args.out) if (args.resume and args.out) else new_folder(args.out, "study")
    mat_file = material.find(args.material)
    levels = [float(s) for s in args.dryness.split(",")]
    rows = dry(out, "tissue", args.width, args.height, mat_file, levels, args)
    study.write_csv(rows, out / f"summary-{datetime.now():%H%M%S}.csv")
    print_table(rows)
    print(f"\ncgms: results in {out}")
    return 0


def target_job(args):
    out = new_folder(args.out, "target")
    mat_file = material.find(args.material)
    mat = material.with_overrides(material.read(mat_file), args.set)
    info = build(out, args.width, args.height, mat, args.cv, args.seed)
    result = study.target_moisture(info["data"], mat_file, args.target, out, xtol=args.xtol,
                                   diameters=info["diameters"], method=args.method,
                                   overrides=args.set)
    for s, x in result["evaluations"]:
        print(f"  start s = {s:.5f} -> steady X/X0 = {x:.5f}")
    print(f"cgms: to reach X/X0 = {args.target} start at s = {result['initial']:.4f} "
          f"({len(result['evaluations'])} runs; results in {out})")
    return 0


def sensitivity_job(args):
    """The paper's section 4.4 on the 86-bead tissue: table, plot."""
    from . import sensitivity

    out = new_folder(args.out, "sensitivity")
    mat_file = material.find(args.material)
    info = build(out, *MICROSCALE["calibration"], material.read(mat_file))
    print(f"cgms: sensitivity study on the {info['n']}-bead tissue; results in {out}", flush=True)
    rows = sensitivity.run(info["data"], mat_file, out)
    done = [r for r in rows if "failed" not in r]
    study.write_csv(done, out / "sensitivity.csv")
    failed = [r for r in rows if "failed" in r]
    if failed:
        (out / "failed.txt").write_text(
            "".join(f"{r['parameter']} x {r['factor']}: {r['failed']}\n" for r in failed))
    plots.sensitivity(done, out / "sensitivity.png")
    # snapshots like the paper's Figs 10, 12 and 14: the dried tissue of every setting,
    # coloured by its local shrinkage from its own fresh state
    for parameter in sensitivity.FACTORS:
        panels = []
        setting = [r for r in done if r["parameter"] == parameter]
        for r in (r for r in setting if r["s"] == 0.3):
            def final(s):
                row = next(q for q in setting if q["factor"] == r["factor"] and q["s"] == s)
                folder = out / f"{parameter}-{r['factor']}"
                folder = folder / "dynamics" if row["method"] == "dynamics" else folder
                return morphology.read_dump(folder / f"tissue.s{s:g}.dump", engine="numpy")[-1]
            dry, fresh = final(0.3), final(1.0)
            panels.append((f"{parameter} x {r['factor']}", dry["xy"],
                           morphology.shrinkage(dry["xy"], fresh["xy"])))
        if panels:
            plots.snapshots(panels, out / f"snapshots-{parameter}.png",
                            "local area shrinkage (s = 0.3)", cmap="magma")
    print(f"cgms: table {out}/sensitivity.csv, plots {out}/sensitivity.png and "
          f"{out}/snapshots-*.png"
          + (f", failed settings {out}/failed.txt" if failed else ""))
    return 0


def calibrate_job(args):
    """Fit k_T, k_PA, beta (or other parameters) to reference centroids by eqn (2): fitted
    values, RMSD per level, a new material file (doc/calibration.md)."""
    return calibrate.job(args)


def positive_int(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def material_overrides(text):
    """--set: 'name value ...' pairs with numeric values (LAMMPS checks the names)."""
    words = text.split()
    if len(words) % 2:
        raise argparse.ArgumentTypeError(f"expected 'name value' pairs, got {text!r}")
    for name, value in zip(words[::2], words[1::2]):
        try:
            float(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"value {value!r} of {name} is not a number")
    return text


def parser():
    p = argparse.ArgumentParser(prog="cgms", description=__doc__)
    sub = p.add_subparsers(dest="command", required=True)

    def common(q, width=True):
        q.add_argument("--out", help="results folder (default results/<kind>/<date-time>)")
        q.add_argument("--material", default="apple", help="material file (default apple)")
        q.add_argument("--set", default="", metavar="'NAME VALUE ...'", type=material_overrides,
                       help="material parameters that replace the file's, as on a pair_coeff "
                            "line, e.g. --set 'k_S 0.5' (doc/pair_cgms.rst)")
        if width:
            q.add_argument("--width", type=float, default=1.5, help="tissue width, mm")
            q.add_argument("--height", type=float, default=1.5, help="tissue height, mm")
        q.add_argument("--cv", type=float, default=0.0,
                       help="coefficient of variation of cell diameters (0: uniform)")
        q.add_argument("--seed", type=int, default=1, help="seed for the cell diameters")
        q.add_argument("--residual", type=float, default=1e-3, help="steady-state residual")
        q.add_argument("--speed", type=float, default=1e-3, help="steady-state speed, m/s")
        q.add_argument("--max-steps", type=positive_int, default=2000000,
                       help="step (or minimiser iteration; Newton: at most 60) limit per level")
        q.add_argument("--method", choices=("quasistatic", "newton", "dynamics"),
                       default="quasistatic",
                       help="solve for the steady state directly: P = -Pi and FIRE "
                            "minimisation (default; MODEL.md 8) or Newton's method (fewer, "
                            "costlier iterations: doc/performance.md), or follow the dynamics "
                            "until the --residual and --speed thresholds hold (the paper's way)")

    m = sub.add_parser("main", help="the microscale study (six tissues, five levels)")
    common(m, width=False)
    m.add_argument("--dryness", default=DEFAULT_LEVELS, help=f"levels (default {DEFAULT_LEVELS})")
    m.add_argument("--resume", action="store_true", help="continue an interrupted study in --out")
    m.set_defaults(func=main_job)

    s = sub.add_parser("study", help="dry one rectangular tissue over moisture levels")
    common(s)
    s.add_argument("--dryness", default=DEFAULT_LEVELS, help=f"levels (default {DEFAULT_LEVELS})")
    s.add_argument("--resume", action="store_true", help="continue an interrupted study in --out")
    s.set_defaults(func=study_job)

    v = sub.add_parser("sensitivity", help="the paper's sensitivity study (k_T, k_PA, beta)")
    v.add_argument("--out", help="results folder (default results/sensitivity/<date-time>)")
    v.add_argument("--material", default="apple", help="material file (default apple)")
    v.set_defaults(func=sensitivity_job)

    c = sub.add_parser("calibrate", help="fit k_T, k_PA, beta to reference centroids (eqn 2)")
    calibrate.add_arguments(c)
    c.set_defaults(func=calibrate_job)

    t = sub.add_parser("target", help="initial dryness whose steady state reaches X/X0")
    common(t)
    t.add_argument("target", type=float, help="moisture X/X0 to reach, e.g. 0.60")
    t.add_argument("--xtol", type=float, default=1e-3, help="tolerance on the initial s")
    t.set_defaults(func=target_job)

    from . import mfc_cli
    mfc_cli.add_parser(sub)
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except (RuntimeError, ValueError, FileNotFoundError) as err:
        # a LAMMPS stop (its ERROR text is in the message) or a bad input: say it, with
        # no traceback (CGMS_DEBUG=1 shows it); the results so far stay in the folder
        if os.environ.get("CGMS_DEBUG"):
            raise
        print(f"cgms: {err} (CGMS_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 1
