# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""k_S from the fine model's shear stiffness (doc/calibration.md): the shear and uniaxial
test of cgms.shear on blocks of cells, in the MFC (fast variant) and in CGMS over a range of
k_S, and the k_S whose shear modulus matches the MFC's.

    /usr/bin/python3 studies/mfc/shear.py OUT [--blocks 8x5,12x7] [--levels 1,0.8]
        [--materials apple-mfc,apple] [--k-s 0,0.5,1,2,4] [--mfc-only | --cgms-only]
        [--tissue potato --mfc-set wall_Et=660 --materials potato-mfc,potato] [--report]
        [--mfc-solver max_iterations=80000]
    /usr/bin/python3 studies/mfc/shear.py OUT --effects [--materials ...] [--k-s ...]

One JSON per run in OUT (``mfc[-<tissue>]-<block>-s<s>.json``, ``cgms-<material>-<block>-s<s>-kS<k>.json``);
a run whose JSON exists is read back, not run again, so an interrupted study resumes.
Prints Markdown tables: per block and level the MFC's moduli and, per material, CGMS's
modulus without k_S, its mean slope in k_S, and the matching k_S (clamped and interior
measures). ``--effects``: the hard cases of tests/plugin/test_hard_cases.py (a sharp moisture step,
cells of cv = 0.05) per material and k_S, instead.
"""

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from cgms import folders, material, shear
from cgms.mfc import model as mfc_model


def _jsonable(o):
    return o.tolist() if hasattr(o, "tolist") else float(o)


#: --report: read the stored runs only, run nothing
REPORT_ONLY = False


def once(path, make):
    """The run stored at ``path``, made by ``make()`` if it is not there yet (None with
    --report)."""
    if path.exists():
        return folders.read_json(path)
    if REPORT_ONLY:
        return None
    start = time.perf_counter()
    try:
        result = make()
    except Exception as err:   # a run LAMMPS stops is recorded, not fatal to the study
        result = dict(error=f"{type(err).__name__}: {err}")
    result["seconds"] = time.perf_counter() - start
    result = json.loads(json.dumps(result, default=_jsonable))
    folders.write_json(path, result)
    return result


def cgms_run(centres, row, mat_path, s, folder, overrides):
    """:func:`cgms.shear.cgms` from FIRE, or where LAMMPS stops FIRE (a bead pulled out of
    the tissue), from the damped dynamics' steady state (as the calibration does)."""
    try:
        return shear.cgms(centres, row, mat_path, s, folder, overrides=overrides)
    except Exception as err:
        result = shear.cgms(centres, row, mat_path, s, folder / "dynamics",
                            overrides=overrides, start="dynamics")
        result["fire_error"] = str(err).splitlines()[0]
        return result


def matching_k_S(ks, values, target):
    """k_S at which CGMS's modulus (``values`` at ``ks``, increasing) equals ``target``:
    piecewise-linear interpolation in the sweep (NaN outside it), and CGMS's modulus at
    k_S = 0 and its mean slope in k_S over the sweep."""
    ks, values = np.asarray(ks, float), np.asarray(values, float)
    inside = values[0] <= target <= values[-1]
    k = float(np.interp(target, values, ks)) if inside else float("nan")
    return k, float((values[-1] - values[0]) / (ks[-1] - ks[0])), float(values[0])


#: the hard cases of tests/plugin/test_hard_cases.py that the paper's forces collapse on: the
#: symmetric 86-bead tissue with a sharp moisture step (wet left half | dry right half), and
#: with cell diameters of cv = 0.05 (seed 1) at one level; damped dynamics to the steady
#: state (residual and speed below 1e-3, checked every 1000 steps), 0.03 s at most
CASE = """units si
dimension 2
boundary f f p
atom_style cgms
atom_modify map array sort 0 0
comm_modify vel yes
fix diam all property/atom d_diameter
read_data {data} fix diam NULL Diameters
variable d atom d_diameter
neighbor 1.5e-5 bin
neigh_modify every 1 delay 0 check yes
variable xc equal 0.5*(bound(all,xmin)+bound(all,xmax))
variable s atom ternary(x<v_xc,1.0,{dry})
pair_style cgms
pair_coeff * * {material} k_S {k_S!r}
fix fluid all cgms/fluid dryness {dryness} diameter v_d
fix nve all nve
fix 2d all enforce2d
timestep {dt!r}
compute cell all property/atom nneigh area
compute nmax all reduce max c_cell[1]
variable steady equal (f_fluid[1]<1e-3)&&(f_fluid[3]<1e-3)
fix halt all halt 1000 v_steady > 0.5 error continue
thermo_style custom step f_fluid[1] f_fluid[2] f_fluid[3] c_nmax
thermo 10000
run {steps}
"""


