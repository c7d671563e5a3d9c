# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shaped coarse model (cgms.shaped) along a drying ramp against the MFC references:
tissue A/A0, P/P0, EL/EL0 (cgms.morphology.measures of the bead outline, longest edge 2.0
median spacings, each model normalised by its own s = 1 state), centroid RMSD (eqn 2,
rigid motion removed) and the cell-level area, contour perimeter and elongation against
reference/mfc/<tissue>/cells.s<s>.csv. Optionally fits the free parameters on one tissue
(scipy.optimize.least_squares) and predicts the others. ``--model tensor`` runs the variant
with a shape tensor per cell (cgms.shaped_tensor) instead of slaved junctions.

    python3 studies/shaped/table.py [--model shaped|tensor] [--tissues calibration,...]
                                    [--params JSON] [--fit calibration] [--levels 1,0.8,...]
                                    [--csv out.csv]
"""

import argparse
import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
from cgms import material, morphology, shaped, shaped_tensor, superpose, tissue  # noqa: E402
from cgms.tissue import MICROSCALE  # noqa: E402

LEVELS = (1.0, 0.8, 0.6, 0.4, 0.3, 0.2, 0.1)
TISSUES = ("calibration", "1.5x1.5", "1.5x2.0", "1.5x2.5", "2.0x2.0", "2.0x2.5",
           "potato-calibration")
KEYS = ("A/A0", "P/P0", "EL/EL0")
#: the issue's targets, |dev| in %
TARGET = {"A/A0": 2.0, "P/P0": 5.0, "EL/EL0": 4.0}
MAX_EDGE = 2.0
#: the coarse models this study compares: slaved junctions, or a shape tensor per cell
MODELS = {"shaped": shaped, "tensor": shaped_tensor}


def positions(model, z, n):
    """The bead positions (n, 2) of a model's state."""
    return model.split(z, n)[0] if model is shaped_tensor else z


def layout(name):
    """(material, bead positions) of a reference tissue: cell i = bead i (ids 1..n)."""
    if name == "potato-calibration":
        mat = material.read("potato")
        w, h = MICROSCALE["calibration"]
        scale = mat["x_ref"] / material.read("apple")["x_ref"]
        return mat, tissue.rectangle(w * 1e-3 * scale, h * 1e-3 * scale, mat["x_ref"])
    mat = material.read("apple")
    w, h = MICROSCALE[name]
    return mat, tissue.rectangle(w * 1e-3, h * 1e-3, mat["x_ref"])


#: the MFC reference sets compared against (``--reference``)
REFERENCE = ROOT / "reference" / "mfc"


def mfc(name, s):
    """MFC centroids (n, 2) and cell table at level s, or None."""
    folder = REFERENCE / name
    path = folder / f"centroids.s{s:g}.txt"
    if not path.is_file():
        return None
    xy = np.loadtxt(path)[:, 1:3]
    cells = np.genfromtxt(folder / f"cells.s{s:g}.csv", delimiter=",", names=True)
    return xy, cells


def ensemble(folder, s):
    """The MFC ensemble of the calibration tissue at level s
    (reference/mfc/calibration/ensemble): {measure: (mean, sd)}, mean centroids, or None."""
    folder = Path(folder)
    path = folder / f"centroids.s{s:g}.txt"
    if not path.is_file():
        return None
    stats = {}
    for line in (folder / "measures.csv").read_text().splitlines()[1:]:
        f = line.split(",")
        if float(f[0]) == s:
            stats[f[1]] = (float(f[3]), float(f[4]) if f[4] else np.nan)
    return stats, np.loadtxt(path)[:, 1:3]


