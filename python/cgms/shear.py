# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Shear and uniaxial stiffness of a block of cells, in the fine model (MFC, fast steady-state
variant) and in CGMS, measured the same way (doc/calibration.md, "k_S from the fine model's
shear stiffness").

The block: ``nrows`` rows of cells along x (:func:`cgms.tissue.hex_rectangle`, short shifted
rows, so the ends are straight and the bottom and top rows are flat); cell i of the MFC is
bead i of CGMS. The block is relaxed free at dryness ``s``; then the bottom row is held and
the top row is held at a displacement (x: shear, y: compression), and the rest relaxed to
steady state at every step. The top row's reaction (the force its held particles feel from
the rest; internal forces of the held cells cancel) divided by the block's width is the
stress (N/m: force per length of a slab of height H, as both models' forces are). Two
moduli per load (:func:`moduli`):

- ``clamped``: stress / applied strain (applied displacement / distance between the held
  rows' centroid lines);
- ``interior``: stress / the interior strain, the slope of the rows' mean centroid
  displacement against their height over the rows not held, which leaves out the held rows
  (an MFC held cell is rigid, a CGMS held bead is a point).

Everything here is 2-D: the moduli are per slab, as the models' forces; divide by the slab
height H for a 3-D modulus in Pa.
"""

import math

import numpy as np

from . import material as material_file
from .mfc import metrics as mfc_metrics, run as mfc_run, tissue as mfc_tissue
from . import positions, run, study, tissue

#: shear strains of the measurement (the brief: 0.5, 1, 2 %), and uniaxial compressions
GAMMAS = (0.005, 0.01, 0.02)
STRAINS = (-0.005, -0.01)


def block(ncols, nrows, spacing):
    """Cell centres (n, 2) of an ``ncols`` x ``nrows`` block, rows along x (the odd rows
    one cell shorter), and the row index of each cell."""
    xy = tissue.hex_rectangle(ncols, nrows, spacing, short_rows=True, rows_along="x")
    row = np.rint((xy[:, 1] - xy[:, 1].min()) / (spacing * math.sqrt(3) / 2)).astype(int)
    return xy, row


def width(centres, row):
    """Width of the block (m): the span of the bottom row's centres plus one spacing."""
    x = np.sort(centres[row == 0, 0])
    return float(x[-1] - x[0] + np.mean(np.diff(x))) if len(x) > 1 else float("nan")


def row_gap(centres, row):
    """Distance (m) between the bottom and the top row's mean centroid heights."""
    return float(centres[row == row.max(), 1].mean() - centres[row == 0, 1].mean())


def interior_strain(c0, c, row, component):
    """Slope of the rows' mean displacement (``component`` 0: x, shear; 1: y, normal)
    against the rows' mean height, over the rows not held (1 .. max - 1): the strain
    inside the block. NaN with fewer than two such rows."""
    inner = np.arange(1, row.max())
    if len(inner) < 2:
        return float("nan")
    h = np.array([c0[row == j, 1].mean() for j in inner])
    u = np.array([(c - c0)[row == j, component].mean() for j in inner])
    return float(np.polyfit(h, u, 1)[0])


def moduli(strain, stress):
    """Least-squares slope through the origin of ``stress`` against ``strain`` and the
    largest relative departure of a single point's ratio from it (linearity)."""
    e, t = np.asarray(strain, float), np.asarray(stress, float)
    slope = float(e @ t / (e @ e))
    ratio = t / e
    return slope, float(np.max(np.abs(ratio / slope - 1)))


# ----------------------------------------------------------------------- the load steps

#: largest strain increment of one step (a larger move is split, each part relaxed with
#: ``approach``): the quasi-static path. Measured on the fresh 12 x 7 MFC block: moving the
#: top row back from 2 % shear in one step left it in another steady state (45 % of the
#: largest shear stress left at zero strain)
INCREMENT = 0.0025


def load(lmp, relax, centroids, bottom, top, centres_row, length, gap, gammas=GAMMAS,
         strains=STRAINS, approach=None, increment=INCREMENT):
    """Hold group ``bottom``, move group ``top`` and relax at every step: shear by
    ``gammas`` (x displacement gamma * gap), back to 0, then compress by ``strains``
    (y). ``relax()`` brings LAMMPS to its steady state and returns a report dict;
    ``centroids()`` gives the cell centroids (n, 2); ``approach()`` (default ``relax``)
    relaxes the intermediate steps of a move larger than ``increment`` x gap. Returns one row per step: kind,
    applied strain, stress (N/m), interior strain, relax report; plus the held rows'
    largest drift (m, must be 0) under key ``held_drift``."""
    lmp.command(f"fix hold {bottom} setforce 0.0 0.0 0.0")
    lmp.command(f"fix pull {top} setforce 0.0 0.0 0.0")
    c0 = centroids()
    report = relax()
    energy0 = report["energy"]
    base = np.array([lmp.extract_fix("pull", 0, 1, k) for k in range(2)])
    base_bottom = np.array([lmp.extract_fix("hold", 0, 1, k) for k in range(2)])
    held = centres_row == 0
    rows, now = [], np.zeros(2)
    steps = [("shear", g, (g * gap, 0.0)) for g in gammas] + [("back", 0.0, (0.0, 0.0))]
    steps += [("uniaxial", e, (0.0, e * gap)) for e in strains]
    drift = 0.0
    for kind, amount, target in steps:
        move = np.asarray(target) - now
        parts = max(1, int(math.ceil(np.abs(move).max() / (increment * gap) - 1e-9)))
        for k in range(parts):
            step = move / parts
            lmp.command(f"displace_atoms {top} move {step[0]:.12g} {step[1]:.12g} 0 units box")
            report = relax() if k == parts - 1 else (approach or relax)()
        now = np.asarray(target, float)
        c = centroids()
        drift = max(drift, float(np.abs(c[held] - c0[held]).max()))
        force = np.array([lmp.extract_fix("pull", 0, 1, k) for k in range(2)]) - base
        # the held bottom row's reaction: minus the top's when the rest is at steady state
        bottom_force = np.array([lmp.extract_fix("hold", 0, 1, k) for k in range(2)]) - base_bottom
        component = 1 if kind == "uniaxial" else 0
        # the agent holding the top row balances the force the rest exerts on it: the
        # stress is that force, reversed, per width
        stress = -force[component] / length
        rows.append(dict(kind=kind, strain=amount, stress=float(stress), move=move.tolist(),
                         top_force=force.tolist(), bottom_force=bottom_force.tolist(),
                         work_energy=float(report["energy"] - energy0),
                         interior=interior_strain(c0, c, centres_row, component),
                         normal=float(-force[1 - component] / length), **report))
    lmp.command("unfix hold")
    lmp.command("unfix pull")
    return dict(rows=rows, held_drift=drift, base_force=base.tolist(), length=length, gap=gap)


def work(rows, length):
    """The work done on the block by the agent that moves the top row, step by step
    (trapezoidal rule over each step's displacement, J), beside the energy the block
    stored (``work_energy``, from the potential energy): equal for an elastic block
    whose reaction is measured right."""
    done, total, last = [], 0.0, np.zeros(2)
    for r in rows:
        now = np.array([r["stress"], r["normal"]]) * length
        if r["kind"] == "uniaxial":
            now = now[::-1]
        total += float(0.5 * (last + now) @ np.asarray(r["move"]))
        done.append(total)
        last = now
    return np.array(done)


def summarise(result):
    """The moduli of a :func:`load` result: ``G`` (clamped, interior), ``M`` (the clamped
    uniaxial modulus, both ways) and the linearity of each; ``return_stress``: the shear
    stress left after going back to 0 (N/m), against the largest shear stress."""
    rows = result["rows"]
    out = {}
    for kind, key in (("shear", "G"), ("uniaxial", "M")):
        sel = [r for r in rows if r["kind"] == kind]
        if not sel:
            continue
        out[f"{key}_clamped"], out[f"{key}_clamped_linearity"] = moduli(
            [r["strain"] for r in sel], [r["stress"] for r in sel])
        out[f"{key}_interior"], out[f"{key}_interior_linearity"] = moduli(
            [r["interior"] for r in sel], [r["stress"] for r in sel])
    back = [r for r in rows if r["kind"] == "back"]
    shear = [abs(r["stress"]) for r in rows if r["kind"] == "shear"]
    out["return_stress"] = back[0]["stress"] / max(shear) if back and shear else float("nan")
    out["held_drift"] = result["held_drift"]
    out["converged"] = all(r.get("converged", True) for r in rows)
    return out


def _ids(values):
    return " ".join(str(int(v)) for v in values)


# ----------------------------------------------------------------------- the two models

def mfc(centres, row, p, s, folder, solver=None, **kwargs):
    """The shear and uniaxial test of the fine model (fast variant, the lamella set in the
    relaxed fresh block as in the reference, ``cgms.mfc.study``) at dryness ``s``: the
    fresh block relaxed, glued, dried along the ramp to ``s``, then :func:`load`. Returns
    the :func:`load` result with the free state's width, row gap and relax reports."""
    from pathlib import Path
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    solver = dict(solver or {})
    data = folder / "walls.data"
    mfc_tissue.write_data(data, centres, p, overwrite=True, title="MFC shear block")
    lmp = run.open_lammps(log=folder / "log.fresh.lammps")
    try:
        mfc_run.require_packages(lmp)
        lmp.commands_list(mfc_run.setup_commands(data.resolve(), p))
        fresh = mfc_run.relax(lmp, p, 1.0, **solver)
        xy = mfc_run.positions(lmp)
    finally:
        lmp.close()
    lamella = None
    rest = ()
    if p["lamella"] == "fresh":
        pairs, types, rest = mfc_tissue.fresh_lamella(xy, mfc_tissue.walls(centres, p)["cell"], p)
        lamella = (pairs, types)
    glued = folder / "lamella.data"
    mfc_tissue.write_data(glued, centres, p, xy=xy, lamella=lamella, overwrite=True,
                          title="MFC shear block, lamella set fresh")
    lmp = run.open_lammps(log=folder / f"log.s{s:g}.lammps")
    try:
        lmp.commands_list(mfc_run.setup_commands(glued.resolve(), p, rest=rest))
        free = (mfc_run.ramp(lmp, p, 1.0, s, **solver) if s < 1
                else mfc_run.relax(lmp, p, 1.0, **solver))
        n = p["n_wall"]

        def centroids():
            return mfc_metrics.cells(mfc_run.positions(lmp), n)["centroid"]

        c = centroids()
        mol = np.arange(1, len(centres) + 1)
        lmp.command(f"group bottom molecule {_ids(mol[row == 0])}")
        lmp.command(f"group top molecule {_ids(mol[row == row.max()])}")
        # no kick under load: the free state is the dried steady state already
        # an intermediate step of a split move: one chunk, as a ramp's intermediate level
        chunk = solver.get("chunk", mfc_run.DEFAULTS["chunk"])
        part = dict(solver, max_iterations=chunk,
                    ftol=1e3 * solver.get("ftol", mfc_run.DEFAULTS["ftol"]))
        result = load(lmp, lambda: mfc_run.relax(lmp, p, s, **solver), centroids,
                      "bottom", "top", row, width(c, row), row_gap(c, row),
                      approach=lambda: mfc_run.relax(lmp, p, s, **part), **kwargs)
    finally:
        lmp.close()
    result.update(model="mfc", s=s, cells=len(centres), fresh=fresh, free=free,
                  width=width(c, row), gap=row_gap(c, row))
    return result


#: CGMS steady state under load: FIRE to this largest force component (N), at most
#: this many iterations per step (cell forces are about 1e-4 N)
CGMS_FTOL = 1e-13
CGMS_ITERATIONS = 200000


def cgms_relax(lmp, ftol=CGMS_FTOL, iterations=CGMS_ITERATIONS):
    """FIRE (the quasi-static solve of cgms.run) to ``ftol``; returns the iterations, the
    largest force component left and ``converged``."""
    start = lmp.extract_global("ntimestep")
    lmp.commands_list(run.fire_commands(f"{ftol:.10g}", iterations))
    fmax = lmp.get_thermo("fmax")
    return dict(iterations=int(lmp.extract_global("ntimestep") - start), fmax=fmax,
                converged=bool(fmax <= ftol), energy=lmp.get_thermo("pe"))


def cgms(centres, row, material, s, folder, overrides="", ftol=CGMS_FTOL, start="fire",
         **kwargs):
    """The same test on CGMS (bead i = cell i): the block relaxed free at ``s`` (every bead
    at P = -Pi, fix cgms/fluid's balance; ``start="dynamics"``: from the damped dynamics'
    steady state, where FIRE from the built lattice pulls a bead out of the tissue, as
    with apple-mfc.cgms at s = 0.6), then :func:`load`. ``overrides``: material
    parameters ("k_S 0.5"). Returns the :func:`load` result as :func:`mfc` does."""
    from pathlib import Path
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    data = folder / "tissue.data"
    path = material_file.find(material)
    positions.write_data(data, centres, 3 * material_file.read(path)["x_ref"], overwrite=True)
    lmp = run.open_lammps(log=folder / f"log.s{s:g}.lammps")
    try:
        if start == "dynamics":   # the damped dynamics first (cgms.study.FALLBACK)
            lmp.commands_string(run.tissue_script(
                data.resolve(), path, s, method="dynamics", overrides=overrides,
                dt=study.FALLBACK["dt"], steady=study.FALLBACK["steady"]))
            # then as the quasi-static solve: no damping, no halt, beads at rest
            lmp.commands_list(["unfix halt", "pair_style cgms damping no",
                               f"pair_coeff * * {path.resolve()} {overrides}",
                               "velocity all set 0.0 0.0 0.0"])
        else:
            lmp.commands_string(run.tissue_script(data.resolve(), path, s, method="newton",
                                                  overrides=overrides))
        free = cgms_relax(lmp, ftol)

        def centroids():
            return run.steady_state(lmp)["xy"]

        c = centroids()
        ids = np.arange(1, len(centres) + 1)
        lmp.command(f"group bottom id {_ids(ids[row == 0])}")
        lmp.command(f"group top id {_ids(ids[row == row.max()])}")
        result = load(lmp, lambda: cgms_relax(lmp, ftol), centroids, "bottom", "top", row,
                      width(c, row), row_gap(c, row), **kwargs)
    finally:
        lmp.close()
    result.update(model="cgms", s=s, cells=len(centres), free=free, overrides=overrides, xy=c,
                  start=start, width=width(c, row), gap=row_gap(c, row))
    return result
