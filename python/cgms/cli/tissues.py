# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The tissue of a command's options (--width x --height, or --data), checked before
anything is created, and the results folder that holds its data file."""

import os
from contextlib import contextmanager
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from .. import folders, material, positions, tissue
from .options import UsageError, describe


MAX_CLI_BEADS = 5e6   # a polygon file larger than this is probably not in metres
#: how far the clipping of the cell diameters may move their mean (see --cv)
MEAN_SHIFT = 0.02


def rectangle_tissue(width_mm, height_mm, mat, cv=0.0, seed=1):
    """The W x H mm rectangle of the paper's fill rule (cgms.tissue.rectangle); UsageError
    for one too small to hold a tissue, or so large it is likely not in millimetres."""
    size = f"--width {width_mm:g} --height {height_mm:g}"
    spacing = f"the material's cell spacing x_ref = {mat['x_ref'] * 1e6:.4g} um"
    estimate = width_mm * height_mm * 1e-6 / (tissue.ROW_PITCH * mat["x_ref"] ** 2)
    if estimate > MAX_CLI_BEADS:
        raise UsageError(f"{size} would hold about {estimate:.3g} beads at {spacing} (limit "
                         f"{MAX_CLI_BEADS:g}): sizes are in millimetres")
    try:
        xy = tissue.rectangle(width_mm * 1e-3, height_mm * 1e-3, mat["x_ref"])
    except ValueError as err:
        if "holds no row" not in str(err):
            raise UsageError(f"{size}: {err}") from None
        xy = np.empty((0, 2))
    if len(xy) < tissue.MIN_BEADS:
        raise UsageError(f"{size} (mm) holds {len(xy)} bead(s) at {spacing}; a tissue needs "
                         f"at least {tissue.MIN_BEADS}")
    return dict(xy=xy, ids=None, diameters=diameters(len(xy), mat, cv, seed),
                title=f"CGMS {width_mm} x {height_mm} mm tissue",
                what=f"{width_mm} x {height_mm} mm")


def read_tissue_file(path):
    """(ids, xy, diameters or None, kind) of a --data file; UsageError naming the file and
    what is wrong with it."""
    try:
        if positions.is_data_file(path):
            d = positions.read_data(path)
            return d["ids"], d["xy"], d["diameters"], "data file"
        ids, xy = positions.read_centroids(path)
    except UnicodeDecodeError:
        raise UsageError(f"--data {path}: not a text file") from None
    except (ValueError, OSError) as err:
        text = describe(err)
        raise UsageError(f"--data {path}: {text.removeprefix(f'{path}: ')}") from None
    if len(np.unique(ids)) != len(ids):
        raise UsageError(f"--data {path}: an id is given twice")
    return ids, xy, None, "centroid list"


def file_tissue(path, mat, cv=0.0, seed=1):
    """The tissue of a LAMMPS data file or an 'id x y' centroid list (metres)."""
    path = Path(path)
    if not path.is_file():
        raise UsageError(f"--data {path}: no such file")
    ids, xy, given, kind = read_tissue_file(path)
    try:
        tissue.check_layout(ids, xy, mat["x_ref"])
    except ValueError as err:
        raise UsageError(f"--data {path}: {err}") from None
    if cv > 0 and given is not None:
        raise UsageError(f"--data {path} has a Diameters section: leave out --cv")
    return dict(xy=xy, ids=ids, diameters=diameters(len(xy), mat, cv, seed) if cv > 0 else given,
                title=f"CGMS tissue from {path.name}",
                what=f"{kind} {path}")


def chosen_tissue(args, mat):
    """The tissue of the options: --data, or --width x --height."""
    if getattr(args, "data", None):
        return file_tissue(args.data, mat, args.cv, args.seed)
    return rectangle_tissue(args.width, args.height, mat, args.cv, args.seed)


def write_tissue(folder, t, mat):
    """``folder/tissue.data`` for the tissue ``t``; when resuming it must be there already
    and be the same tissue (another --width, --data, --cv ... is refused)."""
    data = folder / "tissue.data"
    fresh = folder / ".tissue.data.new"
    positions.write_data(fresh, t["xy"], 3 * mat["x_ref"], title=t["title"],
                         diameters=t["diameters"], ids=t["ids"], overwrite=True)
    if data.exists():
        same = data.read_bytes() == fresh.read_bytes()
        fresh.unlink()
        if not same:
            raise folders.FolderError(
                f"{data} is another tissue than these options build ({t['what']}); resume "
                "with the options of the first run or choose another --out")
    else:
        os.replace(fresh, data)
    return data


@contextmanager
def tissue_in_folder(args, kind, resume=False):
    """Material, tissue and the locked results folder holding the tissue's data file, for
    commands on one tissue; everything is checked before the folder is made."""
    mat_file, mat = material_of(args)
    t = chosen_tissue(args, mat)
    with folders.claim(args.out, kind, resume, resumable=hasattr(args, "resume")) as out:
        yield SimpleNamespace(out=out, data=write_tissue(out, t, mat), tissue=t,
                              mat_file=mat_file, mat=mat, n=len(t["xy"]),
                              diameters=t["diameters"] is not None)


def material_of(args):
    """(material file, parameters with --set applied), checked: UsageError for a missing or
    bad file or --set."""
    try:
        mat_file = material.find(args.material)
        return mat_file, material.with_overrides(material.read(mat_file),
                                                 getattr(args, "set", ""))
    except (ValueError, OSError) as err:
        raise UsageError(describe(err)) from None


def diameters(n, mat, cv, seed, dist="lognormal"):
    """Per-bead cell diameters for --cv (None for 0); UsageError when the clipping would
    move their mean more than MEAN_SHIFT from the material's diameter."""
    if not cv:
        return None
    factor = tissue.clipped_mean(cv, dist)
    if abs(factor - 1) > MEAN_SHIFT:
        raise UsageError(f"--cv {cv:g}: {dist} diameters clipped at half the mean would "
                         f"average {factor:.3g} x the material's {mat['diameter'] * 1e6:g} um "
                         f"(more than {MEAN_SHIFT:.0%} off); use a smaller --cv")
    return tissue.cell_diameters(n, mat["diameter"], cv, seed, dist=dist)
