# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Command line: ``python3 -m cgms main`` runs the main job (the microscale study);
``study`` dries any tissue over moisture levels; ``target`` finds the initial dryness that
reaches a given moisture; ``calibrate`` fits material parameters to reference centroid
positions (eqn 2); ``sensitivity`` runs the paper's sensitivity study. A tissue is a
W x H mm rectangle (--width, --height) or read from a file (--data): a LAMMPS data file
(python3 -m cgms.tissue: rectangles, discs, polygons with holes, heterogeneous cells) or
a list of cell centroids, one 'id x y' line each, in metres.

This module is the top of the package: it parses options, checks them before anything is
created, and turns every error into one line on stderr; no library module imports it."""

import argparse
import math
import os
import re
import sys
from contextlib import contextmanager
from datetime import datetime
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from . import (calibrate, dry_cli, fitparams, folders, material, mfc_cli, morphology, parallel,
               pictures, plots, positions, study, superpose, tissue)
from .fitparams import BETA_BOUNDS, BOUNDS

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
#: a tissue read with --data may have its median bead spacing this far from x_ref
SPACING_RANGE = (0.5, 2.0)


class UsageError(ValueError):
    """A bad option or input file, found before anything runs."""


# --------------------------------------------------------------------------- tissues

def rectangle_tissue(width_mm, height_mm, mat, cv=0.0, seed=1):
    """The W x H mm rectangle of the paper's fill rule (cgms.tissue.rectangle); UsageError
    for one too small to hold a tissue, or so large it is likely not in millimetres."""
    size = f"--width {width_mm:g} --height {height_mm:g}"
    spacing = f"the material's cell spacing x_ref = {mat['x_ref'] * 1e6:.4g} um"
    estimate = width_mm * height_mm * 1e-6 / (tissue.ROW_PITCH * mat["x_ref"] ** 2)
    if estimate > MAX_CLI_BEADS:
        raise UsageError(f"{size} would hold about {estimate:.3g} beads at {spacing} (limit "
                         f"{MAX_CLI_BEADS:g}): sizes are in millimetres")
    try:
        xy = tissue.rectangle(width_mm * 1e-3, height_mm * 1e-3, mat["x_ref"])
    except ValueError as err:
        if "holds no row" not in str(err):
            raise UsageError(f"{size}: {err}") from None
        xy = np.empty((0, 2))
    if len(xy) < MIN_BEADS:
        raise UsageError(f"{size} (mm) holds {len(xy)} bead(s) at {spacing}; a tissue needs "
                         f"at least {MIN_BEADS}")
    return dict(xy=xy, ids=None, diameters=diameters(len(xy), mat, cv, seed),
                title=f"CGMS {width_mm} x {height_mm} mm tissue",
                what=f"{width_mm} x {height_mm} mm")


def read_tissue_file(path):
    """(ids, xy, diameters or None, kind) of a --data file; UsageError naming the file and
    what is wrong with it."""
    try:
        if positions.is_data_file(path):
            d = positions.read_data(path)
            return d["ids"], d["xy"], d["diameters"], "data file"
        ids, xy = positions.read_centroids(path)
    except UnicodeDecodeError:
        raise UsageError(f"--data {path}: not a text file") from None
    except (ValueError, OSError) as err:
        text = describe(err)
        raise UsageError(f"--data {path}: {text.removeprefix(f'{path}: ')}") from None
    if len(np.unique(ids)) != len(ids):
        raise UsageError(f"--data {path}: an id is given twice")
    return ids, xy, None, "centroid list"


def check_layout(path, ids, xy, mat):
    """UsageError for bead positions no tissue has: non-finite, two beads at one place, not
    in metres (the median spacing far from x_ref), all in a row, or in pieces that no chain
    of neighbours links (LAMMPS would stop on an isolated bead, or on no area at the end)."""
    where = f"--data {path}"
    bad = np.flatnonzero(~np.isfinite(xy).all(axis=1))
    if len(bad):
        raise UsageError(f"{where}: bead id {ids[bad[0]]} has a non-finite position "
                         f"({len(bad)} bead(s) in all)")
    if len(xy) < MIN_BEADS:
        raise UsageError(f"{where}: {len(xy)} bead(s); a tissue needs at least {MIN_BEADS}")
    order = np.lexsort((xy[:, 1], xy[:, 0]))
    same = np.flatnonzero((np.diff(xy[order], axis=0) == 0).all(axis=1))
    if len(same):
        a, b = ids[order[same[0]]], ids[order[same[0] + 1]]
        raise UsageError(f"{where}: beads {a} and {b} are at the same position; remove the "
                         "duplicate")
    gap = morphology.spacing(xy)
    ratio = gap / mat["x_ref"]
    if not SPACING_RANGE[0] < ratio < SPACING_RANGE[1]:
        unit = next((f" (these look like {name})" for name, scale in
                     (("micrometres", 1e6), ("millimetres", 1e3))
                     if SPACING_RANGE[0] < ratio / scale < SPACING_RANGE[1]), "")
        raise UsageError(f"{where}: neighbouring beads are {gap:.4g} m apart (median), "
                         f"{ratio:.3g} times the material's cell spacing x_ref = "
                         f"{mat['x_ref']:.4g} m: positions must be cell centres in "
                         f"metres{unit}")
    label = morphology.pieces(xy)
    if label.max() > 0:
        away = ids[label > 0]
        raise UsageError(
            f"{where}: the beads form {label.max() + 1} pieces: bead id(s) "
            f"{', '.join(str(i) for i in away[:5])}{' ...' if len(away) > 5 else ''} are "
            f"more than {morphology.MAX_EDGE_FACTOR:g} x the median spacing from the largest "
            "piece; a tissue is one piece of neighbouring cells")
    try:
        morphology.outline(xy)
    except ValueError as err:
        raise UsageError(f"{where}: {err}") from None


def file_tissue(path, mat, cv=0.0, seed=1):
    """The tissue of a LAMMPS data file or an 'id x y' centroid list (metres)."""
    path = Path(path)
    if not path.is_file():
        raise UsageError(f"--data {path}: no such file")
    ids, xy, given, kind = read_tissue_file(path)
    check_layout(path, ids, xy, mat)
    if cv > 0 and given is not None:
        raise UsageError(f"--data {path} has a Diameters section: leave out --cv")
    return dict(xy=xy, ids=ids, diameters=diameters(len(xy), mat, cv, seed) if cv > 0 else given,
                title=f"CGMS tissue from {path.name}",
                what=f"{kind} {path}")


def chosen_tissue(args, mat):
    """The tissue of the options: --data, or --width x --height."""
    if getattr(args, "data", None):
        return file_tissue(args.data, mat, args.cv, args.seed)
    return rectangle_tissue(args.width, args.height, mat, args.cv, args.seed)


def write_tissue(folder, t, mat):
    """``folder/tissue.data`` for the tissue ``t``; when resuming it must be there already
    and be the same tissue (another --width, --data, --cv ... is refused)."""
    data = folder / "tissue.data"
    fresh = folder / ".tissue.data.new"
    positions.write_data(fresh, t["xy"], 3 * mat["x_ref"], title=t["title"],
                         diameters=t["diameters"], ids=t["ids"], overwrite=True)
    if data.exists():
        same = data.read_bytes() == fresh.read_bytes()
        fresh.unlink()
        if not same:
            raise folders.FolderError(
                f"{data} is another tissue than these options build ({t['what']}); resume "
                "with the options of the first run or choose another --out")
    else:
        os.replace(fresh, data)
    return data


@contextmanager
def tissue_in_folder(args, kind, resume=False):
    """Material, tissue and the locked results folder holding the tissue's data file, for
    commands on one tissue; everything is checked before the folder is made."""
    mat_file, mat = material_of(args)
    t = chosen_tissue(args, mat)
    with folders.claim(args.out, kind, resume) as out:
        yield SimpleNamespace(out=out, data=write_tissue(out, t, mat), tissue=t,
                              mat_file=mat_file, mat=mat, n=len(t["xy"]),
                              diameters=t["diameters"] is not None)


def material_of(args):
    """(material file, parameters with --set applied), checked: UsageError for a missing or
    bad file or --set."""
    try:
        mat_file = material.find(args.material)
        return mat_file, material.with_overrides(material.read(mat_file),
                                                 getattr(args, "set", ""))
    except (ValueError, OSError) as err:
        raise UsageError(describe(err)) from None


# --------------------------------------------------------------------------- main, study

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
    plots.curves(rows, folder / "curves.png", title=f"{name}: {n} beads")
    # the pictures of the cells at every level are drawn by pictures.study_pictures
    return rows


def fallback_of(args):
    """--fallback as it runs: by default the dynamics after a quasi-static method (FIRE or
    Newton) that stops, nothing after the dynamics; 'none' turns it off."""
    if args.fallback == "none":
        return None
    if args.fallback is None:
        return None if args.method == "dynamics" else study.FALLBACKS[0]
    return args.fallback


#: the table's words for the methods (study.solved_by)
SOLVERS = {"quasistatic": "FIRE", "newton": "Newton", "dynamics": "dynamics"}


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
              "(large dried tissues: doc/validation.md); try --method newton or dynamics.")


def check_fallback(args):
    """UsageError for a --fallback with nothing to fall back from."""
    if args.fallback not in (None, "none") and args.method == "dynamics":
        raise UsageError(f"--fallback {args.fallback} needs --method quasistatic or newton: "
                         "the dynamics has nothing to fall back to")


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
    path = out / f"summary-{datetime.now():%H%M%S}.csv"
    while path.exists():   # a resume within the same second
        path = path.with_name(path.stem + "x.csv")
    study.write_csv(rows, path)


def main_job(args):
    """The microscale study: the calibration tissue and the paper's five microscale
    tissues, each dried to steady state at every level."""
    mat_file, mat = material_of(args)
    kept, left_out = levels_in_range(args, mat_file)
    tissues = {name: rectangle_tissue(w, h, mat, args.cv, args.seed)
               for name, (w, h) in MICROSCALE.items()}
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


# --------------------------------------------------------------------------- sensitivity

def sensitivity_job(args):
    """The paper's section 4.4 on the 86-bead tissue (or --data): table, plot."""
    from . import sensitivity

    with tissue_in_folder(args, "sensitivity") as job:
        out = job.out
        print(f"cgms: sensitivity study on the {job.n}-bead tissue; results in {out}",
              flush=True)
        rows = sensitivity.run(job.data, job.mat_file, out)
        done = [r for r in rows if "failed" not in r]
        study.write_csv(done, out / "sensitivity.csv")
        failed = [r for r in rows if "failed" in r]
        if failed:
            (out / "failed.txt").write_text(
                "".join(f"{r['parameter']} x {r['factor']}: {r['failed']}\n" for r in failed))
        plots.sensitivity(done, out / "sensitivity.png")
        sensitivity_snapshots(out, done, sensitivity.FACTORS)
        print(f"cgms: table {out}/sensitivity.csv, plots {out}/sensitivity.png and "
              f"{out}/snapshots-*.png"
              + (f", failed settings {out}/failed.txt" if failed else ""))
    return 0


