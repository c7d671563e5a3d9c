# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The plugin's laws (src/CGMS/cgms_laws.h) and their Python twins (python/cgms/model.py)
agree on a grid of inputs.

A small C++ driver is compiled against the header alone (skipped without a C++ compiler),
reads "law n x1 .. xn" lines and prints each law's value with %.17g; the inputs go in as
Python's shortest repr, which reads back to the same double, so both sides evaluate the law
at the very same numbers and differ only by rounding.

Tolerance, derived from the operations: an expression of n floating-point operations
(+ - * /, sqrt and log correctly rounded or within 1 ulp, pow within 2) carries at most
about n eps times the magnitude each operation passes on; for the laws here (sums and
products of the inputs) that is bounded by n eps (|f| + sum_j |x_j df/dx_j|), the relative
condition number of f in its inputs times |f|, plus |f| for the final rounding. The two
sides' errors add, so each law gets (n_C++ + n_Python) eps (|f| + sum_j |x_j df/dx_j|),
n counted from the two implementations (OPS below); the partial derivatives come from
central differences (their own error, 1e-5 relative, only scales the bound).
The last test checks that the comparison catches a law changed by 1e-13 relative (about
450 ulp, far below anything a physical test sees)."""

import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(ROOT / "python"))
from cgms import material, model  # noqa: E402

EPS = np.finfo(float).eps
COMPILER = shutil.which("g++") or shutil.which("c++")

DRIVER = r"""
#include "cgms_laws.h"
#include <cstdio>
#include <string>
using namespace LAMMPS_NS::CGMS;
int main()
{
  char name[64];
  int n;
  while (std::scanf("%63s %d", name, &n) == 2) {
    double a[12];
    for (int k = 0; k < n; k++) std::scanf("%lf", &a[k]);
    const std::string law = name;
    double out = 0.0;
    if (law == "A_ref" || law == "b_ref" || law == "l_ref" || law == "x_ref") {
      const ReferenceCell c = reference_cell(a[0], a[1]);
      out = law == "A_ref" ? c.A_ref : law == "b_ref" ? c.b_ref : law == "l_ref" ? c.l_ref : c.x_ref;
    } else if (law == "beta") out = beta(a[0], a[1], a[2]);
    else if (law == "lj_radius") out = lj_radius(a[0], a[1], a[2]);
    else if (law == "cell_side") out = cell_side(a[0], a[1], a[2], a[3], a[4]);
    else if (law == "perimeter_gradient") out = perimeter_gradient(a[0], a[1]);
    else if (law == "tait_pressure") out = tait_pressure(pow7(a[0]), a[1], a[2]);
    else if (law == "tait_density") out = tait_density(a[0], a[1], a[2], 1.0 / a[3]);
    else if (law == "perimeter_contraction") out = perimeter_contraction(a[0], a[1], a[2]);
    else if (law == "mass_rate") out = mass_rate(a[0], a[1] * a[2], a[3], a[4], a[5]);
    else if (law == "transfer_rate")
      out = transfer_rate(a[0], a[1], 1.0 / a[2], a[3], a[4], a[5], pow7(a[6]));
    else if (law == "pair_coefficient") out = pair_coefficient(a[0], a[1], a[2], a[3], a[4], a[5]);
    else if (law == "quasi_static_energy")
      out = quasi_static_energy(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]);
    else if (law == "shape_stiffness") out = shape_stiffness(a[0], a[1], a[2], a[3]);
    else if (law == "damping_dt_limit") out = damping_dt_limit(a[0], a[1], a[2]);
    else if (law == "shape_dt_limit") out = shape_dt_limit(a[0], a[1], a[2]);
    else if (law == "turgor_omega2") out = turgor_omega2(a[0], a[1], pow7(a[2]), a[3], a[4]);
    else if (law == "balance_density")    // the fluid pass's P = -Pi (s, P_f, Pi_f, K, rho0)
      out = tait_density(-(a[0] * a[2]), a[0] * a[1], a[3], 1.0 / (a[0] * a[4]));
    else {
      std::printf("unknown\n");
      continue;
    }
    std::printf("%.17g\n", out);
  }
  return 0;
}
"""

MAT = material.read("apple")


def _mat(**values):
    return dict(MAT, **values)


def _ref(key):
    return lambda d, p: model.reference_cell(d, p)[key]


# law: (its Python twin on the driver's argument list, operations C++ + Python)
LAWS = {
    "A_ref": (_ref("A_ref"), 3 + 3),
    "b_ref": (_ref("b_ref"), 7 + 6),
    "l_ref": (_ref("l_ref"), 8 + 7),
    "x_ref": (_ref("x_ref"), 9 + 9),
    "beta": (lambda a, b, s: model.beta(_mat(beta_a=a, beta_b=b), s), 3 + 3),
    "lj_radius": (lambda r0, k, s: model.lj_radius(_mat(r0=r0, lj_slope=k), s), 4 + 4),
    "cell_side": (model.cell_side, 10 + 10),
    "perimeter_gradient": (model.perimeter_gradient, 6 + 6),
    "tait_pressure": (model.tait_pressure, 7 + 5),
    "tait_density": (model.tait_density, 6 + 6),
    "perimeter_contraction": (
        lambda a, b, s: model.perimeter_contraction(_mat(perim_a=a, perim_b=b), s), 4 + 4),
    "mass_rate": (model.mass_rate, 6 + 6),
    "transfer_rate": (model.transfer_rate, 12 + 10),
    "pair_coefficient": (model.pair_coefficient, 6 + 6),
    "quasi_static_energy": (model.quasi_static_energy, 12 + 12),
    "shape_stiffness": (
        lambda k, n, f, s: model.shape_stiffness(_mat(k_S=k, k_S_exponent=n, k_S_floor=f), s),
        4 + 4),
    "damping_dt_limit": (model.damping_dt_limit, 4 + 4),
    "shape_dt_limit": (model.shape_dt_limit, 4 + 4),
    "turgor_omega2": (model.turgor_omega2, 12 + 8),
    "balance_density": (
        lambda s, P_f, Pi_f, K, rho0: model.balance_density(
            _mat(P_f=P_f, Pi_f=Pi_f, K=K, rho0=rho0), s), 12 + 10),
}


def _grid():
    """(law, args) at the values the model meets: the apple material and variations of it,
    every dryness level, every neighbour count of a bead."""
    m = MAT
    cell = model.reference_cell(m["diameter"], m["pectin"])
    dryness = [0.05, 0.1, 0.3, 0.5, 0.8, 1.0]
    counts = range(1, 13)
    beta_s = [0.7, 0.9, 1.0, 1.03, 1.2]
    q = [0.6, 0.9, 0.999, 1.0, 1.001, 1.2, 1.6]
    rows = []
    for d in [50e-6, m["diameter"], 400e-6]:
        for p in [0.0, m["pectin"], 3e-6]:
            rows += [(k, (d, p)) for k in ("A_ref", "b_ref", "l_ref", "x_ref")]
    for s in dryness:
        rows.append(("beta", (m["beta_a"], m["beta_b"], s)))
        rows.append(("lj_radius", (m["r0"] or cell["x_ref"], m["lj_slope"], s)))
        rows.append(("perimeter_contraction", (m["perim_a"], m["perim_b"], s)))
        for kS, n, fl in [(0.5, 0.0, 0.0), (0.5, 2.0, 0.0), (0.5, 2.0, 0.02), (900.0, 1.5, 1.0)]:
            rows.append(("shape_stiffness", (kS, n, fl, s)))
        rows.append(("balance_density", (s, m["P_f"], m["Pi_f"], m["K"], m["rho0"])))
    for nn in counts:
        for b in beta_s:
            for x in [0.8, 0.95, 1.0, 1.1]:
                sum_r = nn * x * cell["x_ref"]
                rows.append(("cell_side", (nn, sum_r, b, m["pectin"], cell["b_ref"])))
            rows.append(("perimeter_gradient", (nn, b)))
        for mass in [1e-10, 1.2e-10]:
            rows.append(("damping_dt_limit", (mass, nn, m["k_d"])))
            rows.append(("shape_dt_limit", (mass, nn, 0.5)))
    rows.append(("cell_side", (0, 0.0, 1.0, m["pectin"], cell["b_ref"])))
    perim, area = cell["l_ref"], cell["A_ref"]
    for s in [0.3, 1.0]:
        P_ref, Pi = s * m["P_f"], s * m["Pi_f"]
        for qq in q:
            P = float(model.tait_pressure(qq, P_ref, m["K"]))
            rho = qq * s * m["rho0"]
            rows.append(("tait_pressure", (qq, P_ref, m["K"])))
            rows.append(("tait_density", (P, P_ref, m["K"], s * m["rho0"])))
            rows.append(("mass_rate", (perim, m["height"], m["L_p"], rho, P, Pi)))
            rows.append(("transfer_rate", (m["L_p"], perim, area, P, Pi, m["K"], qq)))
            for l in [0.9 * perim, perim, 1.1 * perim]:
                ld = 0.95 * perim
                rows.append(("pair_coefficient", (m["k_T"], m["k_PA"], m["P_f"], P, l, ld)))
                for nn in [2, 6]:
                    g = float(model.perimeter_gradient(nn, 0.9))
                    rows.append(("quasi_static_energy", (m["k_T"], m["k_PA"], m["P_f"], P,
                                                         nn * cell["x_ref"], l, ld, g)))
            rows.append(("turgor_omega2", (m["k_T"], m["K"], qq, 1e-10, 6 * cell["b_ref"])))
    return rows


def _driver(tmp_path, header_dir):
    source = tmp_path / "laws_driver.cpp"
    source.write_text(DRIVER)
    exe = tmp_path / "laws_driver"
    subprocess.run([COMPILER, "-std=c++17", "-O2", "-I", str(header_dir), str(source), "-o",
                    str(exe)], check=True, capture_output=True, text=True)
    return exe


def _cpp_values(exe, rows):
    text = "".join(f"{law} {len(args)} {' '.join(repr(float(a)) for a in args)}\n"
                   for law, args in rows)
    out = subprocess.run([str(exe)], input=text, check=True, capture_output=True, text=True)
    return [float(v) for v in out.stdout.split()]


def _bound(law, args):
    """(|f| + sum_j |x_j df/dx_j|) times the law's operation count times eps."""
    twin, ops = LAWS[law]
    f = float(twin(*args))
    cond = abs(f)
    for j, xj in enumerate(args):
        if xj == 0 or (law == "cell_side" and j == 0) or (law in ("perimeter_gradient",) and j == 0):
            continue    # a count N is an integer, not a perturbed input
        h = 1e-6 * abs(xj)
        up, down = list(args), list(args)
        up[j], down[j] = xj + h, xj - h
        cond += abs(xj * (float(twin(*up)) - float(twin(*down))) / (2 * h))
    return f, ops * EPS * cond * (1 + 1e-5)


