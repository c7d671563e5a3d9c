"""Calibration: fit CGMS material parameters to reference cell-centroid positions.

The paper (section 2.3) calibrates k_T, k_PA and beta on the 86-bead tissue: at each
dryness level the steady-state bead positions ``p_i`` are compared with the cell
centroids ``q_i`` of a reference (there: the MFC model) by eqn (2),

    RMSD = ( 1/n_r  sum_i |p_i - q_i|^2 )^(1/2)

(``|.|`` the Euclidean distance in the plane, ``n_r`` the number of beads), and the
parameters minimise it. Here:

- **references**: one per dryness level, an ``id x y`` text file (metres) or a LAMMPS
  dump (its last frame); beads are matched to centroids by atom id, and a reference with
  another bead count or other ids is rejected with a ValueError naming the ids;
- **steady states**: :func:`cgms.study.relax` with the quasi-static solve (FIRE); where it
  stops or does not converge, the dynamics at dt = 5e-8 s (as :mod:`cgms.sensitivity`);
  each run writes into its own folder under ``<out>/runs``;
- **rigid motion**: the steady state is defined only up to a rigid motion, so the
  simulated positions are first moved onto the reference by the best translation
  (``align="translation"``, default) or translation and rotation (``"rigid"``); the RMSD
  is then the minimum of eqn (2) over those motions (``"none"``: eqn (2) as written);
- **parameters** (``parameters=``): material names (``k_T``, ``k_PA``, any other name of the
  material file), ``beta`` (one factor on beta(s), i.e. on beta_a and beta_b),
  ``beta_a``/``beta_b`` (the coefficients of beta(s) = beta_a + beta_b ln s), or
  ``beta@<s>`` / ``beta@*`` (a separate beta at one / every level; the law a + b ln s is then
  fitted through them for the material file). Each is searched as ``ln(value / start)``
  between bounds (a factor 0.05-20 of the start; 0.8-1.15 for beta, about the range in
  which the 86-bead tissue keeps a steady state);
- **minimiser**: eqn (2) is a root mean square of residuals, so the fit minimises the mean
  over levels of RMSD^2 as a bounded nonlinear least-squares problem
  (:func:`scipy.optimize.least_squares`, trust-region reflective) with a forward-difference
  Jacobian whose columns (one steady state per parameter and level) run in parallel;
- **resume**: every steady state (parameter overrides, level -> positions, X/X0, method) is
  appended to ``<out>/evaluations.jsonl``; a rerun in the same folder reads them back, the
  deterministic minimiser retraces its path through them and continues where it stopped;
- **output**: fitted values, RMSD per level, evaluation counts, wall time
  (``<out>/result.json``) and a material file in the format of ``potentials/``.

Command line: ``python3 -m cgms.calibrate --help`` (and ``python3 -m cgms calibrate``).
Method and measured results: ``doc/calibration.md``.
"""

import argparse
import hashlib
import json
import math
import os
import sys
import time
from datetime import date
from pathlib import Path

import numpy as np

from . import material as material_mod

#: default search interval (factors of the start value) for each kind of parameter
BOUNDS = (0.05, 20.0)
BETA_BOUNDS = (0.8, 1.15)
#: forward-difference step in ln(value): large against the FIRE noise of the steady state
#: (about 2e-7 x_ref on positions), small against the curvature
FD_STEP = 1e-3
#: RMSD (in x_ref) given to a level without a steady state, so that the minimiser backs off
PENALTY = 1.0
#: fallback when the quasi-static solve fails (cgms.sensitivity does the same)
FALLBACK = dict(method="dynamics", dt=5e-8, steady=dict(max_steps=4000000))
ALIGN = ("translation", "rigid", "none")
CACHE = "evaluations.jsonl"
SETUP = "setup.json"
DERIVED = ("A_ref", "b_ref", "l_ref", "x_ref")


# --------------------------------------------------------------------------- references

def tissue_ids(data):
    """Atom ids of a LAMMPS data file (its Atoms section), sorted."""
    lines = Path(data).read_text().splitlines()
    start = next((k for k, line in enumerate(lines)
                  if line.split("#", 1)[0].strip() == "Atoms"), None)
    if start is None:
        raise ValueError(f"{data}: no Atoms section")
    ids, k = [], start + 1
    while k < len(lines) and not lines[k].strip():
        k += 1
    while k < len(lines) and lines[k].split("#", 1)[0].strip():
        ids.append(int(lines[k].split()[0]))
        k += 1
    return np.sort(np.array(ids, dtype=np.int64))


