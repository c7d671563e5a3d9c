# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Where an MFC tissue's internal stress sits, and which way its cells flatten
(doc/results/shaped-results.md, "What elongates the fine model's long tissues").

Per dried level of a study folder (``cgms mfc --out``; every ``state.s<s>.data`` it holds,
written at full precision, so a study run with ``--dryness 0.8,0.75,0.7,...`` is measured
stage by stage; ``lamella.txt`` and ``setup.json``):

- the mean stress (N/m, tension positive) of the interior cells and of the rim cells (the
  cells on the fresh centroids' outline). Only the middle lamella (8-4 LJ between walls
  of different cells, and the truss bonds set in the fresh tissue) acts between cells, so
  for a region R of whole cells in static equilibrium the mean stress is exactly
  ``(1/A_R) sum x_c (x) f``, over the lamella pairs that cross R's edge, ``f`` the force on
  R's particle and ``x_c`` the pair's midpoint (with the midpoint the regions' stresses
  add up: interior A_int + rim A_rim = 0 for the free tissue). The check: the net force
  on each region over the sum of the pair forces' sizes (zero at a steady state, so the
  forces are the model's). ``A_R`` is R's share of the outline area (2.0 median
  spacings) by cell count.
- the cells' flattening: each wall polygon's second-moment elongation and the direction
  of its long axis; per region the mean elongation and the nematic order
  ``|<(cos 2t, sin 2t)>|`` with its angle from x;
- the interior network's stretch along x and y (least-squares affine map of the fresh
  interior bonds, the fresh centroids' Delaunay edges between interior cells).

    source build/env.sh
    /usr/bin/python3 studies/mfc/stress.py FOLDER [FOLDER ...]   # seconds per level
