# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Calibration: fit CGMS material parameters to reference cell-centroid positions.

The paper (section 2.3) calibrates k_T, k_PA and beta on the 86-bead tissue: at each
dryness level the steady-state bead positions ``p_i`` are compared with the cell
centroids ``q_i`` of a reference (there: the MFC model) by eqn (2),

    RMSD = ( 1/n_r  sum_i |p_i - q_i|^2 )^(1/2)

(``|.|`` the Euclidean distance in the plane, ``n_r`` the number of beads), and the
parameters minimise it. Here:

- **references**: one per dryness level, an ``id x y`` text file (metres) or a LAMMPS
  dump (its last frame) (:func:`cgms.positions.read_centroids`); beads are matched to
  centroids by atom id, and a reference with another bead count or other ids is rejected
  with a ValueError naming the ids;
- **steady states**: :func:`cgms.study.relax_or_fallback` (the quasi-static solve, the
  dynamics where it stops or does not converge), run in parallel and cached by
  :mod:`cgms.pool`; each run writes into its own folder under ``<out>/runs``;
- **rigid motion**: the steady state is defined only up to a rigid motion, so the
  simulated positions are first moved onto the reference by the best translation
  (``align="translation"``, default) or translation and rotation (``"rigid"``); the RMSD
  is then the minimum of eqn (2) over those motions (``"none"``: eqn (2) as written;
  :mod:`cgms.superpose`);
- **parameters** (``parameters=``): see :mod:`cgms.calibration.fitparams`;
- **minimiser**: eqn (2) is a root mean square of residuals, so the fit minimises the mean
  over levels of RMSD^2 as a bounded nonlinear least-squares problem
  (:func:`scipy.optimize.least_squares`, trust-region reflective) with a forward-difference
  Jacobian whose columns (one steady state per parameter and level) run in parallel;
- **resume**: every steady state (parameter overrides, level -> positions, X/X0, method) is
  appended to ``<out>/evaluations.jsonl``; a rerun in the same folder reads them back, the
  deterministic minimiser retraces its path through them and continues where it stopped;
- **output**: fitted values, RMSD per level, evaluation counts, wall time
  (``<out>/result.json``) and a material file in the format of ``potentials/``.

Command line: ``python3 -m cgms calibrate --help``.
Method and measured results: ``doc/calibration.md``.
"""

import math
import os
import time
from pathlib import Path

import numpy as np

from . import fitparams
from .. import folders, material as material_mod, morphology, positions
from ..pool import CACHE, Runner  # noqa: F401 - CACHE: the cache file name, for callers
from ..superpose import ALIGN, align

#: forward-difference step in ln(value): large against the FIRE noise of the steady state
#: (about 2e-7 x_ref on positions), small against the curvature
FD_STEP = 1e-3
#: RMSD (in x_ref) given to a level without a steady state, so that the minimiser backs off
PENALTY = 1.0


# --------------------------------------------------------------------------- references

def match(ids, xy, expected, what="reference"):
    """Positions of ``xy`` ordered like the sorted tissue ids ``expected``; ValueError when
    the reference has another bead count, repeated ids, or ids the tissue does not have."""
    ids = np.asarray(ids, dtype=np.int64).ravel()
    xy = np.asarray(xy, dtype=float)
    expected = np.sort(np.asarray(expected, dtype=np.int64).ravel())
    if xy.ndim != 2 or xy.shape[1] < 2 or len(xy) != len(ids):
        raise ValueError(f"{what}: positions must be an (n, 2) array with one id per row, "
                         f"got {len(ids)} ids and shape {xy.shape}")
    xy = xy[:, :2]
    uniq, counts = np.unique(ids, return_counts=True)
    if np.any(counts > 1):
        raise ValueError(f"{what}: repeated id(s) {_some(uniq[counts > 1])}")
    missing = np.setdiff1d(expected, ids)
    extra = np.setdiff1d(ids, expected)
    problems = []
    if len(ids) != len(expected):
        problems.append(f"has {len(ids)} beads but the tissue has {len(expected)}")
    if len(missing):
        problems.append(f"lacks tissue id(s) {_some(missing)}")
    if len(extra):
        problems.append(f"has id(s) {_some(extra)} that the tissue does not "
                        f"(tissue ids {expected[0]}..{expected[-1]})")
    if problems:
        raise ValueError(f"{what} " + "; ".join(problems)
                         + ": beads are matched to reference centroids by atom id")
    if not np.all(np.isfinite(xy)):
        bad = ids[~np.all(np.isfinite(xy), axis=1)]
        raise ValueError(f"{what}: non-finite position for id(s) {_some(bad)}")
    return xy[np.argsort(ids)]


def _some(values, k=10):
    values = [int(v) for v in values]
    return ", ".join(map(str, values[:k])) + (f" ... ({len(values)} in all)" if len(values) > k
                                              else "")


def load_references(references, data):
    """``{level: (n, 2) positions ordered by tissue id}`` from ``{level: source}``; a source
    is a file (see :func:`read_centroids`), an (n, 2) array (ids 1..n) or ``(ids, xy)``."""
    expected = positions.read_data(data)["ids"]
    if not references:
        raise ValueError("no reference: give at least one dryness level and its centroids")
    out = {}
    for level, source in references.items():
        s = float(level)
        if not 0 < s <= 1:
            raise ValueError(f"dryness level {level!r} is outside (0, 1]")
        if s in out:
            raise ValueError(f"two references for s = {s:g}")
        if isinstance(source, (str, os.PathLike)):
            ids, xy = positions.read_centroids(source)
            what = f"reference for s = {s:g} ({source})"
        elif isinstance(source, tuple) and len(source) == 2:
            ids, xy = source
            what = f"reference for s = {s:g}"
        else:
            xy = np.asarray(source, float)
            ids = np.arange(1, len(xy) + 1)
            what = f"reference for s = {s:g}"
        out[s] = match(ids, xy, expected, what)
    return dict(sorted(out.items(), reverse=True))


def check_units(ref, lattice, what):
    """Reject references whose size is far from the tissue's (not in metres?)."""
    size = lambda p: math.sqrt(((p - p.mean(axis=0)) ** 2).sum(axis=1).mean())  # noqa: E731
    ratio = size(ref) / size(lattice)
    if not 0.2 < ratio < 5:
        raise ValueError(f"{what} spans {ratio:.3g} times the tissue's size: positions must "
                         "be in metres and belong to this tissue")


