# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Steady states over moisture levels (the paper's moisture-domain approach, section 2.4),
their morphology, and the initial dryness that lands on a requested moisture.

Each level is one LAMMPS run to steady state, from the built tissue (the paper's way) or,
along a drying ramp, from the previous (wetter) level's steady state. Results go to a folder,
one ``level.s<s>.json`` (+ ``.npy`` positions) per level, each written whole or not at all,
so an interrupted sweep resumes without redoing finished levels; ``sweep.json`` records what
defines the results (tissue, material, method, options), and a resume with another setup
is refused rather than mixed. Nothing existing is overwritten."""

import hashlib
import re
import time
from pathlib import Path

import numpy as np

from . import folders, material as material_file, model, morphology, run

LEVELS = (1.0, 0.8, 0.6, 0.4, 0.3)
#: a steady state at rest for the dynamics (steady=dict(rest=REST), cgms.run.rest_test):
#: what is left of the fastest bead's path (its speed times the decay time of that speed)
#: below 0.3 um. Not the fallback's default: on apple-mfc it costs 1.3x the steps and
#: lowers A/A0 by 0.2-0.4 %, but on shear-soft materials (the paper's apple) the lattice
#: creeps with tau ~ 0.1 s and a level takes the whole 4e6-step cap (doc/results/performance.md)
REST = 3e-7
#: the fallback when the quasi-static solve stops or does not converge: the dynamics at
#: half the paper's time step (extreme settings crowd beads to 8 neighbours; dt = 5e-8 s
#: keeps the damping inside its stability limit)
FALLBACK = dict(method="dynamics", dt=5e-8, steady=dict(max_steps=4000000))
#: the sub-folder of a level's folder that holds the fallback's log and dump
FALLBACK_FOLDER = "dynamics"
#: the values of :func:`sweep`'s ``fallback``: what follows where the quasi-static solve stops
FALLBACKS = ("dynamics",)
#: the values of :func:`sweep`'s ``start``: every level from the built tissue (the paper's
#: moisture-domain approach), or each from the previous level's steady state (a drying
#: ramp, as the MFC references are made: cgms.mfc.run.ramp)
STARTS = ("built", "previous")


class RampError(RuntimeError):
    """A level of a ramp (``start="previous"``) that has no steady state to start from."""


class LammpsError(RuntimeError):
    """A LAMMPS run that stopped: ``reason`` is LAMMPS's whole ERROR message, ``log`` the
    log file, ``dryness`` the level; ``first``: where the dynamics of a fallback stopped,
    why the quasi-static solve before it stopped ("" otherwise)."""

    def __init__(self, dryness, reason, log, first=""):
        self.dryness, self.reason, self.log, self.first = dryness, reason, log, first
        before = f" (after the quasi-static solve stopped: {first})" if first else ""
        super().__init__(f"s = {dryness:g}: LAMMPS stopped: {reason}{before} (log: {log})")


def level_name(s):
    """``s<s>``: the shortest decimal that reads back as ``s`` when ``%g`` does not
    (0.3 -> s0.3, 0.30000001 -> s0.30000001), so distinct levels never share a file."""
    short = f"{s:g}"
    return f"s{short}" if float(short) == s else f"s{float(s)!r}"


def lammps_reason(err, log):
    """LAMMPS's whole ERROR line from the log (the Python module cuts it at about 100
    characters), else the exception's text."""
    try:
        lines = Path(log).read_text(errors="replace").splitlines()
    except OSError:
        lines = []
    errors = [line.strip() for line in lines if line.startswith("ERROR")]
    return errors[-1] if errors else str(err).strip()


