# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""CGMS material files (``potentials/*.cgms``): find, read with the plugin's rules, derive
the reference cell, apply ``name value`` overrides, and write a new file.

One set of rules, the same as the plugin's reader (``src/CGMS/cgms_material.cpp``): one
``name value`` per line, ``#`` comments; every name known and given once; every value a
number in its range; the required names present; perim_a below perim_b; k_S_floor not
above k_S. Every message names the file and, where there is one, the line."""

import math
import os
from datetime import date
from pathlib import Path

from . import folders, model

POTENTIALS = Path(os.environ.get("CGMS_POTENTIALS",
                                 Path(__file__).resolve().parents[2] / "potentials"))

#: name -> (range, required), as the plugin's table of parameters
PARAMETERS = {
    "k_T": ("> 0", True), "k_PA": ("> 0", True), "k_d": ("> 0", True),
    "f0_a": ("> 0", True), "f0_r": ("> 0", True),
    "beta_a": ("> 0", True), "beta_b": ("finite", True),
    "lj_slope": (">= 0", True), "r0": (">= 0", False),
    "diameter": ("> 0", True), "height": ("> 0", True), "pectin": (">= 0", True),
    "perim_a": (">= 0", True), "perim_b": ("> 0", True),
    "P_f": ("> 0", True), "Pi_f": ("< 0", True), "K": ("> 0", True),
    "turgid_ratio": ("> 0", True), "rho0": ("> 0", True), "L_p": ("> 0", True),
    "solid_ratio": (">= 0", True), "k_S": (">= 0", False),
    "k_S_exponent": (">= 0", False), "k_S_floor": (">= 0", False),
}
#: quantities derived from the parameters (not read from a file)
DERIVED = ("A_ref", "b_ref", "l_ref", "x_ref")
_IN_RANGE = {"> 0": lambda v: v > 0, ">= 0": lambda v: v >= 0, "< 0": lambda v: v < 0,
             "finite": lambda v: True}


def find(name):
    """Path of a material file: as given, or in the CGMS potentials folder."""
    path = Path(name)
    if path.is_file():
        return path
    for candidate in (POTENTIALS / name, POTENTIALS / f"{name}.cgms"):
        if candidate.is_file():
            return candidate
    raise FileNotFoundError(f"CGMS material file {name!r} not found (looked in {POTENTIALS})")


def _value(name, text, where):
    if name not in PARAMETERS:
        raise ValueError(f"{where}: unknown CGMS parameter {name!r} (known: "
                         f"{' '.join(PARAMETERS)})")
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{where}: value {text!r} of parameter {name} is not a number") \
            from None
    if not math.isfinite(value):
        raise ValueError(f"{where}: value {text!r} of parameter {name} is not finite")
    return value


def check(params, where):
    """Raise ValueError (naming ``where``) unless ``params`` holds every required name, each
    in its range, perim_a < perim_b and k_S_floor <= k_S."""
    for name, (limits, required) in PARAMETERS.items():
        if name not in params:
            if required:
                raise ValueError(f"{where}: CGMS parameter {name} is missing")
            continue
        if not _IN_RANGE[limits](params[name]):
            raise ValueError(f"{where}: CGMS parameter {name} = {params[name]:g} must be "
                             f"{limits}")
    if params["perim_a"] >= params["perim_b"]:
        raise ValueError(f"{where}: perim_a ({params['perim_a']:g}) must be below perim_b "
                         f"({params['perim_b']:g}) so that l_d > 0")
    floor, k_S = params.get("k_S_floor", 0.0), params.get("k_S", 0.0)
    if floor > k_S:   # the plugin's time-step check bounds k_S(s) by the fresh k_S
        raise ValueError(f"{where}: k_S_floor ({floor:g}) must not exceed k_S ({k_S:g}): "
                         "the floor is the lowest cell-shape stiffness, k_S the fresh "
                         "(largest) one")


def read(name="apple"):
    """Parameters of a material file as a dict of floats, plus the derived reference-cell
    values (``A_ref``, ``b_ref``, ``l_ref``, ``x_ref``, and ``r0`` = x_ref unless given).
    ValueError with the file and line for anything the plugin would refuse."""
    path = find(name)
    params = {}
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise ValueError(f"CGMS material file {path}: cannot be read ({err})") from None
    for lineno, raw in enumerate(text.splitlines(), 1):
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        where = f"CGMS material file {path} line {lineno}"
        if len(words) != 2:
            raise ValueError(f"{where}: expected 'name value', got {raw.strip()!r}")
        if words[0] in params:
            raise ValueError(f"{where}: parameter {words[0]} given twice")
        params[words[0]] = _value(words[0], words[1], where)
    check(params, f"CGMS material file {path}")
    return derive(params)


def derive(params):
    """Add the reference-cell quantities to a parameter dict (returns a new dict)."""
    p = dict(params)
    p.update({k: float(v) for k, v in model.reference_cell(p["diameter"], p["pectin"]).items()})
    if not p.get("r0"):
        p["r0"] = p["x_ref"]
    return p


def with_overrides(mat, overrides=""):
    """``mat`` with the "name value ..." pairs of a pair_coeff line applied (checked by the
    same rules as a file)."""
    words = overrides.split()
    if len(words) % 2:
        raise ValueError(f"overrides must be 'name value' pairs, got {overrides!r}")
    derived = set(DERIVED)
    if mat.get("r0") == mat.get("x_ref"):
        derived.add("r0")  # the default r0 = x_ref follows a changed diameter or pectin
    params = {k: v for k, v in mat.items() if k not in derived}
    for name, text in zip(words[::2], words[1::2]):
        params[name] = _value(name, text, f"--set {name} {text}")
    if words:
        check(params, f"material with --set {overrides!r}")
    return derive(params)


def steady_spacing(mat, s):
    """See :func:`cgms.model.steady_spacing` (kept here for existing callers)."""
    return model.steady_spacing(mat, s)


def write(path, source, values, note="", overwrite=False, contributor="cgms calibrate",
          model="cgms", origin=None, mark="fitted (start {old:.6g})"):
    """A new material file: ``source`` (a file of ``potentials/``) with ``values``
    ({name: value}) replacing its own, marked as fitted, under a header saying how it was
    made. Names absent from ``source`` are appended. An existing ``path`` is kept unless
    ``overwrite`` (FileExistsError). The file is read back and checked. Its first line
    carries ``MODEL: <model>``, the pair style the values were fitted for (cgms.calibrate
    fits pair_style cgms): the plugin's other styles refuse the file. ``origin``: the
    header's second line (default: calibrated from ``source``); ``mark``: the comment on a
    replaced value, a format of ``old`` (``source``'s value) and ``source`` (its name). The
    source's own ``# DATE:`` and ``# TEMPERATURE:`` lines are kept as its header's."""
    source = find(source)
    lines = source.read_text().splitlines()
    old = read(source)
    left = dict(values)
    body = []
    for raw in lines:
        if raw.startswith(("# DATE:", "# TEMPERATURE:")):
            body.append("# (start file header) " + raw[2:])
            continue
        words = raw.split("#", 1)[0].split()
        if len(words) == 2 and words[0] in left:
            name = words[0]
            v = left.pop(name)
            comment = raw.split("#", 1)[1].strip() if "#" in raw else ""
            width = max(len(name), 13)
            body.append(f"{name:<{width}} {v!r:<9} # "
                        + mark.format(old=old[name], source=source.name)
                        + (f"; {comment}" if comment else ""))
        else:
            body.append(raw)
    for name, v in left.items():
        body.append(f"{name:<13} {v!r:<9} # fitted (not in {source.name})")
    header = [f"# DATE: {date.today().isoformat()} UNITS: si CONTRIBUTOR: {contributor} "
              f"MODEL: {model}",
              "# " + (origin or f"Calibrated by cgms.calibrate from {source.name}:")]
    words, line = note.split(), "#"
    for w in words:
        if len(line) + len(w) + 1 > 92:
            header.append(line)
            line = "#"
        line += " " + w
    if words:
        header.append(line)
    text = "\n".join(header + body) + "\n"
    try:   # whole or not at all: an interrupted write leaves no half material file
        folders.write_text(path, text, overwrite=overwrite)
    except FileExistsError:
        raise FileExistsError(f"{os.fspath(path)} exists; pass overwrite=True (--force) to "
                              "replace it") from None
    back = read(path)
    for name, v in values.items():
        if back[name] != v:
            raise RuntimeError(f"{path}: {name} reads back as {back[name]!r}, not {v!r}")
    return Path(path)
