# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""What a single MFC cell's predictions owe to the temperature (doc/drying.md,
"Temperature in the mechanics"): one free cell relaxed fresh and ramped to each dried
level, unheated and at each temperature; per level the cell's area, perimeter, roundness
and pressure, the fresh ones as they are, the dried ones against the unheated cell's.

    /usr/bin/python3 studies/mfc/temperature.py OUT [TEMPERATURES] [LEVELS] [key=value ...]

TEMPERATURES: C, e.g. 40,60,80 (default); LEVELS: dried levels, e.g. 0.6,0.3 (default);
key=value: entries of cgms.mfc_model.HEAT, e.g. softening_hours=4 membrane_onset=40.
"""

import math
import sys
from pathlib import Path

from cgms import run
from cgms.mfc import metrics as mfc_metrics, model as mfc_model, run as mfc_run, tissue as mfc_tissue


def cell(folder, p, levels):
    """One free cell relaxed fresh, then ramped through ``levels``: its measures per level."""
    folder.mkdir(parents=True, exist_ok=True)
    data = folder / "walls.data"
    mfc_tissue.write_data(data, [[0.0, 0.0]], p, overwrite=True)
    lmp = run.open_lammps(log=str(folder / "log.lammps"))
    rows = []
    try:
        lmp.commands_list(mfc_run.setup_commands(data, p))
        s_was = 1.0
        for s in [1.0] + list(levels):
            if s == 1.0:
                lmp.commands_list(mfc_run.level_commands(p, 1.0))
                report = mfc_run.relax(lmp, p, 1.0, ftol=1e-10)
            else:
                report = mfc_run.ramp(lmp, p, s_was, s, ftol=1e-10)
            s_was = s
            c = mfc_metrics.cells(mfc_run.positions(lmp), p["n_wall"])
            rows.append(dict(s=s, area=c["area"][0] / p["A_ref"], perimeter=c["perimeter"][0],
                             roundness=c["roundness"][0], converged=report["converged"],
                             pressure=float(lmp.numpy.extract_fix("mfc", 0, 2, 0, 1))))
    finally:
        lmp.close()
    return rows


def main(out, temperatures="40,60,80", levels="0.6,0.3", *options):
    for item in options:
        key, value = item.split("=", 1)
        mfc_model.HEAT[key] = float(value)
    levels = [float(v) for v in levels.split(",")]
    cases = [None] + [float(v) for v in temperatures.split(",")]
    base = None
    print("  T (C)  wall  turgor     s   area/A0  perim/fresh  perim/unheated  roundness  "
          "P (kPa)  converged")
    for T in cases:
        p = mfc_model.parameters(temperature=T)
        rows = cell(Path(out) / ("unheated" if T is None else f"T{T:g}"), p, levels)
        base = base or rows
        for r, b in zip(rows, base):
            print(f"  {'-' if T is None else f'{T:5g}':>5s}  {p.get('wall_factor', 1):.3f}  "
                  f"{p.get('turgor_factor', 1):6.3f}  {r['s']:4.2f}  {r['area']:7.4f}  "
                  f"{r['perimeter'] / rows[0]['perimeter']:11.4f}  "
                  f"{r['perimeter'] / b['perimeter']:14.4f}  {r['roundness']:9.4f}  "
                  f"{r['pressure'] / 1e3:7.2f}  {'yes' if r['converged'] else 'NO'}",
                  flush=True)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(*sys.argv[1:])
