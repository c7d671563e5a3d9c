# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The coarse parameters at a temperature (doc/drying.md, "The coarse parameters at a
temperature").

CGMS's coarse parameters follow the fine model (``cgms.mfc.model.heated``) by calibration:
``potentials/<family>-T<deg>.cgms`` is ``<family>`` fitted to the fine model at one
temperature, which its header gives on a line ``# TEMPERATURE: <T> C``. Between two such
files on one side of the membrane window, each parameter c that differs between them goes
as ``ln c`` linear in ``1/T`` (absolute temperature; a decision: the wall softening's own
Arrhenius form). The membrane window (turgor lost between ``membrane_onset`` and
``membrane_gone``, ``cgms.mfc.model.HEAT``) is a step, not a line: no interpolation reaches
across it, and no temperature outside the calibrated ones is extrapolated to."""

import math
import re

from scipy.constants import zero_Celsius

from . import material

#: the line of a calibrated file's header that gives its temperature
TEMPERATURE_LINE = re.compile(r"^#\s*TEMPERATURE:\s*([-+0-9.eE]+)\s*C\b")


def temperature_of(name):
    """The temperature (C) a material file's header says it was calibrated at, else None."""
    for line in material.find(name).read_text().splitlines():
        if not line.startswith("#"):
            break
        found = TEMPERATURE_LINE.match(line)
        if found:
            return float(found.group(1))
    return None


def calibrated(family="apple-mfc"):
    """{temperature (C): path} of the files ``<family>-T*.cgms`` in the potentials folder.
    ValueError if one has no temperature line, or one inside the membrane window."""
    from .mfc.model import HEAT   # cgms.mfc.model reads materials: imported when used
    found = {}
    for path in sorted(material.POTENTIALS.glob(f"{family}-T*.cgms")):
        T = temperature_of(path)
        if T is None:
            raise ValueError(f"{path}: no '# TEMPERATURE: <T> C' line in its header")
        if HEAT["membrane_onset"] < T < HEAT["membrane_gone"]:
            raise ValueError(f"{path}: calibrated at {T:g} C, inside the membrane window")
        found[T] = path
    if not found:
        raise ValueError(f"no calibrated material {family}-T*.cgms in {material.POTENTIALS}")
    return dict(sorted(found.items()))


def bracket(temperature, family="apple-mfc"):
    """The two calibrated temperatures (C) between which ``temperature`` is interpolated
    (equal if it is one of them). ValueError, naming the calibrated ones, for a temperature
    across the membrane window or outside them."""
    from .mfc.model import HEAT
    T = float(temperature)
    known = list(calibrated(family))
    sides = {"membranes intact": [t for t in known if t <= HEAT["membrane_onset"]],
             "membranes gone": [t for t in known if t >= HEAT["membrane_gone"]]}
    said = "; ".join(f"{', '.join(f'{t:g}' for t in ts)} C ({name})"
                     for name, ts in sides.items() if ts)
    for ts in sides.values():
        if ts and ts[0] <= T <= ts[-1]:
            lo = max(t for t in ts if t <= T)
            hi = min(t for t in ts if t >= T)
            return lo, hi
    if not math.isfinite(T):
        raise ValueError(f"temperature must be a number of degrees C, got {temperature!r}")
    if known[0] < T < known[-1]:
        below = max(t for t in known if t < T)
        above = min(t for t in known if t > T)
        raise ValueError(
            f"no coarse parameters at {T:g} C: the calibrated temperatures nearest it, "
            f"{below:g} and {above:g} C, lie across the membrane window "
            f"({HEAT['membrane_onset']:g}-{HEAT['membrane_gone']:g} C, where the turgor is "
            f"lost as a step that no line carries); {family} is calibrated at {said}: pick a "
            "temperature on one side, or calibrate one nearer (doc/drying.md)")
    raise ValueError(f"no coarse parameters at {T:g} C: outside the calibrated range "
                     f"{known[0]:g}-{known[-1]:g} C ({family} is calibrated at {said}), "
                     "which is not extrapolated: calibrate there (doc/drying.md)")


def at_temperature(temperature, family="apple-mfc"):
    """``(values, source)``: the parameters of ``family`` at ``temperature`` (C) as
    :func:`cgms.material.read` gives them, and the calibrated file of the nearer end (whose
    other values they keep). Each value that differs between the two ends goes as
    ``ln c`` linear in ``1/T``; at a calibrated temperature they are that file's exactly."""
    lo, hi = bracket(temperature, family)
    files = calibrated(family)
    a, b = material.read(files[lo]), material.read(files[hi])
    if lo == hi:
        return a, files[lo]
    x = ((1 / (float(temperature) + zero_Celsius) - 1 / (lo + zero_Celsius))
         / (1 / (hi + zero_Celsius) - 1 / (lo + zero_Celsius)))
    values = dict(a)
    for name in a:
        if a[name] == b[name] or name in material.DERIVED:
            continue
        if a[name] <= 0 or b[name] <= 0:
            raise ValueError(f"{name} is {a[name]:g} at {lo:g} C and {b[name]:g} at {hi:g} C: "
                             "ln c cannot be interpolated through a value that is not positive")
        values[name] = a[name] ** (1 - x) * b[name] ** x
    return material.derive({k: v for k, v in values.items() if k not in material.DERIVED}), \
        files[lo if x <= 0.5 else hi]


def how(temperature, family="apple-mfc"):
    """How :func:`at_temperature` makes ``temperature``'s values, in words."""
    lo, hi = bracket(temperature, family)
    files = calibrated(family)
    if lo == hi:
        return f"calibrated at {lo:g} C ({files[lo].name})"
    return (f"ln c linear in 1/T between {files[lo].name} ({lo:g} C) and {files[hi].name} "
            f"({hi:g} C)")


def write(path, temperature, family="apple-mfc", overwrite=False):
    """A material file at ``path`` with the parameters of ``family`` at ``temperature``
    (C): the values of :func:`at_temperature`, under a header whose second line is
    ``# TEMPERATURE: <T> C, ...`` and says how they were made. Usable as any
    ``--material``."""
    values, source = at_temperature(temperature, family)
    start = material.read(source)
    changed = {k: v for k, v in values.items()
               if k not in material.DERIVED and v != start[k]}
    return material.write(path, source, changed, overwrite=overwrite,
                          contributor="cgms.temperature",
                          origin=f"TEMPERATURE: {float(temperature):g} C, {family}: "
                                 f"{how(temperature, family)} (cgms.temperature; "
                                 "doc/drying.md):",
                          mark="interpolated ({source}: {old:.6g})")
