# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Pictures of dried tissues a food scientist recognises (matplotlib, PNG).

The model places one bead at each cell centroid; these functions draw the cells around
them, as a micrograph shows a tissue:

- :func:`voronoi_cells`: the Voronoi cell of every bead, cut off by a disc around the bead,
  so cells on the tissue edge get a rounded free wall (and holes stay holes);
- :func:`hexagon_cells`: the model's own virtual cells, regular hexagons of the side ``b``
  that fix cgms/fluid computes (column ``side``), turned with the lattice; the gaps between
  them are the pectin layers;
- :func:`draw_tissue`: cells on a matplotlib axes, coloured by a per-bead field, with the
  outline of the fresh tissue drawn over the dried one;
- :func:`snapshots`: one figure of a tissue at every moisture level (the paper's Figs 3
  and 6), cells coloured by a field on one scale, every panel at the same magnification;
- :func:`curves_all`: A/A0, EL/EL0 and P/P0 against the moisture reached for several
  tissues together (the paper's Fig. 5), or for one;
- :func:`sensitivity`: the morphology against the factor on each parameter (the paper's
  Figs 11, 13 and 15);
- :func:`study_pictures`: all of the above for a results folder of ``python3 -m cgms main``
  or ``study``.

Positions are in metres (drawn in mm); polygons are lists of (k, 2) vertex arrays.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from scipy.spatial import Voronoi, cKDTree  # noqa: E402

from . import folders, morphology, study  # noqa: E402

#: per-bead fields that can colour the cells: dump column -> (label, factor to the unit)
FIELDS = {
    "pressure": ("turgor pressure P (kPa)", 1e-3),
    "shrinkage": ("local area shrinkage 1 - a/a0", 1.0),
    "area": ("virtual-cell area A (um$^2$)", 1e12),
    "side": ("virtual-cell side b (um)", 1e6),
    "perim": ("virtual-cell perimeter l (um)", 1e6),
    "mf": ("fluid mass m$_f$ (ng)", 1e12),
    "rho": ("fluid density (kg/m$^3$)", 1.0),
    "dryness": ("prescribed dryness s", 1.0),
    "nneigh": ("neighbours N", 1.0),
    "dmdt": ("mass rate dm$_f$/dt (ng/s)", 1e12),
}

#: cell walls are drawn for tissues of at most this many beads
MAX_WALLED = 1600

#: the Voronoi cells are cut off by a disc of this radius (times the median bead spacing):
#: above the circumradius 1/sqrt(3) = 0.577 of a lattice cell, so inner cells stay whole
CLIP_RADIUS = 0.6


def _clip_convex(subject, clip):
    """Sutherland-Hodgman: the part of polygon ``subject`` inside the convex,
    counter-clockwise polygon ``clip`` ((k, 2) arrays)."""
    # plain floats: a cell has a few dozen vertices, where NumPy calls cost more than sums
    out = [tuple(v) for v in subject.tolist()]
    clip = clip.tolist()
    for (ax, ay), (bx, by) in zip(clip, clip[1:] + clip[:1]):
        if not out:
            break
        ex, ey = bx - ax, by - ay
        side = [ex * (y - ay) - ey * (x - ax) for x, y in out]    # >= 0: inside
        kept = []
        for k, (px, py) in enumerate(out):
            qx, qy = out[k - len(out) + 1]
            sp, sq = side[k], side[k - len(out) + 1]
            if sp >= 0:
                kept.append((px, py))
            if (sp >= 0) != (sq >= 0):
                t = sp / (sp - sq)
                kept.append((px + (qx - px) * t, py + (qy - py) * t))
        out = kept
    return np.array(out, dtype=float).reshape(-1, 2)


def voronoi_cells(xy, radius=None, sides=24):
    """The Voronoi cell of every bead, cut off by a regular ``sides``-gon of ``radius``
    around the bead (default ``CLIP_RADIUS`` times the median bead spacing; a number or one
    per bead). Returns a list of (k, 2) counter-clockwise vertex arrays, one per bead."""
    p = np.asarray(xy, dtype=float)[:, :2]
    n = len(p)
    spacing = morphology.spacing(p)
    radius = np.broadcast_to(CLIP_RADIUS * spacing if radius is None else radius, (n,))
    # a far frame of points closes the regions of the outer beads
    lo, hi = p.min(axis=0) - 10 * spacing, p.max(axis=0) + 10 * spacing
    frame = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    vor = Voronoi(np.vstack([p, frame]))
    angles = 2 * np.pi * (np.arange(sides) + 0.5) / sides
    disc = np.column_stack([np.cos(angles), np.sin(angles)])
    inside = radius * np.cos(np.pi / sides)    # a cell within this needs no clipping
    cells = []
    for i in range(n):
        region = vor.regions[vor.point_region[i]]
        vertices = vor.vertices[region]
        offsets = vertices - p[i]
        order = np.argsort(np.arctan2(offsets[:, 1], offsets[:, 0]))    # convex, around p_i
        if np.max(np.hypot(offsets[:, 0], offsets[:, 1])) <= inside[i]:
            cells.append(vertices[order])
        else:
            cells.append(_clip_convex(vertices[order], p[i] + radius[i] * disc))
    return cells


def lattice_angle(xy):
    """Direction of the lattice rows (radians, modulo 60 degrees): the circular mean of six
    times the angle of every nearest-neighbour bond, divided by six."""
    p = np.asarray(xy, dtype=float)[:, :2]
    spacing = morphology.spacing(p)
    pairs = cKDTree(p).query_pairs(1.3 * spacing, output_type="ndarray")
    d = p[pairs[:, 1]] - p[pairs[:, 0]]
    six = 6 * np.arctan2(d[:, 1], d[:, 0])
    return float(np.arctan2(np.sin(six).sum(), np.cos(six).sum()) / 6)


def hexagon_cells(xy, side, angle=None):
    """The virtual cells of the model: a regular hexagon of side ``side`` (one per bead, m;
    fix cgms/fluid's ``side`` column) around every bead, its flat walls facing the
    neighbours (``angle``: direction of a neighbour bond, default :func:`lattice_angle`)."""
    p = np.asarray(xy, dtype=float)[:, :2]
    side = np.broadcast_to(np.asarray(side, dtype=float), (len(p),))
    if angle is None:
        angle = lattice_angle(p)
    corners = angle + np.pi / 6 + np.pi / 3 * np.arange(6)    # between the bond directions
    unit = np.column_stack([np.cos(corners), np.sin(corners)])
    return list(p[:, None, :] + side[:, None, None] * unit[None, :, :])


def _loops(p):
    """Closed outlines through the peripheral bead centres: the outer one and those of the
    holes (:func:`cgms.morphology.boundary_cycles`), each as (k + 1, 2) positions."""
    return [p[np.r_[c, c[:1]]] for c, _ in morphology.boundary_cycles(p)]


def _centroid(p):
    """Area centroid of the outer outline (holes counted as tissue: no warning)."""
    outer = morphology.boundary_cycles(p)[0][0]
    return morphology._polygon_moments(p[outer])[1]


def draw_tissue(ax, xy, values, cells="voronoi", side=None, norm=None, cmap="viridis",
                fresh_xy=None):
    """Draw the cells of one tissue state on ``ax``, coloured by ``values`` (one per bead,
    already in display units), in mm. ``cells``: ``"voronoi"`` or ``"hexagon"`` (needs
    ``side``). ``fresh_xy``: bead positions of the fresh tissue, whose outline (through the
    peripheral bead centres, the line the paper's A and P measure) is drawn dashed over
    this one, centred on this one's outline. Returns the PolyCollection (for a colour bar)."""
    p = np.asarray(xy, dtype=float)[:, :2]
    if cells == "voronoi":
        polys = voronoi_cells(p)
    elif cells == "hexagon":
        if side is None:
            raise ValueError("cells='hexagon' needs the per-bead side b (the dump's 'side')")
        polys = hexagon_cells(p, side)
    else:
        raise ValueError(f"cells must be 'voronoi' or 'hexagon', got {cells!r}")
    # cell walls while a panel shows fewer than about 40 cells across; beyond that they
    # would only darken the colours
    walls = dict(edgecolors="0.35", linewidths=0.3) if len(p) <= MAX_WALLED else \
        dict(edgecolors="face", linewidths=0.0)
    collection = PolyCollection([c * 1e3 for c in polys], array=np.asarray(values, float),
                                cmap=cmap, norm=norm, **walls)
    ax.add_collection(collection)
    for loop in _loops(p):
        ax.plot(*(loop.T * 1e3), color="k", lw=0.8)
    if fresh_xy is not None:
        f = np.asarray(fresh_xy, dtype=float)[:, :2]
        shift = np.subtract(_centroid(p), _centroid(f))
        for loop in _loops(f):
            ax.plot(*((loop + shift).T * 1e3), color="k", lw=1.0, ls="--")
    ax.set_aspect("equal")
    return collection


def snapshots(states, path, field="pressure", cells="voronoi", cmap=None, title=""):
    """One figure with a panel per state, like the paper's Figs 3 and 6. ``states``: a list
    of dicts with ``title``, ``xy`` and ``values`` (SI units of ``field``, one per bead) and,
    for hexagons, ``side``; the state with the largest ``dryness`` (or the first) is the
    fresh one, whose outline is drawn over the others, unless a state names its own fresh
    positions (``fresh_xy``; None: no fresh outline). Every panel has the same scale."""
    label, factor = FIELDS.get(field, (field, 1.0))
    cmap = cmap or ("YlOrRd" if field == "shrinkage" else "viridis")
    values = [np.asarray(s["values"], float) * factor for s in states]
    finite = np.concatenate([v[np.isfinite(v)] for v in values])
    norm = plt.Normalize(*(np.percentile(finite, [0, 100]) if finite.size else (0, 1)))
    fresh = max(range(len(states)), key=lambda k: states[k].get("dryness", -k))
    half = 0.5e3 * max(np.ptp(np.asarray(s["xy"])[:, :2], axis=0).max() for s in states)
    half += 1e3 * morphology.spacing(states[fresh]["xy"])
    width = 2.9 * len(states) + 1.2
    fig, axes = plt.subplots(1, len(states), figsize=(width, 3.7), squeeze=False)
    fig.subplots_adjust(left=0.8 / width, right=1 - 1.3 / width, bottom=0.14, top=0.8,
                        wspace=0.25)
    for k, (ax, state, v) in enumerate(zip(axes[0], states, values)):
        coll = draw_tissue(ax, state["xy"], v, cells, state.get("side"), norm, cmap,
                           fresh_xy=fresh_outline(states, k, fresh))
        cx, cy = _centroid(np.asarray(state["xy"], dtype=float)[:, :2]) * 1e3
        ax.set_xlim(cx - half, cx + half)
        ax.set_ylim(cy - half, cy + half)
        ax.set_title(state["title"], fontsize=9)
        ax.set_xlabel("x (mm)")
    axes[0][0].set_ylabel("y (mm)")
    fig.colorbar(coll, cax=fig.add_axes([1 - 1.0 / width, 0.18, 0.12 / width, 0.58]),
                 label=label)
    key = "solid line: outline through the peripheral bead centres" + \
        ("; dashed: the fresh one" if any(fresh_outline(states, k, fresh) is not None
                                          for k in range(len(states))) else "")
    fig.suptitle(f"{title}\n{key}" if title else key, fontsize=9)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def fresh_outline(states, k, fresh):
    """The fresh positions whose outline :func:`snapshots` draws over state ``k``."""
    if "fresh_xy" in states[k]:
        return states[k]["fresh_xy"]
    return None if k == fresh else states[fresh]["xy"]


def curves_all(tables, path, title=""):
    """A/A0, EL/EL0 and P/P0 against the moisture reached X/X0, every tissue in one figure
    (the paper's Fig. 5 a-c). ``tables``: {tissue label: rows of :func:`cgms.study.table`}."""
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8), constrained_layout=True)
    markers = "osD^v<>ph*"
    for k, (name, rows) in enumerate(tables.items()):
        rows = sorted(rows, key=lambda r: -r["X/X0"])
        x = [r["X/X0"] for r in rows]
        for ax, key in zip(axes, ("A/A0", "EL/EL0", "P/P0")):
            ax.plot(x, [r[key] for r in rows], marker=markers[k % len(markers)], ms=4, lw=1,
                    label=name)
    for ax, key, letter in zip(axes, ("A/A0", "EL/EL0", "P/P0"), "abc"):
        ax.set_xlabel("moisture reached X/X$_0$")
        ax.set_ylabel(key)
        ax.set_title(f"({letter}) {key}", fontsize=10, loc="left")
        ax.invert_xaxis()    # drying goes from left to right
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, frameon=False)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def _levels(folder):
    """The finished levels of one tissue folder of a study (``level.s<s>.json`` and
    ``.npy``), wettest first, as :func:`cgms.study.sweep` returns them."""
    results = []
    for done in Path(folder).glob("level.s*.json"):
        result = folders.read_json(done)
        result["xy"] = folders.read_npy(done.with_suffix(".npy"))
        results.append(result)
    return sorted(results, key=lambda r: -r["dryness"])


