# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Dry a fine-scale (MFC) tissue over moisture levels and write the reference outputs.

One folder per tissue. Per level ``s``:

- ``centroids.s<s>.txt``: cell centroids ``id x y`` (m), the reference format
  ``python3 -m cgms calibrate`` reads (cell id = CGMS bead id);
- ``cells.s<s>.csv``: per-cell area, perimeter, roundness, elongation, compactness;
- ``walls.s<s>.dump``: the wall particles (OVITO), ``state.s<s>.data``: the state a
  resumed study continues from;
- ``level.s<s>.json``: tissue A, P, EL (and normalised by the fresh state), cell means,
  minimiser iterations, largest force left, seconds.

A level whose ``level.s<s>.json`` exists is read back, not run again (resume). That
record is written last and whole (:func:`cgms.folders.write_json`), so the other files of a
level without one are the leftovers of an interrupted attempt and are replaced.
"""

import csv
import hashlib
import io
import time
from pathlib import Path

import numpy as np

from .. import folders, morphology, positions, run, study
from . import metrics as mfc_metrics, run as mfc_run, tissue as mfc_tissue
from .model import SELF_E0_FOLDS
from ..study import level_name


def _write_cells(path, cell):
    """Per-cell measures as CSV, replacing an interrupted attempt's file."""
    text = io.StringIO(newline="")
    w = csv.writer(text)
    w.writerow(["id", "x", "y", "area", "perimeter", "roundness", "elongation",
                "compactness"])
    for k in range(len(cell["area"])):
        w.writerow([k + 1, *(f"{v:.10g}" for v in cell["centroid"][k]),
                    *(f"{cell[q][k]:.10g}" for q in ("area", "perimeter", "roundness",
                                                      "elongation", "compactness"))])
    folders.write_atomic(path, lambda fh: fh.write(text.getvalue().encode()))


def glue_fresh_lamella(out, centres, p):
    """The lamella set in the relaxed fresh tissue of study folder ``out`` (its
    ``walls.s1.dump``): ``lamella.data`` (the fresh walls with the lamella bonds) and
    ``lamella.txt`` (the rest length of each bond type), made once and read back on
    resume. Returns the data file and the rest lengths."""
    data, table = out / "lamella.data", out / "lamella.txt"
    if data.exists() and table.exists():
        # one cell: no bond, an empty table (np.loadtxt warns on it)
        rows = [line.split() for line in table.read_text().splitlines()
                if line.strip() and not line.startswith("#")]
        return data, np.array([float(r[1]) for r in rows])
    xy = morphology.read_dump(out / f"walls.{level_name(1.0)}.dump")[-1]["xy"]   # id order
    w = mfc_tissue.walls(centres, p)
    pairs, types, rest = mfc_tissue.fresh_lamella(xy, w["cell"], p)
    mfc_tissue.write_data(data, centres, p, xy=xy, lamella=(pairs, types), overwrite=True,
                          title=f"MFC tissue, lamella set in the fresh state: {len(pairs)} bonds")
    folders.write_text(table, "# bond type, rest length (m)\n" + "".join(
        f"{t} {r:.10g}\n" for t, r in enumerate(rest, start=2)), overwrite=True)
    return data, rest