def centroid_distance_slope(fresh, dried, neighbour=1.3):
    """The paper's LJ-radius law (Table 2: r/r0 = 1 + lj_slope ln s, r the average distance
    between cell centroids relative to fresh) measured on reference centroids.
    ``fresh``: (n, 2) centroids at s = 1; ``dried``: {s: (n, 2)}, rows in the same order.
    The distances are those of the fresh state's neighbour pairs (centres closer than
    ``neighbour`` x the median nearest-neighbour distance), each relative to its fresh
    length. Returns ``(lj_slope, {s: mean ratio})``, lj_slope the least-squares slope of
    ratio - 1 against ln s (through s = 1, ratio 1). doc/calibration.md, "Five levels"."""
    from scipy.spatial import cKDTree

    fresh = np.asarray(fresh, float)
    i, k = cKDTree(fresh).query_pairs(neighbour * morphology.spacing(fresh),
                                      output_type="ndarray").T
    length = np.linalg.norm(fresh[i] - fresh[k], axis=1)
    ratio = {float(s): float(np.mean(np.linalg.norm(np.asarray(xy)[i] - np.asarray(xy)[k],
                                                    axis=1) / length))
             for s, xy in dried.items()}
    ln_s = np.log(list(ratio))
    return float(ln_s @ (np.array(list(ratio.values())) - 1) / (ln_s @ ln_s)), ratio


# --------------------------------------------------------------------------- the fit