def sensitivity_snapshots(out, done, factors):
    """Snapshots like the paper's Figs 10, 12 and 14: the dried tissue of every setting,
    coloured by its local shrinkage from its own fresh state."""
    for parameter in factors:
        panels = []
        setting = [r for r in done if r["parameter"] == parameter]
        for r in (r for r in setting if r["s"] == 0.3):
            def final(s):
                row = next(q for q in setting if q["factor"] == r["factor"] and q["s"] == s)
                folder = out / f"{parameter}-{r['factor']}"
                folder = folder / "dynamics" if row["method"] == "dynamics" else folder
                return morphology.read_dump(folder / f"tissue.{study.level_name(s)}.dump")[-1]
            dried, fresh = final(0.3), final(1.0)
            panels.append((f"{parameter} x {r['factor']}", dried["xy"],
                           morphology.shrinkage(dried["xy"], fresh["xy"])))
        if panels:
            plots.snapshots(panels, out / f"snapshots-{parameter}.png",
                            "local area shrinkage (s = 0.3)", cmap="magma")


# --------------------------------------------------------------------------- calibrate

def pairs(text, what, convert):
    """``["a=1,b=2", ...]`` -> ``{"a": convert("1"), ...}``."""
    out = {}
    for item in text or []:
        for word in item.split(","):
            if not word.strip():
                continue
            if "=" not in word:
                raise UsageError(f"{what}: expected name=value, got {word!r}")
            k, v = word.split("=", 1)
            try:
                out[k.strip()] = convert(v.strip())
            except ValueError:
                raise UsageError(f"{what}: bad value in {word!r}") from None
    return out