def relax(data, material, dryness, out, steady=None, diameters=False, dt=1e-7, pair_args="",
          fix_args="", dump_every=None, method="dynamics", overrides="", start_dump=None):
    """Relax the tissue in ``data`` to steady state at ``dryness``; write the final dump and
    the log into ``out`` and return the result (positions, X/X0 reached, steps, ...).
    ``start_dump``: a dump of this tissue (e.g. another level's) whose positions the run
    starts from instead of those of ``data``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    name = level_name(dryness)
    max_steps = dict(run.STEADY_DEFAULTS, **(steady or {}))["max_steps"]
    began = time.perf_counter()
    lmp = run.open_lammps(log=out / f"log.{name}.lammps")
    try:
        dump = (out / f"tissue.{name}.dump").resolve()
        lmp.commands_string(run.tissue_script(
            Path(data).resolve(), Path(material).resolve(), dryness, dump=dump,
            dump_every=dump_every, steady=steady, diameters=diameters, dt=dt,
            pair_args=pair_args, fix_args=fix_args, method=method, overrides=overrides,
            start_dump=start_dump and (Path(start_dump).resolve(),
                                       morphology.read_dump(start_dump)[-1]["timestep"])))
        solver = None
        if method == "newton":
            # progress of the Newton iterations, one line each, beside the LAMMPS log
            mat = material_file.with_overrides(material_file.read(material), overrides)
            # --max-steps bounds the iterations too: a lever for large tissues, where
            # Newton lands near the dynamics' shape in a few iterations and then creeps
            # (doc/results/performance.md)
            with open(out / f"newton.{name}.log", "w") as fh:
                solver = run.solve_newton(lmp, dump=dump, max_iterations=min(60, max_steps),
                                          spacing=model.steady_spacing(mat, dryness),
                                          log=lambda line: print(line, file=fh, flush=True))
        state = run.steady_state(lmp)
        # every method: a minimiser or Newton lands on a folded tissue without a word, and
        # the dynamics, which stops on a folded one, ends on a tissue in pieces as quietly
        folded = run.folded(lmp)
    except Exception as err:
        log = out / f"log.{name}.lammps"
        lmp.close()
        raise LammpsError(dryness, lammps_reason(err, log), log) from err
    lmp.close()
    if folded:
        raise LammpsError(dryness, folded, out / f"log.{name}.lammps")
    state.update(dryness=dryness, seconds=time.perf_counter() - began, method=method,
                 converged=bool(state["steps"] < max_steps))
    if solver:
        # steps: Newton iterations; the residual is 0 by construction (P = -Pi)
        state.update(steps=solver["iterations"], converged=bool(solver["converged"]),
                     fmax=solver["fmax"], evaluations=solver["evaluations"])
    return state


#: stops of the quasi-static solve that the dynamics would meet the same way: the checks of
#: the input at setup, before either solve moves a bead (no fallback runs after them; a
#: bead lost later may be FIRE's doing: apple-mfc.cgms at s = 0.3, which the dynamics solves)
INPUT_STOP = re.compile(r"at setup|at step 0:|is not positive|CGMS material|CGMS parameter")


def relax_or_fallback(data, material, dryness, out, fallback_unconverged=True, **kwargs):
    """:func:`relax` with the quasi-static solve (FIRE, or the given ``method``), and
    where LAMMPS stops it (or, with ``fallback_unconverged``, it reaches its iteration
    limit) the dynamics of :data:`FALLBACK` in ``out/dynamics``, except after a stop at
    setup (:data:`INPUT_STOP`). Returns ``(result, note)``: ``note`` says why the fallback
    ran ("" if it did not). A stop of the fallback raises :class:`LammpsError` with
    ``first``, the quasi-static solve's stop."""
    kwargs = dict(kwargs)
    kwargs.setdefault("method", "quasistatic")
    note = ""
    try:
        result = relax(data, material, dryness, out, **kwargs)
        if result["converged"] or not fallback_unconverged:
            return result, note
        solver = {"quasistatic": "FIRE", "newton": "Newton"}.get(kwargs["method"],
                                                                  kwargs["method"])
        note = f"{solver} reached its iteration limit ({result['steps']} iterations)"
    except LammpsError as err:
        if INPUT_STOP.search(err.reason):
            raise
        note = err.reason
    # the user's steady-state thresholds hold for the fallback too; only its step cap is
    # the dynamics' own (FIRE's iteration cap would stop it long before steady state)
    steady = dict(kwargs.get("steady") or {}, **FALLBACK["steady"])
    kwargs.update(FALLBACK, steady=steady)
    try:
        return relax(data, material, dryness, Path(out) / FALLBACK_FOLDER, **kwargs), note
    except LammpsError as err:
        # both stops matter: the dynamics' says what ended the level, the first why the
        # dynamics ran at all
        raise LammpsError(err.dryness, err.reason, err.log, first=note) from err


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def sweep(data, material, out, levels=LEVELS, progress=True, fallback=None, start="built",
          **kwargs):
    """:func:`relax` at every level, resuming: a level whose result file exists in ``out``
    is read back, not run again. ``out/sweep.json`` records the tissue, the material and
    the options (``kwargs``, and ``fallback`` when given); a folder with another record is
    refused (FolderError). ``fallback="dynamics"``: where the quasi-static solve stops or
    does not converge, follow the dynamics instead (:func:`relax_or_fallback`); every
    result then has ``fallback``, why it ran ("" where it did not), and a level the
    fallback solved has its log and dump in ``out/dynamics`` (:func:`dump_file`).
    ``start="previous"``: a drying ramp. The levels run from the wettest to the driest, the
    first from the built tissue, every other from the previous level's steady state (its
    dump; the fluid at P = -Pi of its own s, as from the built tissue): a dried
    level's cutoff then need not reach across the built lattice (doc/calibration.md,
    "Five levels"). Each result records where it started (``start``: "built" or the
    level's name); a level that did not converge stops the ramp (:class:`RampError`)
    before a drier level starts from it, and a resume whose levels would start a finished
    one from elsewhere is refused (FolderError). Returns the results in level order
    (wettest first for a ramp)."""
    if start not in STARTS:
        raise ValueError(f"start must be one of {', '.join(STARTS)}, not {start!r}")
    if fallback not in (None, *FALLBACKS):
        raise ValueError(f"fallback must be one of {', '.join(FALLBACKS)}, not {fallback!r}")
    if fallback and kwargs.get("method", "dynamics") == "dynamics":
        raise ValueError("a fallback to the dynamics needs a quasi-static method "
                         "(quasistatic or newton): the dynamics has none to fall back to")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    setup = dict(data_sha256=sha256(data), material_sha256=sha256(material_file.find(material)),
                 **{k: kwargs[k] for k in sorted(kwargs)})
    if fallback:
        setup["fallback"] = fallback    # only when given: folders of before read the same
    if start != "built":
        setup["start"] = start          # likewise
        levels = sorted(levels, reverse=True)
    folders.same_setup(out / "sweep.json", setup, kept=(SOLVED_BY,))
    results = []
    bar = _progress(levels, progress)
    for s in bar:
        done = out / f"level.{level_name(s)}.json"
        positions = out / f"level.{level_name(s)}.npy"
        options = dict(kwargs)
        origin = level_name(results[-1]["dryness"]) if results else "built"
        if done.exists():
            result = folders.read_json(done)
            result["xy"] = folders.read_npy(positions)
            if start == "previous" and result.get("start") != origin:
                raise folders.FolderError(
                    f"{out}: s = {s:g} was started from {result.get('start')}, but with these "
                    f"levels it starts from {origin}; resume with the levels of the first "
                    "run or choose another --out")
        else:
            if start == "previous":
                options["start_dump"] = _ramp_dump(out, s, results)
            if fallback:
                begun = time.perf_counter()
                result, note = relax_or_fallback(data, material, s, out, **options)
                # the level's time: the solve that stopped and the dynamics after it
                result.update(fallback=note, seconds=time.perf_counter() - begun)
            else:
                result = relax(data, material, s, out, **options)
            if start == "previous":
                result["start"] = origin
            folders.write_npy(positions, result["xy"])    # first: the .json says it is done
            folders.write_json(done, {k: v for k, v in result.items() if k != "xy"})
            _record_solver(out / "sweep.json", s, result)
        results.append(result)
        if hasattr(bar, "set_postfix"):
            bar.set_postfix(s=s, moisture=f"{result['moisture']:.3f}", steps=result["steps"])
    return results


