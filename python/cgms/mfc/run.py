# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Run the fine-scale (MFC) model in LAMMPS: the fast steady-state variant.

Each cell's fluid is at rest at a steady state, so it is one pressure from the equation
of state of the area its wall ring encloses (``fix mfc/pressure``, doc/fix_mfc_pressure.rst).
The walls are LAMMPS's own styles: harmonic bonds (stretching) and cosine angles (bending) along
each ring, and 8-4 Lennard-Jones (``pair nm/cut``) for the wall's self-avoidance and the
middle lamella between adjacent cells (types = cell colours, so 1-1, 2-2, 3-3 are own-cell
pairs and the rest neighbour-cell pairs). The whole model has a potential energy, so a
steady state is a minimum: ``minimize`` (conjugate gradients) and Newton's method find it.

Steady-state criterion (doc/mfc.md): the largest force component on any wall particle is
below ``ftol`` (N; the turgor load on a fresh wall particle is about 6e-6 N). Conjugate
gradients run in chunks of ``chunk`` iterations until the largest force is below ``newton``
(N); Newton's method (:mod:`cgms.mfc.newton`) then finishes the level, which the minimiser
alone does not for large dried tissues (their softest modes, the glued sheet sliding, creep
for tens of thousands of iterations). With ``newton`` None the minimiser runs alone and a
level is also taken as steady when over one chunk no cell centroid moved more than
``shift`` (m) and no cell area changed by more than ``area`` (relative). A level that
meets neither within ``max_iterations`` is reported as not converged, with its last
chunk's centroid shift. Once the minimiser's iterations are spent, Newton is all that is left:
it gets up to ``SPENT_NEWTON_CALLS`` calls (of 40 steps), and stops early when it cannot
lower the energy (the driest levels of the 203- and 248-cell tissues needed more than one).

