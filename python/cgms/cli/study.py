# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms main``, ``study`` and ``target``: dry tissues to steady state at
moisture levels; the table of A/A0, P/P0, EL/EL0."""

import sys

from .. import folders, pictures, study, tissue
from .options import (UsageError, check_fallback, common_arguments, fallback_argument,
                      fallback_of, positive_float, sweep_arguments)
from .tissues import chosen_tissue, material_of, rectangle_tissue, tissue_in_folder, write_tissue


def dry(out, name, t, mat_file, mat, levels, args):
    """One tissue through every level: the table and the curves."""
    folder = out / name
    folder.mkdir(exist_ok=True)
    data = write_tissue(folder, t, mat)
    n = len(t["xy"])
    print(f"cgms: {name}: {n} beads ({t['what']})", flush=True)
    fallback = fallback_of(args)
    record = folder / "sweep.json"
    if args.fallback is None and record.exists() and "fallback" not in folders.read_json(record):
        fallback = None   # a folder made without a fallback resumes as it was made
    results = study.sweep(data, mat_file, folder, levels, progress=sys.stderr.isatty(),
                          fallback=fallback, start=args.start,
                          diameters=t["diameters"] is not None,
                          method=args.method, overrides=args.set,
                          steady=dict(residual=args.residual, speed=args.speed,
                                      max_steps=args.max_steps))
    rows = study.table(results)
    for r in rows:
        r["tissue"] = name
        r["beads"] = n
    pictures.curves_all({name: rows}, folder / "curves.png", title=f"{name}: {n} beads")
    # the pictures of the cells at every level are drawn by pictures.study_pictures
    return rows


#: the table's words for the methods (study.solved_by)
SOLVERS = {"quasistatic": "FIRE", "newton": "Newton", "dynamics": "dynamics",
           "shaped-newton": "Newton (shaped)"}


def solver_name(row):
    """Which method produced a row's level, as the table shows it."""
    name = SOLVERS.get(row.get("method", "dynamics"), row.get("method"))
    return f"{name} (fallback)" if row.get("fallback") else name


def print_table(rows):
    print("\n  tissue        beads     s  mf/mf0   A/A0    P/P0   EL/EL0  steps*  converged  "
          "solved by")
    for r in rows:
        print(f"  {r['tissue']:12s} {r['beads']:6d}  {r['s']:4.2f}  {r['X/X0']:.4f}  "
              f"{r['A/A0']:.4f}  {r['P/P0']:.4f}  {r['EL/EL0']:.4f}  {r['steps']:6d}  "
              f"{'yes' if r['converged'] else 'NO':9s}  {solver_name(r)}")
    print("  * time steps (dynamics) or minimiser iterations (FIRE) or Newton iterations")
    for name in dict.fromkeys(r["tissue"] for r in rows):
        wettest = max(r["s"] for r in rows if r["tissue"] == name)
        if wettest < 1:   # study.table normalises by the wettest level it has
            print(f"  {name}: A/A0, P/P0, EL/EL0 are relative to s = {wettest:g}, the wettest "
                  "level run; add 1 to --dryness to compare with the fresh tissue")
    if any(r.get("fallback") for r in rows):
        print(f"  (fallback): the quasi-static solve stopped or did not converge; the steady "
              f"state is the dynamics' at dt = {study.FALLBACK['dt']:g} s (in "
              f"<tissue>/{study.FALLBACK_FOLDER}/; why: the CSV's fallback column; "
              "--fallback none turns this off)")
    if any(not r["converged"] and r["method"] == "quasistatic" for r in rows):
        print("  The quasi-static solve (FIRE) can stall where the potential is not convex "
              "(large dried tissues: doc/results/validation.md); try --method newton or dynamics.")


def levels_in_range(args, mat_file):
    """(levels to run, a line naming those left out or ''): the levels of --dryness that
    the material file is valid for (its 'VALID FOR lo <= s <= hi' comment). UsageError
    when none is left, or for a --fallback with nothing to fall back from."""
    check_fallback(args)
    lo, hi = study.valid_range(mat_file)
    kept = [s for s in args.dryness if lo <= s <= hi]
    if len(kept) == len(args.dryness):
        return kept, ""
    outside = ", ".join(f"{s:g}" for s in args.dryness if s not in kept)
    why = f"{mat_file.name} is valid for {lo:g} <= s <= {hi:g} only (its header)"
    if not kept:
        raise UsageError(f"--dryness {outside}: {why}; no level to run")
    return kept, f"cgms: s = {outside} not run: {why}"


def fallback_files(out, rows):
    """Where the levels the fallback solved keep their dumps and logs (for the list of
    files a study prints), or '' when there are none."""
    if not any(r.get("fallback") for r in rows):
        return ""
    return (f"; levels solved by the fallback: dump and log in "
            f"{out}/*/{study.FALLBACK_FOLDER}/")


def write_summary(rows, out):
    study.write_csv(rows, folders.summary_path(out))


def main_job(args):
    """The microscale study: the calibration tissue and the paper's five microscale
    tissues, each dried to steady state at every level."""
    mat_file, mat = material_of(args)
    kept, left_out = levels_in_range(args, mat_file)
    tissues = {name: rectangle_tissue(w, h, mat, args.cv, args.seed)
               for name, (w, h) in tissue.MICROSCALE.items()}
    with folders.claim(args.out, "microscale", args.resume) as out:
        print(f"cgms: microscale study, material {mat_file.name}, levels {args.dryness}; "
              f"results in {out}", flush=True)
        if left_out:
            print(left_out, flush=True)
        rows = []
        for name, t in tissues.items():
            rows += dry(out, name, t, mat_file, mat, kept, args)
        write_summary(rows, out)
        print_table(rows)
        pictures.study_pictures(out)
        print(f"\ncgms: table {out}/summary-*.csv; plots {out}/curves-all.png, */curves.png, "
              f"*/cells-pressure.png, */cells-shrinkage.png; dumps (OVITO) "
              f"{out}/*/tissue.s*.dump; logs {out}/*/log.*.lammps{fallback_files(out, rows)}")
    return 0