#: the entry of ``sweep.json`` that says which method solved each finished level (not part
#: of the setup a resume must match)
SOLVED_BY = "solved_by"


def solved_by(result):
    """Which method produced a level's steady state, in the options' words: "quasistatic",
    "newton", "dynamics", or "dynamics (fallback)" where the quasi-static solve stopped."""
    method = result.get("method", "dynamics")
    return f"{method} (fallback)" if result.get("fallback") else method


def _record_solver(path, s, result):
    """Add level ``s``'s method to ``sweep.json``'s :data:`SOLVED_BY` (and why the fallback
    ran, where it did)."""
    record = folders.read_json(path)
    entry = {"method": solved_by(result)}
    if result.get("fallback"):
        entry["why"] = result["fallback"]
    record.setdefault(SOLVED_BY, {})[level_name(s)] = entry
    folders.write_json(path, record)


def _ramp_dump(out, s, done):
    """The dump level ``s`` of a ramp starts from after the levels ``done``: None (the
    built tissue) for the first, else the previous level's final dump. RampError when that
    level did not converge or its dump is gone."""
    if not done:
        return None
    before = done[-1]
    if not before["converged"]:
        raise RampError(
            f"s = {before['dryness']:g} did not reach its steady state, and a ramp (start "
            f"previous) would start s = {s:g} from it: run again in a new folder with "
            "--fallback dynamics or a larger --max-steps")
    dump = dump_file(out, before)
    if not dump.exists():
        raise RampError(f"{dump}, the steady state s = {s:g} starts from (start previous), "
                        "is missing: a ramp needs the dumps of its finished levels")
    return dump


