# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""CGMS against the fine-scale (MFC) reference, tissue by tissue and level by level.

Usage (after ``source build/env.sh``; doc/results/validation.md, "CGMS against the MFC"):

    python3 studies/calibration/compare.py --mfc MFC_FOLDER \
        --cgms paper=results/microscale/apple --cgms calibrated=results/microscale/apple-mfc \
        --out doc/results/validation-mfc

MFC_FOLDER holds one folder per tissue (``python3 -m cgms mfc ... --out MFC_FOLDER``) with
``centroids.s<s>.txt``; each ``--cgms`` folder is a ``python3 -m cgms main`` study with
``<tissue>/level.s<s>.npy``. Cell i of the MFC is bead i of CGMS (the same builder), so
per level it writes: A/A0, P/P0, EL/EL0 of both (outline of the cell centroids,
``cgms.morphology.measures``, each normalised by its own s = 1 state; in the CSV also the
second-moment elongation ELpca/ELpca0, after the others), their relative
deviations CGMS/MFC - 1, and the centroid RMSD of eqn (2) with rigid motion removed.
Outputs: ``<out>.csv``, a Markdown table on stdout, ``<out>.png`` (like the paper's Fig. 5).
Only tissue-level pairs present in both are compared; the rest is listed as missing.
"""

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

from cgms import morphology, positions, study, superpose
from cgms.tissue import MICROSCALE

LEVELS = (1.0, 0.8, 0.6, 0.4, 0.3)
KEYS = ("A/A0", "P/P0", "EL/EL0")
#: beside the paper's three: the second-moment elongation (cgms.morphology.polygon_elongation),
#: in the CSV after the columns above and in the largest deviations, not in the table
EXTRA = ("ELpca/ELpca0",)


def mfc_folder(root, name):
    """The MFC folder of a tissue: its name, or ``Path(name).stem`` as older ``cgms mfc``
    runs named it (``2.0x2.5`` -> ``2.0x2``, shared with 2.0x2.0: :func:`compare` checks the
    cell count)."""
    exact = Path(root) / name
    return exact if exact.is_dir() else Path(root) / Path(name).stem


def mfc_xy(root, name, s):
    path = mfc_folder(root, name) / f"centroids.s{s:g}.txt"
    if not path.is_file():
        return None
    ids, xy = positions.read_centroids(path)
    return xy[np.argsort(ids)]


def cgms_xy(root, name, s):
    path = Path(root) / name / f"level.{study.level_name(s)}.npy"
    return np.load(path) if path.is_file() else None


#: longest outline edge as a factor of the median nearest-neighbour distance (None: the
#: outline's default, 1.5); set by --max-edge
EDGE = [None]


def _measures(xy):
    if EDGE[0] is None:
        return morphology.measures(xy)
    nearest = np.sort(np.linalg.norm(xy[:, None] - xy[None], axis=-1), axis=1)[:, 1]
    return morphology.measures(xy, max_edge=EDGE[0] * float(np.median(nearest)))


def normalised(xy, fresh):
    return morphology.normalise(_measures(xy), _measures(fresh))


def compare(mfc_root, cgms_roots, tissues=tuple(MICROSCALE), levels=LEVELS):
    """Rows ``{tissue, beads, s, set, MFC A/A0 ..., CGMS A/A0 ..., dev A/A0 ..., rmsd_um}``
    and the list of (tissue, s) pairs without an MFC or CGMS state."""
    rows, missing = [], []
    for name in tissues:
        q0 = mfc_xy(mfc_root, name, 1.0)
        for s in levels:
            q = mfc_xy(mfc_root, name, s)
            if q is None or q0 is None:
                missing.append((name, s, "MFC"))
                continue
            ref = normalised(q, q0)
            for label, root in cgms_roots.items():
                p, p0 = cgms_xy(root, name, s), cgms_xy(root, name, 1.0)
                if p is None or p0 is None:
                    missing.append((name, s, label))
                    continue
                if len(p) != len(q):   # an old shared MFC folder holds another tissue
                    missing.append((name, s, f"MFC folder has {len(q)} cells, not {len(p)}"))
                    continue
                got = normalised(p, p0)
                row = dict(tissue=name, beads=len(q), s=s, set=label,
                           rmsd_um=superpose.rmsd(p, q, "rigid") * 1e6)
                for k in KEYS + EXTRA:
                    row[f"MFC {k}"] = ref[k]
                    row[f"CGMS {k}"] = got[k]
                    row[f"dev {k} %"] = 100 * (got[k] / ref[k] - 1)
                rows.append(row)
    return rows, missing


def markdown(rows):
    head = ("| tissue | s | set | MFC A/A0 | CGMS A/A0 | dev % | MFC P/P0 | CGMS P/P0 | dev % "
            "| MFC EL/EL0 | CGMS EL/EL0 | dev % | RMSD (um) |")
    lines = [head, "|" + "---|" * 13]
    for r in rows:
        lines.append(f"| {r['tissue']} | {r['s']:g} | {r['set']} | "
                     + " | ".join(f"{r['MFC ' + k]:.4f} | {r['CGMS ' + k]:.4f} | "
                                  f"{r['dev ' + k + ' %']:+.2f}" for k in KEYS)
                     + f" | {r['rmsd_um']:.2f} |")
    return "\n".join(lines)


def worst(rows):
    """Largest |deviation| per set and measure, and the largest RMSD, over dried levels."""
    out = {}
    for label in dict.fromkeys(r["set"] for r in rows):
        sub = [r for r in rows if r["set"] == label and r["s"] < 1]
        if sub:
            out[label] = {k: max(abs(r[f"dev {k} %"]) for r in sub) for k in KEYS + EXTRA}
            out[label]["rmsd_um"] = max(r["rmsd_um"] for r in sub)
    return out


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tissues = list(dict.fromkeys(r["tissue"] for r in rows))
    sets = list(dict.fromkeys(r["set"] for r in rows))
    styles = ["--", "-", ":", "-."]
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6), constrained_layout=True)
    for ax, k in zip(axes, KEYS):
        for c, name in enumerate(tissues):
            colour = f"C{c}"
            mine = [r for r in rows if r["tissue"] == name]
            first = [r for r in mine if r["set"] == sets[0]]
            ax.plot([r["s"] for r in first], [r[f"MFC {k}"] for r in first], "o",
                    color=colour, mfc="none", label=f"{name} MFC" if k == KEYS[0] else None)
            for j, label in enumerate(sets):
                sub = [r for r in mine if r["set"] == label]
                ax.plot([r["s"] for r in sub], [r[f"CGMS {k}"] for r in sub],
                        styles[j % len(styles)], color=colour, lw=1,
                        label=f"CGMS {label}" if (k == KEYS[0] and c == 0) else None)
        ax.set_xlabel("X/X0 (dryness level s)")
        ax.set_ylabel(k)
        ax.invert_xaxis()
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mfc", required=True, help="folder of the MFC study (one folder per tissue)")
    ap.add_argument("--cgms", action="append", required=True, metavar="LABEL=FOLDER",
                    help="a 'cgms main' study folder and its label; repeat")
    ap.add_argument("--tissues", default=",".join(MICROSCALE), help="comma separated")
    ap.add_argument("--out", help="write <out>.csv and <out>.png (never replaced)")
    ap.add_argument("--max-edge", type=float,
                    help="longest outline edge, times the median nearest-neighbour distance "
                         "(default 1.5; 2-2.5 follows an MFC tissue whose dried cells "
                         "wrinkle apart: reference/mfc/README.md)")
    args = ap.parse_args(argv)
    roots = dict(item.split("=", 1) for item in args.cgms)
    EDGE[0] = args.max_edge
    rows, missing = compare(args.mfc, roots, args.tissues.split(","))
    if not rows:
        sys.exit(f"compare: no tissue level with both an MFC and a CGMS state under {args.mfc}")
    print(markdown(rows))
    for label, w in worst(rows).items():
        print(f"\nlargest |deviation| at s < 1, {label}: "
              + ", ".join(f"{k} {w[k]:.2f} %" for k in KEYS + EXTRA)
              + f", RMSD {w['rmsd_um']:.2f} um")
    if missing:
        print("\nmissing: " + ", ".join(f"{n} s={s:g} ({what})" for n, s, what in missing))
    if args.out:
        csv_path, png = Path(args.out + ".csv"), Path(args.out + ".png")
        for p in (csv_path, png):
            if p.exists():
                sys.exit(f"compare: {p} exists; choose another --out")
        with open(csv_path, "x", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        plot(rows, png)
        print(f"\ncompare: {csv_path}, {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