def dry(centres, p, out, levels=(1.0, 0.8, 0.6, 0.4, 0.3), say=print, **solver):
    """Relax the MFC tissue whose cells sit at ``centres`` (CGMS bead positions, m) at
    every level (descending; the fresh level 1 first, it is the reference), along the
    drying ramp of :func:`cgms.mfc.run.ramp`, by default on its reference path
    (``REFERENCE_PATH``: quasi-static, stages 0.025 apart). Returns the per-level summaries.
    ``out/setup.json`` records the centres, the parameters and the solver options,
    the ramp's kick ``seed`` among them; a folder with another record is refused
    (FolderError), so a resume never mixes them. The default seed and the chunked path
    (``steady_stages`` off) are left out of the record: folders made before they were
    options used them and resume as they are; a resume on the other path is refused by
    name."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    solver.setdefault("stage", mfc_run.REFERENCE_PATH["stage"])
    # a jump (stage 0) has no levels between the asked ones: nothing to relax on the way
    solver.setdefault("steady_stages", mfc_run.REFERENCE_PATH["steady_stages"]
                      and solver["stage"] > 0)
    centres_sha256 = hashlib.sha256(np.ascontiguousarray(centres, float).tobytes()).hexdigest()
    recorded = {k: solver[k] for k in sorted(solver)
                if not (k == "seed" and solver[k] == mfc_run.DEFAULTS["seed"])
                and not (k == "steady_stages" and not solver[k])}
    setup = dict(centres_sha256=centres_sha256, parameters=p, **recorded)
    _same_path(out / "setup.json", setup)
    folders.same_setup(out / "setup.json", setup)
    levels = sorted({1.0, *map(float, levels)}, reverse=True)
    data = out / "walls.data"
    if not data.exists():
        mfc_tissue.write_data(data, centres, p, title=f"MFC tissue: {len(centres)} cells")
    results, previous, lmp = [], None, None
    glue = p["lamella"] == "fresh"
    fresh = None
    try:
        for s in levels:
            name = level_name(s)
            record = out / f"level.{name}.json"
            if record.exists():
                results.append(folders.read_json(record))
                fresh = fresh or results[0]
                previous = s
                continue
            start = time.perf_counter()
            log = out / f"log.{name}.lammps"
            k = 1
            while log.exists():   # an interrupted attempt's log is kept
                k += 1
                log = out / f"log.{name}.{k}.lammps"
            if lmp is None:
                lmp = run.open_lammps(log=log)
                mfc_run.require_packages(lmp)
                source = data if previous is None else out / f"state.{level_name(previous)}.data"
                rest = ()
                if glue and previous is not None:   # the lamella set in the fresh state
                    lamella, rest = glue_fresh_lamella(out, centres, p)
                    source = lamella if previous == 1.0 else source
                lmp.commands_list(mfc_run.setup_commands(source.resolve(), p, rest=rest))
            else:
                lmp.command(f"log {log.resolve()}")
            try:
                report = mfc_run.ramp(lmp, p, previous, s, **solver)
                xy = mfc_run.positions(lmp)
                summary, cell = mfc_metrics.summary(xy, p["n_wall"], fresh)
                if fresh is None:   # the fresh state is its own reference: A/A0 = 1 ...
                    summary, cell = mfc_metrics.summary(xy, p["n_wall"], summary)
            except mfc_metrics.RingError as err:
                dump = out / log.name.replace("log.", "walls.failed.", 1).replace(
                    ".lammps", ".dump")
                lmp.command(f"write_dump all custom {dump.resolve()} id mol type x y "
                            "modify sort id")
                raise RingFailure(err, s, previous, results, dump) from None
            summary.update(report, seconds=time.perf_counter() - start, particles=len(xy))
            positions.write_centroids(out / f"centroids.{name}.txt", cell["centroid"],
                                      comment=f"MFC cell centroids at s = X/X0 = {s:g}",
                                      overwrite=True)
            _write_cells(out / f"cells.{name}.csv", cell)
            lmp.command(f"write_dump all custom {(out / f'walls.{name}.dump').resolve()} "
                        "id mol type x y modify sort id")
            lmp.command(f"write_data {(out / f'state.{name}.data').resolve()} nocoeff")
            folders.write_json(record, summary)
            results.append(summary)
            fresh = fresh or summary
            previous = s
            if glue and s == 1.0:   # the dried levels start from the fresh walls, glued
                lmp.close()
                lmp = None
            say(f"cgms mfc: s = {s:g}: cell area / fresh {summary['cell_area/A0']:.4f}, "
                f"{report['iterations']} iterations, {summary['seconds']:.1f} s"
                + ("" if report["converged"] else " (NOT converged)")
                + "".join(f"; the ramp's level s = {v:g} did NOT reach its steady state"
                          for v in report.get("unsteady_stages", ())))
    finally:
        if lmp is not None:
            lmp.close()
    return results


def _same_path(record, setup):
    """A folder dried on the other path (quasi-static or chunked) is refused with the
    option that resumes it: the generic record check would only say ``steady_stages:
    None there, True now``."""
    if not Path(record).exists():
        return
    old = folders.read_json(record)
    was, now = bool(old.get("steady_stages")), bool(setup.get("steady_stages"))
    if was != now:
        name = {True: "quasi-static (--stages steady)", False: "chunked (--stages chunk)"}
        raise folders.FolderError(
            f"{Path(record).parent} was dried on the {name[was]} path and this run asks for "
            f"the {name[now]} one; the two reach different dried shapes (doc/mfc.md), so "
            f"resume it with --stages {'steady' if was else 'chunk'} or choose another --out")


class RingFailure(RuntimeError):
    """A level stopped on a wall ring the cell measures cannot take
    (:class:`cgms.mfc.metrics.RingError`): what, where, what is kept and what to try."""

    def __init__(self, err, s, previous, results, dump):
        where = f"s = {s:g}" + ("" if err.level in (None, s) else
                                f" (on the ramp from s = {previous:g}, at s = {err.level:g})")
        done = ", ".join(f"{r['s']:g}" for r in results)
        kept = f"the levels finished (s = {done}) stay in {dump.parent}" if results else (
            "no level finished")
        cure = ("--resume with --dryness holding a level between s = "
                f"{previous:g} and {s:g} continues from the last finished level; a gentler "
                "ramp (--stage), another --seed or a stronger self-avoidance (--self-E0 above "
                f"this run's; the default {SELF_E0_FOLDS:g} J holds pressed folds apart) needs a new "
                "--out; the fine model may not reach this dryness (doc/mfc.md)"
                if previous is not None else
                "check the cell centres: the built walls of adjacent cells must not overlap")
        super().__init__(f"{where}: {err}, so the level has no cell measures; {kept}; the "
                         f"walls where it stopped are in {dump.name} (OVITO); {cure}")
        self.ring = err


COLUMNS = ("s", "A/A0", "P/P0", "EL/EL0", "cell_area/A0", "cell_perimeter/P0",
           "cell_roundness", "cell_elongation", "iterations", "fmax", "converged", "seconds",
           "ELpca/ELpca0")   # the second-moment elongation, added after the others


def write_table(results, path):
    """The per-level summaries as CSV (new file only)."""
    return study.write_csv(results, path, columns=COLUMNS)


def read_centres(path):
    """Cell centres (ordered by id) from a CGMS data file or an ``id x y`` centroid list."""
    if positions.is_data_file(path):
        return positions.read_data(path)["xy"]
    ids, xy = positions.read_centroids(path)
    return np.asarray(xy, float)[np.argsort(ids)]
