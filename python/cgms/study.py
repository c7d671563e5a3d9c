"""Steady states over moisture levels (the paper's moisture-domain approach, section 2.4),
their morphology, and the initial dryness that lands on a requested moisture.

Each level is one LAMMPS run from the built tissue to steady state. Results go to a folder,
one ``level.s<s>.json`` (+ ``.npy`` positions) per level, so an interrupted sweep resumes
without redoing finished levels, and nothing existing is overwritten."""

import json
import time
from pathlib import Path

import numpy as np

from . import material as material_file, morphology, run

LEVELS = (1.0, 0.8, 0.6, 0.4, 0.3)


def level_name(s):
    return f"s{s:g}"


def relax(data, material, dryness, out, steady=None, diameters=False, dt=1e-7, pair_args="",
          fix_args="", dump_every=None, method="dynamics", overrides=""):
    """Relax the tissue in ``data`` to steady state at ``dryness``; write the final dump and
    the log into ``out`` and return the result (positions, X/X0 reached, steps, ...)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    name = level_name(dryness)
    max_steps = dict(run.STEADY_DEFAULTS, **(steady or {}))["max_steps"]
    start = time.perf_counter()
    lmp = run.open_lammps(log=out / f"log.{name}.lammps")
    try:
        dump = (out / f"tissue.{name}.dump").resolve()
        lmp.commands_string(run.tissue_script(
            Path(data).resolve(), Path(material).resolve(), dryness, dump=dump,
            dump_every=dump_every, steady=steady, diameters=diameters, dt=dt,
            pair_args=pair_args, fix_args=fix_args, method=method, overrides=overrides))
        solver = None
        if method == "newton":
            # progress of the Newton iterations, one line each, beside the LAMMPS log
            mat = material_file.with_overrides(material_file.read(material), overrides)
            # --max-steps bounds the iterations too: a lever for large tissues, where
            # Newton lands near the dynamics' shape in a few iterations and then creeps
            # (doc/performance.md)
            with open(out / f"newton.{name}.log", "w") as fh:
                solver = run.solve_newton(lmp, dump=dump, max_iterations=min(60, max_steps),
                                          spacing=material_file.steady_spacing(mat, dryness),
                                          log=lambda line: print(line, file=fh, flush=True))
        state = run.steady_state(lmp)
    except Exception as err:
        hint = (" The quasi-static solve (FIRE) can stall or diverge where the potential is "
                "not convex (large dried tissues: doc/validation.md); try --method newton "
                "or dynamics." if method == "quasistatic" else "")
        raise RuntimeError(f"s = {dryness:g}: LAMMPS stopped: {err} (log: "
                           f"{out / f'log.{name}.lammps'}).{hint}") from err
    finally:
        lmp.close()
    state.update(dryness=dryness, seconds=time.perf_counter() - start, method=method,
                 converged=bool(state["steps"] < max_steps))
    if solver:
        # steps: Newton iterations; the residual is 0 by construction (P = -Pi)
        state.update(steps=solver["iterations"], converged=bool(solver["converged"]),
                     fmax=solver["fmax"], evaluations=solver["evaluations"])
    return state


def sweep(data, material, out, levels=LEVELS, progress=True, **kwargs):
    """:func:`relax` at every level, resuming: a level whose result file exists in ``out``
    is read back, not run again. Returns the results in level order."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results = []
    bar = _progress(levels, progress)
    for s in bar:
        done = out / f"level.{level_name(s)}.json"
        if done.exists():
            result = json.loads(done.read_text())
            result["xy"] = np.load(out / f"level.{level_name(s)}.npy")
        else:
            result = relax(data, material, s, out, **kwargs)
            np.save(out / f"level.{level_name(s)}.npy", result["xy"])
            done.write_text(json.dumps({k: v for k, v in result.items() if k != "xy"}, indent=1))
        results.append(result)
        if hasattr(bar, "set_postfix"):
            bar.set_postfix(s=s, moisture=f"{result['moisture']:.3f}", steps=result["steps"])
    return results


def table(results):
    """Rows of X/X0 reached, A/A0, P/P0, EL/EL0 (normalised by the s = 1 steady state, or the
    wettest level), steps and wall time, one per level."""
    shapes = [morphology.measures(r["xy"]) for r in results]
    fresh = shapes[int(np.argmax([r["dryness"] for r in results]))]
    rows = []
    for r, m in zip(results, shapes):
        norm = morphology.normalise(m, fresh)
        rows.append({"s": r["dryness"], "X/X0": r["moisture"], **norm, "area": m["area"],
                     "perimeter": m["perimeter"], "elongation": m["elongation"],
                     "steps": r["steps"], "residual": r["residual"], "speed": r["speed"],
                     "method": r.get("method", "dynamics"), "converged": r["converged"],
                     "seconds": r["seconds"]})
    return rows


def write_csv(rows, path):
    import csv
    with open(path, "x", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def target_moisture(data, material, target, out, xtol=1e-3, **kwargs):
    """The initial dryness s whose steady state reaches X/X0 = ``target`` (paper: start at
    0.68 to reach 0.60). X/X0 reached grows with s, so a bracketed root search (Brent)
    finds it; every evaluation is a steady-state run kept in ``out``."""
    from scipy.optimize import brentq

    evaluations = []
    reached = {}

    def miss(s):
        s = round(s, 6)
        if s not in reached:    # brentq asks again for the bracket ends
            result = relax(data, material, s, Path(out) / f"eval{len(evaluations):02d}",
                           **kwargs)
            reached[s] = result["moisture"]
            evaluations.append((s, result["moisture"]))
        return reached[s] - target

    lo, hi = target, 1.0
    if miss(lo) > 0:
        raise ValueError(f"a tissue started at s = {lo} already ends above X/X0 = {target}")
    if miss(hi) < 0:
        raise ValueError(f"even the fresh tissue ends below X/X0 = {target}")
    s = brentq(miss, lo, hi, xtol=xtol)
    return dict(target=target, initial=s, evaluations=evaluations)


def _progress(items, enabled):
    if not enabled:
        return items
    try:
        from tqdm import tqdm
    except ImportError:
        return items
    return tqdm(items, unit="level", leave=False)
