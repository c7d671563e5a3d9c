# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The harness of pair_style cgms/shaped's tests: a tissue of the shaped tensor model
(cgms.shaped_tensor) in a state, written with cgms.shaped_data, run by LAMMPS, and read
back as the oracle's state vector and gradient."""

import math

import numpy as np

from cgms import material, shaped_data, shaped_tensor as st, tissue
from cgmstest import PLUGIN, run_lmp

MAT = material.read("apple")
L = MAT["x_ref"]
EPS = np.finfo(float).eps
#: the best parameter set of doc/results/shaped-results.md (the pair's defaults)
BEST = {"soft": 0.002, "kg_ratio": 1.0, "strip": "contour", "lamella": 0.391, "void": 0.063,
        "iso": 1.0, "beta_b": 0.04}
#: the other branches: the chord strip, no void, the whole F as bond target
OTHER = {"soft": 0.05, "kg_ratio": 0.3, "strip": "chord", "lamella": 0.5, "void": 0.0,
         "iso": 0.0, "beta_a": 1.1, "beta_b": 0.05}
APPLE = str(material.find("apple"))
DUMP_COLUMNS = "id x y fx fy " + " ".join(f"d2_shaped_fF[{k}]" for k in range(1, 5)) + " " + \
    " ".join(f"d2_shaped_F[{k}]" for k in range(1, 5))


def calibration_tissue(params):
    """The 86-cell calibration tissue (the MFC's, doc/mfc.md) built for ``params``."""
    w, h = tissue.MICROSCALE["calibration"]
    xy = tissue.rectangle(w * 1e-3, h * 1e-3, L)
    return xy, st.build(xy, MAT, params)


def perturbed_state(xy, geo, s, seed=3, jitter=4e-6, spread=0.25):
    """A state far from balance: beads shrunk by sqrt(s) and jittered, every F sqrt(s) times
    a random stretch of +-``spread``, one pair of non-neighbours pushed inside the LJ radius
    (so that walls stretch and buckle and the LJ term acts)."""
    lev = st.at_level(geo, s)
    rng = np.random.default_rng(seed)
    c = xy.mean(axis=0)
    x = c + (xy - c) * math.sqrt(s) + rng.normal(0, jitter, xy.shape)
    pairs = lev["pairs"]
    d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    i, k = pairs[np.argmin(d)]
    x[k] = x[i] + 0.85 * lev["r_lj"] * (x[k] - x[i]) / np.linalg.norm(x[k] - x[i])
    F = math.sqrt(s) * (np.eye(2) + rng.uniform(-spread, spread, (geo["n"], 2, 2)))
    return st.join(x, F), lev


def header(geo, data="tissue.data", newton="on", nprocs=1):
    return "\n".join([
        f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
        f"newton {newton}", f"processors {nprocs} 1 1" if nprocs > 1 else "",
        "atom_style atomic", "atom_modify map array sort 0 0",
        shaped_data.fix_command(geo), shaped_data.read_command(data),
        "neighbor 1.5e-5 bin", "neigh_modify every 1 delay 0 check yes"]) + "\n"


def physics(s, params, material_file, extra=""):
    return f"{shaped_data.pair_style(s, params)} {extra}\npair_coeff * * {material_file}\n"


def output(every=1):
    return (f"dump d all custom {every} state.dump {DUMP_COLUMNS}\n"
            "dump_modify d format float %.17g sort id\n"
            "thermo_style custom step pe fnorm fmax\nthermo_modify format float %.17g\n")


def thermo_rows(stdout):
    """The thermo rows (step, pe, fnorm, fmax) of every run in the output."""
    rows, take = [], False
    for line in stdout.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            take = True
            continue
        if take:
            try:
                rows.append([float(w) for w in words])
            except ValueError:
                take = False
    return rows


def read_state(path):
    """(z, generalised force -dE/dF (n, 4), bead forces (n, 2)) of a dump's last frame."""
    from cgmstest import read_dump
    d = read_dump(path)
    x = np.c_[d["x"], d["y"]]
    F = np.stack([d[f"d2_shaped_F[{k}]"] for k in range(1, 5)], axis=1)
    fF = np.stack([d[f"d2_shaped_fF[{k}]"] for k in range(1, 5)], axis=1)
    return st.join(x, F), fF, np.c_[d["fx"], d["fy"]]


def run(folder, geo, z, s, params, material_file, commands="run 0\n", nprocs=1, newton="on",
        check=True, extra=""):
    """Write the tissue in state z, run ``commands``; returns the process."""
    shaped_data.write_data(folder / "tissue.data", geo, z, overwrite=True)
    script = header(geo, newton=newton, nprocs=nprocs) + physics(s, params, material_file, extra) \
        + output() + commands
    return run_lmp(folder, script, nprocs=nprocs, check=check)