def measures(xy):
    nearest = np.sort(np.linalg.norm(xy[:, None] - xy[None], axis=-1), axis=1)[:, 1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return morphology.measures(xy, max_edge=MAX_EDGE * float(np.median(nearest)))
        except ValueError:   # a folded tissue can have no outline
            return dict(area=np.nan, perimeter=np.nan, elongation=np.nan)


def given_params(model, text):
    """The model's defaults, with the wall stiffness as EA_ratio (1: the MFC's), updated by
    the JSON of a --params option."""
    params = dict(model.DEFAULTS)
    params.pop("wall_EA")
    params.update(EA_ratio=1.0)
    params.update(json.loads(text))
    return params


def geometry(name, params):
    """The named tissue's material, bead layout and shaped-model geometry."""
    mat, xy = layout(name)
    return mat, xy, shaped.build(xy, mat, wall_params(mat, params))


def wall_params(mat, params):
    """The shaped model's parameters for a material: the MFC's wall stiffness E t H (apple
    330 N/m, potato 660 N/m, H = 6 um) times ``EA_ratio``; the rest as given, with the
    entries of a ``potato`` sub-dict replacing them on potato tissues (the gap law is
    measured per material: studies/shaped/gap.py)."""
    p = dict(params)
    potato = mat["diameter"] > 175e-6
    overrides = p.pop("potato", {})      # {"potato": {...}}: values for potato tissues only
    if potato:
        p.update(overrides)
    Et = 660.0 if potato else 330.0
    p["wall_EA"] = Et * mat["height"] * p.pop("EA_ratio", 1.0)
    return p


def run(name, params, levels=LEVELS, ftol=1e-9, model=shaped, ens=None, save=None,
        solver=None):
    """Rows of one tissue along the ramp: one dict per level. ``save``: a folder to write
    the states to (``<tissue>.npz``: levels and one state vector per level); ``solver``
    (tensor model only): the steady-state solver, default its dense ``relax``."""
    mat, xy = layout(name)
    t0 = time.time()
    p = wall_params(mat, params)
    kick = p.pop("kick", 0.0 if model is shaped else 1e-3)
    extra = dict(solver=solver) if solver else {}
    geo, states = model.ramp(xy, mat, levels, p, ftol=ftol, kick=kick, **extra)
    seconds = time.time() - t0
    n = geo["n"]
    if save:
        Path(save).mkdir(parents=True, exist_ok=True)
        np.savez(Path(save) / f"{name}.npz", levels=np.array([s for s, _, _ in states]),
                 states=np.array([z for _, z, _ in states]))
    p0 = positions(model, states[0][1], n)
    m0 = measures(p0)
    ref0 = mfc(name, 1.0)
    q0m = measures(ref0[0])
    c0 = None
    rows = []
    for s, z, info in states:
        lev = model.at_level(geo, s)
        cm = model.cell_measures(z, lev)
        x = positions(model, z, n)
        if c0 is None:
            c0 = cm
        got = morphology.normalise(measures(x), m0)
        row = dict(tissue=name, s=s, fmax=info["fmax"], converged=info["converged"],
                   iterations=info["iterations"], seconds=seconds,
                   cell_area=float(np.mean(cm["area"] / c0["area"])),
                   cell_perim=float(np.mean(cm["perimeter"] / c0["perimeter"])),
                   cell_elong=float(np.nanmean(cm["elongation"])),
                   folded=int(np.sum(shaped.triangle_areas(x, geo["triangles"]) <= 0)))
        for k in KEYS:
            row[f"shaped {k}"] = got[k]
        ref = mfc(name, s)
        if ref is not None:
            q, cells = ref
            want = morphology.normalise(measures(q), q0m)
            row["rmsd_um"] = superpose.rmsd(x, q, "rigid") * 1e6
            for k in KEYS:
                row[f"MFC {k}"] = want[k]
                row[f"dev {k} %"] = 100 * (got[k] / want[k] - 1)
            cells0 = ref0[1]
            row["MFC cell_area"] = float(np.mean(cells["area"] / cells0["area"]))
            row["MFC cell_perim"] = float(np.mean(cells["perimeter"] / cells0["perimeter"]))
            row["MFC cell_elong"] = float(np.mean(cells["elongation"]))
            row["MFC cell_elong_sd"] = float(np.std(cells["elongation"]))
        got_ens = ensemble(ens, s) if ens and name == "calibration" else None
        if got_ens is not None:
            stats, mean_xy = got_ens
            for k in KEYS:
                mean, sd = stats[k]
                row[f"ens {k}"] = mean
                row[f"ens z {k}"] = (got[k] - mean) / sd if sd > 0 else np.nan
            row["ens rmsd_um"] = superpose.rmsd(x, mean_xy, "rigid") * 1e6
            row["ens floor_um"] = stats["floor_um"][0] if "floor_um" in stats else np.nan
        rows.append(row)
    return rows


def print_rows(rows, out=sys.stdout):
    head = ("| tissue | s | A/A0 MFC | shaped | dev % | P/P0 MFC | shaped | dev % | EL/EL0 MFC "
            "| shaped | dev % | RMSD um | cell A/A0 MFC / shaped | cell P/P0 MFC / shaped "
            "| cell elong. MFC (sd) / shaped | inverted triangles | largest force N |")
    print(head, file=out)
    print("|" + "---|" * (head.count("|") - 1), file=out)
    for r in rows:
        if "MFC A/A0" in r:
            cells = (f"{r['MFC cell_area']:.4f} / {r['cell_area']:.4f} | "
                     f"{r['MFC cell_perim']:.4f} / {r['cell_perim']:.4f} | "
                     f"{r['MFC cell_elong']:.2f} ({r['MFC cell_elong_sd']:.2f}) / "
                     f"{r['cell_elong']:.2f}")
            vals = " | ".join(f"{r[f'MFC {k}']:.4f} | {r[f'shaped {k}']:.4f} | "
                              f"{r[f'dev {k} %']:+.2f}" for k in KEYS)
            rm = f"{r['rmsd_um']:.1f}"
        else:
            cells = (f"- / {r['cell_area']:.4f} | - / {r['cell_perim']:.4f} | "
                     f"- / {r['cell_elong']:.2f}")
            vals = " | ".join(f"- | {r[f'shaped {k}']:.4f} | -" for k in KEYS)
            rm = "-"
        print(f"| {r['tissue']} | {r['s']:g} | {vals} | {rm} | {cells} | {r['folded']} | "
              f"{r['fmax']:.1e} |",
              file=out)


def worst(rows, levels):
    """Largest |dev| per key and largest RMSD over the rows at the given levels."""
    sub = [r for r in rows if r["s"] in levels and "MFC A/A0" in r]
    out = {k: max(abs(r[f"dev {k} %"]) for r in sub) for k in KEYS}
    out["rmsd_um"] = max(r["rmsd_um"] for r in sub)
    return out


FREE = ("EA_ratio", "buckle", "soft", "beta_a", "beta_b", "lamella", "kg_ratio")


def fit(name, params, free, levels=(1.0, 0.8, 0.6, 0.4, 0.3), model=shaped, max_nfev=40,
        solver=None):
    """least_squares on the tissue's deviations (A/A0, P/P0, EL/EL0 in %, over the
    targets) and its centroid RMSD (over 10 um) at the dried levels, each state solved by
    ``solver`` (None: the model's own)."""
    from scipy.optimize import least_squares
    logs = {"buckle", "EA_ratio", "soft", "kg_ratio", "net_shear"}

    def unpack(z):
        p = dict(params)
        for k, v in zip(free, z):
            p[k] = math.exp(v) if k in logs else v
        return p

    def resid(z):
        p = unpack(z)
        try:
            rows = run(name, p, levels, model=model, solver=solver)
        except (ValueError, np.linalg.LinAlgError) as err:
            print("  failed:", err, flush=True)
            return np.full(4 * (len(levels) - 1), 10.0)
        res = []
        for r in rows[1:]:
            res += [r[f"dev {k} %"] / TARGET[k] for k in KEYS] + [r["rmsd_um"] / 10]
        res = np.array(res)
        print("  ", {k: round(v, 6) for k, v in p.items() if k in free},
              f"cost {0.5 * np.sum(res ** 2):.3f}", flush=True)
        return res

    z0 = [math.log(params[k]) if k in logs else params[k] for k in free]
    sol = least_squares(resid, z0, diff_step=1e-3, max_nfev=max_nfev, xtol=1e-3, ftol=1e-3)
    return unpack(sol.x), sol


def main(argv=None):
    global REFERENCE
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", default="shaped", choices=sorted(MODELS))
    ap.add_argument("--tissues", default="calibration")
    ap.add_argument("--levels", default=",".join(f"{s:g}" for s in LEVELS))
    ap.add_argument("--params", default="{}", help="JSON overrides of cgms.shaped.DEFAULTS "
                    "(and EA_ratio, kick)")
    ap.add_argument("--fit", default=None, help="tissue to fit the --free parameters on first")
    ap.add_argument("--free", default="buckle,beta_a,beta_b,lamella")
    ap.add_argument("--fit-levels", default="1,0.8,0.6")
    ap.add_argument("--max-nfev", type=int, default=40, help="evaluations the fit may take")
    ap.add_argument("--csv", default=None)
    ap.add_argument("--save", default=None, help="folder for each tissue's states "
                    "(<tissue>.npz), e.g. for studies/shaped/rim.py --states")
    ap.add_argument("--solver", default="relax", choices=("relax", "newton"),
                    help="tensor model: dense trust region (relax) or sparse Newton "
                    "(cgms.shaped_newton; faster, may land on another of the nearby minima)")
    ap.add_argument("--ensemble", default=None, help="folder of the calibration tissue's MFC "
                    "ensemble (measures.csv, centroids.s<s>.txt) to judge against its spread")
    ap.add_argument("--reference", default=str(REFERENCE), help="folder of the MFC sets, one "
                    "per tissue (default reference/mfc, the chunked ramp's; reference/mfc/steady: "
                    "the quasi-static path's)")
    args = ap.parse_args(argv)
    REFERENCE = Path(args.reference)
    if not REFERENCE.is_dir():
        ap.error(f"--reference {args.reference}: no such folder")
    model = MODELS[args.model]
    solver = None
    if args.solver == "newton" and model is not shaped_tensor:
        ap.error("--solver newton solves the tensor model's state (cgms.shaped_newton): "
                 "give --model tensor, or leave out --solver")
    if args.solver == "newton":
        from cgms import shaped_newton
        solver = shaped_newton.newton
    params = given_params(model, args.params)
    levels = tuple(float(v) for v in args.levels.split(","))
    t0 = time.time()
    if args.fit:
        params, sol = fit(args.fit, params, args.free.split(","),
                          tuple(float(v) for v in args.fit_levels.split(",")), model,
                          args.max_nfev, solver)
        print("fitted:", json.dumps(params), f"cost {sol.cost:.3f}, {sol.nfev} evaluations",
              flush=True)
    rows = []
    for name in args.tissues.split(","):
        rows += run(name, params, levels, model=model, ens=args.ensemble, save=args.save,
                    solver=solver)
        print(f"{name}: {rows[-1]['seconds']:.1f} s", file=sys.stderr, flush=True)
    print_rows(rows)
    for lv in ((0.8,), (0.6,), (0.4,), (0.3,)):
        if lv[0] not in levels:    # a level not run has no largest deviation
            continue
        w = worst(rows, lv)
        print(f"s = {lv[0]:g}: largest |dev| " + ", ".join(f"{k} {w[k]:.2f} %" for k in KEYS)
              + f", RMSD {w['rmsd_um']:.1f} um")
    for r in rows:
        if "ens A/A0" in r:
            print(f"ensemble s = {r['s']:g}: " + ", ".join(
                f"{k} {r[f'shaped {k}']:.4f} vs {r[f'ens {k}']:.4f} ({r[f'ens z {k}']:+.1f} sd)"
                for k in KEYS) + f"; RMSD to the mean centroids {r['ens rmsd_um']:.1f} um "
                f"(floor {r['ens floor_um']:.1f})")
    # the solver may land on another nearby minimum: which one made the table is part of it
    print(f"params {json.dumps(params)}; solver {args.solver}; {time.time() - t0:.1f} s")
    if args.csv:
        import csv
        keys = sorted({k for r in rows for k in r})
        with open(args.csv, "w", newline="") as f:
            wr = csv.DictWriter(f, keys)
            wr.writeheader()
            wr.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
