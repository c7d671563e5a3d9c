# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms calibrate``: fit material parameters to reference centroids by
eqn (2) (doc/calibration.md)."""

import sys
from pathlib import Path

import numpy as np

from .. import positions, superpose
from ..calibration import calibrate, fitparams
from ..calibration.fitparams import BETA_BOUNDS, BOUNDS
from .options import UsageError, describe, positive_int, tissue_source_arguments
from .tissues import chosen_tissue, material_of, tissue_in_folder


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


def arguments(p):
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


def job(args):
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
