# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states for a calibration, run in parallel and cached: each parameter vector and
level is one :func:`cgms.study.relax_or_fallback` in a worker process (along a drying ramp,
``level_start="previous"``: all levels of a parameter vector in one worker, each from the
previous level's steady state); every record is appended to ``<out>/evaluations.jsonl`` so
that a rerun in the same folder reads it back."""

import hashlib
import json
import os
import sys
import time
from pathlib import Path

from . import folders, positions, study

CACHE = "evaluations.jsonl"
SETUP = "setup.json"


def run_level(job, start_dump=None):
    """One steady state (runs in a worker process): :func:`cgms.study.relax_or_fallback`,
    from the built tissue or from ``start_dump``. Returns a JSON-able record (``error``:
    LAMMPS's message where no steady state was found; ``note``: why the fallback ran) and
    the final dump (None without a steady state)."""
    t0 = time.perf_counter()
    rec = dict(level=job["level"], overrides=job["overrides"], folder=job["folder"])
    dump = None
    try:
        result, note = study.relax_or_fallback(
            job["data"], job["material"], job["level"], job["folder"],
            overrides=job["overrides"], pair_args=job["pair_args"],
            diameters=job.get("diameters", False), start_dump=start_dump)
        if note:
            rec["note"] = note
        rec.update(method=result["method"], converged=bool(result["converged"]),
                   steps=int(result["steps"]), moisture=float(result["moisture"]),
                   residual=float(result["residual"]), xy=result["xy"].tolist())
        dump = study.dump_file(job["folder"], dict(result, fallback=note))
    except study.LammpsError as err:
        rec["error"] = err.reason
    rec["seconds"] = time.perf_counter() - t0
    return rec, dump


def run_ramp(job):
    """The steady states of one parameter vector at ``job["levels"]`` (wettest first), each
    level from the previous level's steady state (:func:`cgms.study.sweep`'s start
    previous). A level after one without a converged steady state gets an ``error``."""
    records, dump = [], None
    for k, s in enumerate(job["levels"]):
        one = dict(job, level=s)
        if k and dump is None:
            before = job["levels"][k - 1]
            records.append(dict(level=s, overrides=job["overrides"], folder=job["folder"],
                                error=f"no converged steady state at s = {before:g} to start "
                                      "from (start previous)"))
            continue
        rec, dump = run_level(one, start_dump=dump)
        if not rec.get("converged"):
            dump = None
        records.append(rec)
    return records


def serve():
    """Worker process loop: one JSON job per line on stdin, one JSON record per line on the
    original stdout (anything else written to stdout goes to stderr)."""
    answer = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    try:
        for line in sys.stdin:
            job = json.loads(line)
            try:
                rec = run_ramp(job) if "levels" in job else run_level(job)[0]
            except Exception as err:  # noqa: BLE001 - reported, the fit goes on
                rec = [dict(level=s, overrides=job["overrides"], folder=job["folder"],
                            error=f"{type(err).__name__}: {err}")
                       for s in job.get("levels", [job.get("level")])]
            answer.write(json.dumps(rec) + "\n")
            answer.flush()
    except (KeyboardInterrupt, BrokenPipeError):   # Ctrl-C reaches the workers too
        sys.exit(130)


class Workers:
    """``n`` long-lived worker processes (``python3 -c 'cgms.pool.serve()'``), each
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
                                     "from cgms.pool import serve; serve()"],
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
            return [dict(level=s, overrides=job["overrides"], folder=job["folder"],
                         error=f"worker process died (exit status {code})")
                    for s in job.get("levels", [job.get("level")])]
        return json.loads(line)

    def run(self, jobs):
        """Records of ``jobs``, yielded as they finish (a ramp job's one by one)."""
        from concurrent.futures import as_completed
        futures = [self.threads.submit(self._one, job) for job in jobs]
        try:
            for fut in as_completed(futures):
                got = fut.result()
                yield from (got if isinstance(got, list) else [got])
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


class Runner:
    """Steady states for parameter vectors: from the cache, or run (in parallel) and
    appended to it."""

    def __init__(self, out, data, material, pair_args, workers, say, ramp=None):
        """``ramp``: the levels (any order) of a drying ramp, each run from the previous
        level's steady state (:func:`run_ramp`); None: every level from the built tissue."""
        self.ramp = sorted(ramp, reverse=True) if ramp else None
        self.out, self.data, self.material = Path(out), str(data), str(material)
        self.pair_args, self.workers, self.say = pair_args, max(1, int(workers)), say
        # a data file with a Diameters section (heterogeneous tissue) is read with it
        self.diameters = positions.read_data(data)["diameters"] is not None
        self.cache_path = self.out / CACHE
        self.cache, self.pool = {}, None
        self.new = 0
        self.used, self.earlier = set(), set()   # keys used; keys read from an earlier session
        self.failed, self.fallbacks = set(), set()
        setup = dict(data_sha256=study.sha256(data), material_sha256=study.sha256(material),
                     pair_args=pair_args, fallback=study.FALLBACK)
        if self.ramp:   # only then: folders of before read the same
            setup["ramp"] = self.ramp
        folders.same_setup(self.out / SETUP, setup)
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
        if todo and self.ramp:
            todo = self._ramps(todo)
        if todo:
            if self.pool is None:
                self.pool = Workers(self.workers)
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

    def _ramps(self, todo):
        """One job per parameter vector of ``todo``: its whole ramp (every level is run
        again, so each starts from the previous one's dump of this run)."""
        ramps = {}
        for (s, over), job in todo.items():
            if s not in self.ramp:
                raise ValueError(f"s = {s:g} is not a level of this ramp ({self.ramp})")
            ramps.setdefault(over, dict(job, levels=self.ramp)).pop("level", None)
        return {over: job for over, job in ramps.items()}

    @property
    def reused(self):
        """Distinct steady states taken from an earlier session's cache."""
        return len(self.used & self.earlier)

    def close(self):
        if self.pool is not None:
            self.pool.close()
            self.pool = None