def interval(v):
    lo, hi = v.split(":")
    return float(lo), float(hi)


def parse_references(items):
    """``["1=ref1.txt", "0.3=run.dump"]`` -> ``{1.0: "ref1.txt", 0.3: "run.dump"}``."""
    refs = {}
    for item in items or []:
        if "=" not in item:
            raise UsageError(f"--reference: expected LEVEL=FILE, got {item!r}")
        level, path = item.split("=", 1)
        try:
            s = float(level)
        except ValueError:
            raise UsageError(f"--reference {item!r}: the level must be a number") from None
        if s in refs:
            raise UsageError(f"--reference: two files for s = {s:g}")
        refs[s] = path
    return refs


def calibrate_arguments(p):
    p.add_argument("--reference", action="append", required=True, metavar="LEVEL=FILE",
                   help="reference centroids at a dryness level: an 'id x y' file (m) or a "
                        "LAMMPS dump (last frame); repeat for each level, e.g. "
                        "--reference 1=fresh.txt --reference 0.3=dried.dump")
    p.add_argument("--fit", default="k_T,k_PA,beta",
                   help="parameters, comma separated: k_T, k_PA, any material name, beta (one "
                        "factor on beta(s)), beta_a, beta_b, beta@<s> or beta@* (beta per "
                        "level) (default k_T,k_PA,beta)")
    p.add_argument("--out", help="results folder (default results/calibrate/<date-time>)")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted fit in --out (cached steady states reused)")
    p.add_argument("--material", default="apple", help="start material file (default apple)")
    tissue_source_arguments(p, width=1.25, what=" (default 1.25 x 1.5: the 86-bead tissue)")
    p.add_argument("--start", action="append", metavar="NAME=VALUE",
                   help="start value (default: the material's; beta: factor 1)")
    p.add_argument("--bounds", action="append", metavar="NAME=LO:HI",
                   help=f"search interval as factors of the start (default {BOUNDS[0]:g}:"
                        f"{BOUNDS[1]:g}, beta {BETA_BOUNDS[0]:g}:{BETA_BOUNDS[1]:g})")
    p.add_argument("--align", choices=superpose.ALIGN, default="translation",
                   help="rigid motion removed before eqn (2) (default translation)")
    p.add_argument("--workers", type=positive_int, default=2,
                   help="processes for independent steady states (default 2)")
    p.add_argument("--max-evaluations", type=positive_int, default=60,
                   help="limit on residual evaluations of the minimiser (default 60)")
    p.add_argument("--write-material", metavar="FILE",
                   help="fitted material file (default <out>/<material>-calibrated.cgms)")
    p.add_argument("--force", action="store_true", help="replace an existing --write-material")


def calibrate_job(args):
    """Fit k_T, k_PA, beta (or other parameters) to reference centroids by eqn (2): fitted
    values, RMSD per level, a new material file (doc/calibration.md)."""
    refs = parse_references(args.reference)
    start = pairs(args.start, "--start", float)
    bounds = pairs(args.bounds, "--bounds", interval)
    check_calibration(args, refs, start, bounds)
    with tissue_in_folder(args, "calibrate", args.resume) as job:
        out = job.out
        print(f"cgms calibrate: fitting {args.fit} on {job.data} ({job.n} beads), "
              f"levels {', '.join(f'{s:g}' for s in sorted(refs, reverse=True))}; results in "
              f"{out}", flush=True)
        try:
            result = calibrate.calibrate(
                job.data, job.mat_file, refs, out, parameters=args.fit.split(","), start=start,
                bounds=bounds, align_mode=args.align, workers=args.workers,
                max_evaluations=args.max_evaluations, material_out=args.write_material,
                overwrite=args.force)
        except KeyboardInterrupt:
            print(f"\ncgms calibrate: interrupted; the finished steady states are kept in "
                  f"{out / calibrate.CACHE}: rerun with --out {out} --resume to continue",
                  file=sys.stderr)
            return 130
        print_report(result)
        print(f"  results: {out}/result.json; runs (dumps, logs): {out}/runs")
    return 0


