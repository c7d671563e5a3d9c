# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The full fine-scale (MFC) model: SPH fluid inside the DEM wall rings (MFC.md 9).

Same walls as the fast variant (:mod:`cgms.mfc.run`, same atom IDs 1..n_cells*n_wall), plus
656 SPH fluid particles per cell (:func:`cgms.mfc.tissue.fluid_points`), all on LAMMPS's
own styles: ``atom_style hybrid sph angle``, ``pair sph/taitwater/morris`` (Lucy kernel,
continuity density, Tait EOS written exactly as CGMS eqn 4), ``pair nm/cut`` for the 8-4 LJ
forces, ``fix sph`` to integrate, ``fix viscous`` to settle.

Types: walls 1-3 and fluid 4-6 by cell colour (walls first: the SPH style sets a type's
EOS from the pair_coeff line whose lower type is that type). Fluid particles interact by
SPH only with their own cell's fluid and wall; every fluid-wall pair also repels at 3 um.

Units are 2-D slab units: densities areal (rho H), pressures and B per length (p H),
viscosity mu H; masses are real slab masses, so forces are in N.
"""

import math

import numpy as np
from scipy.spatial import cKDTree

from .. import folders, tissue
from . import metrics as mfc_metrics, run as mfc_run, tissue as mfc_tissue
from .model import level

MU = 1.0e-3          # water viscosity, Pa s
SUPPORT = 13.0e-6    # kernel support h (2.6 fluid spacings, LAMMPS's cavity-flow ratio)
TAU = 2.0e-7         # damping time of fix viscous, s (2 us: the fresh cell inflates, doc/mfc.md)


#: how the walls meet the fluid (doc/mfc.md): "dynamic", walls are SPH particles with their
#: own continuity density (MFC.md's coupling); "adami", a wall takes the pressure of the
#: fluid around it (Adami, Hu and Adams, J. Comput. Phys. 231, 2012, 7057)
BOUNDARIES = ("dynamic", "adami")


def fluid_style(p):
    """``(style, settings)`` of the SPH fluid's pair style, chosen by three optional
    parameters: ``sph_ap`` (Monaghan's artificial pressure factor epsilon; 0 = off),
    ``sph_kernel`` ("lucy" or "wendland") and ``sph_boundary`` (BOUNDARIES). All at their
    defaults: LAMMPS's own sph/taitwater/morris; otherwise the plugin's sph/taitwater/ap
    (doc/pair_sph_taitwater_ap.rst), which holds the fluid in tension and has Adami's
    walls (types 1-3)."""
    ap, kernel = p.get("sph_ap", 0.0), p.get("sph_kernel", "lucy")
    boundary = p.get("sph_boundary", "dynamic")
    if kernel not in ("lucy", "wendland"):
        raise ValueError(f"sph_kernel must be lucy or wendland, got {kernel!r}")
    if not ap >= 0:
        raise ValueError(f"sph_ap (artificial pressure factor) must be >= 0, got {ap!r}")
    if boundary not in BOUNDARIES:
        raise ValueError(f"sph_boundary must be one of {', '.join(BOUNDARIES)}, "
                         f"got {boundary!r}")
    if ap == 0 and kernel == "lucy" and boundary == "dynamic":
        return "sph/taitwater/morris", ""
    walls = " wall 1*3" if boundary == "adami" else ""
    return "sph/taitwater/ap", f"kernel {kernel} epsilon {ap:g}{walls}"


def tait(p, s):
    """The EOS of level s in LAMMPS's Tait form: P_T + K[(rho/rho0)^7 - 1] =
    B[(rho/rho_r)^7 - 1] with B = K - P_T, rho_r = rho0 (1 - P_T/K)^(1/7),
    c0 = sqrt(7 B / rho_r). Returns areal rho_r H (kg/m^2) and c0 (m/s)."""
    pt = level(p, s)["turgor"]
    b = p["K"] - pt
    rho_r = p["rho0"] * (1 - pt / p["K"]) ** (1 / 7)
    return rho_r * p["height"], math.sqrt(7 * b / rho_r)


def pressure(p, s, rho):
    """Pressure (Pa) of SPH particles of areal density ``rho`` at level s: LAMMPS's Tait EOS
    B [(rho/rho_r)^7 - 1] per slab height, B = c0^2 rho_r / 7."""
    rho_r, c0 = tait(p, s)
    return c0 * c0 * rho_r / 7 * ((np.asarray(rho) / rho_r) ** 7 - 1) / p["height"]


def fluid_mass(p):
    """Fresh fluid particle mass: its lattice cell s_f^2 at the fresh rest density, so
    that an SPH particle's volume m/rho is the area it occupies."""
    return tait(p, 1.0)[0] * p["fluid_spacing"] ** 2


def write_data(path, centres, p, overwrite=False):
    """Data file (``atom_style hybrid sph angle``: ``id type x y z rho esph cv mol``) of the
    fresh tissue: walls as :func:`cgms.mfc.tissue.write_data`, then the fluid."""
    w = mfc_tissue.walls(centres, p)
    fluid = [mfc_tissue.fluid_points(c, p, w["angle"]) for c in np.asarray(centres, float)]
    rho = np.full(len(fluid), tait(p, 1.0)[0])
    return _write(path, w["xy"], w["colour"], fluid, p, rho, fluid_mass(p),
                  p["wall_mass"], f"MFC tissue (SPH): {len(centres)} cells", overwrite)


def fill(ring, p, s, offset=(0.0, 0.0)):
    """SPH fluid particles filling one wall ring of any shape (a dried, wrinkled one) at
    level ``s``: the fluid lattice contracted with the fluid, spacing
    ``fluid_spacing * sqrt(s)``, on the ring's mean, kept inside the ring and at least
    ``fluid_margin`` from its polyline (the rule :func:`cgms.mfc.tissue.fluid_points`
    applies to the fresh hexagon). ``offset`` shifts the lattice (m; the tests measure the
    count's spread over offsets)."""
    ring = np.asarray(ring, float)
    h = p["fluid_spacing"] * math.sqrt(s)
    centre = ring.mean(axis=0)
    m = int(np.ceil(np.abs(ring - centre).max() / h)) + 1
    g = (np.arange(-m, m) + 0.5) * h
    pts = centre + np.asarray(offset) + np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
    pts = pts[tissue._inside(pts, ring, 0.0, closed=False)]
    return pts[tissue._boundary_distance(pts, ring) >= p["fluid_margin"]]


def write_state(path, walls, colour, p, s, pressure=None, overwrite=False):
    """Data file of a steady state of the fast variant at level ``s`` (wall positions
    ``walls`` by atom ID, cell colours ``colour`` 0-2 per wall particle) with every cell
    filled by :func:`fill`: fluid at rest at the cell's ``pressure`` (Pa, per cell, e.g.
    ``fix mfc/pressure``'s; default 0) through the EOS of level s, each particle of the
    mass of its lattice cell at the level's rest density, walls of the level's mass.
    Returns the counts, the fluid particle mass and the fluid area per cell (its lattice
    cells)."""
    walls = np.asarray(walls, float)
    rings = walls.reshape(-1, p["n_wall"], 2)
    fluid = [fill(ring, p, s) for ring in rings]
    rho_r, c0 = tait(p, s)
    pressure = np.zeros(len(rings)) if pressure is None else np.asarray(pressure, float)
    # LAMMPS's Tait EOS, p H = B [(rho/rho_r)^7 - 1], B = c0^2 rho_r / 7, solved for rho
    rho = rho_r * (1 + pressure * p["height"] / (c0 * c0 * rho_r / 7)) ** (1 / 7)
    mass = rho_r * p["fluid_spacing"] ** 2 * s
    out = _write(path, walls, np.asarray(colour, int), fluid, p, rho, mass,
                 level(p, s)["wall_mass"], f"MFC tissue (SPH) at s = {s:g}", overwrite)
    out.update(fluid_mass=mass, fluid_area=np.array([len(f) for f in fluid]) * mass / rho_r)
    return out


def _write(path, walls, colour, fluid, p, rho, fluid_mass_, wall_mass, title, overwrite):
    """The data file of walls (``n_cells * n_wall``, consecutive IDs per cell ring) and
    their cells' fluid points; ``rho`` per cell (its walls and fluid)."""
    nf = [len(f) for f in fluid]
    col = colour[:: p["n_wall"]]
    xy = np.concatenate([walls] + list(fluid))
    ncell, nw = len(fluid), len(walls)
    cell = np.arange(nw) // p["n_wall"]
    types = np.concatenate([colour + 1, np.repeat(col + 4, nf)])
    mols = np.concatenate([cell + 1, np.repeat(np.arange(1, ncell + 1), nf)])
    margin = 3 * p["x_ref"]
    lo, hi = xy.min(axis=0) - margin, xy.max(axis=0) + margin
    ids = np.arange(1, nw + 1)
    first = cell * p["n_wall"] + 1
    nxt = first + (ids - first + 1) % p["n_wall"]
    prv = first + (ids - first - 1) % p["n_wall"]
    lines = [title, "", f"{len(xy)} atoms", f"{nw} bonds",
             f"{nw} angles", "6 atom types", "1 bond types", "1 angle types", "",
             f"{lo[0]:.10e} {hi[0]:.10e} xlo xhi", f"{lo[1]:.10e} {hi[1]:.10e} ylo yhi",
             f"{-margin:.10e} {margin:.10e} zlo zhi", "", "Masses", ""]
    lines += [f"{t} {wall_mass:.10e}" for t in (1, 2, 3)]
    lines += [f"{t} {fluid_mass_:.10e}" for t in (4, 5, 6)]
    lines += ["", "Atoms # hybrid", ""]
    lines += [f"{i + 1} {t} {x:.12e} {y:.12e} 0.0 {rho[m - 1]:.10e} 0.0 1.0 {m}"
              for i, (t, m, (x, y)) in enumerate(zip(types, mols, xy))]
    lines += ["", "Bonds", ""] + [f"{i} 1 {i} {j}" for i, j in zip(ids, nxt)]
    lines += ["", "Angles", ""] + [f"{i} 1 {a} {i} {b}" for i, a, b in zip(ids, prv, nxt)]
    folders.write_text(path, "\n".join(lines) + "\n", overwrite)
    return dict(walls=nw, fluid=int(sum(nf)))


def setup_commands(data, p, newton="on", processors=None):
    """Read an SPH data file and define every force of MFC.md 9 at the fresh level."""
    lines = ["units si", "dimension 2", "boundary s s p", f"newton {newton}",
             f"processors {processors} 1 1" if processors else "",
             "atom_style hybrid sph angle", "atom_modify map array",
             "comm_modify vel yes", f"read_data {data}",
             "group wall type 1 2 3", "group fluid type 4 5 6",
             "special_bonds lj 1.0 1.0 1.0", "bond_style harmonic", *mfc_run.wall_bending(p),
             f"pair_style hybrid/overlay {' '.join(fluid_style(p))} nm/cut {p['lamella_rc']:.10g}"]
    rep = f"nm/cut {p['self_E0']:.10g} {p['self_r0']:.10g} 8 4 {p['self_r0']:.10g}"
    lam = f"nm/cut {p['lamella_E0']:.10g} {p['pectin']:.10g} 8 4 {p['lamella_rc']:.10g}"
    for i in (1, 2, 3):
        for j in range(i, 7):
            if j <= 3:
                lines.append(f"pair_coeff {i} {j} {rep if i == j else lam}")
            else:
                lines.append(f"pair_coeff {i} {j} {rep}")
    for i in (4, 5, 6):
        for j in range(i + 1, 7):
            lines.append(f"pair_coeff {i} {j} none")
    lines += sph_commands(p, 1.0)
    lines += ["neighbor 1.5e-6 bin", "neigh_modify every 1 delay 0 check yes",
              "fix int all sph", "fix 2d all enforce2d"]
    return [line for line in lines if line]


def sph_commands(p, s):
    """SPH coefficients of level s: the EOS (through rho_r and c0) and the viscosity; for
    sph/taitwater/ap also the fluid spacing of level s, ``fluid_spacing * sqrt(s)``."""
    rho, c0 = tait(p, s)
    style = fluid_style(p)[0]
    coef = f"{style} {rho:.10g} {c0:.10g} {MU * p['height']:.10g} {SUPPORT:.10g}"
    if style == "sph/taitwater/ap":
        coef += f" {p['fluid_spacing'] * math.sqrt(s):.10g}"
    return [f"pair_coeff {c} {c + 3} {coef}" for c in (1, 2, 3)] + \
        [f"pair_coeff {c} {c} {coef}" for c in (4, 5, 6)]


def level_commands(p, s, mf=None):
    """The levers of level ``s`` (MFC.md 5.2) but the densities (:func:`dry`): masses of
    fluid (``mf``, default s x the fresh one) and wall, the EOS of s, the contracted wall
    rest length, the damping of the new masses."""
    lv = level(p, s)
    mw, mf = lv["wall_mass"], s * fluid_mass(p) if mf is None else mf
    return [f"mass 1*3 {mw:.10g}", f"mass 4*6 {mf:.10g}"] + sph_commands(p, s) + [
        f"bond_coeff 1 {p['k_bond'] / 2:.10g} {lv['r0_bond']:.10g}",
        f"fix dw wall viscous {mw / TAU:.10g}", f"fix df fluid viscous {mf / TAU:.10g}"]


#: the ways :func:`dry` takes a drying stage (doc/mfc.md, "An SPH drying path")
PATHS = ("density", "affine")
#: how :func:`dry` sets the fluid mass of a level: "scaled" (the default), s times the fresh
#: fill's; "water" (affine path only), the fast variant's water s A0 per cell, the layer
#: between fluid and wall included (:func:`water_mass`; measured not to move the dried
#: ring, doc/mfc.md)
MASSES = ("water", "scaled")


def dry(lmp, p, s, s_old, path="affine", mass="scaled"):
    """Dry from ``s_old`` to ``s``, then :func:`level_commands`. ``path`` "density" (the
    route before, which reaches the fast variant's states only at s = 1): masses
    and densities of fluid and wall scaled by s / s_old together, so SPH volumes m/rho are
    unchanged and the fluid goes into tension (-6 MPa for a stage of 0.05) until the cells
    have contracted to their new fluid mass. "affine": masses set by ``mass`` (MASSES),
    densities kept, and every particle moved towards the tissue's
    centroid by sqrt(s / s_old), so the fluid stays at its pressure and packing in the
    smaller area, and the walls, now compressed against their contracted rest length, fold
    (the default). ``s == s_old`` with mass "water" recalibrates the fluid mass to the
    layer measured now, moving nothing. Every rank executes it (under mpirun): the
    positions are each rank's own, the mass is gathered."""
    if path not in PATHS:
        raise ValueError(f"path must be one of {', '.join(PATHS)}, got {path!r}")
    if mass not in MASSES:
        raise ValueError(f"mass must be one of {', '.join(MASSES)}, got {mass!r}")
    if path == "density" and mass == "water":
        raise ValueError("mass 'water' needs path 'affine': the density path keeps the "
                         "volumes m/rho of a stage, so its masses are the scaled ones")
    mf = water_mass(lmp, p, s, s_old) if mass == "water" else None
    nlocal = lmp.extract_global("nlocal")
    if path == "density":
        rho = lmp.numpy.extract_atom("rho")
        rho[:nlocal] *= s / s_old
    else:
        centre = wall_positions(lmp, p).mean(axis=0)
        x = lmp.numpy.extract_atom("x")
        x[:nlocal, :2] = centre + (x[:nlocal, :2] - centre) * math.sqrt(s / s_old)
    lmp.commands_list(level_commands(p, s, mf))


def water_mass(lmp, p, s, s_old):
    """Fluid particle mass of level ``s`` for which an SPH cell holds the fast variant's
    water, ``fluid_area = s A0``: its particles' area sum m/rho (at their present
    densities, which the affine path keeps) plus the layer between them and the wall.
    The fast variant's fluid fills its ring; SPH particles stay about a spacing from the
    wall, so a cell whose particles held s A0 would enclose s A0 plus that layer, which
    thins only with the spacing (doc/mfc.md). The layer is measured on the present state
    (level ``s_old``) and carried to ``s`` by the spacing, sqrt(s / s_old), and the wall's
    rest length (its perimeter). Masses are per type: the mean over the cells."""
    now = fluid_state(lmp, p, s_old)
    carry = math.sqrt(s / s_old) * level(p, s)["r0_bond"] / level(p, s_old)["r0_bond"]
    layer = (now["ring"] - now["fluid"]) * carry
    m_old = lmp.numpy.extract_atom("mass")[4]
    return m_old * float(np.mean((level(p, s)["fluid_area"] - layer) / now["fluid"]))


def wall_positions(lmp, p):
    """Wall particle positions (n_cells * n_wall, 2), by atom ID."""
    return mfc_run.positions(lmp)[: lmp.extract_global("nbonds")]


def fluid_state(lmp, p, s):
    """The SPH state of every cell at level ``s``, gathered from all ranks: wall positions
    (by atom ID) and per cell arrays ``fluid`` (its particles' area sum m/rho, m^2), ``ring``
    (the area its wall encloses), ``layer`` ((ring - fluid) / wall perimeter: the mean
    width between wall and fluid, m), ``void`` (share of the ring farther than one fluid
    spacing of level s from every fluid particle: holes the fluid left), ``nearest`` (mean
    distance to the nearest fluid particle of the cell over that spacing: a fluid that
    pairs up falls towards 0), ``pressure`` and ``pressure_sd`` (its particles' Tait
    pressure, Pa), the mean ``near_wall_pressure`` of its particles within the kernel support
    of its wall (Pa) and the walls' mean ``wall_pressure`` (Pa)."""
    n = lmp.get_natoms()
    x = np.array(lmp.gather_atoms("x", 1, 3), float).reshape(n, 3)[:, :2]
    rho = np.array(lmp.gather_atoms("rho", 1, 1), float)
    mol = np.array(lmp.gather_atoms("molecule", 0, 1))
    kind = np.array(lmp.gather_atoms("type", 0, 1))
    mass = lmp.numpy.extract_atom("mass")[kind]
    nw = lmp.extract_global("nbonds")
    walls = x[:nw]
    cells = mfc_metrics.cells(walls, p["n_wall"])
    press = pressure(p, s, rho)
    dx = p["fluid_spacing"] * math.sqrt(s)
    out = {k: np.empty(len(cells["area"])) for k in (
        "fluid", "void", "nearest", "pressure", "pressure_sd", "near_wall_pressure",
        "wall_pressure")}
    for c, ring in enumerate(walls.reshape(-1, p["n_wall"], 2)):
        own = np.flatnonzero((mol == c + 1) & (np.arange(n) >= nw))
        tree = cKDTree(x[own])
        out["fluid"][c] = (mass[own] / rho[own]).sum()
        out["nearest"][c] = tree.query(x[own], 2)[0][:, 1].mean() / dx
        lo, hi = ring.min(axis=0), ring.max(axis=0)
        g = [np.arange(lo[k], hi[k], dx / 8) for k in (0, 1)]
        grid = np.stack(np.meshgrid(*g), axis=-1).reshape(-1, 2)
        grid = grid[tissue._inside(grid, ring, 0.0, closed=False)]
        out["void"][c] = np.mean(tree.query(grid)[0] > dx)
        out["pressure"][c], out["pressure_sd"][c] = press[own].mean(), press[own].std()
        near = cKDTree(ring).query(x[own])[0] < SUPPORT
        out["near_wall_pressure"][c] = press[own][near].mean() if near.any() else np.nan
        out["wall_pressure"][c] = press[c * p["n_wall"]:(c + 1) * p["n_wall"]].mean()
    out.update(walls=walls, ring=cells["area"],
               layer=(cells["area"] - out["fluid"]) / cells["perimeter"])
    return out
