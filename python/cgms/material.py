"""Read CGMS material files (``potentials/*.cgms``) and derive the reference cell."""

import math
import os
from pathlib import Path

POTENTIALS = Path(os.environ.get("CGMS_POTENTIALS", Path(__file__).resolve().parents[2] / "potentials"))


def find(name):
    """Path of a material file: as given, or in the CGMS potentials folder."""
    path = Path(name)
    if path.exists():
        return path
    for candidate in (POTENTIALS / name, POTENTIALS / f"{name}.cgms"):
        if candidate.exists():
            return candidate
    raise FileNotFoundError(f"CGMS material file {name!r} not found (looked in {POTENTIALS})")


def read(name="apple"):
    """Parameters of a material file as a dict of floats, plus derived reference-cell values
    (``A_ref``, ``b_ref``, ``l_ref``, ``x_ref``, ``r0``), following MODEL.md section 3."""
    params = {}
    for lineno, raw in enumerate(find(name).read_text().splitlines(), 1):
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) != 2:
            raise ValueError(f"{name} line {lineno}: expected 'name value', got {raw.strip()!r}")
        params[words[0]] = float(words[1])
    return derive(params)


def derive(params):
    """Add the reference-cell quantities to a parameter dict (returns a new dict)."""
    p = dict(params)
    p["A_ref"] = math.pi * p["diameter"] ** 2 / 4
    p["b_ref"] = math.sqrt(2 * p["A_ref"] / (3 * math.sqrt(3)))
    p["l_ref"] = 6 * p["b_ref"]
    p["x_ref"] = math.sqrt(3) * p["b_ref"] + p["pectin"]
    if not p.get("r0"):
        p["r0"] = p["x_ref"]
    return p


def with_overrides(mat, overrides=""):
    """``mat`` with the "name value ..." pairs of a pair_coeff line applied."""
    words = overrides.split()
    if len(words) % 2:
        raise ValueError(f"overrides must be 'name value' pairs, got {overrides!r}")
    derived = {"A_ref", "b_ref", "l_ref", "x_ref"}
    if mat.get("r0") == mat.get("x_ref"):
        derived.add("r0")  # the default r0 = x_ref follows a changed diameter or pectin
    params = {k: v for k, v in mat.items() if k not in derived}
    params.update({words[i]: float(words[i + 1]) for i in range(0, len(words), 2)})
    return derive(params)


def steady_spacing(mat, s):
    """Centre distance of two inner beads (6 neighbours) of a uniform tissue at steady state
    at dryness ``s``: every bead's pair coefficient vanishes there (doc/validation.md, hard
    cases), so its perimeter is l* = l_d - (k_T / k_PA) (P_f + s Pi_f), and an inner
    bead's l = 2 sqrt(3) (x - d_p)."""
    ld = mat["turgid_ratio"] * mat["l_ref"] * (1 - mat["perim_a"] / mat["perim_b"] * (1 - s))
    lstar = ld - mat["k_T"] / mat["k_PA"] * (mat["P_f"] + s * mat["Pi_f"])
    return lstar / (2 * math.sqrt(3)) + mat["pectin"]