def read_centroids(path):
    """``(ids, xy)`` of a reference: a LAMMPS dump (last frame; any dump the
    :func:`cgms.morphology.read_dump` parser reads) or a text file with one ``id x y`` line
    per cell (metres; ``#`` comments, blank lines and a first header line such as
    ``id x y`` are skipped; further columns are ignored)."""
    path = Path(path)
    text = path.read_text()
    first = next((line.strip() for line in text.splitlines() if line.strip()), "")
    if first.startswith("ITEM:"):
        from . import morphology
        frame = morphology.read_dump(path, engine="numpy")[-1]
        return frame["ids"], frame["xy"]
    ids, xy, seen = [], [], False
    for lineno, raw in enumerate(text.splitlines(), 1):
        words = raw.split("#", 1)[0].replace(",", " ").split()
        if not words:
            continue
        if not seen and not _is_number(words[0]):
            seen = True   # a header line (id x y)
            continue
        seen = True
        if len(words) < 3:
            raise ValueError(f"{path} line {lineno}: expected 'id x y', got {raw.strip()!r}")
        try:
            ident = int(words[0])
            x, y = float(words[1]), float(words[2])
        except ValueError:
            raise ValueError(f"{path} line {lineno}: expected an integer id and two numbers, "
                             f"got {raw.strip()!r}") from None
        ids.append(ident)
        xy.append((x, y))
    if not ids:
        raise ValueError(f"{path}: no 'id x y' lines")
    return np.array(ids, dtype=np.int64), np.array(xy, dtype=float)


def _is_number(word):
    try:
        float(word)
        return True
    except ValueError:
        return False


def write_centroids(path, xy, ids=None, comment="", overwrite=False):
    """Write positions (metres) as an ``id x y`` reference file (ids 1..n by default)."""
    xy = np.asarray(xy, float)
    ids = np.arange(1, len(xy) + 1) if ids is None else np.asarray(ids, int)
    lines = [f"# {line}" for line in comment.splitlines()] + ["# id x y (m)"]
    lines += [f"{i} {x!r} {y!r}" for i, (x, y) in zip(ids, xy)]
    with open(path, "w" if overwrite else "x") as fh:
        fh.write("\n".join(lines) + "\n")
    return Path(path)


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
    expected = tissue_ids(data)
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
            ids, xy = read_centroids(source)
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


def _check_units(ref, lattice, what):
    """Reject references whose size is far from the tissue's (not in metres?)."""
    size = lambda p: math.sqrt(((p - p.mean(axis=0)) ** 2).sum(axis=1).mean())  # noqa: E731
    ratio = size(ref) / size(lattice)
    if not 0.2 < ratio < 5:
        raise ValueError(f"{what} spans {ratio:.3g} times the tissue's size: positions must "
                         "be in metres and belong to this tissue")


def data_positions(data):
    """Positions of a data file's Atoms section, ordered by id."""
    lines = Path(data).read_text().splitlines()
    start = next(k for k, line in enumerate(lines) if line.split("#", 1)[0].strip() == "Atoms")
    rows, k = [], start + 1
    while k < len(lines) and not lines[k].strip():
        k += 1
    while k < len(lines) and lines[k].split("#", 1)[0].strip():
        w = lines[k].split()
        rows.append((int(w[0]), float(w[2]), float(w[3])))
        k += 1
    rows.sort()
    return np.array([r[1:] for r in rows])


# --------------------------------------------------------------------------- eqn (2)

def align(p, q, mode="translation"):
    """``p`` moved rigidly onto ``q`` by the motion that minimises eqn (2): the centroid
    shift (``"translation"``), that and the best rotation (``"rigid"``, 2-D Kabsch), or
    nothing (``"none"``)."""
    if mode not in ALIGN:
        raise ValueError(f"align must be one of {ALIGN}, got {mode!r}")
    p = np.asarray(p, float)
    q = np.asarray(q, float)
    if mode == "none":
        return p
    pc, qc = p - p.mean(axis=0), q.mean(axis=0)
    if mode == "rigid":
        qq = q - qc
        angle = math.atan2(np.sum(pc[:, 0] * qq[:, 1] - pc[:, 1] * qq[:, 0]),
                           np.sum(pc * qq))
        c, s = math.cos(angle), math.sin(angle)
        pc = pc @ np.array([[c, s], [-s, c]])
    return pc + qc


