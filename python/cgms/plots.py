# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Figures: morphology curves against moisture, and tissue snapshots (matplotlib, PNG)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def curves(rows, path, title=""):
    """A/A0, P/P0 and EL/EL0 against the moisture reached, X/X0 (like the paper's Fig. 5)."""
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), constrained_layout=True)
    x = [r["X/X0"] for r in rows]
    for ax, key in zip(axes, ("A/A0", "P/P0", "EL/EL0")):
        ax.plot(x, [r[key] for r in rows], "o-")
        for r in rows:
            ax.annotate(f"s={r['s']:g}", (r["X/X0"], r[key]), fontsize=7,
                        textcoords="offset points", xytext=(3, 3))
        ax.set_xlabel("X/X0 reached")
        ax.set_ylabel(key)
        ax.invert_xaxis()
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def snapshots(panels, path, label, cmap="viridis", outlines=None):
    """Side-by-side tissue snapshots: ``panels`` is a list of (title, xy, values); beads
    are drawn at their centres, coloured by ``values`` on one shared scale (like the
    paper's Figs 3 and 6). Positions in metres, drawn in millimetres."""
    vmin = min(np.min(v) for _, _, v in panels)
    vmax = max(np.max(v) for _, _, v in panels)
    fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 3.6),
                             constrained_layout=True, squeeze=False)
    for k, (ax, (title, xy, values)) in enumerate(zip(axes[0], panels)):
        size = min(40.0, max(0.3, 6000.0 / len(xy)))    # marker area shrinks with bead count
        sc = ax.scatter(xy[:, 0] * 1e3, xy[:, 1] * 1e3, c=values, s=size, cmap=cmap,
                        vmin=vmin, vmax=vmax, linewidths=0)
        if outlines is not None:
            loop = np.r_[outlines[k], outlines[k][:1]]
            ax.plot(xy[loop, 0] * 1e3, xy[loop, 1] * 1e3, "k-", lw=0.6)
        ax.set_title(title, fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
    axes[0][0].set_ylabel("y (mm)")
    fig.colorbar(sc, ax=axes[0].tolist(), label=label, shrink=0.8)
    fig.savefig(path, dpi=120)
    plt.close(fig)


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
