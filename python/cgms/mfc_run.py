"""Run the fine-scale (MFC) model in LAMMPS: the fast steady-state variant.

Each cell's fluid is at rest at a steady state, so it is one pressure from the equation
of state of the area its wall ring encloses (``fix mfc/pressure``, doc/fix_mfc_pressure.rst).
The walls are LAMMPS's own styles: harmonic bonds (stretching) and angles (bending) along
each ring, and 8-4 Lennard-Jones (``pair nm/cut``) for the wall's self-avoidance and the
middle lamella between adjacent cells (types = cell colours, so 1-1, 2-2, 3-3 are own-cell
pairs and the rest neighbour-cell pairs). The whole model has a potential energy, so a
steady state is a minimum: ``minimize`` (FIRE) finds it.

Steady-state criterion: the largest force component on any wall particle is below
``ftol`` (N; the turgor load on a fresh wall particle is about 6e-6 N).

Drying path (the ramp): the fresh tissue is relaxed first; every later level starts from
the previous level's steady state and passes through intermediate levels ``stage`` apart
(each relaxed to ``stage_ftol``), as a slowly dried tissue would. A jump from s = 1 to 0.8
in one go starts the fluid at -16 MPa.
"""

import math

import numpy as np

from .mfc_model import level

DEFAULTS = dict(ftol=1e-10, stage=0.05, stage_ftol=1e-8, max_iterations=200000,
                timestep=5e-9, dmax=2e-7)


def setup_commands(data, p, newton="on", processors=None, boundary="s s p"):
    """LAMMPS commands that read an MFC wall data file (:func:`cgms.mfc_tissue.write_data`)
    and define the wall forces; the drying levers follow with :func:`level_commands`."""
    per = p["self_r0"]
    lines = [
        "units si",
        "dimension 2",
        f"boundary {boundary}",
        f"newton {newton}",
        f"processors {processors} 1 1" if processors else "",
        "atom_style angle",
        "atom_modify map array",
        f"read_data {data}",
        # bonded neighbours stay in the pair list: the 3 um repulsion acts on crushed bonds
        "special_bonds lj 1.0 1.0 1.0",
        "bond_style harmonic",
        "angle_style harmonic",
        # LAMMPS's harmonic energies have no 1/2: K = k/2
        f"angle_coeff 1 {p['k_bend'] / 2:.10g} 180.0",
        f"pair_style nm/cut {p['lamella_rc']:.10g}",
        "pair_modify shift yes",
        # middle lamella: walls of different cells (types = colours) rest d_p apart
        f"pair_coeff * * {p['lamella_E0']:.10g} {p['pectin']:.10g} 8 4 {p['lamella_rc']:.10g}",
    ]
    lines += [f"pair_coeff {t} {t} {p['self_E0']:.10g} {per:.10g} 8 4 {per:.10g}"
              for t in (1, 2, 3)]
    lines += [
        "neighbor 2e-6 bin",
        "neigh_modify every 1 delay 0 check yes",
        "fix 2d all enforce2d",
    ]
    return [line for line in lines if line]


def level_commands(p, s, fix_id="mfc"):
    """The drying levers at dryness ``s``: bond rest length (wall contraction), the cell
    fluid's area at rest density and its turgor (``fix mfc/pressure``), wall masses."""
    lv = level(p, s)
    return [
        f"bond_coeff 1 {p['k_bond'] / 2:.10g} {lv['r0_bond']:.10g}",
        f"mass * {lv['wall_mass']:.10g}",
        f"fix {fix_id} all mfc/pressure height {p['height']:.10g} modulus {p['K']:.10g} "
        f"turgor {lv['turgor']:.10g} area {lv['fluid_area']:.10g}",
        f"fix_modify {fix_id} energy yes",
    ]


def minimize_commands(ftol, max_iterations, timestep=DEFAULTS["timestep"],
                      dmax=DEFAULTS["dmax"]):
    """FIRE down to the largest force component ``ftol`` (N). Statics do not depend on
    the masses, so the time step only sets FIRE's pace (below the wall springs' limit
    sqrt(m/k) = 8.9e-9 s at s = 0.3); ``dmax`` (m) caps a step's displacement."""
    return [f"timestep {timestep:.10g}",
            "min_style fire",
            f"min_modify norm max dmax {dmax:.10g}",
            f"minimize 0.0 {ftol:.10g} {int(max_iterations)} {10 * int(max_iterations)}"]


def positions(lmp):
    """Wall particle positions (n, 2) ordered by atom ID (any number of ranks)."""
    n = lmp.get_natoms()
    x = np.array(lmp.gather_atoms("x", 1, 3), dtype=float).reshape(n, 3)
    return x[:, :2]


def relax(lmp, p, s, ftol=DEFAULTS["ftol"], max_iterations=DEFAULTS["max_iterations"],
          **kwargs):
    """Set the levers of ``s`` and minimise. Returns iterations, the largest force
    component left (N), the fluid energy and whether ``ftol`` was reached."""
    start = lmp.extract_global("ntimestep")
    lmp.commands_list(level_commands(p, s))
    lmp.commands_list(minimize_commands(ftol, max_iterations, **kwargs))
    fmax = lmp.get_thermo("fmax")
    return dict(s=s, iterations=int(lmp.extract_global("ntimestep") - start), fmax=fmax,
                converged=bool(fmax <= ftol), energy=lmp.get_thermo("pe"))


def stages(s_from, s_to, stage):
    """Intermediate levels strictly between ``s_from`` and ``s_to``, ``stage`` apart."""
    if s_from is None or stage <= 0:
        return []
    k = int(math.floor((s_from - s_to) / stage - 1e-9))
    return [s_from - j * stage for j in range(1, k + 1)]


def ramp(lmp, p, s_from, s_to, ftol=DEFAULTS["ftol"], stage=DEFAULTS["stage"],
         stage_ftol=DEFAULTS["stage_ftol"], max_iterations=DEFAULTS["max_iterations"],
         **kwargs):
    """From the steady state at ``s_from`` (None: the built tissue) to that at ``s_to``
    through the intermediate levels. Returns the final :func:`relax` report with the
    total iterations."""
    total = 0
    for s in stages(s_from, s_to, stage):
        total += relax(lmp, p, s, stage_ftol, max_iterations, **kwargs)["iterations"]
    report = relax(lmp, p, s_to, ftol, max_iterations, **kwargs)
    report["iterations"] += total
    return report
