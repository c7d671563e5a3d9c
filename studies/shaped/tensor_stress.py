# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The tensor variant's interior and rim stresses, as studies/mfc/stress.py measures the
MFC's (doc/results/shaped-results.md, "2026-12-03 (fourth session)"): from the states
``table.py --save`` wrote, the lamella's compatibility bonds are the forces between cells
(the LJ repulsion is left out and the net force on each region, printed, says what it
would have added), and the regions are the cells on the fresh outline and the rest.

    source build/env.sh
    /usr/bin/python3 studies/shaped/tensor_stress.py STATES_FOLDER PARAMS_JSON [--tissue 1.5x2.5]
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from cgms import morphology, shaped_tensor

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "mfc"))
import table  # noqa: E402
from stress import region_stress  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("states")
    ap.add_argument("params")
    ap.add_argument("--tissue", default="1.5x2.5")
    args = ap.parse_args(argv)
    saved = np.load(Path(args.states) / f"{args.tissue}.npz")
    mat, xy = table.layout(args.tissue)
    p = table.wall_params(mat, json.loads(Path(args.params).read_text()))
    p.pop("kick", None)
    geo = shaped_tensor.build(xy, mat, p, local=True)
    n = geo["n"]
    rim = np.zeros(n, bool)
    rim[morphology.measures(xy)["outline"]] = True
    print("| s | interior sxx, syy (mN/m) | rim sxx, syy (mN/m) | largest net force (N) |")
    print("|---|---|---|---|")
    for s, z in zip(saved["levels"], saved["states"]):
        if s == 1:
            continue
        lev = shaped_tensor.at_level(geo, s)
        x = shaped_tensor.split(z, n)[0]
        i, k = lev["bonds"][:, 0], lev["bonds"][:, 1]
        # E = k_g / 2 |m|^2 with m = x_k - x_i - target: the force on i is k_g m
        f_on_i = lev["k_g"] * shaped_tensor.mismatch(z, lev).reshape(-1, 2)
        area = morphology.measures(x, morphology.default_max_edge(
            x, morphology.FINE_EDGE_FACTOR))["area"]
        cols, nets = [], []
        for cells in (~rim, rim):
            sigma, net = region_stress(x, cells, i, k, f_on_i, area * cells.sum() / n)
            cols.append(f"{1e3 * sigma[0, 0]:+.2f}, {1e3 * sigma[1, 1]:+.2f}")
            nets.append(np.abs(net).max())
        print(f"| {s:g} | {cols[0]} | {cols[1]} | {max(nets):.1e} |")


if __name__ == "__main__":
    main()
