# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Dry a 3-D fine-scale (MFC) tissue block over moisture levels and write its reference
(doc/mfc.md, "3-D tissue"; reference/mfc3d/README.md).

    python3 -m cgms.mfc.study3d OUT [--cubes 2] [--subdivision 5] [--levels 1,0.8,...]
                                    [--seed 1] [--stage 0.05] [--material apple]

The path is the 2-D one: the fresh block relaxed with the lamella's LJ alone, the lamella
bonds set at rest there, then each level reached from the previous one through stages
0.05 apart (one minimisation chunk each), and minimised to the force test; before every
level, the fresh one too (unlike 2-D), the walls are kicked by up to 0.1 um (LAMMPS seed
``seed + round(1e4 s)``). Per level
``cells.s<s>.csv`` (id, centroid x y z, volume, wall area) and ``level.s<s>.json`` (the
tissue's hull volume and surface, summed cell volume, extents, iterations, largest force,
seconds, and the count of wall particles inside another cell's wall, 0 when the lamella
kept the walls apart); ``walls.s<s>.dump`` the wall particles (OVITO); ``summary.csv`` the
levels in one table; ``lamella.txt`` the lamella's rest lengths; ``setup.json`` the
block, the levels, the seed, the solver and the walls' self-avoidance. An existing folder
is refused.

