# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Why the MFC's long tissues elongate (doc/results/shaped-results.md, "2026-12-03"): the
stretch of the MFC's centroid network by bond class, on the reference tissues.

The bonds are the edges of the fresh centroids' Delaunay network (gap.py's, longest edge
1.5 median edges; the same bonds at every level). Classes: *outline* (an edge of one
triangle only: both cells on the boundary, the bond runs along the outline), *spoke* (one
end on the boundary: across the boundary layer), *interior* (no end on the boundary). Per
level and class the mean stretch |b| / |b0| over sqrt(s) (1: the bond shrinks as the
cells' linear size), the outline bonds split into those along the long sides (fresh bond
within 30 degrees of the tissue's long axis y) and the short sides; the interior
network's own shape change (least-squares affine map of the interior bonds: stretch along
x and y over sqrt(s)); the tissue's extent (centroid span) along y and x over sqrt(s);
each boundary cell's least-squares map of its bonds along the outline's tangent and its
normal (``rim Ftt``, ``rim Fnn``, over sqrt(s)); the boundary cells' area and perimeter
ratios and elongation against the interior's.

    python3 studies/shaped/rim.py [--tissues calibration,...] [--root FOLDER]
                                  [--model JSON | --states FOLDER]

``--root`` reads another MFC run's tissue folders (e.g. a second kick seed). ``--model
JSON`` measures the tensor variant's beads (cgms.shaped_tensor, parameters as table.py's
--params, a ramp run here: 1-25 min per tissue) on the same bonds instead of the MFC's
centroids; ``--states FOLDER`` measures the states table.py --save wrote there and adds
the boundary cells' own |F t| / |F n| and the interior cells' orientation order (of the
long axes of their F, with the mean axis from x). A few seconds for the MFC.
"""

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
LEVELS = ("0.8", "0.6", "0.4", "0.3")


def load(tissue, s, root=ROOT / "reference" / "mfc"):
    t = np.genfromtxt(root / tissue / f"cells.s{s}.csv", delimiter=",", names=True)
    return np.column_stack([t["x"], t["y"]]), t


def classes(xy0, longest=1.5):
    """Bonds (b, 2), boundary cells (n bool), bond class per bond ('outline', 'spoke',
    'interior', 'corner': both ends on the boundary but not an outline edge)."""
    tri = Delaunay(xy0).simplices
    edge = np.stack([np.linalg.norm(xy0[tri[:, i]] - xy0[tri[:, (i + 1) % 3]], axis=1)
                     for i in range(3)], 1)
    tri = tri[edge.max(axis=1) < longest * np.median(edge)]
    count = Counter(tuple(sorted((int(t[i]), int(t[(i + 1) % 3])))) for t in tri
                    for i in range(3))
    bonds = np.array(sorted(count))
    outline = np.array([count[tuple(b)] == 1 for b in bonds])
    rim = np.zeros(len(xy0), bool)
    rim[bonds[outline].ravel()] = True
    on = rim[bonds].sum(axis=1)
    kind = np.where(outline, "outline", np.where(on == 2, "corner",
                                                 np.where(on == 1, "spoke", "interior")))
    return bonds, rim, kind


def affine(b0, b):
    """Least-squares F with b = F b0; its stretches along x and y (diagonal of F)."""
    F = np.linalg.lstsq(b0, b, rcond=None)[0].T
    return F[0, 0], F[1, 1]


def measure(xy0, xy, s, bonds, rim, kind, cells=None, cells0=None):
    b0 = xy0[bonds[:, 1]] - xy0[bonds[:, 0]]
    b = xy[bonds[:, 1]] - xy[bonds[:, 0]]
    st = np.linalg.norm(b, axis=1) / np.linalg.norm(b0, axis=1) / np.sqrt(s)
    along_y = np.abs(b0[:, 1]) > np.cos(np.radians(30)) * np.linalg.norm(b0, axis=1)
    r = dict(s=s)
    for k in ("outline", "spoke", "interior"):
        r[k] = st[kind == k].mean()
    r["outline long"] = st[(kind == "outline") & along_y].mean()
    r["outline short"] = st[(kind == "outline") & ~along_y].mean()
    r["interior Fx"], r["interior Fy"] = (v / np.sqrt(s) for v in
                                          affine(b0[kind == "interior"], b[kind == "interior"]))
    r["span x"] = np.ptp(xy[:, 0]) / np.ptp(xy0[:, 0]) / np.sqrt(s)
    r["span y"] = np.ptp(xy[:, 1]) / np.ptp(xy0[:, 1]) / np.sqrt(s)
    # the spokes' component along the boundary cell's outward normal (fresh spoke direction)
    sp = kind == "spoke"
    u0 = b0[sp] / np.linalg.norm(b0[sp], axis=1)[:, None]
    r["spoke normal"] = np.mean(np.abs(np.sum(b[sp] * u0, axis=1))
                                / np.linalg.norm(b0[sp], axis=1)) / np.sqrt(s)
    # each boundary cell's least-squares F of its bonds, along the outline's tangent t and
    # its outward normal n (fresh: from the mean of its neighbours to the cell)
    ftt, fnn = [], []
    for i in np.flatnonzero(rim):
        k = np.concatenate([bonds[bonds[:, 0] == i, 1], bonds[bonds[:, 1] == i, 0]])
        F = np.linalg.lstsq(xy0[k] - xy0[i], xy[k] - xy[i], rcond=None)[0].T
        n = xy0[i] - xy0[k].mean(axis=0)
        n /= np.linalg.norm(n)
        t = np.array([-n[1], n[0]])
        ftt.append(t @ F @ t)
        fnn.append(n @ F @ n)
    r["rim Ftt"], r["rim Fnn"] = np.mean(ftt) / np.sqrt(s), np.mean(fnn) / np.sqrt(s)
    if cells is not None:
        for name, sel in (("rim", rim), ("inner", ~rim)):
            r[f"A {name}"] = np.mean(cells["area"][sel] / cells0["area"][sel])
            r[f"P {name}"] = np.mean(cells["perimeter"][sel] / cells0["perimeter"][sel])
            r[f"el {name}"] = np.mean(cells["elongation"][sel])
    return r


def model_states(tissue, params):
    """The tensor variant's bead positions per level (table.py's run, kick 1e-3)."""
    sys.path.insert(0, str(ROOT / "studies" / "shaped"))
    import table
    from cgms import shaped_tensor
    mat, xy = table.layout(tissue)
    p = table.wall_params(mat, table.given_params(shaped_tensor, json.dumps(params)))
    kick = p.pop("kick", 1e-3)
    levels = (1.0,) + tuple(float(s) for s in LEVELS)
    geo, states = shaped_tensor.ramp(xy, mat, levels, p, kick=kick)
    return {f"{s:g}": shaped_tensor.split(z, geo["n"])[0] for s, z, _ in states}


def saved_states(tissue, folder):
    """Bead positions per level of a state file written by table.py --save; with the
    shape tensors F per level."""
    sys.path.insert(0, str(ROOT / "studies" / "shaped"))
    import table
    from cgms import shaped_tensor
    d = np.load(Path(folder) / f"{tissue}.npz")
    n = len(table.layout(tissue)[1])       # 6 numbers a cell, 8 with the network's shear
    out = {f"{s:g}": shaped_tensor.split(z, n) for s, z in zip(d["levels"], d["states"])}
    return {k: v[0] for k, v in out.items()}, {k: v[1] for k, v in out.items()}


def cell_flattening(xy0, F, rim, bonds):
    """Mean over the boundary cells of their own stretch along the outline over that
    along its normal, |F t| / |F n| (the tensor variant's cells)."""
    out = []
    for i in np.flatnonzero(rim):
        k = np.concatenate([bonds[bonds[:, 0] == i, 1], bonds[bonds[:, 1] == i, 0]])
        n = xy0[i] - xy0[k].mean(axis=0)
        n /= np.linalg.norm(n)
        t = np.array([-n[1], n[0]])
        out.append(np.linalg.norm(F[i] @ t) / np.linalg.norm(F[i] @ n))
    return float(np.mean(out))


def cell_order(F, sel):
    """Orientation order of the selected cells' long axes (the major axis of F F^T):
    |<exp(2 i theta)>| (0 unordered, 1 all parallel) and its mean axis in degrees from x."""
    B = np.einsum("nij,nkj->nik", F[sel], F[sel])
    theta = 0.5 * np.arctan2(2 * B[:, 0, 1], B[:, 0, 0] - B[:, 1, 1])
    z = np.mean(np.exp(2j * theta))
    return float(abs(z)), float(np.degrees(np.angle(z) / 2))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tissues", default="calibration,1.5x1.5,1.5x2.0,1.5x2.5,2.0x2.0,"
                    "2.0x2.5,potato-calibration")
    ap.add_argument("--model", default=None, help="JSON parameters of the tensor variant")
    ap.add_argument("--states", default=None, help="folder of table.py --save states to "
                    "measure instead of the MFC (adds the boundary cells' |F t| / |F n|)")
    ap.add_argument("--root", default=str(ROOT / "reference" / "mfc"),
                    help="folder of MFC tissue folders (cells.s<s>.csv)")
    args = ap.parse_args(argv)
    cols = ("outline", "outline long", "outline short", "spoke", "spoke normal", "rim Ftt",
            "rim Fnn", "interior", "interior Fx", "interior Fy", "span x", "span y")
    model = args.model or args.states
    if args.states:
        extra = ("cell Ft/Fn", "inner order", "inner axis deg")
    elif args.model:
        extra = ()
    else:
        extra = ("A rim", "A inner", "P rim", "P inner", "el rim", "el inner")
    print("| tissue | s | " + " | ".join(cols + extra) + " |")
    print("|---|---|" + "---|" * len(cols + extra))
    for tissue in args.tissues.split(","):
        xy0, c0 = load(tissue, "1", Path(args.root))
        bonds, rim, kind = classes(xy0)
        states = model_states(tissue, json.loads(args.model)) if args.model else None
        if args.states:
            states, Fs = saved_states(tissue, args.states)
        for s in LEVELS:
            if not model:
                xy, c = load(tissue, s, Path(args.root))
                r = measure(xy0, xy, float(s), bonds, rim, kind, c, c0)
            else:
                r = measure(states["1"], states[s], float(s), bonds, rim, kind)
                if args.states:
                    r["cell Ft/Fn"] = cell_flattening(states["1"], Fs[s], rim, bonds)
                    r["inner order"], r["inner axis deg"] = cell_order(Fs[s], ~rim)
            print(f"| {tissue} | {s} | " + " | ".join(f"{r[k]:.3f}" for k in cols + extra)
                  + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