def hard_case(folder, material_path, k_S, case, dry):
    """Run one hard case (``case`` "step": s = 1 | ``dry``; "cv": cv = 0.05 at s = ``dry``)
    with ``k_S``; returns whether it reached its steady state, the steps, the largest
    neighbour count, X/X0, the dry / wet (or small / large) cell area ratio and LAMMPS's
    message if it stopped."""
    from cgms import model, positions, run, tissue
    folder.mkdir(parents=True, exist_ok=True)
    mat = material.read(material_path)
    xy = tissue.hex_rectangle(10, 9, mat["x_ref"], short_rows=True)
    xy = xy - 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    d = (tissue.cell_diameters(len(xy), mat["diameter"], 0.05, seed=1) if case == "cv"
         else np.full(len(xy), mat["diameter"]))
    data = folder / "tissue.data"
    positions.write_data(data, xy, 5 * mat["x_ref"], diameters=d, overwrite=True)
    # 0.9 of the smallest cell's time-step limits (damping as in tests/plugin/test_hard_cases.py,
    # k_S, and the turgor force at 1.1 x the dried reference density (the dried cells start
    # compressed on the fresh lattice): apple-mfc's
    # k_T is 300 x apple's), at most the paper's 1e-7 s
    mass = model.fresh_mass(mat, d.min())
    side = model.reference_cell(d.min(), mat["pectin"])["b_ref"]
    limits = [model.damping_dt_limit(mass, 6, mat["k_d"]),
              model.turgor_dt_limit(mat, mass, 6, side, 1.1 * dry * mat["rho0"], dry)]
    if k_S > 0:
        limits.append(model.shape_dt_limit(mass, 6, k_S))
    dt = min(1e-7, 0.9 * float(min(limits)))
    steps = int(0.03 / dt)
    script = CASE.format(data=data.resolve(), material=Path(material_path).resolve(), k_S=k_S,
                         dry=dry, dryness="v_s" if case == "step" else dry, dt=dt,
                         steps=steps)
    lmp = run.open_lammps(log=folder / "log.lammps")
    out = dict(case=case, dry=dry, k_S=k_S, material=Path(material_path).stem)
    try:
        lmp.commands_string(script)
        nlocal = lmp.extract_global("nlocal")
        state = run.steady_state(lmp)
        cell = lmp.numpy.extract_compute("cell", 1, 2)[:nlocal]
        ids = np.array(lmp.numpy.extract_atom("id")[:nlocal])
        area = np.asarray(cell[np.argsort(ids), 1])
        x = state["xy"][:, 0]
        small = x >= 0.5 * (x.min() + x.max()) if case == "step" else d < np.median(d)
        out.update(steady=bool(state["steps"] < steps), steps=int(state["steps"]),
                   nmax=float(lmp.extract_compute("nmax", 0, 0)), moisture=state["moisture"],
                   area_ratio=float(area[small].mean() / area[~small].mean()))
    except Exception as err:
        out.update(steady=False, error=str(err).splitlines()[0][:300])
    finally:
        lmp.close()
    return out


