# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Parameters of the fine-scale (MFC) model and the drying levers per level (doc/mfc.md).

The MFC (Karunasena et al., Soft Matter 10, 2014, 5249) resolves every cell: a closed ring
of wall particles (DEM) around its fluid. Values shared with CGMS (cell diameter, slab
height, pectin layer, turgor, compression modulus, density, perimeter law, solid ratio)
come from the CGMS material file, so the two models describe the same tissue; the values
below are the MFC's own, each with its source or the reason it was chosen (doc/mfc.md,
"Decisions").
"""

import math

from scipy.constants import R as GAS_CONSTANT, zero_Celsius

from .. import material, model

#: the MFC's own parameters (SI units)
MFC = dict(
    per_side=16,             # wall particles per hexagon side: 96 per cell (Wijerathne 2019 2.1)
    wall_Et=330.0,           # wall extensional stiffness E t, N/m: 4.5 % turgid strain
    wall_thickness=1.0e-6,   # wall thickness t, m (bending k_b = E H t^3 / (12 r0_b))
    self_E0=1.0e-10,         # wall self-avoidance: 8-4 LJ, repulsive only, E0 = f0/8, J;
                             # holds the folds of dried walls apart (SELF_E0_FOLDS)
    self_r0=3.0e-6,          # its radius (= cutoff), m: below the shortest bond (3.96 um)
    lamella_E0=1.45e-11,     # middle lamella: 8-4 LJ between walls of adjacent cells, J
    lamella_rc=12.0e-6,      # its cutoff, m (its radius is the pectin layer d_p)
    # the middle lamella glues the walls of adjacent cells for good (van Opheusden and
    # Molenaar, R. Soc. Open Sci. 5, 2018, 181127): harmonic bonds from every wall particle
    # to the facing one and its two neighbours (a truss, so walls cannot slide along each
    # other), on top of the LJ. "fresh": set in the relaxed fresh tissue, at rest there
    # (the fresh tissue is the LJ-only one); "bonded": set in the built hexagons; "facing":
    # the built facing bonds only; "lj": the LJ alone (doc/mfc.md, decisions)
    lamella="fresh",
    lamella_k=7.3,           # its bond stiffness, N/m: the LJ's stiffness at d_p, 32 E0 / d_p^2
    bend_factor=1.0,         # multiplies the thin-plate bending stiffness k_b (MFC.md: up to 10)
    fluid_spacing=5.0e-6,    # SPH fluid lattice, m (656 particles per cell)
    fluid_margin=3.25e-6,    # fluid points at least this far from every wall line, m
)

#: a self-avoidance strength (J) that holds the pressed layers of a dried wall's folds apart:
#: the most its repulsion resists a wall particle pushed through the gap of a bond at the
#: s = 0.3 rest length (3.96 um) is 3.4e-3 N, 10 x the largest force a ramp stage starts
#: with (3.3e-4 N) and 100 x the contact forces of folds at rest (2-3e-5 N); E0 = 1e-12 J
#: resists 3.4e-5 N and the layers passed through each other, 1e-11 J still let the
#: 86-cell tissue cross at s = 0.4 (doc/mfc.md, "Wall self-avoidance"). The default
#: (:data:`MFC`), since a reference whose walls pass through themselves is not a tissue;
#: it leaves every state without wall contact unchanged (s = 1 and 0.8 bit-identical)
SELF_E0_FOLDS = 1.0e-10

#: temperature in the mechanics (doc/drying.md, "Temperature in the mechanics"). Without a
#: temperature the material's values stand as they are: those of unheated fresh tissue.
HEAT = dict(
    # first-order softening of the tissue's E-modulus, k = k_100 exp(-E_a/R (1/T - 1/373.15 K))
    # (carrot, Verlinden et al. 1996, as tabled by Lee 2017, Food Eng. Prog. 21, 303, Table 1:
    # the one Young's-modulus row; apple and potato rows give firmness, not a modulus)
    softening_k100=0.161 / 60,   # 1/s at 100 C (0.161 1/min)
    softening_Ea=138e3,          # J/mol
    # Decision: the share of stiffness the fast softening cannot remove (two-mechanism
    # theory, Bourne 1989: the slow mechanism carries 3-20 % of firmness); range 0.03-0.2
    softening_residual=0.1,
    softening_hours=1.0,         # Decision: time at temperature, h; range 0.25-4 (drying times)
    # Decision: membranes intact up to 50 C, none left at 60 C, linear between (heated apple
    # flesh: no membrane damage at 40 C, damage at 60 and 80 C; J. Food Eng. 261, 2019, 26);
    # range: onset 40-60 C, complete 60-80 C
    membrane_onset=50.0,         # C
    membrane_gone=60.0,          # C
    T_min=0.0, T_max=100.0,      # C: liquid cell water; the softening data reach 100 C
)


def wall_softening(temperature, heat=HEAT):
    """E(T)/E of unheated tissue after ``softening_hours`` at ``temperature`` (C): first-order
    loss of all but the residual share, Arrhenius in the absolute temperature."""
    T = temperature + zero_Celsius
    k = heat["softening_k100"] * math.exp(-heat["softening_Ea"] / GAS_CONSTANT
                                          * (1 / T - 1 / (100 + zero_Celsius)))
    r = heat["softening_residual"]
    return r + (1 - r) * math.exp(-k * heat["softening_hours"] * 3600)


def membrane_intact(temperature, heat=HEAT):
    """Share of cells whose membranes still hold turgor at ``temperature`` (C)."""
    lo, hi = heat["membrane_onset"], heat["membrane_gone"]
    return min(1.0, max(0.0, (hi - temperature) / (hi - lo)))


def turgor_factor(temperature, reference, heat=HEAT):
    """P_T(T)/P_T(reference): van 't Hoff's Pi = c R T at the same solutes (absolute
    temperatures), held only by intact membranes."""
    return ((temperature + zero_Celsius) / (reference + zero_Celsius)
            * membrane_intact(temperature, heat))


def heated(p, temperature, reference=20.0):
    """The parameter set ``p`` at ``temperature`` (C): walls and lamella softened, turgor
    scaled. The rest lengths stay those of the unheated wall (they are its shape, which
    heating does not set), so the fresh cell keeps its water and only its stiffness and
    turgor change. ``reference``: the temperature of the material's values (Decision: room
    temperature, 20 C)."""
    T = float(temperature)
    if not HEAT["T_min"] <= T <= HEAT["T_max"]:
        raise ValueError(f"temperature must be in {HEAT['T_min']:g} .. {HEAT['T_max']:g} C "
                         f"(liquid cell water), got {temperature!r}")
    w = wall_softening(T)
    p = dict(p, temperature=T, wall_factor=w, turgor_factor=turgor_factor(T, reference))
    for name in ("wall_Et", "k_bond", "k_bend", "lamella_k", "lamella_E0"):
        p[name] = p[name] * w
    return p


#: the forms of the middle lamella (:data:`MFC`, ``lamella``)
LAMELLA = ("fresh", "bonded", "facing", "lj")


def parameters(material_name="apple", temperature=None, **overrides):
    """The MFC parameters: the CGMS material's shared values plus :data:`MFC`, and the
    derived fresh wall: turgid strain, rest bond length, bond and angle constants. With a
    ``temperature`` (C), those of :func:`heated`; without, the material's as they are."""
    p = dict(material.read(material_name))
    p.update(MFC)
    p.update(overrides)
    n = 6 * int(p["per_side"])
    p["n_wall"] = n
    # a free turgid cell is a circle of diameter D at P_f: Laplace's law P R = E t eps
    p["strain_turgid"] = p["P_f"] * p["diameter"] / (2 * p["wall_Et"])
    p["r0_bond"] = math.pi * p["diameter"] / (1 + p["strain_turgid"]) / n
    p["k_bond"] = p["wall_Et"] * p["height"] / p["r0_bond"]          # N/m, F = -k (l - r0)
    p["k_bend"] = (p["bend_factor"] * p["wall_Et"] * p["height"] * p["wall_thickness"] ** 2
                   / (12 * p["r0_bond"]))
    if p["lamella"] not in LAMELLA:
        raise ValueError(f"lamella must be one of {', '.join(LAMELLA)}, got {p['lamella']!r}")
    p["fluid_mass"] = p["rho0"] * p["A_ref"] * p["height"]            # fresh, per cell (kg)
    p["wall_mass"] = p["solid_ratio"] * p["fluid_mass"] / n           # per particle, fresh
    return p if temperature is None else heated(p, temperature)


