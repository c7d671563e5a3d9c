# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Command line: ``python3 -m cgms main`` runs the main job (the microscale study);
``study`` dries any tissue over moisture levels; ``target`` finds the initial dryness that
reaches a given moisture; ``calibrate`` fits material parameters to reference centroid
positions (eqn 2); ``sensitivity`` runs the paper's sensitivity study. A tissue is a
W x H mm rectangle (--width, --height) or read from a file (--data): a LAMMPS data file
(python3 -m cgms.tissue: rectangles, discs, polygons with holes, heterogeneous cells) or
a list of cell centroids, one 'id x y' line each, in metres.

This package is the top of cgms: it parses options, checks them before anything is
created, and turns every error into one line on stderr; no library module imports it.
One module per command (study: main, study, target; tissue; calibrate; sensitivity; dry;
mfc; material), with the options they share (options), the tissue of the options
(tissues) and the one-line errors (errors)."""

import argparse
import os
import sys

from .. import parallel
from . import calibrate, dry, material, mfc, sensitivity, study, tissue
from .errors import failure
from .options import UsageError


#: the subcommands: name -> (help, options, job). A new subcommand is one line here.
COMMANDS = {
    "main": ("the microscale study (six tissues, five levels)", study.main_arguments,
             study.main_job),
    "study": ("dry one tissue over moisture levels", study.study_arguments, study.study_job),
    "sensitivity": ("the paper's sensitivity study (k_T, k_PA, beta)", sensitivity.arguments,
                    sensitivity.job),
    "calibrate": ("fit k_T, k_PA, beta to reference centroids (eqn 2)", calibrate.arguments,
                  calibrate.job),
    "target": ("initial dryness whose steady state reaches X/X0", study.target_arguments,
               study.target_job),
    "tissue": ("build a tissue data file (python3 -m cgms.tissue)", tissue.arguments, tissue.job),
    "dry": ("dry a tissue slice in air over time (doc/drying.md)", dry.add_arguments, dry.job),
    "mfc": (mfc.HELP, mfc.arguments, mfc.main),
    "material": (material.HELP, material.arguments, material.job),
}


def parser():
    p = argparse.ArgumentParser(prog="cgms", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    for name, (text, arguments, job) in COMMANDS.items():
        q = sub.add_parser(name, help=text, description=text)
        arguments(q)
        q.set_defaults(func=job)
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    parallel.one_voice(argv)
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        # only commands that have --resume offer it
        more = " (--resume continues)" if hasattr(args, "resume") else ""
        print(f"cgms {args.command}: interrupted; finished results stay in the folder{more}",
              file=sys.stderr)
        return 130
    except Exception as err:
        if os.environ.get("CGMS_DEBUG") and not isinstance(err, UsageError):
            raise
        status, line = failure(err, args)
        print(line, file=sys.stderr)
        return status
