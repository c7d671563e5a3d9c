# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Which way a flattened cell of the tensor variant (cgms.shaped_tensor) prefers to point:
from a steady state that ``table.py --model tensor --save`` wrote, one interior cell's
stretch axes are turned by phi (F_i = Q V Q^T R, the rest of the state held) and the
tissue's energy is evaluated. A cell whose energy depended only on its area and its
stretches would give a flat line. Two parts do not: turning one cell against its held
neighbours (their shared bonds, and the glue where on) costs a term in cos(2 phi), a
stretch axis having period 180 deg; the hexagon's walls give cos(6 phi), which is what
picks a lattice axis for every cell at once when nothing else does (doc/results/
shaped-results.md, "2026-12-03 (fifth session)"). The last two columns split dE(phi) by a
least-squares fit into these two (amplitudes with their sine parts; 7 angles, 5 numbers).
Seconds.

    python3 studies/shaped/anisotropy.py FOLDER TISSUE 'JSON of the run' [--levels 0.6,0.4]
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "studies" / "shaped"))
import table  # noqa: E402
from cgms import shaped_tensor as st  # noqa: E402


def turned(F, phi):
    """F = V R with its stretch axes turned by phi: (Q V Q^T) R."""
    U, S, Vt = np.linalg.svd(F)
    c, s = np.cos(phi), np.sin(phi)
    QU = np.array([[c, -s], [s, c]]) @ U
    return QU @ np.diag(S) @ QU.T @ (U @ Vt)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder")
    ap.add_argument("tissue")
    ap.add_argument("params", help="the JSON the states were made with (table.py --params)")
    ap.add_argument("--levels", default="0.6,0.4")
    args = ap.parse_args(argv)
    mat, xy = table.layout(args.tissue)
    p = table.wall_params(mat, table.given_params(st, args.params))
    p.pop("kick", None)
    geo = st.build(xy, mat, p)
    n = geo["n"]
    saved = np.load(Path(args.folder) / f"{args.tissue}.npz")
    inner = np.flatnonzero(~geo["boundary"])
    i = inner[len(inner) // 2]
    asked = [float(v) for v in args.levels.split(",")]
    found = [(s, z) for s, z in zip(saved["levels"], saved["states"])
             if any(abs(s - v) <= 1e-9 for v in asked)]    # 0.6 and 0.60 alike
    if not found:
        ap.error(f"{args.tissue}.npz holds the levels "
                 f"{', '.join(f'{s:g}' for s in saved['levels'])}, none of --levels")
    print("| s | cell | stretches / sqrt(s) | dE(phi) for phi = 0, 15, ..., 90 deg (J) "
          "| amplitude / (P_T A H) | cos 2 phi part / (P_T A H) | cos 6 phi part / (P_T A H) |")
    print("|---|---|---|---|---|---|---|")
    phis = np.radians(np.arange(0, 91, 15))
    basis = np.column_stack([np.ones_like(phis), np.cos(2 * phis), np.sin(2 * phis),
                             np.cos(6 * phis), np.sin(6 * phis)])
    for s, z in found:
        lev = st.at_level(geo, s)
        x, F = st.split(z, n)
        E0 = st.energy(z, lev, gradient=False)
        dE = []
        for phi in phis:
            G = F.copy()
            G[i] = turned(F[i], phi)
            dE.append(st.energy(st.join(x, G, st.shear(z, n)), lev, gradient=False) - E0)
        scale = lev["P_T"] * lev["A_f"][i] * mat["height"]
        c = np.linalg.lstsq(basis, np.array(dE), rcond=None)[0]
        stretch = np.linalg.svd(F[i], compute_uv=False) / np.sqrt(s)
        print(f"| {s:g} | {i} | {stretch[0]:.3f}, {stretch[1]:.3f} | "
              + ", ".join(f"{v:.2e}" for v in dE)
              + f" | {(max(dE) - min(dE)) / scale:.1e} | {np.hypot(*c[1:3]) / scale:.1e} | "
              f"{np.hypot(*c[3:5]) / scale:.1e} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
