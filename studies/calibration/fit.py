# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Calibrate CGMS against the fine-scale (MFC) reference of the 86-cell calibration tissue
(doc/results/calibration.md, "Against the MFC"). From the repository root, after
``source build/env.sh``:

    python3 studies/calibration/fit.py [--material NAME] [--mfc FOLDER] [--out OUT]
            [--hold NAME[,NAME]] [--install]

``--material``: the start material (default apple; potato: the second tissue, whose
86-cell tissue is apple's scaled to potato's cell spacing, studies/calibration/potato.py).
``--mfc``: the calibration tissue's MFC results, ``centroids.s<s>.txt`` per level (default
reference/mfc/calibration for apple, made by ``python3 -m cgms mfc``;
reference/mfc/potato-calibration for potato, made by potato.py).
Results in OUT (default results/calibration-mfc), one folder per fit:

- ``paper-<n>``: k_T, k_PA, beta_a, beta_b (the paper's parameters) on the n wettest levels,
  each fit started from the one before (continuation in dryness: started from apple's
  values, the three-level fit stops in a local minimum whose objective is 5 times larger);
- ``kS``: the same four and the cell-shape stiffness k_S on every level, started from the
  last ``paper-<n>`` fit and the start material's k_S (0.02 N/m when it has none); its
  k_S_exponent (k_S(s) = k_S s^n) is held.

``--material`` may be a path: a start material with a measured k_S(s) (k_S and k_S_exponent
lines) is then held at it in the ``paper-<n>`` fits; ``--install-as NAME`` names the
installed file (default <material>-mfc).

``--lj-slope VALUE``: the start material's lj_slope replaced (a copy in OUT); ``--also
lj_slope`` fits it. r(s) = r0 (1 + lj_slope ln s) sets the cutoff 1.35 r(s), which bounds
how far a hexagonal tissue can shrink (the second shell must stay outside it) and must
hold the built lattice every level starts from: lj_slope is kept below
(1 - 1.01/1.35) / -ln(driest level) (0.209 for s = 0.3; doc/calibration.md, "Five levels").
``--start previous`` runs each level from the previous level's steady state (a drying ramp,
as ``cgms study --start previous``; the levels of one parameter vector in sequence in one
worker): the built lattice then bounds nothing, and lj_slope's upper end is where the LJ
radius at the driest level is half of r0 (0.415 for s = 0.3; "A drying ramp").

``--hold``: parameters of the paper's four kept at the start material's value, not fitted
(k_T and k_PA are collinear on the converged levels: only their ratio is determined, and a
free fit drifts along that valley to a stiff material; doc/calibration.md).

