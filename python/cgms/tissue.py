"""Build tissues: bead positions on a hexagonal lattice, written as LAMMPS data files."""

import math

import numpy as np


def hex_rectangle(ncols, nrows, spacing):
    """Centres of a hexagonal lattice patch: ``nrows`` rows of ``ncols`` beads, rows
    ``spacing*sqrt(3)/2`` apart, odd rows shifted by half a spacing. Returns (n, 2)."""
    if ncols < 1 or nrows < 1 or not spacing > 0:
        raise ValueError("ncols and nrows must be >= 1 and spacing > 0")
    j, i = np.mgrid[0:nrows, 0:ncols]
    x = (i + 0.5 * (j % 2)) * spacing
    y = j * spacing * math.sqrt(3) / 2
    return np.column_stack([x.ravel(), y.ravel()]).astype(float)


def write_data(path, xy, margin, title="CGMS tissue"):
    """Write positions ``xy`` (n, 2) in metres as a LAMMPS data file for atom_style cgms
    (Atoms columns: id type x y z). The box leaves ``margin`` metres around the tissue."""
    xy = np.asarray(xy, dtype=float)
    lo = xy.min(axis=0) - margin
    hi = xy.max(axis=0) + margin
    lines = [
        f"{title}",
        "",
        f"{len(xy)} atoms",
        "1 atom types",
        "",
        f"{lo[0]:.10e} {hi[0]:.10e} xlo xhi",
        f"{lo[1]:.10e} {hi[1]:.10e} ylo yhi",
        f"{-margin:.10e} {margin:.10e} zlo zhi",
        "",
        "Atoms # cgms",
        "",
    ]
    lines += [f"{k + 1} 1 {x:.12e} {y:.12e} 0.0" for k, (x, y) in enumerate(xy)]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    return len(xy)
