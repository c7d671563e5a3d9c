# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""How a command ends on an error: one line in the CLI's own terms, never a traceback."""

import re
from types import SimpleNamespace

from .. import study
from .options import UsageError, describe, fallback_of


# --------------------------------------------------------------------------- LAMMPS stops

# A LAMMPS stop names its cure in LAMMPS commands (min_style, timestep, pair_coeff ...),
# which a command-line user does not write. Each entry: the stop's words in LAMMPS's ERROR
# line (or cgms.run.folded's), and a function of the match and the run's context giving
# (cause, cure) in the CLI's own terms. LAMMPS's whole line stays in the log.

_NUM = r"(-?[0-9.eE+-]+|-?nan|-?inf)"


def _isolated_low(m, c):
    cause = (f"bead {m['bead']}'s nearest neighbour ({m['near']} m away) is beyond the "
             f"interaction cutoff, which shrinks with the dryness ({m['cut']} m at s = "
             f"{c.s:g}; the built lattice keeps its neighbours only down to s = "
             f"{m['lowest']}, with little room to move)")
    if c.start == "built":
        return cause, ("--start previous dries the levels in turn, each from the previous "
                       "level's steady state")
    return cause, "add levels between the previous one and this to --dryness"


def _minimizer_away(m, c):
    return (f"the quasi-static solve (FIRE) moved bead {m['bead']} out of its neighbours' "
            f"reach at iteration {m['step']}",
            "--fallback dynamics (the default) solves such a level with the dynamics instead "
            "of stopping" if not c.fallback else
            "--method newton is another quasi-static solve")


def _isolated(m, c):
    return (f"bead {m['bead']} lost every neighbour at step {m['step']} ({m['where']}): the "
            "tissue tore apart at this level",
            "check the material (--material, --set); --start previous reaches a dried level "
            "in turn, from the previous level's steady state")


def _unstable(m, c):
    solve = "the dynamics" if c.method == "dynamics" else "the quasi-static solve"
    cause = f"{solve} became unstable at step {m['step']} ({m['what']})"
    if c.method == "dynamics" and not c.first:
        return cause, ("--method quasistatic or newton solves for the steady state with no "
                       "time step")
    if c.method != "dynamics" and not c.fallback:
        return cause, "--fallback dynamics (the default) follows the dynamics instead"
    return cause, ("no method solved this level: the material (--material, --set) may be "
                   "outside what the model holds at this dryness (doc/errors.md)")


def _damping_step(m, c):
    return (f"the dynamics' time step is above the damping's stability limit ({m['limit']} s) "
            f"for bead {m['bead']} (mass {m['mass']} kg) at step {m['step']}",
            "the limit, 2 m / (1.5 N k_d), grows with the bead mass m (the material's height, "
            "diameter, rho0) and falls with k_d (--set); --method quasistatic or newton take "
            "no time step" if c.method == "dynamics" and not c.first else
            "the limit, 2 m / (1.5 N k_d), grows with the bead mass m (the material's height, "
            "diameter, rho0) and falls with k_d (--set)")


def _shape_step(m, c):
    return (f"the cell-shape stiffness k_S = {m['kS']} N/m is too stiff for the dynamics' "
            f"time step (step {m['step']})",
            "a smaller k_S (--set), or --method quasistatic or newton, which take no time step")


def _collapse(m, c):
    return (f"the tissue collapsed at step {m['step']}: bead {m['bead']} has {m['n']} "
            "neighbours within the cutoff, where a hexagonal tissue has 6 (the paper's forces "
            "do not resist shear)",
            "a cell-shape stiffness resists it: --set 'k_S 0.5' (a larger k_S where the "
            "material has one; doc/pair_cgms.rst)")


def _folded(m, c):
    return (f"the steady state folded onto itself (bead {m['bead']} has {m['n']} neighbours "
            "within the cutoff, where a hexagonal tissue has 6)",
            "a cell-shape stiffness or a stiffer perimeter law resists it: --set 'k_S 0.5' "
            "or a larger k_PA (doc/pair_cgms.rst)")


def _apart(m, c):
    return (f"the steady state came apart into {m['pieces']} pieces: the interaction cutoff "
            "may have fallen below the bead spacing",
            "a smaller lj_slope (--set), or --start previous")


def _crowded(m, c):
    near = re.search(r"nearest beads (\S+) m apart", m["reason"])
    return (f"the beads are too close for the material: bead {m['bead']} has {m['n']} "
            "neighbours at the start"
            + (f" (nearest beads {near.group(1)} m apart" if near else " (")
            + f"{'; ' if near else ''}the material's cell spacing x_ref = {m['xref']} m)",
            "--data positions must be cell centres in metres, and the material's diameter "
            "and pectin (--material, --set) must fit them")


def _overlap(m, c):
    return (f"beads {m['a']} and {m['b']} are {m['d']} m apart, closer than the pectin "
            "layer between two cells",
            "remove the overlapping or duplicated beads from the --data file")


def _nonfinite(m, c):
    return (f"bead {m['bead']} has a non-finite {m['what']}",
            "check the --data file's numbers")


def _low_dryness(m, c):
    return (f"at s = {c.s:g} the material's {m['what']} is not positive",
            f"--dryness levels above {m['lowest']}, or another {m['params']} (--set)")