def _field(folder, result, field, fresh, cells):
    """One level's values of ``field``: local shrinkage from the fresh level, or a column
    of the level's final dump; and the cell sides (the dump's ``side``) for hexagons."""
    dump = study.dump_file(folder, result)
    names = {field} - {"shrinkage"} | ({"side"} if cells == "hexagon" else set())
    frame = morphology.read_dump(dump, columns=sorted(names))[-1]
    if not np.allclose(frame["xy"], result["xy"], rtol=0, atol=1e-9):
        raise ValueError(f"{dump} does not hold the positions of {folder}/level.*.npy")
    if field == "shrinkage":
        values = morphology.shrinkage(result["xy"], fresh["xy"])
    else:
        values = frame["columns"][field]
    return values, frame["columns"].get("side")


def study_pictures(folder, field="pressure", cells="voronoi"):
    """The pictures of a results folder of ``python3 -m cgms main`` (or ``study``): for every
    tissue in it, ``<tissue>/cells-<field>.png`` (its cells at every level, coloured by
    ``field``, the fresh outline dashed over each dried state) and ``cells-shrinkage.png``;
    and ``curves-all.png`` beside the tissues (all tissues' A/A0, EL/EL0, P/P0 against
    X/X0). Returns the paths written."""
    folder = Path(folder)
    tissues = sorted(p.parent for p in folder.glob("*/level.s*.json"))
    tissues = list(dict.fromkeys(tissues))
    if not tissues:
        raise FileNotFoundError(f"{folder} holds no study results (*/level.s*.json)")
    written, tables = [], {}
    for tissue_dir in tissues:
        results = _levels(tissue_dir)
        fresh = results[0]
        label = f"{tissue_dir.name} ({len(fresh['xy'])} beads)"
        tables[label] = [dict(r, beads=len(fresh["xy"])) for r in study.table(results)]
        for name in dict.fromkeys((field, "shrinkage")):
            states = []
            for r in results:
                values, side = _field(tissue_dir, r, name, fresh, cells)
                states.append(dict(title=f"s = {r['dryness']:g}, X/X0 = {r['moisture']:.3f}",
                                   xy=r["xy"], values=values, side=side,
                                   dryness=r["dryness"]))
            written.append(snapshots(states, tissue_dir / f"cells-{name}.png", name, cells,
                                     title=label))
    by_size = sorted(tables.items(), key=lambda item: item[1][0]["beads"])
    written.append(curves_all(dict(by_size), folder / "curves-all.png"))
    return written


def sensitivity(rows, path, level=0.3):
    """A/A0, P/P0, EL/EL0 at one dryness against the factor on each parameter (like the
    paper's Figs 11, 13 and 15, at their driest level)."""
    params = list(dict.fromkeys(r["parameter"] for r in rows))
    fig, axes = plt.subplots(3, len(params), figsize=(3.6 * len(params), 7.5),
                             constrained_layout=True, squeeze=False)
    for j, param in enumerate(params):
        sel = [r for r in rows if r["parameter"] == param and r.get("s") == level]
        labels = [r["factor"] for r in sel]
        for i, key in enumerate(("A/A0", "P/P0", "EL/EL0")):
            ax = axes[i][j]
            ax.plot(range(len(sel)), [r[key] for r in sel], "o-")
            ax.set_xticks(range(len(sel)), labels)
            ax.set_ylabel(key)
            ax.grid(alpha=0.3)
            if i == 0:
                ax.set_title(f"{param} x factor, s = {level:g}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
