# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms mfc``: dry fine-scale (MFC) tissues to steady state at each moisture
level and write the reference centroids (doc/mfc.md)."""

import sys
from pathlib import Path

from ..mfc import (model as mfc_model, run as mfc_run, study as mfc_study,
                   tissue as mfc_tissue)
from .. import folders, tissue

SINGLE = "single"


HELP = ("the fine-scale MFC model: dry cell-resolved tissues (every cell a ring of wall "
        "particles around its fluid; fast variant: one pressure per cell) and write reference "
        "centroids; cell i sits at bead i of the CGMS tissue of the same name")


def arguments(q):
    """The options of ``cgms mfc``."""
    from .options import checked, levels, positive_float, positive_int
    # LAMMPS's displace_atoms takes seeds of 1 .. 2^31 - 1, and a level adds 1e4 s to it
    seed = checked(int, lambda v: 1 <= v <= mfc_run.MAX_SEED, f"in 1 .. {mfc_run.MAX_SEED}")
    q.add_argument("tissues", nargs="*", default=["calibration"],
                   help="tissue names: calibration (86 cells, default), 1.5x1.5, 1.5x2.0, "
                        "1.5x2.5, 2.0x2.0, 2.0x2.5, all (the six), single (one cell), or a "
                        "CGMS data file (cells at its beads)")
    q.add_argument("--dryness", type=levels, default="1,0.8,0.6,0.4,0.3",
                   help="levels X/X0 (default 1,0.8,0.6,0.4,0.3; the fresh level is always run)")
    q.add_argument("--out", help="results folder (default results/mfc/<date-time>)")
    q.add_argument("--resume", action="store_true", help="continue an interrupted study in --out")
    q.add_argument("--material", default="apple", help="CGMS material of the shared values")
    q.add_argument("--temperature", type=float, default=None,
                   help="tissue temperature, C: walls and lamella softened and turgor scaled "
                        "as doc/drying.md's \"Temperature in the mechanics\" says (default: "
                        "none, the material's unheated values)")
    q.add_argument("--self-E0", type=positive_float, default=mfc_model.MFC["self_E0"],
                   help="strength E0 of a wall's self-avoidance (8-4 LJ within 3 um), J "
                        "(default %(default)g, which keeps the folds of dried walls from passing "
                        "through each other; 1e-12, the value before, let them: doc/mfc.md, "
                        "\"Wall self-avoidance\")")
    q.add_argument("--ftol", type=positive_float, default=mfc_run.DEFAULTS["ftol"],
                   help="steady state: largest force on a wall particle, N (default %(default)g)")
    q.add_argument("--shift", type=positive_float, default=mfc_run.DEFAULTS["shift"],
                   help="steady state, or: no cell centroid moved more than this (m) over a "
                        "chunk of 2000 iterations (default %(default)g)")
    q.add_argument("--stage", type=float, default=None,
                   help=f"dryness step of the ramp between levels (default "
                        f"{mfc_run.REFERENCE_PATH['stage']:g} on the quasi-static path, "
                        f"{mfc_run.DEFAULTS['stage']:g} on the chunked one; 0: jump)")
    q.add_argument("--stages", choices=("steady", "chunk"), default=None,
                   help="the ramp's levels between the asked ones: steady (each relaxed to its "
                        "steady state: the quasi-static path of a slowly dried tissue and of "
                        "reference/mfc/steady; default) or chunk (one chunk of minimisation "
                        "each, about half the cost at its own --stage, not at rest; the "
                        "path of the sets in reference/mfc/, on which the long tissues "
                        "elongate instead of widening: doc/mfc.md)")
    q.add_argument("--newton", type=float, default=mfc_run.DEFAULTS["newton"],
                   help="Newton's method finishes a level once the minimiser's largest force is "
                        "below this, N (default %(default)g; 0: the minimiser alone, with the "
                        "shift test)")
    q.add_argument("--seed", type=seed, default=mfc_run.DEFAULTS["seed"],
                   help="seed of the ramp's random wall kicks (default %(default)d); the dried "
                        "levels land on neighbouring minima that the seed alone moves, so a "
                        "reference ensemble is one study per seed (results of different seeds "
                        "never share a folder)")
    q.add_argument("--max-iterations", type=positive_int,
                   default=mfc_run.DEFAULTS["max_iterations"],
                   help="minimiser iteration limit per stage (default %(default)d)")


def _centres(name, p):
    """Cell centres of a named tissue (the CGMS builder's) or of a CGMS data file."""
    if name == SINGLE:
        return [[0.0, 0.0]]
    if name in tissue.MICROSCALE:
        w, h = tissue.MICROSCALE[name]
        return tissue.rectangle(w * 1e-3, h * 1e-3, p["x_ref"])
    if Path(name).is_file():
        try:
            return mfc_study.read_centres(name)
        except ValueError as err:     # the readers' messages name the file
            from .options import UsageError
            raise UsageError(str(err)) from None
    from .options import UsageError
    raise UsageError(f"unknown tissue {name!r}: give one of {SINGLE}, "
                     f"{', '.join(tissue.MICROSCALE)}, all, or a CGMS data file")


def folder_name(name):
    """The results folder of a tissue: its name, or a data file's stem. (``Path(name).stem``
    of a tissue name drops its last ".5" or ".0": 1.5x2.0 and 1.5x2.5 shared ``1.5x2``,
    and the second read the first one's levels back as its own.)"""
    return name if name in tissue.MICROSCALE or name == SINGLE else Path(name).stem


def main(args):
    """Run the study; returns an exit status."""
    from .options import UsageError
    levels = args.dryness
    if args.stage is not None and not 0 <= args.stage < 1:
        raise UsageError(f"--stage must be in [0, 1), got {args.stage}")
    if args.stages is None:   # a jump (--stage 0) has no levels between: nothing to relax
        args.stages = "chunk" if args.stage == 0 else "steady"
    if args.stage is None:    # each path's own default, that of the sets made on it
        args.stage = mfc_run.REFERENCE_PATH["stage"] if args.stages == "steady" else \
            mfc_run.DEFAULTS["stage"]
    if args.stages == "steady" and args.stage == 0:
        # a jump has no levels between the asked ones: steady would change nothing but
        # the folder's record, which then refuses to resume the identical --stage 0 study
        raise UsageError("--stages steady relaxes the ramp's levels between "
                         "the asked ones, and --stage 0 jumps (there are none): give --stage "
                         "above 0, or leave out --stages")
    if not args.newton >= 0:
        raise UsageError(f"--newton must be >= 0 (N; 0: off), got {args.newton}")
    T = args.temperature
    if T is not None and not mfc_model.HEAT["T_min"] <= T <= mfc_model.HEAT["T_max"]:
        raise UsageError(f"--temperature must be in {mfc_model.HEAT['T_min']:g} .. "
                         f"{mfc_model.HEAT['T_max']:g} (C, liquid cell water), got {T}")
    names = list(tissue.MICROSCALE) if args.tissues == ["all"] else args.tissues
    try:
        p = mfc_model.parameters(args.material, temperature=T, self_E0=args.self_E0)
    except (ValueError, OSError) as err:    # a material file missing or wrong: an input
        raise UsageError(str(err).strip('"')) from None
    folder_of = {}
    for name in names:   # each tissue its own results folder: one would resume the other's
        if folder_name(name) in folder_of:
            raise UsageError(f"tissues {folder_of[folder_name(name)]} and {name} would share "
                             f"the results folder {folder_name(name)}: give each once, and "
                             "data files of different names")
        folder_of[folder_name(name)] = name
    centres = {name: _centres(name, p) for name in names}   # bad names stop before any run
    for name in names:       # ... and so do cell centres that cannot be built into walls
        try:
            mfc_tissue.walls(centres[name], p)
        except ValueError as err:
            raise UsageError(f"{name}: {err}") from None
    with folders.claim(args.out, "mfc", args.resume) as out:
        rows = run(out, names, centres, p, levels, args)
    print_table(rows)
    print(f"\ncgms mfc: centroids {out}/*/centroids.s*.txt; cells.s*.csv; walls.s*.dump "
          "(OVITO)")
    return 0


def run(out, names, centres, p, levels, args):
    """Every tissue through every level; returns the per-level summaries."""
    print(f"cgms mfc: {', '.join(names)}; levels {levels}; results in {out}", flush=True)
    rows = []
    for name in names:
        folder = out / folder_name(name)
        print(f"cgms mfc: {name}: {len(centres[name])} cells, "
              f"{len(centres[name]) * p['n_wall']} wall particles", flush=True)
        results = mfc_study.dry(centres[name], p, folder, levels, ftol=args.ftol,
                                shift=args.shift, stage=args.stage,
                                steady_stages=args.stages == "steady",
                                max_iterations=args.max_iterations, seed=args.seed,
                                newton=args.newton if args.newton > 0 else None,
                                say=lambda line: print(line, flush=True))
        for r in results:
            r["tissue"] = name
        rows += results
        mfc_study.write_table(results, folders.summary_path(folder))
    return rows


def print_table(rows):
    print("\n  tissue        cells     s    A/A0    P/P0   EL/EL0  cellA/A0  cellP/P0  "
          "converged")
    for r in rows:
        print(f"  {r['tissue']:12s} {r['cells']:6d}  {r['s']:4.2f}  "
              + "  ".join(f"{r[k]:.4f}" if k in r else "   -  " for k in
                          ("A/A0", "P/P0", "EL/EL0", "cell_area/A0", "cell_perimeter/P0"))
              + f"  {'yes' if r['converged'] else 'NO'}")


if __name__ == "__main__":
    sys.exit("use: python3 -m cgms mfc ...")