def check_calibration(args, refs, start, bounds):
    """UsageError for references or fit options calibrate would refuse, before its folder
    is made: each --reference file read and matched to the tissue's ids in metres, and
    --fit, --start, --bounds parsed as the fit will."""
    _, mat = material_of(args)
    t = chosen_tissue(args, mat)
    ids = t["ids"] if t["ids"] is not None else np.arange(1, len(t["xy"]) + 1)
    for s, path in refs.items():
        where = f"--reference {s:g}={path}"
        if not 0 < s <= 1:
            raise UsageError(f"{where}: the level must be in (0, 1]")
        if not Path(path).is_file():
            raise UsageError(f"{where}: no such file")
        try:
            found, xy = positions.read_centroids(path)
            q = calibrate.match(found, xy, ids, "the file")
            calibrate.check_units(q, t["xy"], "the file")
        except UnicodeDecodeError:
            raise UsageError(f"{where}: not a text file") from None
        except (ValueError, OSError) as err:
            raise UsageError(f"{where}: {describe(err).removeprefix(f'{path}: ')}") from None
    try:
        fitparams.parse_parameters(args.fit.split(","), mat, sorted(refs, reverse=True),
                                   start, bounds)
    except ValueError as err:
        option = ("--start" if "start value" in str(err) else
                  "--bounds" if "bounds" in str(err) else f"--fit {args.fit}")
        raise UsageError(f"{option}: {err}") from None


def print_report(result):
    print("\n  parameter     start          fitted         factor    std. error*")
    for name, v in result["parameters"].items():
        print(f"  {name:12s}  {result['start'][name]:<13.6g}  {v:<13.6g}  "
              f"{result['factors'][name]:.5f}   {100 * result['stderr'][name]:.2g} %"
              + ("  (on a bound)" if name in result["on_bound"] else ""))
    names = list(result["parameters"])
    strong = [f"{a}/{b} {result['correlation'][i][j]:+.3f}" for i, a in enumerate(names)
              for j, b in enumerate(names) if j > i and abs(result["correlation"][i][j]) > 0.9]
    if strong:
        print("  strongly correlated (|r| > 0.9): " + ", ".join(strong)
              + ": the references fix a combination, not each value")
    print("  * linearised, from the residual as if it were independent noise")
    print("\n  s      RMSD start (um)  RMSD fitted (um)  RMSD/x_ref   X/X0    solved by")
    for s in result["levels"]:
        r0, r1 = result["rmsd_start"][s], result["rmsd"][s]
        print(f"  {s:<5g}  {r0 * 1e6:15.5g}  {r1 * 1e6:16.5g}  {r1 / result['x_ref']:10.3e}"
              f"  {result['moisture'][s] or float('nan'):.4f}  {result['methods'][s]}")
    print(f"\n  {result['evaluations']} evaluations, {result['jacobians']} Jacobians; "
          f"{result['runs']} steady states run, {result['reused']} taken from the cache of an "
          f"earlier session ({result['fallbacks']} solved by the dynamics fallback, "
          f"{result['failures']} without a steady state); "
          f"{result['seconds']:.1f} s wall time")
    print(f"  minimiser: {result['message']}")
    if result["material_file"]:
        print(f"  material file: {result['material_file']}")


# --------------------------------------------------------------------------- tissue builder

MAX_CLI_BEADS = 5e6   # a polygon file larger than this is probably not in metres
#: the fewest beads the commands build or read as a tissue (its outline needs three)
MIN_BEADS = 3
#: how far the clipping of the cell diameters may move their mean (see --cv)
MEAN_SHIFT = 0.02


def diameters(n, mat, cv, seed, dist="lognormal"):
    """Per-bead cell diameters for --cv (None for 0); UsageError when the clipping would
    move their mean more than MEAN_SHIFT from the material's diameter."""
    if not cv:
        return None
    factor = tissue.clipped_mean(cv, dist)
    if abs(factor - 1) > MEAN_SHIFT:
        raise UsageError(f"--cv {cv:g}: {dist} diameters clipped at half the mean would "
                         f"average {factor:.3g} x the material's {mat['diameter'] * 1e6:g} um "
                         f"(more than {MEAN_SHIFT:.0%} off); use a smaller --cv")
    return tissue.cell_diameters(n, mat["diameter"], cv, seed, dist=dist)


def tissue_parser_arguments(p):
    """The options of the tissue builder (``python3 -m cgms tissue`` and ``python3 -m
    cgms.tissue``)."""
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--material", default="apple",
                        help="material file or name; sets the lattice spacing x_ref and the "
                             "mean cell diameter (default apple)")
    common.add_argument("--spacing", type=float, metavar="UM",
                        help="lattice spacing in micrometres (default: the material's x_ref)")
    common.add_argument("--rows-along", choices=("x", "y"), default="y",
                        help="direction of the lattice rows (default y, as in the paper)")
    common.add_argument("--out", default="tissue.data", help="data file (default tissue.data)")
    common.add_argument("--force", action="store_true", help="replace an existing --out file")
    common.add_argument("--margin", type=float, default=3.0,
                        help="box margin around the tissue, in lattice spacings (default 3)")
    common.add_argument("--cv", type=float, default=0.0,
                        help="coefficient of variation of the cell diameter; > 0 writes a "
                             "Diameters section (default 0: homogeneous tissue)")
    common.add_argument("--seed", type=seed_int, default=0,
                        help="random seed for --cv (default 0)")
    common.add_argument("--dist", choices=("lognormal", "normal"), default="lognormal",
                        help="distribution of the diameters (default lognormal)")
    sub = p.add_subparsers(dest="shape", required=True)
    r = sub.add_parser("rect", parents=[common], help="W x H rectangle (mm)",
                       description="Lattice filling a W x H mm rectangle (W along x, H along y).")
    r.add_argument("width", type=float, metavar="W", help="width in mm (along x)")
    r.add_argument("height", type=float, metavar="H", help="height in mm (along y)")
    r.add_argument("--rule", choices=tissue.RECTANGLE_RULES, default="paper",
                   help="fill rule (default paper: reproduces the paper's bead counts)")
    r.add_argument("--inset", type=float, default=0.0,
                   help="shrink the rectangle by this many mm on every side (e.g. D/2 = 0.075 "
                        "to read W x H as the cell outline)")
    d = sub.add_parser("disc", parents=[common], help="disc of radius R (mm)",
                       description="Lattice points inside a disc of radius R mm.")
    d.add_argument("radius", type=float, metavar="R", help="radius in mm")
    g = sub.add_parser("polygon", parents=[common], help="closed polygon from a file (m)",
                       description="Lattice points inside a closed polygon read from a text "
                                   "file: one 'x y' vertex per line, in metres.")
    g.add_argument("file", help="vertex file (x y per line, metres; '#' comments)")


