# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The options the commands share, checked as argparse reads them, and the error a
bad option or input file raises (:class:`UsageError`: one line, exit status 2)."""

import argparse
import math

from .. import study


DEFAULT_LEVELS = ",".join(f"{s:g}" for s in study.LEVELS)


class UsageError(ValueError):
    """A bad option or input file, found before anything runs."""


def checked(convert, test, rule):
    """An argparse type: ``convert`` the text; refuse non-finite values and those that fail
    ``test`` (``rule`` says what is wanted)."""
    def parse(text):
        try:
            value = convert(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not (math.isfinite(value) and test(value)):
            raise argparse.ArgumentTypeError(f"must be {rule}, got {text}")
        return value
    return parse


positive_int = checked(int, lambda v: v >= 1, "at least 1")
positive_float = checked(float, lambda v: v > 0, "a positive number")
fraction = checked(float, lambda v: v >= 0, "a number >= 0")   # e.g. a coefficient of variation
seed_int = checked(int, lambda v: 0 <= v < 2 ** 32, "an integer from 0 to 2**32 - 1")


def levels(text):
    """--dryness: distinct levels in (0, 1], wettest first as given."""
    out = []
    for word in text.split(","):
        try:
            s = float(word)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{word!r} is not a number") from None
        if not 0 < s <= 1:
            raise argparse.ArgumentTypeError(f"level {word} is outside (0, 1]")
        if s in out:
            raise argparse.ArgumentTypeError(f"level {word} is given twice")
        out.append(s)
    return out


def material_overrides(text):
    """--set: 'name value ...' pairs with numeric values (LAMMPS checks the names)."""
    words = text.split()
    if len(words) % 2:
        raise argparse.ArgumentTypeError(f"expected 'name value' pairs, got {text!r}")
    for name, value in zip(words[::2], words[1::2]):
        try:
            float(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"value {value!r} of {name} is not a number")
    return text


def tissue_source_arguments(q, width=1.5, what=""):
    q.add_argument("--data", metavar="FILE",
                   help="tissue file instead of --width/--height: a LAMMPS data file "
                        "(python3 -m cgms.tissue) or cell centroids, one 'id x y' line each, "
                        "in metres")
    q.add_argument("--width", type=positive_float, default=width,
                   help=f"tissue width, mm{what}")
    q.add_argument("--height", type=positive_float, default=1.5, help="tissue height, mm")
    q.add_argument("--cv", type=fraction, default=0.0,
                   help="coefficient of variation of cell diameters (0: uniform)")
    q.add_argument("--seed", type=seed_int, default=1, help="seed for the cell diameters")


def common_arguments(q, kind, width=True):
    q.add_argument("--out", help=f"results folder (default results/{kind}/<date-time>)")
    q.add_argument("--material", default="apple", help="material file (default apple)")
    q.add_argument("--set", default="", metavar="'NAME VALUE ...'", type=material_overrides,
                   help="material parameters that replace the file's, as on a pair_coeff "
                        "line, e.g. --set 'k_S 0.5' (doc/pair_cgms.rst)")
    if width:
        tissue_source_arguments(q)
    else:
        q.add_argument("--cv", type=fraction, default=0.0,
                       help="coefficient of variation of cell diameters (0: uniform)")
        q.add_argument("--seed", type=seed_int, default=1, help="seed for the cell diameters")
    q.add_argument("--residual", type=positive_float, default=1e-3,
                   help="steady-state residual")
    q.add_argument("--speed", type=positive_float, default=1e-3, help="steady-state speed, m/s")
    q.add_argument("--max-steps", type=positive_int, default=2000000,
                   help="step (or minimiser iteration; Newton: at most 60) limit per level")
    q.add_argument("--method", choices=("quasistatic", "newton", "dynamics"),
                   default="quasistatic",
                   help="solve for the steady state directly: P = -Pi and FIRE "
                        "minimisation (default; doc/model.md) or Newton's method (fewer, "
                        "costlier iterations: doc/results/performance.md), or follow the dynamics "
                        "until the --residual and --speed thresholds hold (the paper's way)")


def fallback_argument(q):
    q.add_argument("--fallback", choices=(*study.FALLBACKS, "none"),
                   help="where the quasi-static solve (FIRE or Newton) stops or does not "
                        "converge, follow the dynamics instead (default with --method "
                        "quasistatic or newton; dt = "
                        f"{study.FALLBACK['dt']:g} s; log and dump in <tissue>/"
                        f"{study.FALLBACK_FOLDER}/; the table says which method solved each "
                        "level); none: stop there instead")


def sweep_arguments(q):
    q.add_argument("--dryness", type=levels, default=DEFAULT_LEVELS,
                   help=f"levels (default {DEFAULT_LEVELS})")
    q.add_argument("--resume", action="store_true", help="continue an interrupted study in --out")
    fallback_argument(q)
    q.add_argument("--start", choices=study.STARTS, default="built",
                   help="where each level starts: the built tissue (default; the paper's "
                        "moisture-domain approach), or the previous level's steady state, "
                        "wettest to driest (a drying ramp: a dried level's cutoff need not "
                        "hold the built lattice; doc/calibration.md, \"Five levels\")")


def fallback_of(args):
    """--fallback as it runs: by default the dynamics after a quasi-static method (FIRE or
    Newton) that stops, nothing after the dynamics; 'none' turns it off."""
    if args.fallback == "none":
        return None
    if args.fallback is None:
        return None if args.method == "dynamics" else study.FALLBACKS[0]
    return args.fallback


def check_fallback(args):
    """UsageError for a --fallback with nothing to fall back from."""
    if args.fallback not in (None, "none") and args.method == "dynamics":
        raise UsageError(f"--fallback {args.fallback} needs --method quasistatic or newton: "
                         "the dynamics has nothing to fall back to")


def describe(err):
    """One line for an error: OS errors as 'reason: file'."""
    if isinstance(err, OSError) and err.strerror:
        return f"{err.strerror}: {err.filename}" if err.filename else err.strerror
    return str(err)
