# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""k_S from the fine model's shear stiffness (doc/calibration.md): the shear and uniaxial
test of cgms.shear on blocks of cells, in the MFC (fast variant) and in CGMS over a range of
k_S, and the k_S whose shear modulus matches the MFC's.

    /usr/bin/python3 examples/mfc/shear.py OUT [--blocks 8x5,12x7] [--levels 1,0.8]
        [--materials apple-mfc,apple] [--k-s 0,0.5,1,2,4] [--mfc-only | --cgms-only]

One JSON per run in OUT (``mfc-<block>-s<s>.json``, ``cgms-<material>-<block>-s<s>-kS<k>.json``);
a run whose JSON exists is read back, not run again, so an interrupted study resumes.
Prints Markdown tables: per block and level the MFC's moduli and, per material, CGMS's
modulus without k_S, its mean slope in k_S, and the matching k_S (clamped and interior
measures).
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from cgms import folders, material, mfc_model, shear


def _jsonable(o):
    return o.tolist() if hasattr(o, "tolist") else float(o)


def once(path, make):
    """The run stored at ``path``, made by ``make()`` if it is not there yet."""
    if path.exists():
        return folders.read_json(path)
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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--blocks", default="8x5,12x7")
    ap.add_argument("--levels", default="1,0.8")
    ap.add_argument("--materials", default="apple-mfc,apple")
    ap.add_argument("--k-s", default="0,0.5,1,2,4")
    ap.add_argument("--mfc-only", action="store_true")
    ap.add_argument("--cgms-only", action="store_true")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    blocks = [tuple(int(v) for v in b.split("x")) for b in args.blocks.split(",")]
    levels = [float(v) for v in args.levels.split(",")]
    ks = [float(v) for v in args.k_s.split(",")]
    materials = args.materials.split(",")
    p = mfc_model.parameters("apple")
    x_ref = p["x_ref"]
    table = []
    for ncols, nrows in blocks:
        centres, row = shear.block(ncols, nrows, x_ref)
        name = f"{ncols}x{nrows}"
        for s in levels:
            mfc = None
            if not args.cgms_only:
                mfc = once(out / f"mfc-{name}-s{s:g}.json",
                           lambda: shear.mfc(centres, row, p, s, out / f"mfc-{name}-s{s:g}"))
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
    report(table, ks)


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
            ok = [(k, shear.summarise(r)) for k, r in zip(ks, runs) if "error" not in r]
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
