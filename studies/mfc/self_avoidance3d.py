# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Would a particle self-avoidance keep the 3-D fine model's dried walls from passing
through themselves? (doc/results/mfc.md, "3-D walls that pass through themselves")

    /usr/bin/python3 studies/mfc/self_avoidance3d.py OUT E0 R0 [--save-walls]

Runs ``cgms.mfc.study3d`` on the 16-cell block with an 8-4 LJ (``pair nm/cut``, repulsive
only: radius = cutoff = R0, m) of strength E0 (J) between the wall particles of one cell,
which the study itself does not have (it excludes a cell's own pairs). LAMMPS cannot tell a
cell's own pairs from its neighbours' by molecule in a pair style, so the cells are coloured
with four atom types, no two neighbours alike (BCC: sublattice x parity of the lattice
indices), the molecule/intra exclusion is dropped, and the type's own pair coefficient is
the self-avoidance (same-coloured cells are never neighbours and far apart); the lamella
between types is the study's. The study stops at a crossing as usual (printed);
``--save-walls`` keeps every level's wall positions as ``walls.s<s>.npy``.
"""

import sys
from pathlib import Path

import numpy as np

from cgms.mfc import model as mfc_model, run3d, study3d, tissue3d


def colours(p, cubes=2):
    """Per cell 0..3, no two neighbours (cells whose walls the lamella joins) alike."""
    centres = tissue3d.block(p, cubes)
    idx = np.rint((centres - centres.min(axis=0)) / (tissue3d.lattice_edge(p) / 2)).astype(int)
    colour = 2 * (idx[:, 0] % 2) + (idx // 2).sum(axis=1) % 2
    x, cell, w = tissue3d.walls(centres, p, 3)
    pairs = tissue3d.lamella_pairs(x, cell, w, p)
    assert np.all(colour[cell[pairs[:, 0]]] != colour[cell[pairs[:, 1]]]), "neighbours alike"
    return colour


def with_self_avoidance(setup_commands, colour, mass, e0, r0):
    """``run3d.setup_commands`` with the cells coloured and their own pairs repelled."""
    def setup(data, w, newton="on", processors=None):
        lines = []
        for line in setup_commands(data, w, newton, processors):
            if line == "neigh_modify exclude molecule/intra all":
                continue
            if line.startswith("read_data"):
                lines += [line + " extra/atom/types 3", f"mass 2*4 {mass:.10e}"]
                for k in range(1, 4):
                    mols = " ".join(str(c + 1) for c in np.nonzero(colour == k)[0])
                    lines += [f"group colour{k} molecule {mols}",
                              f"set group colour{k} type {k + 1}"]
                continue
            lines.append(line)
            if line.startswith("pair_coeff * *"):
                lines += [f"pair_coeff {t} {t} {e0:.10g} {r0:.10g} 8 4 {r0:.10g}"
                          for t in range(1, 5)]
        return lines
    return setup


def main(argv):
    out, e0, r0 = Path(argv[0]), float(argv[1]), float(argv[2])
    p = mfc_model.parameters("apple")
    w = tissue3d.wall(p)
    mass = p["solid_ratio"] * p["rho0"] * w["fluid_volume"] / len(w["x"])
    run3d.setup_commands = with_self_avoidance(run3d.setup_commands, colours(p), mass, e0, r0)
    if "--save-walls" in argv:
        record = study3d.record

        def saving(o, lmp, w, s, result, seconds):
            np.save(o / f"walls.s{s:g}.npy", run3d.positions(lmp))
            return record(o, lmp, w, s, result, seconds)
        study3d.record = saving
    try:
        study3d.dry(out, p, 2, say=lambda m: print(m[:300], flush=True))
    except study3d.WallCrossing as err:
        print(f"stopped: {err}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