TISSUE_DESCRIPTION = ("Build a CGMS tissue (hexagonal lattice of beads) and write it as a "
                      "LAMMPS data file for atom_style cgms. Sizes W, H, R are in MILLIMETRES; "
                      "polygon vertex files are in METRES.")



def tissue_main(argv=None):
    """``python3 -m cgms.tissue rect W H | disc R | polygon FILE [options]``: build the
    tissue, write the data file and print the bead count. Returns an exit status."""
    p = argparse.ArgumentParser(prog="python3 -m cgms.tissue", description=TISSUE_DESCRIPTION)
    tissue_parser_arguments(p)
    return tissue_job(p.parse_args(argv))


def tissue_job(args):
    """Build and write the tissue; every refusal (a bad option or input file, found before
    anything is written) is one line and status 2, as in the other commands."""
    for name in ("width", "height", "radius", "spacing", "margin"):
        value = getattr(args, name, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            print(f"cgms.tissue: {name} must be positive, got {value:g}", file=sys.stderr)
            return 2
    try:
        mat = material.read(args.material)
        spacing = args.spacing * 1e-6 if args.spacing else mat["x_ref"]
        if args.shape == "polygon":
            vertices = positions.read_vertices(args.file)
            if vertices.size:
                box = np.ptp(vertices, axis=0)
                estimate = box[0] * box[1] / (tissue.ROW_PITCH * spacing * spacing)
                if estimate > MAX_CLI_BEADS:
                    raise ValueError(f"the outline in {args.file} spans {box[0]:g} x "
                                     f"{box[1]:g} m, room for up to {estimate:.3g} beads "
                                     f"(limit {MAX_CLI_BEADS:g}); vertices must be in metres")
        if args.shape != "polygon":
            mm = (args.width * args.height if args.shape == "rect"
                  else math.pi * args.radius ** 2)
            estimate = mm * 1e-6 / (tissue.ROW_PITCH * spacing * spacing)
            if estimate > MAX_CLI_BEADS:
                raise ValueError(f"the {args.shape} would hold about {estimate:.3g} beads at "
                                 f"spacing {spacing * 1e6:.4g} um (limit {MAX_CLI_BEADS:g}): "
                                 "sizes are in millimetres, --spacing in micrometres")
        if args.shape == "rect":
            xy = tissue.rectangle(args.width * 1e-3, args.height * 1e-3, spacing,
                                  rule=args.rule, rows_along=args.rows_along,
                                  inset=args.inset * 1e-3)
            what = f"rectangle {args.width:g} x {args.height:g} mm, rule {args.rule}"
        elif args.shape == "disc":
            xy = tissue.disc(args.radius * 1e-3, spacing, rows_along=args.rows_along)
            what = f"disc of radius {args.radius:g} mm"
        else:
            xy = tissue.polygon(vertices, spacing, rows_along=args.rows_along)
            what = f"polygon {args.file}"
        if len(xy) < MIN_BEADS:
            raise ValueError(f"the {what} holds {len(xy)} bead(s) at spacing "
                             f"{spacing * 1e6:.2f} um; a tissue needs at least {MIN_BEADS}")
        diam = diameters(len(xy), mat, args.cv, args.seed, args.dist)
        n = positions.write_data(args.out, xy, args.margin * spacing,
                                 title=f"CGMS tissue: {what}", diameters=diam,
                                 overwrite=args.force)
    except FileExistsError:
        print(f"cgms.tissue: {args.out} exists; use --force to replace it or choose another "
              "--out", file=sys.stderr)
        return 2
    except UnicodeDecodeError:
        print(f"cgms.tissue: {args.file}: not a text file", file=sys.stderr)
        return 2
    except (ValueError, OSError) as e:
        print(f"cgms.tissue: {describe(e)}", file=sys.stderr)
        return 2
    extra = ""
    if diam is not None:
        extra = (f"; Diameters section: mean {diam.mean() * 1e6:.2f} um, cv "
                 f"{diam.std() / diam.mean():.3f} ({args.dist}, seed {args.seed})")
    print(f"{n} beads -> {args.out} ({what}, spacing {spacing * 1e6:.2f} um, rows along "
          f"{args.rows_along}{extra})")
    return 0


# --------------------------------------------------------------------------- LAMMPS stops

# A LAMMPS stop names its cure in LAMMPS commands (min_style, timestep, pair_coeff ...),
# which a command-line user does not write. Each entry: the stop's words in LAMMPS's ERROR
# line (or cgms.run.folded's), and a function of the match and the run's context giving
# (cause, cure) in the CLI's own terms. LAMMPS's whole line stays in the log.

_NUM = r"(-?[0-9.eE+-]+|-?nan|-?inf)"


def _isolated_low(m, c):
    cause = (f"bead {m['bead']}'s nearest neighbour ({m['near']} m away) is beyond the "
             f"interaction cutoff, which shrinks with the dryness ({m['cut']} m at s = "
             f"{c.s:g}; the built lattice keeps its neighbours only down to s = "
             f"{m['lowest']}, with little room to move)")
    if c.start == "built":
        return cause, ("--start previous dries the levels in turn, each from the previous "
                       "level's steady state")
    return cause, "add levels between the previous one and this to --dryness"


def _minimizer_away(m, c):
    return (f"the quasi-static solve (FIRE) moved bead {m['bead']} out of its neighbours' "
            f"reach at iteration {m['step']}",
            "--fallback dynamics (the default) solves such a level with the dynamics instead "
            "of stopping" if not c.fallback else
            "--method newton is another quasi-static solve")


def _isolated(m, c):
    return (f"bead {m['bead']} lost every neighbour at step {m['step']} ({m['where']}): the "
            "tissue tore apart at this level",
            "check the material (--material, --set); --start previous reaches a dried level "
            "in turn, from the previous level's steady state")


def _unstable(m, c):
    solve = "the dynamics" if c.method == "dynamics" else "the quasi-static solve"
    cause = f"{solve} became unstable at step {m['step']} ({m['what']})"
    if c.method == "dynamics" and not c.first:
        return cause, ("--method quasistatic or newton solves for the steady state with no "
                       "time step")
    if c.method != "dynamics" and not c.fallback:
        return cause, "--fallback dynamics (the default) follows the dynamics instead"
    return cause, ("no method solved this level: the material (--material, --set) may be "
                   "outside what the model holds at this dryness (doc/errors.md)")


def _damping_step(m, c):
    return (f"the dynamics' time step is above the damping's stability limit ({m['limit']} s) "
            f"for bead {m['bead']} (mass {m['mass']} kg) at step {m['step']}",
            "the limit, 2 m / (1.5 N k_d), grows with the bead mass m (the material's height, "
            "diameter, rho0) and falls with k_d (--set); --method quasistatic or newton take "
            "no time step" if c.method == "dynamics" and not c.first else
            "the limit, 2 m / (1.5 N k_d), grows with the bead mass m (the material's height, "
            "diameter, rho0) and falls with k_d (--set)")


def _shape_step(m, c):
    return (f"the cell-shape stiffness k_S = {m['kS']} N/m is too stiff for the dynamics' "
            f"time step (step {m['step']})",
            "a smaller k_S (--set), or --method quasistatic or newton, which take no time step")


def _collapse(m, c):
    return (f"the tissue collapsed at step {m['step']}: bead {m['bead']} has {m['n']} "
            "neighbours within the cutoff, where a hexagonal tissue has 6 (the paper's forces "
            "do not resist shear)",
            "a cell-shape stiffness resists it: --set 'k_S 0.5' (a larger k_S where the "
            "material has one; doc/pair_cgms.rst)")


def _folded(m, c):
    return (f"the steady state folded onto itself (bead {m['bead']} has {m['n']} neighbours "
            "within the cutoff, where a hexagonal tissue has 6)",
            "a cell-shape stiffness or a stiffer perimeter law resists it: --set 'k_S 0.5' "
            "or a larger k_PA (doc/pair_cgms.rst)")


def _apart(m, c):
    return (f"the steady state came apart into {m['pieces']} pieces: the interaction cutoff "
            "may have fallen below the bead spacing",
            "a smaller lj_slope (--set), or --start previous")


def _crowded(m, c):
    near = re.search(r"nearest beads (\S+) m apart", m["reason"])
    return (f"the beads are too close for the material: bead {m['bead']} has {m['n']} "
            "neighbours at the start"
            + (f" (nearest beads {near.group(1)} m apart" if near else " (")
            + f"{'; ' if near else ''}the material's cell spacing x_ref = {m['xref']} m)",
            "--data positions must be cell centres in metres, and the material's diameter "
            "and pectin (--material, --set) must fit them")


def _overlap(m, c):
    return (f"beads {m['a']} and {m['b']} are {m['d']} m apart, closer than the pectin "
            "layer between two cells",
            "remove the overlapping or duplicated beads from the --data file")


def _nonfinite(m, c):
    return (f"bead {m['bead']} has a non-finite {m['what']}",
            "check the --data file's numbers")


def _low_dryness(m, c):
    return (f"at s = {c.s:g} the material's {m['what']} is not positive",
            f"--dryness levels above {m['lowest']}, or another {m['params']} (--set)")


LAMMPS_STOPS = [
    (r"bead (?P<bead>\d+) has no neighbour within the pair cutoff .*? at step \d+: "
     r"(?:its nearest bead is (?P<near>\S+) m away|[^;]*); at dryness \S+ the cutoff is "
     r"(?P<cut>\S+) m .*down to a dryness of about (?P<lowest>\S+)\)", _isolated_low),
    (r"bead (?P<bead>\d+) has no neighbour within the pair cutoff .*? at step (?P<step>\d+):"
     r".*the minimizer moved it away", _minimizer_away),
    (r"bead (?P<bead>\d+) has no neighbour within the pair cutoff .*? at step (?P<step>\d+): "
     r"(?P<where>[^;]*)", _isolated),
    (r"(?P<what>fluid mass of bead \d+ became \S+) at step (?P<step>\d+)", _unstable),
    (r"(?P<what>bead \d+ has a non-finite pressure) at step (?P<step>\d+)", _unstable),
    (r"stability limit of the cell-shape stiffness k_S = (?P<kS>\S+) N/m at step "
     r"(?P<step>\d+)", _shape_step),
    (r"the change of dryness at step (?P<step>\d+) (?P<what>compresses bead \d+)", _unstable),
    (r"stability limit of the damping at step (?P<step>\d+), about (?P<limit>\S+) s = .*? for "
     r"bead (?P<bead>\d+) \(m = (?P<mass>\S+) kg", _damping_step),
    (r"(?P<what>stability limit of the turgor force) at step (?P<step>\d+)", _unstable),
    (r"bead (?P<bead>\d+) has (?P<n>\S+) neighbours within the cutoff at step (?P<step>\d+), "
     r"more than the 6 of a hexagonal tissue: the tissue is collapsing", _collapse),
    (r"folded onto itself: bead (?P<bead>\d+) has (?P<n>\S+) neighbours", _folded),
    (r"came apart: (?P<pieces>\d+) pieces", _apart),
    (r"bead (?P<bead>\d+) has (?P<n>\S+) neighbours within the pair cutoff (?:\(\S+ m\) )?at "
     r"setup.*x_ref = (?:sqrt\(3\) b_ref \+ d_p = )?(?P<xref>[0-9.eE+-]+) m", _crowded),
    (r"beads (?P<a>\d+) and (?P<b>\d+) are (?P<d>\S+) m apart at setup", _overlap),
    (r"bead (?P<bead>\d+) has a non-finite (?P<what>position|velocity)", _nonfinite),
    (r"the (?P<what>periphery factor beta) .* is not positive.*dryness above "
     r"exp\(-beta_a/beta_b\) = (?P<lowest>\S+)(?P<params>)", _low_dryness),
    (r"the (?P<what>LJ radius) r0 .* is not positive.*dryness above exp\(-1/lj_slope\) = "
     r"(?P<lowest>\S+)(?P<params>)", _low_dryness),
]
_PARAMS = {"periphery factor beta": "beta_a, beta_b", "LJ radius": "lj_slope"}


def cause_and_cure(reason, context):
    """(cause, cure) of a LAMMPS ERROR line in the CLI's terms, or None for a stop the
    table does not know (its line is then shown as LAMMPS gave it)."""
    reason = re.sub(r" \(\S+\.cpp:\d+\)", "", reason)   # LAMMPS's source line
    for pattern, explain in LAMMPS_STOPS:
        m = re.search(pattern, reason)
        if m:
            groups = {k: v.rstrip(".,;") if v else v for k, v in m.groupdict().items()}
            groups["reason"] = reason
            if "params" in groups:
                groups["params"] = _PARAMS[groups["what"]]
            return explain(groups, context)
    return None


def _same_cause(a, b):
    """Whether two causes differ only in their numbers (steps, distances)."""
    return re.sub(_NUM, "#", a) == re.sub(_NUM, "#", b)


def lammps_stop(err, args):
    """One line for a level LAMMPS stopped, in the CLI's terms: the level, the cause, the
    option that cures it, and the log that holds LAMMPS's own message."""
    method = getattr(args, "method", "quasistatic")
    context = SimpleNamespace(s=err.dryness, start=getattr(args, "start", "built"),
                              fallback=fallback_of(args) if hasattr(args, "fallback") else None,
                              first=err.first, method="dynamics" if err.first else method)
    known = cause_and_cure(err.reason, context)
    if known:
        text = f"{known[0]}; {known[1]}"
    else:
        text = f"LAMMPS stopped: {err.reason.removeprefix('ERROR: ')}"
    if err.first:
        first = cause_and_cure(err.first, SimpleNamespace(**{**vars(context),
                                                             "method": method, "first": ""}))
        first = first[0] if first else err.first
        if known and _same_cause(first, known[0]):
            text = f"the quasi-static solve and the dynamics it fell back to stopped alike: {text}"
        else:
            text = (f"the quasi-static solve stopped ({first}), and the dynamics it fell back "
                    f"to stopped too: {text}")
    return f"s = {err.dryness:g}: {text} (LAMMPS log: {err.log})"


# --------------------------------------------------------------------------- options

def checked(convert, test, rule):
    """An argparse type: ``convert`` the text; refuse non-finite values and those that fail
    ``test`` (``rule`` says what is wanted)."""
    def parse(text):
        try:
            value = convert(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not (math.isfinite(value) and test(value)):
            raise argparse.ArgumentTypeError(f"must be {rule}, got {text}")
        return value
    return parse


positive_int = checked(int, lambda v: v >= 1, "at least 1")
positive_float = checked(float, lambda v: v > 0, "a positive number")
fraction = checked(float, lambda v: v >= 0, "a number >= 0")   # e.g. a coefficient of variation
seed_int = checked(int, lambda v: 0 <= v < 2 ** 32, "an integer from 0 to 2**32 - 1")


def levels(text):
    """--dryness: distinct levels in (0, 1], wettest first as given."""
    out = []
    for word in text.split(","):
        try:
            s = float(word)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{word!r} is not a number") from None
        if not 0 < s <= 1:
            raise argparse.ArgumentTypeError(f"level {word} is outside (0, 1]")
        if s in out:
            raise argparse.ArgumentTypeError(f"level {word} is given twice")
        out.append(s)
    return out


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


def tissue_source_arguments(q, width=1.5, what=""):
    q.add_argument("--data", metavar="FILE",
                   help="tissue file instead of --width/--height: a LAMMPS data file "
                        "(python3 -m cgms.tissue) or cell centroids, one 'id x y' line each, "
                        "in metres")
    q.add_argument("--width", type=positive_float, default=width,
                   help=f"tissue width, mm{what}")
    q.add_argument("--height", type=positive_float, default=1.5, help="tissue height, mm")
    q.add_argument("--cv", type=fraction, default=0.0,
                   help="coefficient of variation of cell diameters (0: uniform)")
    q.add_argument("--seed", type=seed_int, default=1, help="seed for the cell diameters")


def common_arguments(q, kind, width=True):
    q.add_argument("--out", help=f"results folder (default results/{kind}/<date-time>)")
    q.add_argument("--material", default="apple", help="material file (default apple)")
    q.add_argument("--set", default="", metavar="'NAME VALUE ...'", type=material_overrides,
                   help="material parameters that replace the file's, as on a pair_coeff "
                        "line, e.g. --set 'k_S 0.5' (doc/pair_cgms.rst)")
    if width:
        tissue_source_arguments(q)
    else:
        q.add_argument("--cv", type=fraction, default=0.0,
                       help="coefficient of variation of cell diameters (0: uniform)")
        q.add_argument("--seed", type=seed_int, default=1, help="seed for the cell diameters")
    q.add_argument("--residual", type=positive_float, default=1e-3,
                   help="steady-state residual")
    q.add_argument("--speed", type=positive_float, default=1e-3, help="steady-state speed, m/s")
    q.add_argument("--max-steps", type=positive_int, default=2000000,
                   help="step (or minimiser iteration; Newton: at most 60) limit per level")
    q.add_argument("--method", choices=("quasistatic", "newton", "dynamics"),
                   default="quasistatic",
                   help="solve for the steady state directly: P = -Pi and FIRE "
                        "minimisation (default; doc/model.md) or Newton's method (fewer, "
                        "costlier iterations: doc/performance.md), or follow the dynamics "
                        "until the --residual and --speed thresholds hold (the paper's way)")


def fallback_argument(q):
    q.add_argument("--fallback", choices=(*study.FALLBACKS, "none"),
                   help="where the quasi-static solve (FIRE or Newton) stops or does not "
                        "converge, follow the dynamics instead (default with --method "
                        "quasistatic or newton; dt = "
                        f"{study.FALLBACK['dt']:g} s; log and dump in <tissue>/"
                        f"{study.FALLBACK_FOLDER}/; the table says which method solved each "
                        "level); none: stop there instead")


def sweep_arguments(q):
    q.add_argument("--dryness", type=levels, default=DEFAULT_LEVELS,
                   help=f"levels (default {DEFAULT_LEVELS})")
    q.add_argument("--resume", action="store_true", help="continue an interrupted study in --out")
    fallback_argument(q)
    q.add_argument("--start", choices=study.STARTS, default="built",
                   help="where each level starts: the built tissue (default; the paper's "
                        "moisture-domain approach), or the previous level's steady state, "
                        "wettest to driest (a drying ramp: a dried level's cutoff need not "
                        "hold the built lattice; doc/calibration.md, \"Five levels\")")


def main_arguments(q):
    common_arguments(q, "microscale", width=False)
    sweep_arguments(q)


def study_arguments(q):
    common_arguments(q, "study")
    sweep_arguments(q)


def target_arguments(q):
    common_arguments(q, "target")
    q.add_argument("target", type=positive_float, help="moisture X/X0 to reach, e.g. 0.60")
    q.add_argument("--xtol", type=positive_float, default=1e-3,
                   help="tolerance on the initial s")
    fallback_argument(q)


def sensitivity_arguments(q):
    q.add_argument("--out", help="results folder (default results/sensitivity/<date-time>)")
    q.add_argument("--material", default="apple", help="material file (default apple)")
    tissue_source_arguments(q, width=1.25, what=" (default 1.25 x 1.5: the 86-bead tissue)")


#: the subcommands: name -> (help, options, job). A new subcommand is one line here.
COMMANDS = {
    "main": ("the microscale study (six tissues, five levels)", main_arguments, main_job),
    "study": ("dry one tissue over moisture levels", study_arguments, study_job),
    "sensitivity": ("the paper's sensitivity study (k_T, k_PA, beta)", sensitivity_arguments,
                    sensitivity_job),
    "calibrate": ("fit k_T, k_PA, beta to reference centroids (eqn 2)", calibrate_arguments,
                  calibrate_job),
    "target": ("initial dryness whose steady state reaches X/X0", target_arguments, target_job),
    "tissue": ("build a tissue data file (python3 -m cgms.tissue)", tissue_parser_arguments,
               tissue_job),
    "dry": ("dry a tissue slice in air over time (doc/drying.md)", dry_cli.add_arguments,
            dry_cli.job),
    "mfc": (mfc_cli.HELP, mfc_cli.arguments, mfc_cli.main),
}


def parser():
    p = argparse.ArgumentParser(prog="cgms", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    for name, (text, arguments, job) in COMMANDS.items():
        q = sub.add_parser(name, help=text, description=text)
        arguments(q)
        q.set_defaults(func=job)
    return p


def describe(err):
    """One line for an error: OS errors as 'reason: file'."""
    if isinstance(err, OSError) and err.strerror:
        return f"{err.strerror}: {err.filename}" if err.filename else err.strerror
    return str(err)


def failure(err, args):
    """The exit status and one line of an exception that ends a command."""
    if isinstance(err, UsageError):
        return 2, f"cgms {args.command}: {err}"
    if isinstance(err, study.LammpsError):
        return 1, f"cgms {args.command}: {lammps_stop(err, args)}"
    if isinstance(err, (RuntimeError, ValueError, OSError)):
        # a LAMMPS stop (its whole ERROR line is in the message) or a bad input: say it,
        # with no traceback; the results so far stay in the folder
        return 1, f"cgms {args.command}: {describe(err)}"
    # a fault of cgms itself: still one line, never a traceback
    return 1, (f"cgms {args.command}: internal error ({type(err).__name__}: {err}); "
               "CGMS_DEBUG=1 shows where; please report it with the command line")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    parallel.one_voice(argv)
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        # only commands that have --resume offer it
        more = " (--resume continues)" if hasattr(args, "resume") else ""
        print(f"cgms {args.command}: interrupted; finished results stay in the folder{more}",
              file=sys.stderr)
        return 130
    except Exception as err:
        if os.environ.get("CGMS_DEBUG") and not isinstance(err, UsageError):
            raise
        status, line = failure(err, args)
        print(line, file=sys.stderr)
        return status