def rmsd(p, q, mode="translation"):
    """Eqn (2): root mean square over beads of the distance between the simulated position
    ``p_i`` (after :func:`align`) and the reference centroid ``q_i``."""
    d = align(p, q, mode) - np.asarray(q, float)
    return float(np.sqrt(np.mean(np.sum(d * d, axis=1))))


# --------------------------------------------------------------------------- parameters

class Parameter:
    """One fitted quantity, searched as u = ln(value / start) in [ln lo, ln hi]."""

    def __init__(self, name, kind, start, lo, hi, level=None):
        self.name, self.kind, self.start, self.level = name, kind, float(start), level
        self.lo, self.hi = float(lo), float(hi)

    def value(self, u):
        return self.start * math.exp(u)

    def __repr__(self):
        return f"Parameter({self.name!r}, start={self.start!r})"


def parse_parameters(names, mat, levels, start=None, bounds=None):
    """Parameter objects for ``names`` (see the module doc). ``start``: {name: value}
    (default: the material's value, for ``beta`` the factor 1); ``bounds``: {name: (lo, hi)}
    as factors of the start value."""
    start, bounds = dict(start or {}), dict(bounds or {})
    levels = [float(s) for s in levels]
    names = [n.strip() for n in ([names] if isinstance(names, str) else names) if n.strip()]
    if not names:
        raise ValueError("no parameter to fit")
    expanded = []
    for n in names:
        if n == "beta@*":
            expanded += [f"beta@{s:g}" for s in levels]
        else:
            expanded.append(n)
    if len(set(expanded)) != len(expanded):
        raise ValueError(f"a parameter is named twice in {names}")
    has = set(expanded)
    per_level = [n for n in expanded if n.startswith("beta@")]
    if "beta" in has and (has & {"beta_a", "beta_b"} or per_level):
        raise ValueError("'beta' scales beta_a and beta_b together: do not fit it with "
                         "beta_a, beta_b or beta@<s>")
    if per_level and has & {"beta_a", "beta_b"}:
        raise ValueError("beta@<s> sets beta at a level directly: do not fit it with beta_a "
                         "or beta_b")
    known = [k for k in mat if k not in DERIVED]
    params = []
    for n in expanded:
        level = None
        if n == "beta":
            kind, default = "beta", 1.0
        elif n.startswith("beta@"):
            try:
                level = float(n[5:])
            except ValueError:
                raise ValueError(f"{n!r}: expected beta@<dryness level> or beta@*") from None
            match_ = [s for s in levels if abs(s - level) < 1e-9]
            if not match_:
                raise ValueError(f"{n!r}: no reference at s = {level:g} (levels "
                                 f"{', '.join(f'{s:g}' for s in levels)})")
            level = match_[0]
            kind, default = "beta_level", mat["beta_a"] + mat["beta_b"] * math.log(level)
            n = f"beta@{level:g}"
        elif n in known:
            kind, default = "material", mat[n]
        else:
            raise ValueError(f"unknown parameter {n!r}: fit one of beta, beta_a, beta_b, "
                             f"beta@<s>, beta@*, {', '.join(known)}")
        value = float(start.pop(n, default))
        if not (math.isfinite(value) and value != 0):
            raise ValueError(f"{n}: the start value must be finite and non-zero (the search "
                             f"runs in ln(value / start)), got {value!r}")
        lo, hi = bounds.pop(n, BETA_BOUNDS if n.startswith("beta") else BOUNDS)
        if not 0 < lo <= 1 <= hi or lo == hi:
            raise ValueError(f"{n}: bounds must be factors lo <= 1 <= hi with lo > 0 and "
                             f"lo < hi, got {lo!r}, {hi!r}")
        params.append(Parameter(n, kind, value, lo, hi, level))
    for left, what in ((start, "start"), (bounds, "bounds")):
        if left:
            raise ValueError(f"{what} given for parameter(s) not fitted: {', '.join(left)}")
    return params


