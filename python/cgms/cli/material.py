# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms material --temperature T --out FILE``: the coarse parameters at a
temperature, from the files calibrated to the heated fine model (``cgms.temperature``;
doc/drying.md, "The coarse parameters at a temperature"), as a material file that any
``--material`` takes."""

from .. import temperature
from .options import UsageError

HELP = "write the coarse parameters at a temperature (doc/drying.md)"


def arguments(q):
    q.add_argument("--temperature", type=float, required=True,
                   help="tissue temperature, C: within the calibrated temperatures on one "
                        "side of the membrane window (the files potentials/<family>-T*.cgms)")
    q.add_argument("--family", default="apple-mfc",
                   help="the calibrated files potentials/<family>-T<deg>.cgms (default "
                        "apple-mfc)")
    q.add_argument("--out", required=True, help="material file to write")
    q.add_argument("--force", action="store_true", help="replace an existing --out file")


def job(args):
    try:
        temperature.bracket(args.temperature, args.family)
    except ValueError as err:   # a temperature the calibration does not reach: a usage error
        raise UsageError(f"--temperature: {err}") from None
    path = temperature.write(args.out, args.temperature, args.family, overwrite=args.force)
    print(f"cgms material: wrote {path} ({args.family} at {args.temperature:g} C; "
          f"{temperature.how(args.temperature, args.family)})")
    return 0