def study_job(args):
    if args.model == "shaped":
        return shaped_study_job(args)
    mat_file, mat = material_of(args)
    kept, left_out = levels_in_range(args, mat_file)
    t = chosen_tissue(args, mat)
    with folders.claim(args.out, "study", args.resume) as out:
        if left_out:
            print(left_out, flush=True)
        rows = dry(out, "tissue", t, mat_file, mat, kept, args)
        write_summary(rows, out)
        print_table(rows)
        pictures.study_pictures(out)
        print(f"\ncgms: results in {out}")
    return 0


#: options of the paper model's study that the shaped route does not take, with their
#: defaults (a value other than the default is refused)
SHAPED_REFUSED = {"method": ("--method", "quasistatic"), "fallback": ("--fallback", None),
                  "start": ("--start", "built"), "set": ("--set", ""),
                  "residual": ("--residual", 1e-3), "speed": ("--speed", 1e-3),
                  "resume": ("--resume", False), "cv": ("--cv", 0.0)}


#: beads above which the shaped route says that LAMMPS is the faster way (1273 beads take
#: about a minute of CPU for five levels; the cost grows faster than the bead count)
SHAPED_LARGE = 5000


def shaped_study_job(args):
    """``study --model shaped``: the shaped tensor model (pair_style cgms/shaped's
    physics, its default parameters) along a drying ramp over --dryness, each level solved
    by Newton's method (cgms.shaped_newton) in this process; the same table and CSV."""
    from .. import shaped_newton
    for key, (option, default) in SHAPED_REFUSED.items():
        if getattr(args, key) != default:
            raise UsageError(f"{option} does not apply to --model shaped (Newton's method on "
                             "the shaped model, each level from the previous one)")
    mat_file, mat = material_of(args)
    from .. import material
    if mat_file.resolve() != material.find("apple").resolve():
        raise UsageError(f"--material {args.material}: --model shaped has its parameters "
                         "for apple only (doc/pair_cgms_shaped.rst, Default)")
    kept, left_out = levels_in_range(args, mat_file)
    kept = sorted(kept, reverse=True)        # a ramp: wettest first
    t = chosen_tissue(args, mat)
    if t["diameters"] is not None:
        raise UsageError(f"{t['what']} gives cell diameters; --model shaped builds every cell "
                         "from the bead lattice and takes none")
    n = len(t["xy"])
    with folders.claim(args.out, "study", False) as out:
        if left_out:
            print(left_out, flush=True)
        print(f"cgms: tissue: {n} beads ({t['what']}), model shaped (Newton)", flush=True)
        if n > SHAPED_LARGE:
            print(f"cgms: note: Newton's method on {n} beads takes long (20 273 beads: 11 min "
                  "for s = 0.8 and 33 min for s = 0.6 on a loaded machine); "
                  "LAMMPS minimize with pair_style cgms/shaped solves a level of that tissue "
                  "in about a minute (doc/using.md)", flush=True)

        def progress(s, info):
            negative = info.get("negative")
            kind = ("a minimum" if negative == 0 else "not certified" if negative is None
                    else f"a saddle ({negative} directions of negative curvature)")
            print(f"cgms: s = {s:g}: {info['iterations']} Newton steps, largest force "
                  f"{info['fmax']:.1e} N, {kind}, {info['wall']:.1f} s", flush=True)

        _, _, rows = shaped_newton.study(t["xy"], mat, kept, max_iterations=min(
            args.max_steps, 10 ** 6), progress=progress)
        for r in rows:
            r["tissue"] = "tissue"
            r["beads"] = n
        write_summary(rows, out)
        print_table(rows)
        print(f"\ncgms: table {out}/summary-*.csv")
    return 0


def target_job(args):
    check_fallback(args)
    with tissue_in_folder(args, "target") as job:
        result = study.target_moisture(job.data, job.mat_file, args.target, job.out,
                                       xtol=args.xtol, diameters=job.diameters,
                                       fallback=fallback_of(args), method=args.method,
                                       overrides=args.set)
        for s, x in result["evaluations"]:
            print(f"  start s = {s:.5f} -> steady X/X0 = {x:.5f}")
        print(f"cgms: to reach X/X0 = {args.target} start at s = {result['initial']:.4f} "
              f"({len(result['evaluations'])} runs; results in {job.out})")
    return 0


def main_arguments(q):
    common_arguments(q, "microscale", width=False)
    sweep_arguments(q)


def study_arguments(q):
    common_arguments(q, "study")
    sweep_arguments(q)
    q.add_argument("--model", choices=("paper", "shaped"), default="paper",
                   help="paper: pair_style cgms, the paper's model (default); shaped: the "
                        "coarse model with a shape tensor per cell (pair_style cgms/shaped's "
                        "physics and defaults, doc/pair_cgms_shaped.rst), a drying ramp "
                        "solved by Newton's method in Python (cgms.shaped_newton); it takes "
                        "neither --method, --fallback, --start, --set, --residual, --speed, "
                        "--resume nor --cv")


def target_arguments(q):
    common_arguments(q, "target")
    q.add_argument("target", type=positive_float, help="moisture X/X0 to reach, e.g. 0.60")
    q.add_argument("--xtol", type=positive_float, default=1e-3,
                   help="tolerance on the initial s")
    fallback_argument(q)