def overrides(params, values, mat, level):
    """The pair_coeff ``name value`` overrides of one run at ``level``."""
    words = []
    for p, v in zip(params, values):
        if p.kind == "beta":
            words += [f"beta_a {mat['beta_a'] * v!r}", f"beta_b {mat['beta_b'] * v!r}"]
        elif p.kind == "beta_level":
            if p.level == level:   # beta constant = v at this level
                words += [f"beta_a {v!r}", "beta_b 0.0"]
        else:
            words.append(f"{p.name} {v!r}")
    return " ".join(words)


def fitted_material(params, values, mat, levels):
    """Material-file values that the fitted parameters stand for: ``{name: value}``.
    Per-level betas become beta_a, beta_b of the law a + b ln s (least squares through the
    levels; with one level, beta_b is kept and beta_a moved)."""
    out = {}
    betas = []
    for p, v in zip(params, values):
        if p.kind == "beta":
            out["beta_a"], out["beta_b"] = mat["beta_a"] * v, mat["beta_b"] * v
        elif p.kind == "beta_level":
            betas.append((p.level, v))
        else:
            out[p.name] = v
    if len(betas) == 1:
        s, v = betas[0]
        out["beta_a"], out["beta_b"] = v - mat["beta_b"] * math.log(s), mat["beta_b"]
    elif betas:
        x = np.log([s for s, _ in betas])
        A = np.column_stack([np.ones_like(x), x])
        (a, b), *_ = np.linalg.lstsq(A, np.array([v for _, v in betas]), rcond=None)
        out["beta_a"], out["beta_b"] = float(a), float(b)
    return out


# --------------------------------------------------------------------------- runs

def _run_level(job):
    """One steady state (runs in a worker process): the quasi-static solve, and the
    dynamics at dt = 5e-8 s if it stops or does not converge. Returns a JSON-able record."""
    from . import study

    t0 = time.perf_counter()
    rec = dict(level=job["level"], overrides=job["overrides"], folder=job["folder"])
    kwargs = dict(overrides=job["overrides"], pair_args=job["pair_args"],
                  diameters=job.get("diameters", False))
    result = None
    try:
        result = study.relax(job["data"], job["material"], job["level"], job["folder"],
                             method="quasistatic", **kwargs)
        if not result["converged"]:
            rec["note"] = "FIRE reached its iteration limit"
            result = None
    except RuntimeError as err:
        rec["note"] = str(err).split("LAMMPS stopped: ")[-1].split(" (log")[0]
    if result is None:
        try:
            result = study.relax(job["data"], job["material"], job["level"],
                                 Path(job["folder"]) / "dynamics", **FALLBACK, **kwargs)
        except RuntimeError as err:
            rec["error"] = str(err).split("LAMMPS stopped: ")[-1].split(" (log")[0]
    if result is not None:
        rec.update(method=result["method"], converged=bool(result["converged"]),
                   steps=int(result["steps"]), moisture=float(result["moisture"]),
                   residual=float(result["residual"]), xy=result["xy"].tolist())
    rec["seconds"] = time.perf_counter() - t0
    return rec


def _serve():
    """Worker process loop: one JSON job per line on stdin, one JSON record per line on the
    original stdout (anything else written to stdout goes to stderr)."""
    answer = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    try:
        for line in sys.stdin:
            job = json.loads(line)
            try:
                rec = _run_level(job)
            except Exception as err:  # noqa: BLE001 - reported, the fit goes on
                rec = dict(level=job["level"], overrides=job["overrides"],
                           folder=job["folder"], error=f"{type(err).__name__}: {err}")
            answer.write(json.dumps(rec) + "\n")
            answer.flush()
    except (KeyboardInterrupt, BrokenPipeError):   # Ctrl-C reaches the workers too
        sys.exit(130)