LAMMPS_STOPS = [
    (r"bead (?P<bead>\d+) has no neighbour within the pair cutoff .*? at step \d+: "
     r"(?:its nearest bead is (?P<near>\S+) m away|[^;]*); at dryness \S+ the cutoff is "
     r"(?P<cut>\S+) m .*down to a dryness of about (?P<lowest>\S+)\)", _isolated_low),
    (r"bead (?P<bead>\d+) has no neighbour within the pair cutoff .*? at step (?P<step>\d+):"
     r".*the minimizer moved it away", _minimizer_away),
    (r"bead (?P<bead>\d+) has no neighbour within the pair cutoff .*? at step (?P<step>\d+): "
     r"(?P<where>[^;]*)", _isolated),
    (r"(?P<what>fluid mass of bead \d+ became \S+) at step (?P<step>\d+)", _unstable),
    (r"(?P<what>bead \d+ has a non-finite pressure) at step (?P<step>\d+)", _unstable),
    (r"stability limit of the cell-shape stiffness k_S = (?P<kS>\S+) N/m at step "
     r"(?P<step>\d+)", _shape_step),
    (r"the change of dryness at step (?P<step>\d+) (?P<what>compresses bead \d+)", _unstable),
    (r"stability limit of the damping at step (?P<step>\d+), about (?P<limit>\S+) s = .*? for "
     r"bead (?P<bead>\d+) \(m = (?P<mass>\S+) kg", _damping_step),
    (r"(?P<what>stability limit of the turgor force) at step (?P<step>\d+)", _unstable),
    (r"bead (?P<bead>\d+) has (?P<n>\S+) neighbours within the cutoff at step (?P<step>\d+), "
     r"more than the 6 of a hexagonal tissue: the tissue is collapsing", _collapse),
    (r"folded onto itself: bead (?P<bead>\d+) has (?P<n>\S+) neighbours", _folded),
    (r"came apart: (?P<pieces>\d+) pieces", _apart),
    (r"bead (?P<bead>\d+) has (?P<n>\S+) neighbours within the pair cutoff (?:\(\S+ m\) )?at "
     r"setup.*x_ref = (?:sqrt\(3\) b_ref \+ d_p = )?(?P<xref>[0-9.eE+-]+) m", _crowded),
    (r"beads (?P<a>\d+) and (?P<b>\d+) are (?P<d>\S+) m apart at setup", _overlap),
    (r"bead (?P<bead>\d+) has a non-finite (?P<what>position|velocity)", _nonfinite),
    (r"the (?P<what>periphery factor beta) .* is not positive.*dryness above "
     r"exp\(-beta_a/beta_b\) = (?P<lowest>\S+)(?P<params>)", _low_dryness),
    (r"the (?P<what>LJ radius) r0 .* is not positive.*dryness above exp\(-1/lj_slope\) = "
     r"(?P<lowest>\S+)(?P<params>)", _low_dryness),
]
_PARAMS = {"periphery factor beta": "beta_a, beta_b", "LJ radius": "lj_slope"}


def cause_and_cure(reason, context):
    """(cause, cure) of a LAMMPS ERROR line in the CLI's terms, or None for a stop the
    table does not know (its line is then shown as LAMMPS gave it)."""
    reason = re.sub(r" \(\S+\.cpp:\d+\)", "", reason)   # LAMMPS's source line
    for pattern, explain in LAMMPS_STOPS:
        m = re.search(pattern, reason)
        if m:
            groups = {k: v.rstrip(".,;") if v else v for k, v in m.groupdict().items()}
            groups["reason"] = reason
            if "params" in groups:
                groups["params"] = _PARAMS[groups["what"]]
            return explain(groups, context)
    return None


def _same_cause(a, b):
    """Whether two causes differ only in their numbers (steps, distances)."""
    return re.sub(_NUM, "#", a) == re.sub(_NUM, "#", b)


def lammps_stop(err, args):
    """One line for a level LAMMPS stopped, in the CLI's terms: the level, the cause, the
    option that cures it, and the log that holds LAMMPS's own message."""
    method = getattr(args, "method", "quasistatic")
    context = SimpleNamespace(s=err.dryness, start=getattr(args, "start", "built"),
                              fallback=fallback_of(args) if hasattr(args, "fallback") else None,
                              first=err.first, method="dynamics" if err.first else method)
    known = cause_and_cure(err.reason, context)
    if known:
        text = f"{known[0]}; {known[1]}"
    else:
        text = f"LAMMPS stopped: {err.reason.removeprefix('ERROR: ')}"
    if err.first:
        first = cause_and_cure(err.first, SimpleNamespace(**{**vars(context),
                                                             "method": method, "first": ""}))
        first = first[0] if first else err.first
        if known and _same_cause(first, known[0]):
            text = f"the quasi-static solve and the dynamics it fell back to stopped alike: {text}"
        else:
            text = (f"the quasi-static solve stopped ({first}), and the dynamics it fell back "
                    f"to stopped too: {text}")
    return f"s = {err.dryness:g}: {text} (LAMMPS log: {err.log})"


def failure(err, args):
    """The exit status and one line of an exception that ends a command."""
    if isinstance(err, UsageError):
        return 2, f"cgms {args.command}: {err}"
    if isinstance(err, study.LammpsError):
        return 1, f"cgms {args.command}: {lammps_stop(err, args)}"
    if isinstance(err, (RuntimeError, ValueError, OSError)):
        # a LAMMPS stop (its whole ERROR line is in the message) or a bad input: say it,
        # with no traceback; the results so far stay in the folder
        return 1, f"cgms {args.command}: {describe(err)}"
    # a fault of cgms itself: still one line, never a traceback
    return 1, (f"cgms {args.command}: internal error ({type(err).__name__}: {err}); "
               "CGMS_DEBUG=1 shows where; please report it with the command line")