"""

import json
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay, cKDTree

from cgms import morphology
from cgms.mfc import model as mfc_model


def _section(lines, name):
    start = lines.index(name) + 2
    rows = []
    for line in lines[start:]:
        if not line.strip():
            break
        rows.append(line.split())
    return rows


def read_state(path):
    """Wall positions (n, 2) in ID order, their cell (0-based) and the lamella bonds
    (type >= 2) as (type, i, j), 0-based, of an MFC state file (atom_style angle)."""
    lines = Path(path).read_text().splitlines()
    atoms = np.array(_section(lines, "Atoms # angle"), dtype=float)
    atoms = atoms[np.argsort(atoms[:, 0])]
    index = {int(a): k for k, a in enumerate(atoms[:, 0])}
    bonds = np.array(_section(lines, "Bonds"), dtype=np.int64)[:, 1:4]
    bonds = bonds[bonds[:, 0] >= 2]
    bonds[:, 1] = [index[a] for a in bonds[:, 1]]
    bonds[:, 2] = [index[a] for a in bonds[:, 2]]
    cell = np.unique(atoms[:, 1].astype(np.int64), return_inverse=True)[1]
    return atoms[:, 3:5], cell, bonds


def inter_cell_forces(x, cell, bonds, rest, p):
    """The lamella's pair forces: (i, j, f), f (k, 2) the force on particle i from j.
    ``bonds`` (type, i, j) 0-based, ``rest`` {type: rest length}."""
    i, j = bonds[:, 1], bonds[:, 2]
    d = x[j] - x[i]
    r = np.linalg.norm(d, axis=1)
    r0 = np.array([rest[t] for t in bonds[:, 0]])
    f_bond = (p["lamella_k"] * (r - r0) / r)[:, None] * d     # LAMMPS harmonic K = k / 2
    pairs = cKDTree(x).query_pairs(p["lamella_rc"], output_type="ndarray")
    pairs = pairs[cell[pairs[:, 0]] != cell[pairs[:, 1]]]
    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    r = np.linalg.norm(d, axis=1)
    # nm/cut 8-4: E = E0 / (n - m) [m (r0/r)^n - n (r0/r)^m], so dE/dr as below
    n, m, E0, rp = 8, 4, p["lamella_E0"], p["pectin"]
    dEdr = E0 * n * m / (n - m) / r * ((rp / r) ** m - (rp / r) ** n)
    f_lj = (dEdr / r)[:, None] * d
    return (np.concatenate([i, pairs[:, 0]]), np.concatenate([j, pairs[:, 1]]),
            np.vstack([f_bond, f_lj]))


def region_stress(x, inside, i, j, f, area):
    """Mean stress of the region ``inside`` (bool per particle) and the net force on it."""
    a, b = inside[i], inside[j]
    cross = a != b
    on = np.where(a[cross, None], f[cross], -f[cross])   # the force on R's particle
    mid = 0.5 * (x[i[cross]] + x[j[cross]])
    return mid.T @ on / area, on.sum(axis=0)


def flattening(polys):
    """Per polygon (n, k, 2): second-moment elongation and long-axis angle (rad)."""
    el, ang = [], []
    for q in polys:
        _, _, (sxx, syy, sxy) = morphology._polygon_moments(q)
        w, v = np.linalg.eigh(np.array([[sxx, sxy], [sxy, syy]]))
        el.append(np.sqrt(w[1] / w[0]))
        ang.append(np.arctan2(v[1, 1], v[0, 1]))
    return np.array(el), np.array(ang)


def order(angles):
    """Nematic order |<e^(2it)>| and its direction (degrees from x)."""
    c, s = np.cos(2 * angles).mean(), np.sin(2 * angles).mean()
    return float(np.hypot(c, s)), float(np.degrees(0.5 * np.arctan2(s, c)))


def affine_stretch(c0, c, edges):
    """Stretch along x and y of the least-squares affine map of the bonds ``edges``."""
    d0, d = c0[edges[:, 1]] - c0[edges[:, 0]], c[edges[:, 1]] - c[edges[:, 0]]
    F = np.linalg.lstsq(d0, d, rcond=None)[0].T
    return float(np.linalg.norm(F[:, 0])), float(np.linalg.norm(F[:, 1]))


def level(folder, s, p, n_wall, rim, rest, c0, edges):
    xy, cell, bonds = read_state(folder / f"state.s{s:g}.data")
    polys = xy.reshape(-1, n_wall, 2)
    c = np.array([morphology._polygon_moments(q)[1] for q in polys])
    tissue_area = morphology.measures(
        c, morphology.default_max_edge(c, morphology.FINE_EDGE_FACTOR))["area"]
    i, j, f = inter_cell_forces(xy, cell, bonds, rest, p)
    scale = np.abs(f).sum()
    row = dict(s=s)
    el, ang = flattening(polys)
    for name, cells in (("interior", ~rim), ("rim", rim)):
        area = tissue_area * cells.sum() / len(cells)
        sigma, net = region_stress(xy, cells[cell], i, j, f, area)
        row[name] = dict(sigma=sigma.round(6).tolist(), net_over_sum=float(
            np.abs(net).max() / scale), elongation=float(el[cells].mean()),
            order=order(ang[cells]))
    row["interior_stretch_xy"] = affine_stretch(c0, c, edges)
    return row


def study(folder):
    folder = Path(folder)
    setup = json.loads((folder / "setup.json").read_text())
    p = setup["parameters"]
    n_wall = 6 * p.get("per_side", mfc_model.MFC["per_side"])
    fresh = read_state(folder / "state.s1.data")[0].reshape(-1, n_wall, 2)
    c0 = np.array([morphology._polygon_moments(q)[1] for q in fresh])
    rim = np.zeros(len(c0), bool)
    rim[morphology.measures(c0)["outline"]] = True
    tri = Delaunay(c0).simplices
    edges = np.unique(np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]),
                              axis=1), axis=0)
    spacing = np.median(np.linalg.norm(c0[edges[:, 1]] - c0[edges[:, 0]], axis=1))
    edges = edges[(np.linalg.norm(c0[edges[:, 1]] - c0[edges[:, 0]], axis=1) < 1.5 * spacing)
                  & ~rim[edges[:, 0]] & ~rim[edges[:, 1]]]
    rest = {int(t): r for t, r in np.loadtxt(folder / "lamella.txt", comments="#")}
    # every dried level the study wrote (a stage-by-stage study has more than the five)
    levels = sorted((float(f.name[len("state.s"):-len(".data")])
                     for f in folder.glob("state.s*.data")), reverse=True)
    return [level(folder, s, p, n_wall, rim, rest, c0, edges) for s in levels if s < 1]


def main(argv=None):
    for folder in (argv if argv is not None else sys.argv[1:]):
        print(f"# {folder}")
        print("| s | interior sxx, syy, sxy (mN/m) | rim sxx, syy, sxy (mN/m) | interior Fx, Fy "
              "| interior cells: elongation, order, angle | rim cells: elongation, order, "
              "angle | net force / sum |")
        print("|---|---|---|---|---|---|---|")
        for r in study(folder):
            a, b = r["interior"], r["rim"]
            fmt = lambda m: ", ".join(f"{1e3 * v:+.2f}" for v in (m[0][0], m[1][1], m[0][1]))  # noqa: E731
            cells = lambda q: f"{q['elongation']:.3f}, {q['order'][0]:.2f}, {q['order'][1]:+.0f}"  # noqa: E731
            print(f"| {r['s']:g} | {fmt(a['sigma'])} | {fmt(b['sigma'])} | "
                  f"{r['interior_stretch_xy'][0]:.3f}, {r['interior_stretch_xy'][1]:.3f} | "
                  f"{cells(a)} | {cells(b)} | {max(a['net_over_sum'], b['net_over_sum']):.0e} |")


if __name__ == "__main__":
    main()