class _Workers:
    """``n`` long-lived worker processes (``python3 -c 'cgms.calibrate._serve()'``), each
    opening its own LAMMPS for every steady state, fed by one thread each.

    Why not multiprocessing: LAMMPS is linked with MPI, so forking a parent that has
    already run LAMMPS is unsafe, and the spawn start method re-imports the caller's main
    script (a script without an ``if __name__ == "__main__"`` guard would start the fit
    again in every worker). A plain subprocess has neither problem."""

    def __init__(self, n):
        import threading
        from concurrent.futures import ThreadPoolExecutor
        self.n, self.procs, self.local = n, [], threading.local()
        self.lock = threading.Lock()
        self.threads = ThreadPoolExecutor(n, thread_name_prefix="cgms-calibrate")

    def _proc(self):
        import subprocess
        proc = getattr(self.local, "proc", None)
        if proc is None or proc.poll() is not None:
            env = dict(os.environ, PYTHONPATH=os.pathsep.join(
                [str(Path(__file__).resolve().parents[1])] + [p for p in sys.path if p]),
                OMP_NUM_THREADS="1")
            proc = subprocess.Popen([sys.executable, "-c",
                                     "from cgms.calibrate import _serve; _serve()"],
                                    stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                    env=env)
            self.local.proc = proc
            with self.lock:
                self.procs.append(proc)
        return proc

    def _one(self, job):
        proc = self._proc()
        try:
            proc.stdin.write(json.dumps(job) + "\n")
            proc.stdin.flush()
            line = proc.stdout.readline()
        except (BrokenPipeError, OSError):
            line = ""
        if not line:
            code = proc.wait()
            return dict(level=job["level"], overrides=job["overrides"], folder=job["folder"],
                        error=f"worker process died (exit status {code})")
        return json.loads(line)

    def run(self, jobs):
        """Records of ``jobs``, yielded as they finish."""
        from concurrent.futures import as_completed
        futures = [self.threads.submit(self._one, job) for job in jobs]
        try:
            for fut in as_completed(futures):
                yield fut.result()
        finally:
            for fut in futures:
                fut.cancel()

    def close(self):
        self.threads.shutdown(wait=False, cancel_futures=True)
        with self.lock:
            procs, self.procs = self.procs, []
        for proc in procs:
            if proc.poll() is None:
                try:
                    proc.stdin.close()
                except OSError:
                    pass
        for proc in procs:
            try:
                proc.wait(timeout=10)
            except Exception:  # noqa: BLE001 - still running: stop it
                proc.kill()
                proc.wait()


def _sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


class _Runner:
    """Steady states for parameter vectors: from the cache, or run (in parallel) and
    appended to it."""

    def __init__(self, out, data, material, pair_args, workers, say):
        self.out, self.data, self.material = Path(out), str(data), str(material)
        self.pair_args, self.workers, self.say = pair_args, max(1, int(workers)), say
        # a data file with a Diameters section (heterogeneous tissue) is read with it
        self.diameters = any(line.strip() == "Diameters"
                             for line in Path(data).read_text().splitlines())
        self.cache_path = self.out / CACHE
        self.cache, self.pool = {}, None
        self.new = 0
        self.used, self.earlier = set(), set()   # keys used; keys read from an earlier session
        self.failed, self.fallbacks = set(), set()
        setup = dict(data_sha256=_sha256(data), material_sha256=_sha256(material),
                     pair_args=pair_args, fallback=FALLBACK)
        setup_path = self.out / SETUP
        if setup_path.exists():
            old = json.loads(setup_path.read_text())
            if old != setup:
                diff = [k for k in setup if old.get(k) != setup[k]]
                raise ValueError(f"{self.out} holds evaluations of another setup (different "
                                 f"{', '.join(diff)}); choose another output folder")
        else:
            setup_path.write_text(json.dumps(setup, indent=1) + "\n")
        if self.cache_path.exists():
            bad = 0
            text = self.cache_path.read_text()
            if text and not text.endswith("\n"):   # cut short: new lines start afresh
                with open(self.cache_path, "a") as fh:
                    fh.write("\n")
            for line in text.splitlines():
                try:
                    rec = json.loads(line)
                    self.cache[(rec["level"], rec["overrides"])] = rec
                except (ValueError, KeyError):
                    bad += 1   # a line cut short by an interruption
            self.earlier = set(self.cache)
            if self.cache:
                say(f"resuming: {len(self.cache)} steady states read from {self.cache_path}"
                    + (f" ({bad} incomplete line(s) ignored)" if bad else ""))

    def folder(self, over):
        tag = hashlib.sha1(over.encode()).hexdigest()[:12] if over else "start"
        return str(self.out / "runs" / tag)

    def get(self, jobs):
        """Records for a list of (level, overrides), running what is not cached."""
        todo = {}
        for key in jobs:
            if key in self.cache:
                continue
            todo.setdefault(key, dict(data=self.data, material=self.material, level=key[0],
                                      overrides=key[1], folder=self.folder(key[1]),
                                      pair_args=self.pair_args, diameters=self.diameters))
        self.used.update(jobs)
        if todo:
            if self.pool is None:
                self.pool = _Workers(self.workers)
            with open(self.cache_path, "a") as fh:
                for rec in self.pool.run(list(todo.values())):
                    fh.write(json.dumps(rec) + "\n")
                    fh.flush()
                    self.cache[(rec["level"], rec["overrides"])] = rec
                    self.new += 1
        out = []
        for key in jobs:
            rec = self.cache[key]
            if "error" in rec:
                self.failed.add(key)
            elif rec.get("method") == "dynamics":
                self.fallbacks.add(key)
            out.append(rec)
        return out

    @property
    def reused(self):
        """Distinct steady states taken from an earlier session's cache."""
        return len(self.used & self.earlier)

    def close(self):
        if self.pool is not None:
            self.pool.close()
            self.pool = None