def level(p, s):
    """The three drying levers at dryness s = X/X0 (moisture-domain approach):

    - moisture: the fluid mass is s times the fresh one, so its area at rest density is
      ``fluid_area = s A0``;
    - turgor: ``P_T = s P_f`` (linear in fluid mass), times ``turgor_factor`` when heated;
    - wall contraction: every bond rest length scales with the perimeter law
      ``l_d / l0' = 1 - (a/b)(1 - s)`` (CGMS eqn 9, a = 0.2, b = 0.9); the bonded
      lamella's diagonals rest at ``sqrt(d_p^2 + r0_bond^2)``, so the lamella is free of
      stress when both walls are at their rest length and follows their contraction.

    Returns a dict with those and the per-particle wall mass (scaled by s too)."""
    s = float(s)
    if not 0 < s <= 1:
        raise ValueError(f"dryness s = X/X0 must be in (0, 1], got {s!r}")
    contraction = float(model.perimeter_contraction(p, s))
    return dict(s=s, fluid_area=s * p["A_ref"], turgor=s * p["P_f"] * p.get("turgor_factor", 1.0),
                r0_bond=p["r0_bond"] * contraction, contraction=contraction,
                r0_diagonal=math.hypot(p["pectin"], p["r0_bond"] * contraction),
                wall_mass=s * p["wall_mass"])