After every stage and level the walls are checked (:mod:`cgms.mfc.crossing3d`): a wall
that passed through itself or through a neighbour's stops the study with
:class:`WallCrossing` (what, where, what is kept, what to try), as the 2-D study stops at a
crossed ring, since the cell volumes and measures of such walls mean nothing.
"""

import argparse
import csv
import io
import json
import sys
import time
from contextlib import closing
from pathlib import Path

import numpy as np

from .. import folders
from ..study import level_name
from . import crossing3d, model as mfc_model, run3d, tissue3d

LEVELS = (1.0, 0.8, 0.6, 0.4, 0.3)


def stages(previous, s, step=run3d.DEFAULTS["stage"]):
    """Intermediate levels from ``previous`` down to ``s`` (exclusive), ``step`` apart."""
    k = int(np.ceil((previous - s) / step - 1e-9))
    return [previous - (previous - s) * j / k for j in range(1, k)]


def _write_cells(path, m):
    text = io.StringIO(newline="")
    out = csv.writer(text)
    out.writerow(["id", "x", "y", "z", "volume", "area"])
    for k in range(len(m["volume"])):
        out.writerow([k + 1, *(f"{v:.10g}" for v in m["centroid"][k]),
                      f"{m['volume'][k]:.10g}", f"{m['area'][k]:.10g}"])
    folders.write_atomic(path, lambda fh: fh.write(text.getvalue().encode()))


def open_lammps(data, w, processors=None, plugin=None):
    """A LAMMPS instance (this build's plugin) holding the 3-D tissue of ``data``."""
    import os
    from lammps import lammps
    lmp = lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    lmp.command(f"plugin load {plugin or os.environ['CGMS_PLUGIN']}")
    lmp.commands_list(run3d.setup_commands(data, w, processors=processors))
    return lmp


def record(out, lmp, w, s, result, seconds):
    """The level's files: per-cell measures and the tissue's."""
    x = run3d.positions(lmp)
    m = run3d.cells(x, w)
    _write_cells(out / f"cells.{level_name(s)}.csv", m)
    info = dict(s=s, **run3d.tissue(x, m), **result, seconds=round(seconds, 1),
                intrusions=len(run3d.intrusions(x, w)),
                cell_volume_over_fluid=float(m["volume"].sum() / (s * w["fluid_volume"]
                                                                  * len(m["volume"]))))
    folders.write_json(out / f"level.{level_name(s)}.json", info)
    lmp.command(f"write_dump all custom {(out / f'walls.{level_name(s)}.dump').resolve()} "
                "id mol x y z modify sort id")
    return info


class WallCrossing(RuntimeError):
    """A level stopped on walls that passed through themselves or each other
    (:func:`cgms.mfc.crossing3d.tissue_crossings`): what, where, what is kept and what to
    try. ``found`` is what the check returned, ``s`` the dryness it was met at."""

    def __init__(self, found, s, target, previous, results, dump,
                 step=run3d.DEFAULTS["stage"]):
        where = f"s = {target:g}" + ("" if s == target else
                                     f" (on the ramp from s = {previous:g}, at s = {s:.4g})")
        done = ", ".join(f"{r['s']:g}" for r in results)
        kept = (f"the levels finished (s = {done}) stay in {dump.parent}" if results else
                "no level finished")
        # name what was passed: a cell's own repulsion, or the lamella's between two
        past = "; ".join(
            what for what, there in (
                ("a wall through itself got past its self-avoidance (radius d_p, "
                 "doc/mfc.md, \"3-D tissue\")", found["self"]),
                ("walls of two cells through each other got past the lamella's repulsion "
                 "(inside d_p)", found["between"])) if there)
        cure = (f"a gentler ramp (--stage below {step:g}), another --seed, or a finer wall "
                f"(--subdivision); {past}; the fine model may not reach this dryness"
                if previous is not None else
                "check the cell centres and the subdivision: the relaxed fresh walls must "
                "not overlap")
        super().__init__(f"{where}: {crossing3d.describe(found)}, so the level is not "
                         f"recorded; {kept}; the walls where it stopped are in {dump.name} "
                         f"(OVITO); {cure}")
        self.found, self.s = found, s


def check_walls(out, lmp, w, s, target, previous, results, step=run3d.DEFAULTS["stage"]):
    """Stop (:class:`WallCrossing`) if a wall crossed itself or another's at dryness
    ``s`` (on the way to the level ``target``); the walls are dumped for a look."""
    found = crossing3d.tissue_crossings(run3d.positions(lmp), w["tri"], len(w["x"]))
    if found["self"] or found["between"]:
        dump = out / f"walls.failed.{level_name(s)}.dump"
        lmp.command(f"write_dump all custom {dump.resolve()} id mol x y z modify sort id")
        raise WallCrossing(found, s, target, previous, results, dump, step)


def dry(out, p, cubes=2, n=tissue3d.TISSUE3D["subdivision"], levels=LEVELS, say=print,
        seed=run3d.DEFAULTS["seed"], **solver):
    """Build, relax, glue and dry the block; write the level files into the new folder
    ``out``. Returns the level records."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=False)
    levels = sorted((float(s) for s in levels), reverse=True)
    if not levels or levels[0] != 1.0:
        raise ValueError("the levels must start at the fresh state, s = 1")
    centres = tissue3d.block(p, cubes)
    x, cell, w = tissue3d.write_data(out / "built.data", centres, p, n=n)
    # the self-avoidance defines the dried levels too (studies/mfc/self_avoidance3d.py
    # varies it), so a folder says which it was made with
    setup = dict(cubes=cubes, subdivision=n, cells=len(centres), particles=len(x),
                 levels=levels, seed=seed, solver={**run3d.DEFAULTS, **solver},
                 self_avoidance=dict(radius=w["self_r0"], E0=w["self_E0"],
                                     special=list(tissue3d.SELF_SPECIAL)))
    folders.write_json(out / "setup.json", setup)
    say(f"3-D MFC block: {len(centres)} cells, {len(x)} wall particles")
    opts = {k: v for k, v in {**run3d.DEFAULTS, **solver}.items()
            if k in ("ftol", "chunk", "max_iterations", "dmax")}
    t0 = time.time()
    with closing(open_lammps(out / "built.data", w)) as lmp:
        # the fresh level is kicked too: unkicked, CG stays on the built block's symmetric
        # saddle (doc/results/mfc.md, "A 3-D tissue")
        run3d.kick(lmp, solver.get("kick", run3d.DEFAULTS["kick"]), seed + round(1e4))
        relaxed = run3d.relax(lmp, p, w, 1.0, **opts)
        check_walls(out, lmp, w, 1.0, 1.0, None, [])
        results = [record(out, lmp, w, 1.0, relaxed, time.time() - t0)]
        say(f"s = 1: {json.dumps(results[-1])}")
        fresh = run3d.positions(lmp)
    pairs, types, rest = tissue3d.fresh_lamella(fresh, cell, w, p)
    folders.write_text(out / "lamella.txt", "# type rest_length_m\n" + "".join(
        f"{t} {r:.10g}\n" for t, r in enumerate(rest, start=len(w["rest_classes"]) + 1)))
    tissue3d.write_data(out / "lamella.data", centres, p, n=n, x=fresh,
                        lamella=(pairs, types, rest),
                        title=f"MFC 3-D tissue, lamella set fresh: {len(pairs)} bonds")
    with closing(open_lammps(out / "lamella.data", w)) as lmp:
        step = solver.get("stage", run3d.DEFAULTS["stage"])
        previous = 1.0
        for s in levels[1:]:
            t0 = time.time()
            run3d.kick(lmp, solver.get("kick", run3d.DEFAULTS["kick"]), seed + round(1e4 * s))
            spent = 0
            for stage in stages(previous, s, step):
                spent += run3d.relax(lmp, p, w, stage, ftol=opts["ftol"],
                                     chunk=opts["chunk"], max_iterations=opts["chunk"],
                                     dmax=opts["dmax"])["iterations"]
                check_walls(out, lmp, w, stage, s, previous, results, step)
            r = run3d.relax(lmp, p, w, s, **opts)
            check_walls(out, lmp, w, s, s, previous, results, step)
            r["iterations"] += spent
            results.append(record(out, lmp, w, s, r, time.time() - t0))
            say(f"s = {s:g}: {json.dumps(results[-1])}")
            previous = s
    write_summary(out / "summary.csv", results)
    return results


#: the columns of ``summary.csv``: one row per level
SUMMARY = ("s", "volume", "surface", "cell_volume", "centroid_volume", "centroid_surface",
           "extent_x", "extent_y", "extent_z", "centroid_extent_x", "centroid_extent_y",
           "centroid_extent_z", "cell_volume_over_fluid", "intrusions", "converged", "fmax",
           "iterations", "seconds")


def write_summary(path, results):
    """The levels' tissue measures in one table (SI units)."""
    rows = []
    for r in results:
        flat = dict(r)
        for d, c in enumerate("xyz"):
            flat[f"extent_{c}"] = r["extents"][d]
            flat[f"centroid_extent_{c}"] = r["centroid_extents"][d]
        rows.append(",".join(f"{flat[k]:.10g}" if isinstance(flat[k], float) else str(flat[k])
                             for k in SUMMARY))
    folders.write_text(path, ",".join(SUMMARY) + "\n" + "\n".join(rows) + "\n",
                       overwrite=True)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m cgms.mfc.study3d", description=__doc__
                                 .split("\n\n")[0])
    ap.add_argument("out", help="a new folder for the level files")
    ap.add_argument("--cubes", type=int, default=2, help="block side in BCC cube edges")
    ap.add_argument("--subdivision", type=int, default=tissue3d.TISSUE3D["subdivision"])
    ap.add_argument("--levels", default=",".join(f"{s:g}" for s in LEVELS))
    ap.add_argument("--material", default="apple")
    ap.add_argument("--seed", type=int, default=run3d.DEFAULTS["seed"],
                    help="kick seed: level s uses seed + round(1e4 s)")
    ap.add_argument("--stage", type=float, default=run3d.DEFAULTS["stage"],
                    help="dryness step between the ramp's stages (default %(default)g)")
    args = ap.parse_args(argv)
    try:
        levels = [float(v) for v in args.levels.split(",")]
        if not 1 <= args.seed <= 2**31 - 1 - 10**4:
            raise ValueError(f"--seed must be in 1..{2**31 - 1 - 10**4}, got {args.seed}")
        if not 0 < args.stage <= 0.5:
            raise ValueError(f"--stage must be in (0, 0.5], got {args.stage:g}")
        dry(args.out, mfc_model.parameters(args.material), args.cubes, args.subdivision,
            levels, seed=args.seed, stage=args.stage)
    except (ValueError, FileExistsError, WallCrossing) as err:
        sys.exit(f"cgms mfc3d: {err}")


if __name__ == "__main__":
    main()