# --------------------------------------------------------------------------- the fit

def calibrate(data, material, references, out, parameters=("k_T", "k_PA", "beta"),
              start=None, bounds=None, align_mode="translation", workers=2,
              max_evaluations=60, xtol=1e-4, ftol=1e-10, gtol=1e-10, fd_step=FD_STEP,
              pair_args="", material_out=None, overwrite=False, progress=True):
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
    taking the line).

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
    lattice = data_positions(data)
    for s, q in refs.items():
        _check_units(q, lattice, f"the reference for s = {s:g}")
    levels = list(refs)
    params = parse_parameters(parameters, mat, levels, start, bounds)
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
    runner = _Runner(out, data, mat_file, pair_args, workers, say)
    lo = np.log([p.lo for p in params])
    hi = np.log([p.hi for p in params])
    trace = []

    def values(u):
        return [p.value(float(x)) for p, x in zip(params, u)]

    def jobs(u):
        v = values(u)
        return [(s, overrides(params, v, mat, s)) for s in levels]

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
    written = fitted_material(params, best, mat, levels)
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
        result["material_file"] = str(write_material(material_out, mat_file, written, note,
                                                     overwrite=overwrite))
    else:
        result["material_file"] = None
    (out / "result.json").write_text(json.dumps(_jsonable(result), indent=1) + "\n")
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


# --------------------------------------------------------------------------- material file

def write_material(path, source, values, note="", overwrite=False):
    """A new material file: ``source`` (a file of ``potentials/``) with ``values``
    ({name: value}) replacing its own, marked as fitted, under a header saying how it was
    made. Names absent from ``source`` are appended. An existing ``path`` is kept unless
    ``overwrite`` (FileExistsError)."""
    source = material_mod.find(source)
    lines = source.read_text().splitlines()
    old = material_mod.read(source)
    left = dict(values)
    body = []
    for raw in lines:
        if raw.startswith("# DATE:"):
            body.append("# (start file header) " + raw[2:])
            continue
        words = raw.split("#", 1)[0].split()
        if len(words) == 2 and words[0] in left:
            name = words[0]
            v = left.pop(name)
            comment = raw.split("#", 1)[1].strip() if "#" in raw else ""
            width = max(len(name), 13)
            body.append(f"{name:<{width}} {v!r:<9} # fitted (start {old[name]:.6g})"
                        + (f"; {comment}" if comment else ""))
        else:
            body.append(raw)
    for name, v in left.items():
        body.append(f"{name:<13} {v!r:<9} # fitted (not in {source.name})")
    header = [f"# DATE: {date.today().isoformat()} UNITS: si CONTRIBUTOR: cgms calibrate",
              f"# Calibrated by cgms.calibrate from {source.name}:"]
    words, line = note.split(), "#"
    for w in words:
        if len(line) + len(w) + 1 > 92:
            header.append(line)
            line = "#"
        line += " " + w
    if words:
        header.append(line)
    text = "\n".join(header + body) + "\n"
    try:
        with open(path, "w" if overwrite else "x") as fh:
            fh.write(text)
    except FileExistsError:
        raise FileExistsError(f"{os.fspath(path)} exists; pass overwrite=True (--force) to "
                              "replace it") from None
    check = material_mod.read(path)
    for name, v in values.items():
        if check[name] != v:
            raise RuntimeError(f"{path}: {name} reads back as {check[name]!r}, not {v!r}")
    return Path(path)


# --------------------------------------------------------------------------- command line