def effects(out, materials, ks):
    """The hard cases with each material and k_S (Markdown table)."""
    print("| material | case | k_S (N/m) | outcome | steps | most neighbours | X/X0 | "
          "cell area dry/wet or small/large |")
    print("|---|---|---|---|---|---|---|---|")
    for mat in materials:
        path = material.find(mat)
        # apple-mfc.cgms holds for 0.6 <= s <= 1 only (its header)
        cases = [("step", 0.2), ("cv", 0.4)] if mat == "apple" else [("step", 0.6), ("cv", 0.6)]
        for case, dry in cases:
            for k in ks:
                tag = f"case-{mat}-{case}{dry:g}-kS{k:g}"
                r = once(out / f"{tag}.json", lambda: hard_case(out / tag, path, k, case, dry))
                if r is None:
                    continue
                outcome = "steady" if r.get("steady") else ("stopped: " + r["error"]
                                                             if "error" in r else "not steady")
                label = f"step 1 / {dry:g}" if case == "step" else f"cv 0.05, s = {dry:g}"
                print(f"| {mat} | {label} "
                      f"| {k:g} | {outcome} | {r.get('steps', '')} | {r.get('nmax', '')} | "
                      f"{r.get('moisture', float('nan')):.4f} | "
                      f"{r.get('area_ratio', float('nan')):.4f} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--blocks", default="8x5,12x7")
    ap.add_argument("--levels", default="1,0.8")
    ap.add_argument("--materials", default="apple-mfc,apple")
    ap.add_argument("--tissue", default="apple",
                    help="CGMS material whose shared values the MFC takes (apple, potato)")
    ap.add_argument("--mfc-set", default="", metavar="NAME=VALUE,...",
                    help="MFC values other than mfc_model.MFC's; potato's reference: "
                         "wall_Et=660 (studies/calibration/potato.py)")
    ap.add_argument("--mfc-solver", default="", metavar="NAME=VALUE,...",
                    help="MFC steady-state solver options other than mfc_run.DEFAULTS, e.g. "
                         "max_iterations=80000 (a dried free state settled longer)")
    ap.add_argument("--k-s", default="0,0.5,1,2,4")
    ap.add_argument("--mfc-only", action="store_true")
    ap.add_argument("--cgms-only", action="store_true")
    ap.add_argument("--report", action="store_true", help="tables of the stored runs only")
    ap.add_argument("--effects", action="store_true",
                    help="instead: the hard cases (sharp moisture step, cv = 0.05) per k_S")
    args = ap.parse_args(argv)
    global REPORT_ONLY
    REPORT_ONLY = args.report
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.effects:
        effects(out, args.materials.split(","), [float(v) for v in args.k_s.split(",")])
        return
    blocks = [tuple(int(v) for v in b.split("x")) for b in args.blocks.split(",")]
    levels = [float(v) for v in args.levels.split(",")]
    ks = [float(v) for v in args.k_s.split(",")]
    materials = args.materials.split(",")
    mfc_set = {k: float(v) for k, v in (kv.split("=") for kv in args.mfc_set.split(",") if kv)}
    solver = {k: float(v) for k, v in (kv.split("=") for kv in args.mfc_solver.split(",") if kv)}
    solver = {k: int(v) if k in ("max_iterations", "chunk") else v for k, v in solver.items()}
    p = mfc_model.parameters(args.tissue, **mfc_set)
    prefix = "mfc" if args.tissue == "apple" else f"mfc-{args.tissue}"
    x_ref = p["x_ref"]
    table = []
    for ncols, nrows in blocks:
        centres, row = shear.block(ncols, nrows, x_ref)
        name = f"{ncols}x{nrows}"
        for s in levels:
            mfc = None
            if not args.cgms_only:
                mfc = once(out / f"{prefix}-{name}-s{s:g}.json",
                           lambda: shear.mfc(centres, row, p, s, out / f"{prefix}-{name}-s{s:g}",
                                             solver=solver))
                if mfc is not None:
                    print(f"mfc {name} s={s:g}: {mfc.get('error') or shear.summarise(mfc)}",
                          file=sys.stderr)
            if args.mfc_only:
                table.append((name, len(centres), s, mfc, {}))
                continue
            sweeps = {}
            for mat in materials:
                mat_path = material.find(mat)
                runs = []
                for k in ks:
                    tag = f"cgms-{mat}-{name}-s{s:g}-kS{k:g}"
                    runs.append(once(out / f"{tag}.json", lambda: cgms_run(
                        centres, row, mat_path, s, out / tag, f"k_S {k!r}")))
                sweeps[mat] = runs
            table.append((name, len(centres), s, mfc, sweeps))
    if args.mfc_only:
        levels_report(table)
        return
    report(table, ks)


def settling(r):
    """How far an MFC run's G can be trusted: its free state (converged, largest force
    left, the last chunk's largest centroid move), G through the origin and with an
    intercept (a constant offset: stress from a free state still creeping), the spread of
    the single strains' stress / strain, the shear stress left back at 0 (of the largest),
    and the stored energy / the agent's work at the largest shear (1 for an elastic block
    measured right)."""
    rows = [x for x in r["rows"] if x["kind"] == "shear"]
    gamma = np.array([x["strain"] for x in rows])
    stress = np.array([x["stress"] for x in rows])
    done = shear.work(r["rows"], r["length"])
    last = len(rows) - 1
    free = r["free"]
    return dict(free_converged=bool(free["converged"]), free_fmax=free["fmax"],
                free_shift=free["shift"], G=float(gamma @ stress / (gamma @ gamma)),
                G_intercept=float(np.polyfit(gamma, stress, 1)[0]),
                G_min=float((stress / gamma).min()), G_max=float((stress / gamma).max()),
                G_interior=shear.summarise(r)["G_interior"],
                back=shear.summarise(r)["return_stress"],
                energy_work=float(r["rows"][last]["work_energy"] / done[last]))


