# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The parameters of a calibration: which material values (or beta) are fitted, their search
intervals, the pair_coeff overrides of one run, and the material values a fit stands for.

Names (``parameters=``): material names (``k_T``, ``k_PA``, any other name of the material
file), ``beta`` (one factor on beta(s), i.e. on beta_a and beta_b), ``beta_a``/``beta_b``
(the coefficients of beta(s) = beta_a + beta_b ln s), or ``beta@<s>`` / ``beta@*`` (a
separate beta at one / every level; the law a + b ln s is then fitted through them for the
material file). Each is searched as ``ln(value / start)`` between bounds (a factor 0.05-20
of the start; 0.8-1.15 for beta, about the range in which the 86-bead tissue keeps a
steady state)."""

import math

import numpy as np

from .. import model
from ..material import DERIVED, PARAMETERS

#: default search interval (factors of the start value) for each kind of parameter
BOUNDS = (0.05, 20.0)
BETA_BOUNDS = (0.8, 1.15)


class Parameter:
    """One fitted quantity, searched as u = ln(value / start) in [ln lo, ln hi]."""

    def __init__(self, name, kind, start, lo, hi, level=None):
        self.name, self.kind, self.start, self.level = name, kind, float(start), level
        self.lo, self.hi = float(lo), float(hi)

    def value(self, u):
        return self.start * math.exp(u)

    def __repr__(self):
        return f"Parameter({self.name!r}, start={self.start!r})"


def parse_parameters(names, mat, levels, start=None, bounds=None):
    """Parameter objects for ``names`` (see the module doc). ``start``: {name: value}
    (default: the material's value, for ``beta`` the factor 1); ``bounds``: {name: (lo, hi)}
    as factors of the start value."""
    start, bounds = dict(start or {}), dict(bounds or {})
    levels = [float(s) for s in levels]
    names = [n.strip() for n in ([names] if isinstance(names, str) else names) if n.strip()]
    if not names:
        raise ValueError("no parameter to fit")
    expanded = []
    for n in names:
        if n == "beta@*":
            expanded += [f"beta@{s:g}" for s in levels]
        else:
            expanded.append(n)
    if len(set(expanded)) != len(expanded):
        raise ValueError(f"a parameter is named twice in {names}")
    has = set(expanded)
    per_level = [n for n in expanded if n.startswith("beta@")]
    if "beta" in has and (has & {"beta_a", "beta_b"} or per_level):
        raise ValueError("'beta' scales beta_a and beta_b together: do not fit it with "
                         "beta_a, beta_b or beta@<s>")
    if per_level and has & {"beta_a", "beta_b"}:
        raise ValueError("beta@<s> sets beta at a level directly: do not fit it with beta_a "
                         "or beta_b")
    # every material name, the optional ones (k_S) too: a file without k_S has k_S = 0
    known = [k for k in dict.fromkeys([*mat, *PARAMETERS]) if k not in DERIVED]
    params = []
    for n in expanded:
        level = None
        if n == "beta":
            kind, default = "beta", 1.0
        elif n.startswith("beta@"):
            try:
                level = float(n[5:])
            except ValueError:
                raise ValueError(f"{n!r}: expected beta@<dryness level> or beta@*") from None
            match_ = [s for s in levels if abs(s - level) < 1e-9]
            if not match_:
                raise ValueError(f"{n!r}: no reference at s = {level:g} (levels "
                                 f"{', '.join(f'{s:g}' for s in levels)})")
            level = match_[0]
            kind, default = "beta_level", float(model.beta(mat, level))
            n = f"beta@{level:g}"
        elif n in known:
            kind, default = "material", mat.get(n, 0.0)
        else:
            raise ValueError(f"unknown parameter {n!r}: fit one of beta, beta_a, beta_b, "
                             f"beta@<s>, beta@*, {', '.join(known)}")
        value = float(start.pop(n, default))
        if not (math.isfinite(value) and value != 0):
            raise ValueError(f"{n}: the start value must be finite and non-zero (the search "
                             f"runs in ln(value / start)), got {value!r}"
                             + (f"; give one, e.g. --start {n}=0.1" if value == 0 else ""))
        lo, hi = bounds.pop(n, BETA_BOUNDS if n.startswith("beta") else BOUNDS)
        if not 0 < lo <= 1 <= hi or lo == hi:
            raise ValueError(f"{n}: bounds must be factors lo <= 1 <= hi with lo > 0 and "
                             f"lo < hi, got {lo!r}, {hi!r}")
        params.append(Parameter(n, kind, value, lo, hi, level))
    for left, what in ((start, "start"), (bounds, "bounds")):
        if left:
            raise ValueError(f"{what} given for parameter(s) not fitted: {', '.join(left)}")
    return params


def overrides(params, values, mat, level):
    """The pair_coeff ``name value`` overrides of one run at ``level``."""
    words = []
    for p, v in zip(params, values):
        if p.kind == "beta":
            words += [f"beta_a {mat['beta_a'] * v!r}", f"beta_b {mat['beta_b'] * v!r}"]
        elif p.kind == "beta_level":
            if p.level == level:   # beta constant = v at this level
                words += [f"beta_a {v!r}", "beta_b 0.0"]
        else:
            words.append(f"{p.name} {v!r}")
    return " ".join(words)


def fitted_material(params, values, mat, levels):
    """Material-file values that the fitted parameters stand for: ``{name: value}``.
    Per-level betas become beta_a, beta_b of the law a + b ln s (least squares through the
    levels; with one level, beta_b is kept and beta_a moved)."""
    out = {}
    betas = []
    for p, v in zip(params, values):
        if p.kind == "beta":
            out["beta_a"], out["beta_b"] = mat["beta_a"] * v, mat["beta_b"] * v
        elif p.kind == "beta_level":
            betas.append((p.level, v))
        else:
            out[p.name] = v
    if len(betas) == 1:
        s, v = betas[0]
        out["beta_a"], out["beta_b"] = v - mat["beta_b"] * math.log(s), mat["beta_b"]
    elif betas:
        x = np.log([s for s, _ in betas])
        A = np.column_stack([np.ones_like(x), x])
        (a, b), *_ = np.linalg.lstsq(A, np.array([v for _, v in betas]), rcond=None)
        out["beta_a"], out["beta_b"] = float(a), float(b)
    return out