def _pairs(text, what, convert):
    out = {}
    for item in text or []:
        for word in item.split(","):
            if not word.strip():
                continue
            if "=" not in word:
                raise ValueError(f"{what}: expected name=value, got {word!r}")
            k, v = word.split("=", 1)
            out[k.strip()] = convert(v.strip())
    return out


def _bounds(v):
    lo, hi = v.split(":")
    return float(lo), float(hi)


def parse_references(items):
    """``["1=ref1.txt", "0.3=run.dump"]`` -> ``{1.0: "ref1.txt", 0.3: "run.dump"}``."""
    refs = {}
    for item in items or []:
        if "=" not in item:
            raise ValueError(f"--reference: expected LEVEL=FILE, got {item!r}")
        level, path = item.split("=", 1)
        try:
            s = float(level)
        except ValueError:
            raise ValueError(f"--reference {item!r}: the level must be a number") from None
        if s in refs:
            raise ValueError(f"--reference: two files for s = {s:g}")
        refs[s] = path
    return refs


def add_arguments(p):
    """The options of the calibrate command (shared by ``python3 -m cgms calibrate`` and
    ``python3 -m cgms.calibrate``)."""
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
    p.add_argument("--data", help="tissue data file (default: build --width x --height)")
    p.add_argument("--width", type=float, default=1.25,
                   help="tissue width, mm, when no --data (default 1.25: the 86-bead tissue)")
    p.add_argument("--height", type=float, default=1.5, help="tissue height, mm (default 1.5)")
    p.add_argument("--start", action="append", metavar="NAME=VALUE",
                   help="start value (default: the material's; beta: factor 1)")
    p.add_argument("--bounds", action="append", metavar="NAME=LO:HI",
                   help=f"search interval as factors of the start (default {BOUNDS[0]:g}:"
                        f"{BOUNDS[1]:g}, beta {BETA_BOUNDS[0]:g}:{BETA_BOUNDS[1]:g})")
    p.add_argument("--align", choices=ALIGN, default="translation",
                   help="rigid motion removed before eqn (2) (default translation)")
    p.add_argument("--workers", type=int, default=2,
                   help="processes for independent steady states (default 2)")
    p.add_argument("--max-evaluations", type=int, default=60,
                   help="limit on residual evaluations of the minimiser (default 60)")
    p.add_argument("--write-material", metavar="FILE",
                   help="fitted material file (default <out>/<material>-calibrated.cgms)")
    p.add_argument("--force", action="store_true", help="replace an existing --write-material")


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


def job(args):
    """Run the calibrate command from parsed ``args`` (see :func:`add_arguments`)."""
    from . import cli

    try:
        refs = parse_references(args.reference)
        start = _pairs(args.start, "--start", float)
        bounds = _pairs(args.bounds, "--bounds", _bounds)
    except ValueError as err:
        print(f"cgms calibrate: {err}", file=sys.stderr)
        return 2
    out = Path(args.out) if (args.resume and args.out) else cli.new_folder(args.out, "calibrate")
    mat_file = material_mod.find(args.material)
    if args.data:
        data = Path(args.data)
    else:
        data = cli.build(out, args.width, args.height, material_mod.read(mat_file))["data"]
    print(f"cgms calibrate: fitting {args.fit} on {data} ({len(tissue_ids(data))} beads), "
          f"levels {', '.join(f'{s:g}' for s in sorted(refs, reverse=True))}; results in {out}",
          flush=True)
    try:
        result = calibrate(data, mat_file, refs, out, parameters=args.fit.split(","),
                           start=start, bounds=bounds, align_mode=args.align,
                           workers=args.workers, max_evaluations=args.max_evaluations,
                           material_out=args.write_material, overwrite=args.force)
    except KeyboardInterrupt:
        print(f"\ncgms calibrate: interrupted; the finished steady states are kept in "
              f"{out / CACHE}: rerun with --out {out} --resume to continue", file=sys.stderr)
        return 130
    except (ValueError, FileExistsError) as err:
        print(f"cgms calibrate: {err}", file=sys.stderr)
        return 1
    print_report(result)
    print(f"  results: {out}/result.json; runs (dumps, logs): {out}/runs")
    return 0


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m cgms.calibrate",
                                description="Fit CGMS material parameters to reference "
                                            "centroid positions by eqn (2) of the paper.")
    add_arguments(p)
    return job(p.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