def exponent(s1, g1, s2, g2):
    """The n of G proportional to s^n through two levels."""
    return float(math.log(g1 / g2) / math.log(s1 / s2))


def levels_report(table):
    """MFC shear modulus per level with its settling, and the exponent n of G ~ s^n
    between consecutive levels (Markdown)."""
    print("| block | s | G (N/m) | G with intercept | G per strain (min-max) | G interior | "
          "back to 0 | "
          "energy / work at 2 % | free state: converged, fmax (N), last move (um) | "
          "seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    done = {}
    for name, n, s, mfc, _ in table:
        if mfc is None or "error" in mfc:
            continue
        q = settling(mfc)
        done.setdefault(name, []).append((s, q["G"], q["G_intercept"]))
        print(f"| {name} | {s:g} | {q['G']:.4g} | {q['G_intercept']:.4g} | "
              f"{q['G_min']:.3g}-{q['G_max']:.3g} | {q['G_interior']:.3g} | "
              f"{100 * q['back']:.1f} % | "
              f"{q['energy_work']:.3f} | {'yes' if q['free_converged'] else 'no'}, "
              f"{q['free_fmax']:.2g}, {1e6 * q['free_shift']:.3g} | {mfc['seconds']:.0f} |")
    print()
    print("| block | levels | n from G | n from G with intercept |")
    print("|---|---|---|---|")
    for name, runs in done.items():
        runs.sort(reverse=True)
        for (s1, g1, h1), (s2, g2, h2) in zip(runs, runs[1:]):
            print(f"| {name} | {s1:g} -> {s2:g} | {exponent(s1, g1, s2, g2):.2f} | "
                  f"{exponent(s1, h1, s2, h2):.2f} |")


def report(table, ks):
    print("| block | cells | s | model | G clamped (N/m) | G interior (N/m) | "
          "M clamped (N/m) | G linearity | back to 0 | converged | seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, n, s, mfc, sweeps in table:
        entries = [("MFC", mfc)] + [(f"CGMS {m} k_S {k:g}", r) for m, runs in sweeps.items()
                                    for k, r in zip(ks, runs)]
        for label, r in entries:
            if r is None:
                continue
            if "error" in r:
                print(f"| {name} | {n} | {s:g} | {label} | {r['error']} | | | | | | |")
                continue
            g = shear.summarise(r)
            print(f"| {name} | {n} | {s:g} | {label} | {g['G_clamped']:.4g} | "
                  f"{g['G_interior']:.4g} | {g.get('M_clamped', float('nan')):.4g} | "
                  f"{g['G_clamped_linearity']:.3f} | {g['return_stress']:.3f} | "
                  f"{'yes' if g['converged'] else 'NO'} | {r['seconds']:.0f} |")
    print()
    print("| block | s | material | measure | MFC G | CGMS G(k_S=0) | dG/dk_S | k_S match | "
          "M_CGMS/M_MFC at match |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, n, s, mfc, sweeps in table:
        if mfc is None or "error" in mfc:
            continue
        gm = shear.summarise(mfc)
        for mat, runs in sweeps.items():
            ok = [(k, shear.summarise(r)) for k, r in zip(ks, runs) if r and "error" not in r]
            if len(ok) < 2:
                continue
            for measure in ("clamped", "interior"):
                key = f"G_{measure}"
                k, slope, g0 = matching_k_S([k for k, _ in ok], [g[key] for _, g in ok],
                                            gm[key])
                m_cgms = np.interp(k, [k for k, _ in ok], [g["M_clamped"] for _, g in ok])
                print(f"| {name} | {s:g} | {mat} | {measure} | {gm[key]:.4g} | {g0:.3g} | "
                      f"{slope:.4g} | **{k:.3g}** | {m_cgms / gm['M_clamped']:.3g} |")


if __name__ == "__main__":
    main()