def dump_file(folder, result):
    """The final dump of a level of :func:`sweep` in ``folder``: in ``folder/dynamics``
    where the fallback solved it."""
    where = Path(folder) / FALLBACK_FOLDER if result.get("fallback") else Path(folder)
    return where / f"tissue.{level_name(result['dryness'])}.dump"


#: the words of a material file's comments that give the levels it holds for
#: ("VALID FOR 0.6 <= s <= 1", calibrated files; may run over two comment lines)
VALID_RANGE = re.compile(r"VALID\s+FOR\s+([0-9.eE+-]+)\s*<=\s*s\s*<=\s*([0-9.eE+-]+)")


def valid_range(material):
    """``(lo, hi)``: the levels s a material file says it is valid for, in its comments
    (``VALID FOR lo <= s <= hi``; doc/calibration.md), else ``(0, 1)``: every level."""
    text = material_file.find(material).read_text()
    comments = " ".join(line.split("#", 1)[1] for line in text.splitlines() if "#" in line)
    found = VALID_RANGE.search(comments)
    return (float(found.group(1)), float(found.group(2))) if found else (0.0, 1.0)


def table(results):
    """Rows of X/X0 reached, A/A0, P/P0, EL/EL0 (normalised by the s = 1 steady state, or the
    wettest level), steps and wall time, one per level; and, for a sweep with a fallback,
    why the fallback solved the level ("" where it did not)."""
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
        if any("fallback" in q for q in results):
            rows[-1]["fallback"] = r.get("fallback", "")
    return rows


def write_csv(rows, path, columns=None):
    """The rows (dicts) as a CSV table at a new ``path`` (FileExistsError if it is there),
    written whole or not at all. ``columns``: the keys to write, in order (a row's other
    keys are left out, a missing one is left empty); default all keys of the first row."""
    import csv
    import io
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=list(columns or rows[0]), restval="",
                            extrasaction="ignore" if columns else "raise")
    writer.writeheader()
    writer.writerows(rows)
    try:
        folders.write_atomic(path, lambda fh: fh.write(text.getvalue().encode()),
                             replace=False)
    except FileExistsError:
        raise FileExistsError(f"{path} exists") from None
    return Path(path)


def target_moisture(data, material, target, out, xtol=1e-3, fallback=None, **kwargs):
    """The initial dryness s whose steady state reaches X/X0 = ``target`` (paper: start at
    0.68 to reach 0.60). X/X0 reached grows with s, so a bracketed root search (Brent)
    finds it; every evaluation is a steady-state run kept in ``out``. ``fallback``: as
    :func:`sweep`'s (each evaluation by :func:`relax_or_fallback`)."""
    from scipy.optimize import brentq

    evaluations = []
    reached = {}

    def solve(s, folder):
        if fallback:
            return relax_or_fallback(data, material, s, folder, **kwargs)[0]
        return relax(data, material, s, folder, **kwargs)

    def miss(s):
        s = round(s, 6)
        if s not in reached:    # brentq asks again for the bracket ends
            result = solve(s, Path(out) / f"eval{len(evaluations):02d}")
            reached[s] = result["moisture"]
            evaluations.append((s, result["moisture"]))
        return reached[s] - target

    # X/X0 reached grows with s but is not below s everywhere (0.85 reaches 0.87):
    # step the lower end down until it lands below the target
    lo, hi = min(target, 1.0), 1.0
    while miss(lo) > 0:
        if lo < 0.02:
            raise ValueError(f"even a tissue started at s = {lo:g} ends above X/X0 = {target}")
        lo = max(0.5 * lo, lo * target / reached[round(lo, 6)] - 0.02)
    if miss(hi) < 0:
        raise ValueError(f"even the fresh tissue (s = 1) ends below X/X0 = {target} (it "
                         f"reaches {reached[1.0]:.4f})")
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
