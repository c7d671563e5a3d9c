# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Two 3-D MFC reference sets of one block, level by level (doc/results/mfc.md, "3-D
walls that pass through themselves"): the tissue's hull volume and surface and the
centroid hull's volume of each and their relative difference, the cell centroids' RMS and
largest distance (each set about its own mean, as the seed comparison), the mean cell wall
area; and, where a folder holds the level's wall dump (``walls.s<s>.dump``, a study's
output folder), what its walls do: triangle pairs through one cell's wall, own-cell
unbonded particle pairs inside the self-avoidance's radius and the closest, the shortest
and longest wall bond.

    /usr/bin/python3 studies/mfc/compare3d.py reference/mfc3d/block2 <study folder>
"""

import json
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from cgms.mfc import crossing3d, model as mfc_model, tissue3d


def level(folder, s):
    info = json.loads((Path(folder) / f"level.s{s}.json").read_text())
    cells = np.loadtxt(Path(folder) / f"cells.s{s}.csv", delimiter=",", skiprows=1)
    return info, cells


def walls(folder, s, w):
    """The level's wall measures from its dump, or None without one."""
    dump = Path(folder) / f"walls.s{s}.dump"
    if not dump.exists():
        return None
    rows = dump.read_text().split("ITEM: ATOMS")[1].splitlines()[1:]
    a = np.array([[float(v) for v in r.split()] for r in rows if r.strip()])
    x = a[np.argsort(a[:, 0]), 2:5]
    m = len(w["x"])
    found = crossing3d.tissue_crossings(x, w["tri"], m)
    pairs = cKDTree(x).query_pairs(w["self_r0"], output_type="ndarray")
    pairs = pairs[pairs[:, 0] // m == pairs[:, 1] // m]
    bonded = {tuple(e) for e in np.sort(w["edges"], axis=1)}
    local = np.sort(pairs % m, axis=1)
    keep = np.array([tuple(p) not in bonded for p in local], bool)
    pairs = pairs[keep] if len(pairs) else pairs
    d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1) if len(pairs) else []
    e = np.concatenate([w["edges"] + c * m for c in range(len(x) // m)])
    length = np.linalg.norm(x[e[:, 1]] - x[e[:, 0]], axis=1)
    return dict(crossed=len({r[0] for r in found["self"]}), self_pairs=len(found["self"]),
                between=len(found["between"]), inside=len(pairs),
                closest=float(min(d)) if len(d) else float("nan"),
                shortest=float(length.min()), longest=float(length.max()))


def main(old, new):
    w = tissue3d.wall(mfc_model.parameters("apple"))
    print("| s | hull V old / new (1e-11 m^3) | dV | hull S old / new (1e-7 m^2) | dS | "
          "centroid hull V old / new (1e-12 m^3) | dV_c | centroids RMS / max (um) | "
          "mean wall area old / new (1e-8 m^2) |")
    print("|---|---|---|---|---|---|---|---|---|")
    names = sorted((f.name[len("level.s"):-len(".json")] for f in Path(new).glob("level.s*.json")),
                   key=lambda n: -float(n))
    for s in names:
        (a, ca), (b, cb) = level(old, s), level(new, s)
        pa, pb = ca[:, 1:4] - ca[:, 1:4].mean(axis=0), cb[:, 1:4] - cb[:, 1:4].mean(axis=0)
        dist = np.linalg.norm(pa - pb, axis=1) * 1e6
        print(f"| {s} | {a['volume'] * 1e11:.4f} / {b['volume'] * 1e11:.4f} | "
              f"{b['volume'] / a['volume'] - 1:+.2%} | {a['surface'] * 1e7:.4f} / "
              f"{b['surface'] * 1e7:.4f} | {b['surface'] / a['surface'] - 1:+.2%} | "
              f"{a['centroid_volume'] * 1e12:.4f} / {b['centroid_volume'] * 1e12:.4f} | "
              f"{b['centroid_volume'] / a['centroid_volume'] - 1:+.2%} | "
              f"{np.sqrt(np.mean(dist ** 2)):.2f} / {dist.max():.2f} | "
              f"{ca[:, 5].mean() * 1e8:.4f} / {cb[:, 5].mean() * 1e8:.4f} |")
    for folder in (old, new):
        rows = [(s, walls(folder, s, w)) for s in names]
        rows = [(s, r) for s, r in rows if r is not None]
        if not rows:
            continue
        print(f"\n{folder}: | s | cells crossing themselves | own triangle pairs | pairs "
              f"between cells | unbonded own pairs inside {w['self_r0'] * 1e6:g} um | "
              "closest (um) | shortest / longest bond (um) |")
        for s, r in rows:
            print(f"| {s} | {r['crossed']} | {r['self_pairs']} | {r['between']} | "
                  f"{r['inside']} | {r['closest'] * 1e6:.2f} | {r['shortest'] * 1e6:.2f} / "
                  f"{r['longest'] * 1e6:.2f} |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