def _mismatches(tmp_path, header_dir):
    rows = _grid()
    values = _cpp_values(_driver(tmp_path, header_dir), rows)
    assert len(values) == len(rows)
    bad = []
    for (law, args), cpp in zip(rows, values):
        py, tol = _bound(law, args)
        if not abs(cpp - py) <= tol:
            bad.append(f"{law}{tuple(args)}: C++ {cpp!r}, Python {py!r}, tolerance {tol:.3g}")
    return bad


needs_compiler = pytest.mark.skipif(COMPILER is None, reason="no C++ compiler (g++) found")


@needs_compiler
def test_every_law_has_its_twin_on_the_grid(tmp_path):
    rows = _grid()
    assert {law for law, _ in rows} == set(LAWS)
    bad = _mismatches(tmp_path, ROOT / "src" / "CGMS")
    assert not bad, "\n".join(bad[:20])


@needs_compiler
def test_a_law_changed_by_1e_13_is_caught(tmp_path):
    header = (ROOT / "src" / "CGMS" / "cgms_laws.h").read_text()
    changed = header.replace("return q2 * q2 * q2 * q;", "return q2 * q2 * q2 * q * (1.0 + 1e-13);")
    assert changed != header
    folder = tmp_path / "changed"
    folder.mkdir()
    (folder / "cgms_laws.h").write_text(changed)
    bad = _mismatches(tmp_path, folder)
    caught = {line.split("(")[0] for line in bad}
    assert {"tait_pressure", "transfer_rate", "turgor_omega2"} <= caught, bad