Rigid motion (translation and rotation) is removed before eqn (2). ``--install`` writes the
``kS`` fit to potentials/<material>-mfc.cgms (never over an existing file) with a header
saying how it was made.
"""

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

from cgms.calibration import calibrate
from cgms.model import CUTOFF_LJ

sys.path.insert(0, str(Path(__file__).resolve().parent))
from potato import calibration_tissue  # noqa: E402  (the 86-cell tissue of any material)

PAPER = ["k_T", "k_PA", "beta_a", "beta_b"]
# search intervals, factors of each fit's start
# (the first fit drives k_PA to a thousandth of apple's, so its bound starts lower)
BOUNDS = {"k_T": (0.01, 100.0), "k_PA": (0.0005, 100.0), "beta_a": (0.85, 1.15),
          "beta_b": (0.2, 5.0), "k_S": (0.01, 100.0), "turgid_ratio": (0.9, 1.1),
          # the upper bound of lj_slope is lj_slope_limit's, whatever the start
          "lj_slope": (0.5, None)}
#: the cutoff at the driest level must reach this far beyond the built lattice's spacing:
#: the first steps move peripheral beads outwards (measured on 105 beads at s = 0.3: a
#: nearest neighbour 1.0004 r0 away at step 6, lost with a cutoff of 1.00002 r0)
START_MARGIN = 1.01
#: along a ramp (--start previous) the cutoff need not reach across the built lattice; the
#: upper end of lj_slope then keeps the LJ radius at the driest level at least this
#: fraction of r0 (0.415 at s = 0.3: beyond the MFC's own centroid-distance value, 0.375)
RAMP_RADIUS = 0.5


def lj_slope_limit(driest, start="built"):
    """The largest lj_slope with which a level ``driest`` can start from the built lattice:
    every run starts at the lattice spacing r0 = x_ref, so the cutoff 1.35 r(s) must hold
    it with START_MARGIN, 1.35 (1 + lj_slope ln s) >= 1.01; above, beads start isolated.
    Along a ramp (``start="previous"``): r(s) >= RAMP_RADIUS r0."""
    if start == "previous":
        return (1 - RAMP_RADIUS) / -math.log(driest)
    return (1 - START_MARGIN / CUTOFF_LJ) / -math.log(driest)


def stage_bounds(fitted, start, driest, level_start="built"):
    """Search intervals (factors of this stage's start) of the ``fitted`` names: BOUNDS, with
    lj_slope's upper end at :func:`lj_slope_limit` of the driest level of the whole fit."""
    out = {k: BOUNDS[k] for k in fitted}
    if "lj_slope" in out:
        out["lj_slope"] = (BOUNDS["lj_slope"][0],
                           lj_slope_limit(driest, level_start) / start["lj_slope"])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--material", default="apple")
    ap.add_argument("--mfc", help="default: reference/mfc/calibration (apple), "
                                  "reference/mfc/<material>-calibration (others)")
    ap.add_argument("--out", default="results/calibration-mfc")
    ap.add_argument("--levels", default="1,0.8,0.6",
                    help="levels to fit (default 1,0.8,0.6: with the paper's lj_slope the "
                         "MFC's 0.4 and 0.3 are beyond what CGMS can shrink to; see --lj-slope "
                         "and doc/calibration.md, \"Five levels\")")
    ap.add_argument("--also", default="",
                    help="material parameters fitted with the paper's four, comma separated "
                         "(e.g. turgid_ratio: the fresh cell's perimeter, the only thing "
                         "that sets the size of the fresh tissue; bounds 0.9-1.1)")
    ap.add_argument("--hold", default="",
                    help="parameters kept at the start material's value (not fitted), comma "
                         "separated, e.g. k_T")
    ap.add_argument("--lj-slope", type=float,
                    help="the start material's lj_slope replaced (r(s) = r0 (1 + lj_slope "
                         "ln s), which sets the cutoff 1.35 r(s) and so how far a hexagonal "
                         "tissue can shrink; doc/calibration.md); fitted with --also lj_slope")
    ap.add_argument("--direct", action="store_true",
                    help="one paper fit on all levels from the start material, no "
                         "continuation (for a start that is already near: the two-level "
                         "fit alone can drift to values with no steady state at s = 0.6)")
    ap.add_argument("--start", choices=("built", "previous"), default="built",
                    help="where each level's steady state starts: the built tissue "
                         "(default), or the previous level's steady state (a drying ramp, "
                         "as cgms study --start previous; lifts lj_slope's upper end: "
                         "doc/calibration.md, \"A drying ramp\")")
    ap.add_argument("--install", action="store_true")
    ap.add_argument("--install-as", help="name of the installed material file in potentials/ "
                                         "(default <material>-mfc)")
    ap.add_argument("--install-fit", choices=("kS", "paper"), default="kS",
                    help="which fit --install writes: kS (default) or the last paper-<n> "
                         "fit, without k_S (when k_S is not determined)")
    ap.add_argument("--temperature", type=float,
                    help="with --install: the temperature (C) of an MFC reference made "
                         "without one (the unheated reference stands for 20 C: "
                         "doc/drying.md); a reference made with python3 -m cgms mfc "
                         "--temperature has its own in setup.json, which this must match. "
                         "Written as the installed header's '# TEMPERATURE:' line, which "
                         "cgms.temperature reads")
    ap.add_argument("--without-kS", action="store_true",
                    help="skip the kS stage (with --install-fit paper: k_S already shown "
                         "not to be determined, and the stage costs as much as the fit)")
    args = ap.parse_args(argv)
    if args.without_kS and args.install_fit == "kS":
        sys.exit("fit.py: --without-kS leaves no kS fit to install: add --install-fit paper")
    if args.mfc is None:
        args.mfc = "reference/mfc/" + ("calibration" if args.material == "apple"
                                       else f"{args.material}-calibration")
    levels = [float(w) for w in args.levels.split(",")]
    held = [w for w in args.hold.split(",") if w]
    if [w for w in held if w not in PAPER]:
        sys.exit(f"fit.py: --hold {args.hold}: each must be one of {', '.join(PAPER)}")
    fitted = [w for w in PAPER if w not in held] + [w for w in args.also.split(",") if w]
    unknown = [w for w in fitted if w not in BOUNDS or w == "k_S"]
    if unknown:
        sys.exit(f"fit.py: --also {', '.join(unknown)}: not one of "
                 f"{', '.join(k for k in BOUNDS if k not in PAPER + ['k_S'])}")
    refs = {s: Path(args.mfc) / f"centroids.s{s:g}.txt" for s in levels}
    missing = [str(p) for p in refs.values() if not p.is_file()]
    if missing:
        sys.exit(f"fit.py: no reference {', '.join(missing)}")
    if len(refs) < 2 or 1.0 not in refs:
        sys.exit(f"fit.py: need centroids.s1.txt and at least one dried level in {args.mfc}")
    heat = reference_temperature(args.mfc, args.temperature)
    from cgms import material
    start_material = material.read(material.find(args.material))
    target = Path(f"potentials/{args.install_as or Path(args.material).stem + '-mfc'}.cgms")
    if args.install and target.exists():
        sys.exit(f"fit.py: {target} exists; move it away first")
    driest = min(levels)
    lj_slope = start_material["lj_slope"] if args.lj_slope is None else args.lj_slope
    if args.start == "previous":
        if not 0 <= lj_slope < lj_slope_limit(driest, "previous"):
            sys.exit(f"fit.py: lj_slope {lj_slope:g}: along a ramp it must be in [0, "
                     f"{lj_slope_limit(driest, 'previous'):.4g}) (the LJ radius at s = "
                     f"{driest:g} at least {RAMP_RADIUS} r0)")
    elif not 0 <= lj_slope < lj_slope_limit(driest):
        reach = CUTOFF_LJ * (1 + lj_slope * math.log(driest))
        sys.exit(f"fit.py: lj_slope {lj_slope:g}: at s = {driest:g} the cutoff {CUTOFF_LJ} r0 "
                 f"(1 + lj_slope ln s) = {reach:.4g} r0 would not safely reach the start "
                 f"lattice's neighbours (r0 apart; {START_MARGIN} r0 is the least): it must be "
                 f"in [0, {lj_slope_limit(driest):.4g})")
    if "lj_slope" in fitted and lj_slope == 0:
        sys.exit("fit.py: --also lj_slope needs a start lj_slope > 0 (the search runs in "
                 "ln(value / start)): give --lj-slope")
    out = Path(args.out)
    if args.lj_slope is not None:   # a copy of the start material with this lj_slope
        out.mkdir(parents=True, exist_ok=True)
        copy = out / f"{Path(args.material).stem}-lj_slope.cgms"
        copy.write_text("".join(
            f"lj_slope {args.lj_slope!r} # set by fit.py --lj-slope; LJ radius r/r0 = 1 + "
            f"lj_slope ln s\n" if line.split()[:1] == ["lj_slope"] else line
            for line in material.find(args.material).read_text().splitlines(keepends=True)))
        given, args.material = args.material, str(copy)
    else:
        given = args.material
    data = out / "tissue.data"
    if not data.exists():   # the 86-bead tissue, as `cgms calibrate` builds it for apple
        out.mkdir(parents=True, exist_ok=True)
        from cgms import tissue
        x_ref = start_material["x_ref"]
        tissue.write_data(data, calibration_tissue(args.material), 3 * x_ref)
    start, levels = None, sorted(refs, reverse=True)
    start_values = {k: material.read(args.material)[k] for k in fitted}
    for n in range(len(levels) if args.direct else 2, len(levels) + 1):
        use = {s: refs[s] for s in levels[:n]}
        result = calibrate.calibrate(data, args.material, use, out / f"paper-{n}", fitted,
                                     start=start,
                                     bounds=stage_bounds(fitted, start or start_values, driest,
                                                         args.start),
                                     align_mode="rigid", level_start=args.start,
                                     max_evaluations=80)
        start = dict(result["parameters"])
        report("paper", n, result)
        paper = result
    if not args.without_kS:
        result = calibrate.calibrate(data, args.material, refs, out / "kS", fitted + ["k_S"],
                                     start=dict(start, k_S=start_material.get("k_S") or 0.02),
                                     bounds=stage_bounds(fitted + ["k_S"], start, driest,
                                                         args.start),
                                     align_mode="rigid", level_start=args.start,
                                     max_evaluations=80)
        report("kS", len(refs), result)
    if args.install_fit == "paper":
        result = paper
    if args.install:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
        lines = Path(result["material_file"]).read_text().splitlines()
        made = [f"# Made by: python3 studies/calibration/fit.py --material {given} "
                f"--mfc {args.mfc} --out {args.out} --levels {args.levels}"
                + (f" --also {args.also}" if args.also else "")
                + (f" --hold {args.hold}" if args.hold else "")
                + (" --direct" if args.direct else "")
                + (f" --lj-slope {args.lj_slope!r}" if args.lj_slope is not None else "")
                + (f" --start {args.start}" if args.start != "built" else "")
                + (f" --temperature {args.temperature:g}" if args.temperature is not None
                   else "")
                + f" --install --install-fit {args.install_fit}"
                + (" --without-kS" if args.without_kS else "") + " (fit "
                + (f"'paper-{len(levels)}'" if args.install_fit == "paper" else "'kS'")
                + f", commit {commit})",
                f"# References: MFC centroids in {args.mfc} "
                "(reference/mfc/README.md)"]
        if heat:   # the levels fitted are the ones it holds for (cgms.study.valid_range)
            made += [f"# TEMPERATURE: {heat}",
                     f"# VALID FOR {min(levels):g} <= s <= 1 (the levels fitted)"]
        with open(target, "x") as fh:
            fh.write("\n".join(lines[:2] + made + lines[2:]) + "\n")
        print(f"fit.py: wrote {target}")
    return 0


def reference_temperature(folder, given):
    """The header text after '# TEMPERATURE: ' for an MFC reference ``folder``: its own
    temperature (setup.json of python3 -m cgms mfc --temperature) or ``given`` (C) for one
    made unheated; None for neither. Exits on a ``given`` that contradicts the folder's."""
    setup = Path(folder) / "setup.json"
    p = json.loads(setup.read_text())["parameters"] if setup.is_file() else {}
    if p.get("temperature") is None:
        if given is None:
            return None
        return (f"{given:g} C (the MFC reference {folder} is unheated, the material's "
                f"values, which stand for {given:g} C; doc/drying.md)")
    if given is not None and given != p["temperature"]:
        sys.exit(f"fit.py: --temperature {given:g}: the reference {folder} was made at "
                 f"{p['temperature']:g} C (its setup.json)")
    return (f"{p['temperature']:g} C (the MFC reference {folder} made at "
            f"{p['temperature']:g} C: wall factor {p['wall_factor']:.4g}, turgor factor "
            f"{p['turgor_factor']:.4g}; doc/drying.md)")


def report(name, n, r):
    print(f"fit.py: {name} on {n} levels: "
          + ", ".join(f"{k} {v:.6g} (+-{100 * r['stderr'][k]:.2g} %)"
                      for k, v in r["parameters"].items())
          + "; RMSD um " + ", ".join(f"s={s:g}: {v * 1e6:.2f}" for s, v in r["rmsd"].items())
          + f"; {r['seconds']:.0f} s; on bound: {', '.join(r['on_bound']) or 'none'}",
          flush=True)
    names = list(r["parameters"])
    pairs = [f"{a}/{b} {r['correlation'][i][j]:+.3f}" for i, a in enumerate(names)
             for j, b in enumerate(names) if i < j]
    print(f"fit.py: {name} correlations: {', '.join(pairs)}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
