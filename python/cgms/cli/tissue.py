# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""``python3 -m cgms tissue`` (and ``python3 -m cgms.tissue``): build a tissue and write
it as a LAMMPS data file."""

import argparse
import math
import sys

import numpy as np

from .. import material, positions, tissue
from . import tissue3d
from .options import describe, seed_int
from .tissues import MAX_CLI_BEADS, diameters


def arguments(p):
    """The options of the tissue builder (``python3 -m cgms tissue`` and ``python3 -m
    cgms.tissue``)."""
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--material", default="apple",
                        help="material file or name; sets the lattice spacing x_ref and the "
                             "mean cell diameter (default apple)")
    common.add_argument("--spacing", type=float, metavar="UM",
                        help="lattice spacing in micrometres (default: the material's x_ref)")
    common.add_argument("--rows-along", choices=("x", "y"), default="y",
                        help="direction of the lattice rows (default y, as in the paper)")
    common.add_argument("--out", default="tissue.data", help="data file (default tissue.data)")
    common.add_argument("--force", action="store_true", help="replace an existing --out file")
    common.add_argument("--margin", type=float, default=3.0,
                        help="box margin around the tissue, in lattice spacings (default 3)")
    common.add_argument("--cv", type=float, default=0.0,
                        help="coefficient of variation of the cell diameter; > 0 writes a "
                             "Diameters section (default 0: homogeneous tissue)")
    common.add_argument("--seed", type=seed_int, default=0,
                        help="random seed for --cv (default 0)")
    common.add_argument("--dist", choices=("lognormal", "normal"), default="lognormal",
                        help="distribution of the diameters (default lognormal)")
    sub = p.add_subparsers(dest="shape", required=True)
    r = sub.add_parser("rect", parents=[common], help="W x H rectangle (mm)",
                       description="Lattice filling a W x H mm rectangle (W along x, H along y).")
    r.add_argument("width", type=float, metavar="W", help="width in mm (along x)")
    r.add_argument("height", type=float, metavar="H", help="height in mm (along y)")
    r.add_argument("--rule", choices=tissue.RECTANGLE_RULES, default="paper",
                   help="fill rule (default paper: reproduces the paper's bead counts)")
    r.add_argument("--inset", type=float, default=0.0,
                   help="shrink the rectangle by this many mm on every side (e.g. D/2 = 0.075 "
                        "to read W x H as the cell outline)")
    d = sub.add_parser("disc", parents=[common], help="disc of radius R (mm)",
                       description="Lattice points inside a disc of radius R mm.")
    d.add_argument("radius", type=float, metavar="R", help="radius in mm")
    g = sub.add_parser("polygon", parents=[common], help="closed polygon from a file (m)",
                       description="Lattice points inside a closed polygon read from a text "
                                   "file: one 'x y' vertex per line, in metres.")
    g.add_argument("file", help="vertex file (x y per line, metres; '#' comments)")
    tissue3d.add_shapes(sub)


TISSUE_DESCRIPTION = ("Build a CGMS tissue (hexagonal lattice of beads; slab, block, cylinder: "
                      "3-D, BCC lattice) and write it as a LAMMPS data file for atom_style "
                      "cgms. Sizes W, H, R, L, T are in MILLIMETRES; polygon vertex files are "
                      "in METRES.")



def tissue_main(argv=None):
    """``python3 -m cgms.tissue rect W H | disc R | polygon FILE [options]``: build the
    tissue, write the data file and print the bead count. Returns an exit status."""
    p = argparse.ArgumentParser(prog="python3 -m cgms.tissue", description=TISSUE_DESCRIPTION)
    arguments(p)
    return job(p.parse_args(argv))


def job(args):
    """Build and write the tissue; every refusal (a bad option or input file, found before
    anything is written) is one line and status 2, as in the other commands."""
    if args.shape in tissue3d.SHAPES:
        return tissue3d.job(args)
    for name in ("width", "height", "radius", "spacing", "margin"):
        value = getattr(args, name, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            print(f"cgms.tissue: {name} must be positive, got {value:g}", file=sys.stderr)
            return 2
    try:
        mat = material.read(args.material)
        spacing = args.spacing * 1e-6 if args.spacing else mat["x_ref"]
        if args.shape == "polygon":
            vertices = positions.read_vertices(args.file)
            if vertices.size:
                box = np.ptp(vertices, axis=0)
                estimate = box[0] * box[1] / (tissue.ROW_PITCH * spacing * spacing)
                if estimate > MAX_CLI_BEADS:
                    raise ValueError(f"the outline in {args.file} spans {box[0]:g} x "
                                     f"{box[1]:g} m, room for up to {estimate:.3g} beads "
                                     f"(limit {MAX_CLI_BEADS:g}); vertices must be in metres")
        if args.shape != "polygon":
            mm = (args.width * args.height if args.shape == "rect"
                  else math.pi * args.radius ** 2)
            estimate = mm * 1e-6 / (tissue.ROW_PITCH * spacing * spacing)
            if estimate > MAX_CLI_BEADS:
                raise ValueError(f"the {args.shape} would hold about {estimate:.3g} beads at "
                                 f"spacing {spacing * 1e6:.4g} um (limit {MAX_CLI_BEADS:g}): "
                                 "sizes are in millimetres, --spacing in micrometres")
        if args.shape == "rect":
            xy = tissue.rectangle(args.width * 1e-3, args.height * 1e-3, spacing,
                                  rule=args.rule, rows_along=args.rows_along,
                                  inset=args.inset * 1e-3)
            what = f"rectangle {args.width:g} x {args.height:g} mm, rule {args.rule}"
        elif args.shape == "disc":
            xy = tissue.disc(args.radius * 1e-3, spacing, rows_along=args.rows_along)
            what = f"disc of radius {args.radius:g} mm"
        else:
            xy = tissue.polygon(vertices, spacing, rows_along=args.rows_along)
            what = f"polygon {args.file}"
        if len(xy) < tissue.MIN_BEADS:
            raise ValueError(f"the {what} holds {len(xy)} bead(s) at spacing "
                             f"{spacing * 1e6:.2f} um; a tissue needs at least {tissue.MIN_BEADS}")
        diam = diameters(len(xy), mat, args.cv, args.seed, args.dist)
        n = positions.write_data(args.out, xy, args.margin * spacing,
                                 title=f"CGMS tissue: {what}", diameters=diam,
                                 overwrite=args.force)
    except FileExistsError:
        print(f"cgms.tissue: {args.out} exists; use --force to replace it or choose another "
              "--out", file=sys.stderr)
        return 2
    except UnicodeDecodeError:
        print(f"cgms.tissue: {args.file}: not a text file", file=sys.stderr)
        return 2
    except (ValueError, OSError) as e:
        print(f"cgms.tissue: {describe(e)}", file=sys.stderr)
        return 2
    extra = ""
    if diam is not None:
        extra = (f"; Diameters section: mean {diam.mean() * 1e6:.2f} um, cv "
                 f"{diam.std() / diam.mean():.3f} ({args.dist}, seed {args.seed})")
    print(f"{n} beads -> {args.out} ({what}, spacing {spacing * 1e6:.2f} um, rows along "
          f"{args.rows_along}{extra})")
    return 0
