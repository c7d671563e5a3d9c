# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The 3-D shapes of ``python3 -m cgms tissue``: ``slab``, ``block`` and ``cylinder``
(:mod:`cgms.tissue3d`, doc/tissues.md, "3-D tissues")."""

import argparse
import math
import sys

from .. import material, tissue3d
from .options import describe, seed_int
from .tissues import diameters

SHAPES = ("slab", "block", "cylinder")
#: the most beads the command line builds (a few ms each); the library takes any number
MAX_3D_BEADS = 2e5


def add_shapes(sub):
    """The 3-D subcommands of the tissue builder, on the builder's subparsers ``sub``."""
    opts = _options()
    s = sub.add_parser("slab", parents=[opts], help="3-D slice W x L mm, T mm thick",
                       description="3-D: a slice W x L mm (x, y), T mm thick (z), BCC cells.")
    for name, text in (("width", "W (x)"), ("length", "L (y)"), ("thickness", "T (z)")):
        s.add_argument(name, type=float, metavar=text.split()[0], help=f"{text} in mm")
    b = sub.add_parser("block", parents=[opts], help="3-D block W x L x H mm",
                       description="3-D: a block W x L x H mm, BCC cells.")
    for name, text in (("width", "W (x)"), ("length", "L (y)"), ("thickness", "H (z)")):
        b.add_argument(name, type=float, metavar=text.split()[0], help=f"{text} in mm")
    c = sub.add_parser("cylinder", parents=[opts], help="3-D cylinder of radius R, height H mm",
                       description="3-D: a cylinder of radius R mm, height H mm (axis z), "
                                   "BCC cells.")
    c.add_argument("radius", type=float, metavar="R", help="radius in mm")
    c.add_argument("height", type=float, metavar="H", help="height in mm (along z)")


def _options():
    o = argparse.ArgumentParser(add_help=False)
    o.add_argument("--material", default="apple",
                   help="material file or name; its cell diameter D sets the BCC cube edge "
                        "(default apple)")
    o.add_argument("--cube", type=float, metavar="UM",
                   help="BCC cube edge in micrometres (default (pi D^3/3)^(1/3): a cell holds "
                        "the volume of the sphere of diameter D)")
    o.add_argument("--jitter", type=float, default=0.0,
                   help=f"move each bead by up to this many cube edges (0..{tissue3d.MAX_JITTER}, "
                        "default 0)")
    o.add_argument("--out", default="tissue.data", help="data file (default tissue.data)")
    o.add_argument("--force", action="store_true", help="replace an existing --out file")
    o.add_argument("--margin", type=float, default=3.0,
                   help="box margin around the tissue, in cube edges (default 3)")
    o.add_argument("--cv", type=float, default=0.0,
                   help="coefficient of variation of the cell diameter; > 0 writes a "
                        "Diameters section (default 0)")
    o.add_argument("--seed", type=seed_int, default=0, help="random seed (default 0)")
    o.add_argument("--dist", choices=("lognormal", "normal"), default="lognormal",
                   help="distribution of the diameters (default lognormal)")
    return o


def job(args):
    """Build and write a 3-D tissue; every refusal is one line and status 2."""
    for name in ("width", "length", "thickness", "radius", "height", "cube", "margin"):
        value = getattr(args, name, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            print(f"cgms tissue: {name} must be positive, got {value:g}", file=sys.stderr)
            return 2
    try:
        mat = material.read(args.material)
        a = args.cube * 1e-6 if args.cube else tissue3d.cube_edge(mat["diameter"])
        if not 0 <= args.jitter <= tissue3d.MAX_JITTER:
            raise ValueError(f"--jitter must be in 0..{tissue3d.MAX_JITTER} cube edges "
                             f"(below a/4, so every bead stays inside), got {args.jitter:g}")
        if args.shape == "cylinder":
            body = tissue3d.cylinder(args.radius * 1e-3, args.height * 1e-3)
            what = f"cylinder R {args.radius:g} mm, H {args.height:g} mm"
        else:
            body = tissue3d.box(args.width * 1e-3, args.length * 1e-3, args.thickness * 1e-3,
                                kind=args.shape)
            what = (f"{args.shape} {args.width:g} x {args.length:g} x {args.thickness:g} mm")
        estimate = body["volume"] / (a ** 3 / 2)
        if estimate > MAX_3D_BEADS:
            raise ValueError(f"the {what} would hold about {estimate:.3g} beads at cube edge "
                             f"{a * 1e6:.4g} um (limit {MAX_3D_BEADS:g}): sizes are in "
                             "millimetres, --cube in micrometres")
        built = tissue3d.build(body, a, args.jitter, args.seed)
        n = len(built["x"])
        diam = diameters(n, mat, args.cv, args.seed, args.dist)
        nb = tissue3d.write_data(args.out, built, args.margin * a, title=f"CGMS 3-D tissue: "
                                 f"{what}, BCC cube edge {a * 1e6:.4g} um", diameters=diam,
                                 overwrite=args.force)
    except FileExistsError:
        print(f"cgms tissue: {args.out} exists; use --force to replace it or choose another "
              "--out", file=sys.stderr)
        return 2
    except (ValueError, OSError) as e:
        print(f"cgms tissue: {describe(e)}", file=sys.stderr)
        return 2
    surface = int(built["surface"].sum())
    print(f"{n} beads -> {args.out} ({what}, BCC cube edge {a * 1e6:.2f} um, {surface} "
          f"surface cells, up to {nb} neighbours; read with: "
          f"{'; '.join(tissue3d.read_commands(args.out, nb, diam is not None))})")
    return 0