def calibrate(data, material, references, out, parameters=("k_T", "k_PA", "beta"),
              start=None, bounds=None, align_mode="translation", workers=2,
              max_evaluations=60, xtol=1e-4, ftol=1e-10, gtol=1e-10, fd_step=FD_STEP,
              pair_args="", material_out=None, overwrite=False, progress=True,
              level_start="built"):
    """Fit ``parameters`` so that the steady states of the tissue in ``data`` match the
    ``references`` ({dryness: source}, see :func:`load_references`) by eqn (2).

    ``material``: name or path of the start material file; ``out``: folder for the runs,
    the evaluation cache (a rerun in the same folder resumes), ``result.json`` and, unless
    ``material_out=False``, the fitted material file (default
    ``<out>/<material>-calibrated.cgms``, or ``-2``, ``-3`` ... when that exists; a given
    path that exists is an error unless ``overwrite``).
    ``align_mode``: "translation" (default), "rigid" or "none" (see :func:`align`).
    ``workers``: processes for independent steady states (at most the CPU count).
    ``max_evaluations``: limit on the minimiser's residual evaluations (parameter vectors,
    Jacobian points not counted). ``progress``: print a line per evaluation (or a callable
    taking the line). ``level_start``: "built" (every level from the built tissue) or
    "previous" (a drying ramp, :func:`cgms.study.sweep`; the levels of a parameter vector
    then run in sequence in one worker).

    Returns a dict: ``parameters`` {name: value}, ``factors`` (fitted / start), ``start``,
    ``rmsd`` and ``rmsd_start`` {level: metres}, ``rmsd_x_ref`` {level: RMSD / x_ref},
    ``moisture`` {level: X/X0 reached}, ``material`` (values written), ``material_file``,
    ``evaluations`` (residual evaluations), ``jacobians``, ``steady_states`` (distinct
    steady states used), ``runs`` (run in this call), ``reused`` (taken from the cache of an
    earlier call), ``fallbacks``, ``failures``, ``seconds``, ``status``,
    ``message``, ``out``."""
    from scipy.optimize import least_squares

    t0 = time.perf_counter()
    say = progress if callable(progress) else (
        (lambda msg: print(f"cgms calibrate: {msg}", flush=True)) if progress else
        (lambda msg: None))
    if align_mode not in ALIGN:
        raise ValueError(f"align must be one of {ALIGN}, got {align_mode!r}")
    mat_file = material_mod.find(material)
    mat = material_mod.read(mat_file)
    data = Path(data)
    refs = load_references(references, data)
    lattice = positions.read_data(data)["xy"]
    for s, q in refs.items():
        check_units(q, lattice, f"the reference for s = {s:g}")
    levels = list(refs)
    params = fitparams.parse_parameters(parameters, mat, levels, start, bounds)
    if level_start not in ("built", "previous"):
        raise ValueError(f"level_start must be built or previous, not {level_start!r}")
    if level_start == "previous" and any(p.kind == "beta_level" for p in params):
        raise ValueError("a ramp (level_start previous) runs one parameter vector through "
                         "every level: fit beta_a and beta_b, not beta per level")
    workers = max(1, min(int(workers), os.cpu_count() or 1))
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if material_out is None:   # the first free name in the fit's folder
        material_out = out / f"{mat_file.stem}-calibrated.cgms"
        k = 2
        while material_out.exists():
            material_out = out / f"{mat_file.stem}-calibrated-{k}.cgms"
            k += 1
    if material_out and Path(material_out).exists() and not overwrite:
        raise FileExistsError(f"{material_out} exists; choose another material file or allow "
                              "overwriting")
    x_ref, n = mat["x_ref"], len(lattice)
    runner = Runner(out, data, mat_file, pair_args, workers, say,
                    ramp=levels if level_start == "previous" else None)
    lo = np.log([p.lo for p in params])
    hi = np.log([p.hi for p in params])
    trace = []

    def values(u):
        return [p.value(float(x)) for p, x in zip(params, u)]

    def jobs(u):
        v = values(u)
        return [(s, fitparams.overrides(params, v, mat, s)) for s in levels]

    def residual_vectors(records):
        """Scaled residuals: ||r||^2 = mean over levels of (RMSD / x_ref)^2."""
        parts, per_level = [], {}
        for s, rec in zip(levels, records):
            q = refs[s]
            if "error" in rec:
                d = np.full((n, 2), PENALTY * x_ref / math.sqrt(2))
                per_level[s] = math.nan
            else:
                p = np.array(rec["xy"])
                d = align(p, q, align_mode) - q
                per_level[s] = float(np.sqrt(np.mean(np.sum(d * d, axis=1))))
            parts.append(d.ravel() / (x_ref * math.sqrt(n * len(levels))))
        return np.concatenate(parts), per_level

    def fun(u):
        records = runner.get(jobs(u))
        r, per_level = residual_vectors(records)
        if not trace and any("error" in rec for rec in records):
            bad = [f"s = {rec['level']:g}: {rec['error']}" for rec in records if "error" in rec]
            raise RuntimeError("no steady state at the start values (" + "; ".join(bad)
                               + f"); logs in {out / 'runs'}")
        total = float(np.linalg.norm(r)) * x_ref
        trace.append(dict(values=values(u), rmsd=per_level, total=total))
        shown = " ".join(f"{p.name} {v:.6g}" for p, v in zip(params, values(u)))
        each = " ".join(f"s={s:g}: {r_ / x_ref:.3e}" if math.isfinite(r_) else
                        f"s={s:g}: no steady state" for s, r_ in per_level.items())
        say(f"evaluation {len(trace):3d}: {shown} | RMSD/x_ref {each} | steady states "
            f"{runner.new} run" + (f", {runner.reused} from the cache" if runner.earlier else "")
            + f", {time.perf_counter() - t0:.1f} s")
        return r

    jac_count = [0]

    def jac(u):
        jac_count[0] += 1
        base, _ = residual_vectors(runner.get(jobs(u)))
        steps = []
        for k in range(len(params)):
            h = fd_step if u[k] + fd_step <= hi[k] else -fd_step
            steps.append(h)
        points = [u + h * np.eye(len(u))[k] for k, h in enumerate(steps)]
        flat = [key for pt in points for key in jobs(pt)]
        records = runner.get(flat)
        J = np.empty((len(base), len(params)))
        L = len(levels)
        for k, h in enumerate(steps):
            recs = records[k * L:(k + 1) * L]
            if any("error" in r_ for r_ in recs):   # try the other side
                h = -h
                pt = u + h * np.eye(len(u))[k]
                recs = runner.get(jobs(pt))
            if any("error" in r_ for r_ in recs):
                say(f"no steady state on either side of {params[k].name}: its Jacobian column "
                    "is set to zero")
                J[:, k] = 0.0
                continue
            J[:, k] = (residual_vectors(recs)[0] - base) / h
        say(f"Jacobian {jac_count[0]}: {len(points) * L} steady states")
        return J

    u0 = np.zeros(len(params))
    try:
        fit = least_squares(fun, u0, jac=jac, bounds=(lo, hi), method="trf", xtol=xtol,
                            ftol=ftol, gtol=gtol, max_nfev=max_evaluations, x_scale=1.0)
        final = runner.get(jobs(fit.x))   # cached: the minimiser evaluated fit.x
    finally:
        runner.close()
    best = values(fit.x)
    _, per_level = residual_vectors(final)
    first = trace[0]["rmsd"]
    onbound = [p.name for p, x, a, b in zip(params, fit.x, lo, hi)
               if min(x - a, b - x) < 1e-6]
    written = fitparams.fitted_material(params, best, mat, levels)
    # linearised standard errors of ln(value), as if the residuals were independent noise
    # of equal variance: a guide to what the references determine (k_T and k_PA, for
    # one, are strongly correlated: doc/calibration.md)
    J = np.asarray(fit.jac, float)
    dof = max(J.shape[0] - J.shape[1], 1)
    cov = (2 * fit.cost / dof) * np.linalg.pinv(J.T @ J)
    err = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(err, err)
    result = dict(
        parameters={p.name: v for p, v in zip(params, best)},
        factors={p.name: v / p.start for p, v in zip(params, best)},
        start={p.name: p.start for p in params},
        levels=levels, align=align_mode,
        rmsd=per_level, rmsd_start=first,
        rmsd_x_ref={s: r_ / x_ref for s, r_ in per_level.items()},
        moisture={s: rec.get("moisture") for s, rec in zip(levels, final)},
        methods={s: rec.get("method", "failed") for s, rec in zip(levels, final)},
        material=written, on_bound=onbound,
        stderr={p.name: float(e) for p, e in zip(params, err)},
        correlation=[[float(c) for c in row] for row in corr],
        evaluations=int(fit.nfev), jacobians=int(jac_count[0]),
        steady_states=len(runner.used), runs=runner.new,
        reused=runner.reused, fallbacks=len(runner.fallbacks), failures=len(runner.failed),
        status=int(fit.status), message=str(fit.message), success=bool(fit.success),
        x_ref=x_ref, beads=n, data=str(data), material_start=str(mat_file), out=str(out),
        trace=trace)
    result["seconds"] = time.perf_counter() - t0
    if material_out:
        note = (f"fitted {', '.join(p.name for p in params)} to reference centroids at s = "
                f"{', '.join(f'{s:g}' for s in levels)} on the {n}-bead tissue {data.name}; "
                "RMSD (eqn 2, " + align_mode + " removed) "
                + ", ".join(f"{r_:.4g} m ({r_ / x_ref:.3g} x_ref) at s = {s:g}"
                            for s, r_ in per_level.items())
                + f"; {fit.nfev} evaluations, {len(runner.used)} steady states, "
                f"{result['seconds']:.1f} s")
        per = [f"{p.level:g}: {v:.6g}" for p, v in zip(params, best) if p.kind == "beta_level"]
        if per:
            note += ("; beta per level (s: beta) " + ", ".join(per) + ", and beta_a, beta_b "
                     "below from a least-squares line in ln s through them")
        result["material_file"] = str(material_mod.write(material_out, mat_file, written, note,
                                                     overwrite=overwrite))
    else:
        result["material_file"] = None
    folders.write_json(out / "result.json", _jsonable(result))
    return result


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k) if not isinstance(k, str) else k: _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    return obj