Drying path (the ramp): the fresh tissue is relaxed first; every later level starts from
the previous level's steady state and passes through intermediate levels ``stage`` apart.
The reference path (``REFERENCE_PATH``) relaxes each of them to its steady state too,
0.025 apart: a quasi-static path, as a slowly dried tissue takes
(drying takes hours, a cell's walls come to rest in well under a second). The path matters:
with one chunk of minimisation per intermediate level, 0.05 apart (``steady_stages`` off,
:func:`ramp`'s defaults and the path of the sets made before 2026-12-04) the long tissues
reach another dried shape (doc/mfc.md,
"The long tissues' two dried shapes"). A jump from s = 1 to 0.8 in one go starts the fluid
at -16 MPa.
"""

import math

import numpy as np

from .model import level

DEFAULTS = dict(ftol=1e-10, shift=5e-8, area=1e-4, chunk=2000, stage=0.05,
                max_iterations=20000, timestep=5e-9, dmax=2e-7, kick=1e-7, style="cg",
                newton=1e-6, seed=1, steady_stages=False)

#: the reference path of ``cgms mfc`` and :func:`cgms.mfc.study.dry`: every stage relaxed to
#: its steady state, stages 0.025 apart (the dried shape still moves between stages of 0.05
#: and 0.025, and no longer between 0.025 and 0.0125: doc/mfc.md, "Path (the ramp)").
#: :func:`ramp`'s own defaults stay the chunked path (one chunk per stage, 0.05 apart) of
#: the sets and studies made before, which call it directly
REFERENCE_PATH = dict(steady_stages=True, stage=0.025)

#: largest kick seed: LAMMPS's random seeds stop at 2^31 - 1, and a level adds up to 1e4 to it
MAX_SEED = 2**31 - 1 - 10**4

#: Newton calls (40 steps each) a level gets once the minimiser's iterations are spent
SPENT_NEWTON_CALLS = 5


#: LAMMPS packages the fast variant's styles come from (bond harmonic, angle cosine; pair nm/cut)
PACKAGES = ("MOLECULE", "EXTRA-PAIR")


def require_packages(lmp, packages=PACKAGES):
    """Stop with one clear message when this LAMMPS lacks a package the MFC model uses
    (``./cgms setup`` builds them; a LAMMPS of one's own may not have them)."""
    missing = [name for name in packages if not lmp.has_package(name)]
    if missing:
        raise RuntimeError(f"the MFC model needs LAMMPS's {', '.join(missing)} package(s), "
                           "which this LAMMPS was built without: build it with "
                           + " ".join(f"-DPKG_{name}=on" for name in missing)
                           + " (./cgms setup does)")



def wall_bending(p):
    """The walls' bending, shared by the fast variant and the SPH model: E = k_b (1 - cos phi)
    at turning angle phi (= k_b phi^2 / 2 for small phi), LAMMPS's cosine style
    E = K (1 + cos theta). Not angle harmonic at theta0 = 180: it caps 1/sin(theta) at 1000,
    so within 1 mrad of straight (8 % of the angles of a dried wrinkled wall) its force is
    not the gradient of its energy, and minimisers stall (doc/mfc.md, "Why the dried levels
    crept")."""
    return ["angle_style cosine", f"angle_coeff 1 {p['k_bend']:.10g}"]

def setup_commands(data, p, newton="on", processors=None, boundary="s s p", rest=()):
    """LAMMPS commands that read an MFC wall data file (:func:`cgms.mfc.tissue.write_data`)
    and define the wall forces; the drying levers follow with :func:`level_commands`.
    ``rest``: the rest lengths of the lamella bond types 2, 3, ... of a lamella set in the
    fresh tissue (:func:`cgms.mfc.tissue.fresh_lamella`)."""
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
        *wall_bending(p),
        f"pair_style nm/cut {p['lamella_rc']:.10g}",
        "pair_modify shift yes",
        # middle lamella: walls of different cells (types = colours) rest d_p apart
        f"pair_coeff * * {p['lamella_E0']:.10g} {p['pectin']:.10g} 8 4 {p['lamella_rc']:.10g}",
    ]
    lines += [f"pair_coeff {t} {t} {p['self_E0']:.10g} {per:.10g} 8 4 {per:.10g}"
              for t in (1, 2, 3)]
    lines += [f"bond_coeff {t} {p['lamella_k'] / 2:.10g} {r:.10g}"
              for t, r in enumerate(rest, start=2)]
    lines += [
        "neighbor 2e-6 bin",
        "neigh_modify every 1 delay 0 check yes",
        "fix 2d all enforce2d",
    ]
    return [line for line in lines if line]


def level_commands(p, s, fix_id="mfc"):
    """The drying levers at dryness ``s``: bond rest length (wall contraction), the cell
    fluid's area at rest density and its turgor (``fix mfc/pressure``). Statics do not
    depend on the wall masses, so they keep their fresh value (FIRE's pace)."""
    lv = level(p, s)
    lamella = []
    if p.get("lamella", "lj") in ("bonded", "facing"):
        lamella = [f"bond_coeff 2 {p['lamella_k'] / 2:.10g} {p['pectin']:.10g}",
                   f"bond_coeff 3 {p['lamella_k'] / 2:.10g} {lv['r0_diagonal']:.10g}"]
    return [
        f"bond_coeff 1 {p['k_bond'] / 2:.10g} {lv['r0_bond']:.10g}",
        *lamella,
        f"fix {fix_id} all mfc/pressure height {p['height']:.10g} modulus {p['K']:.10g} "
        f"turgor {lv['turgor']:.10g} area {lv['fluid_area']:.10g}",
        f"fix_modify {fix_id} energy yes",
    ]


def minimize_commands(ftol, max_iterations, timestep=DEFAULTS["timestep"],
                      dmax=DEFAULTS["dmax"], style=DEFAULTS["style"]):
    """Minimise down to the largest force component ``ftol`` (N): conjugate gradients
    with a quadratic line search (default; measured 10x faster than FIRE on the fresh
    86-cell tissue, doc/mfc.md) or FIRE, whose time step sets its pace (statics do not
    depend on the masses). ``dmax`` (m) caps a step's displacement."""
    line = " line quadratic" if style == "cg" else ""
    return [f"timestep {timestep:.10g}",
            f"min_style {style}",
            f"min_modify norm max dmax {dmax:.10g}{line}",
            f"minimize 0.0 {ftol:.10g} {int(max_iterations)} {10 * int(max_iterations)}"]


def positions(lmp):
    """Wall particle positions (n, 2) ordered by atom ID (any number of ranks)."""
    n = lmp.get_natoms()
    x = np.array(lmp.gather_atoms("x", 1, 3), dtype=float).reshape(n, 3)
    return x[:, :2]


def _cells(lmp, n_wall, s):
    """Area centroids and areas of the cells (the polygon measures of cgms.mfc.metrics) at
    dryness ``s``; a ring those cannot measure stops with the level it was met at."""
    from .metrics import RingError, cells
    try:
        c = cells(positions(lmp), n_wall)
    except RingError as err:
        err.level = s
        raise
    return c["centroid"], c["area"]


def remaining(changes, last=6):
    """Extrapolate a decaying series of per-chunk changes (e.g. the mean centroid shift of
    each chunk): fit ``|c_k| = a r^k`` to the last ``last`` chunks (least squares in log)
    and return ``(r, rest)``, ``rest`` the sum of the chunks still to come,
    ``a r^n r / (1 - r)`` after the n-th. ``rest`` is inf when the changes do not decay
    (r >= 1) and nan with fewer than three chunks."""
    c = np.abs(np.asarray(changes, float))[-last:]
    if len(c) < 3:
        return math.nan, math.nan
    k = np.arange(len(c))
    slope, intercept = np.polyfit(k, np.log(np.maximum(c, 1e-300)), 1)
    r = math.exp(slope)
    if r >= 1:
        return r, math.inf
    return r, math.exp(intercept + slope * k[-1]) * r / (1 - r)


def relax(lmp, p, s, ftol=DEFAULTS["ftol"], shift=DEFAULTS["shift"], area=DEFAULTS["area"],
          chunk=DEFAULTS["chunk"], max_iterations=DEFAULTS["max_iterations"],
          timestep=DEFAULTS["timestep"], dmax=DEFAULTS["dmax"], style=DEFAULTS["style"],
          newton=DEFAULTS["newton"]):
    """Set the levers of ``s`` and minimise to the steady-state criterion (module doc).
    ``newton`` (N): once the largest force is below it (or the iterations are spent),
    Newton's method (:func:`cgms.mfc.newton.newton`) finishes the level to ``ftol``; the
    shift test is then not used. None: the minimiser alone. Returns the iterations, the
    largest force component left (N), the centroid shift (m) and relative area change of
    the last chunk (for Newton: over its steps), the energy, ``converged``, ``newton`` (its
    successful calls ``attempts``, iterations, force evaluations and seconds, and the
    ``error`` of a call that failed; None if it never ran), and for a level that did not
    converge, the mean centroid shift of each chunk (``mean_shifts``, m) and what
    :func:`remaining` extrapolates from them (``shift_ratio`` per chunk,
    ``remaining_shift``: the mean centroid travel still to come, m)."""
    start = lmp.extract_global("ntimestep")
    lmp.commands_list(level_commands(p, s))
    centroid, cell_area = _cells(lmp, p["n_wall"], s)
    done, now, means, finish = 0, style, [], None
    while True:
        before = lmp.extract_global("ntimestep")
        lmp.commands_list(minimize_commands(ftol, chunk, timestep, dmax, now))
        done = int(lmp.extract_global("ntimestep") - start)
        fmax = lmp.get_thermo("fmax")
        # CG stops early, short of ftol, when its line search fails (the energy is flat to
        # round-off along the search direction); a FIRE chunk then carries on
        stalled = fmax > ftol and lmp.extract_global("ntimestep") - before < chunk
        now = "fire" if stalled else style
        new_centroid, new_area = _cells(lmp, p["n_wall"], s)
        shifts = np.hypot(*(new_centroid - centroid).T)
        moved = float(shifts.max())
        means.append(float(shifts.mean()))
        changed = float(np.abs(new_area / cell_area - 1).max())
        centroid, cell_area = new_centroid, new_area
        steady = fmax <= ftol or (not newton and moved <= shift and changed <= area
                                  and not stalled)
        spent = done >= max_iterations
        if newton and not steady and (fmax <= newton or spent):
            # no minimiser chunk comes after a spent budget: Newton carries on alone while
            # it can take steps (each lowers the energy; the largest force need not fall
            # far from the minimum). Only this call's failure stops it: an earlier chunk's
            # failed call stays in the report
            for _ in range(SPENT_NEWTON_CALLS if spent else 1):
                attempts = finish["attempts"] if finish else 0
                finish = _newton(lmp, p, ftol, finish)
                fmax = lmp.get_thermo("fmax")
                if fmax <= ftol or finish["attempts"] == attempts:
                    break
            steady = fmax <= ftol
            new_centroid, new_area = _cells(lmp, p["n_wall"], s)
            shifts = np.hypot(*(new_centroid - centroid).T)
            moved = float(shifts.max())
            means[-1] += float(shifts.mean())
            changed = float(np.abs(new_area / cell_area - 1).max())
            centroid, cell_area = new_centroid, new_area
        if steady or spent:
            break
    report = dict(s=s, iterations=done, fmax=fmax, shift=moved, area_change=changed,
                  converged=bool(steady), energy=lmp.get_thermo("pe"),
                  newton=finish)
    if not steady:
        ratio, rest = remaining(means)
        # None, not nan or inf, in the level record: too few chunks, or not decaying
        report.update(mean_shifts=means, shift_ratio=ratio if math.isfinite(ratio) else None,
                      remaining_shift=rest if math.isfinite(rest) else None)
    return report


def _newton(lmp, p, ftol, before=None, iterations=40):
    """Newton's method from the current state (:func:`cgms.mfc.newton.newton`), at most
    ``iterations`` steps. Returns its totals added to ``before`` (attempts, iterations,
    force evaluations, seconds); a failure (no step lowers the energy) is recorded, not
    raised: the minimiser carries on."""
    from .newton import newton
    total = dict(before or dict(attempts=0, iterations=0, evaluations=0, seconds=0.0))
    try:
        r = newton(lmp, p, ftol=ftol, max_iterations=iterations)
    except RuntimeError as error:
        total["error"] = str(error)
        return total
    total["attempts"] += 1
    for key in ("iterations", "evaluations", "seconds"):
        total[key] += r[key]
    return total


def stages(s_from, s_to, stage):
    """Intermediate levels strictly between ``s_from`` and ``s_to``, ``stage`` apart."""
    if s_from is None or stage <= 0:
        return []
    k = int(math.floor((s_from - s_to) / stage - 1e-9))
    return [s_from - j * stage for j in range(1, k + 1)]


def ramp(lmp, p, s_from, s_to, stage=DEFAULTS["stage"], kick=DEFAULTS["kick"],
         seed=DEFAULTS["seed"], steady_stages=DEFAULTS["steady_stages"], **kwargs):
    """From the steady state at ``s_from`` (None: the built tissue) to that at ``s_to``
    through the intermediate levels (module doc: one chunk of minimisation each at a 1e3
    times looser force test, or with ``steady_stages`` each at rest). Before each
    dried level every wall particle is displaced at random by up to ``kick`` (m): a
    contracted wall held at its circle is a saddle (it must buckle: MFC.md 5.3), which a
    minimiser started exactly on it never leaves; the kicks of level ``s`` are seeded with
    ``seed + round(1e4 s)``, so a study is reproducible and ``seed`` alone picks which of
    the dried levels' neighbouring minima it lands on. The quasi-static path costs 1.5-2
    times the chunked one. Returns the final :func:`relax` report with the total iterations;
    with ``steady_stages`` also ``unsteady_stages``, the intermediate levels that did not
    reach their steady state (the iterations spent first), so a path that was not
    quasi-static says so."""
    total, unsteady = 0, []
    levels = stages(s_from, s_to, stage) + [s_to]
    for k, s in enumerate(levels):
        if kick and s < 1:
            lmp.command(f"displace_atoms all random {kick:.10g} {kick:.10g} 0 "
                        f"{seed + int(round(1e4 * s))} units box")
        last = k == len(levels) - 1
        # off the quasi-static path an intermediate level is one chunk (or less, at 1e3
        # ftol): cheaper, but not at rest, and the long tissues then elongate instead
        options = dict(kwargs) if last or steady_stages else dict(
            kwargs, max_iterations=kwargs.get("chunk", DEFAULTS["chunk"]),
            ftol=1e3 * kwargs.get("ftol", DEFAULTS["ftol"]), newton=None)
        report = relax(lmp, p, s, **options)
        total += report["iterations"]
        if steady_stages and not last and not report["converged"]:
            unsteady.append(s)
    report["iterations"] = total
    if steady_stages:
        report["unsteady_stages"] = unsteady
    return report
