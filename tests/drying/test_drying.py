# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Time-domain drying coupled to the LAMMPS mechanics (cgms.drying; doc/drying.md)."""

import os
import subprocess
import sys

import numpy as np
import pytest

import drying_oracle
from cgmstest import APPLE, MAT, ROOT, lammps_env
from cgms import drying, morphology, study, tissue

PARAMS = drying.read_params()


def small_tissue(folder, width=1.25e-3, height=1.5e-3):
    xy = tissue.rectangle(width, height, MAT["x_ref"])
    data = folder / "tissue.data"
    tissue.write_data(data, xy, 3 * MAT["x_ref"])
    return xy, data


def test_water_balance_with_moving_mechanics(tmp_path):
    """The tissue shrinks and the transport geometry follows it; what the tissue loses
    still equals what crossed its faces and outline, to 1e-10 of the water it held."""
    xy, data = small_tissue(tmp_path)
    mech = drying.Mechanics(data, APPLE)
    try:
        res = drying.dry(xy, PARAMS, hours=2, stop=0.4, mechanics=mech,
                         levers=dict(layers=4, resolve=0.05))
    finally:
        mech.close()
    rows = res["rows"]
    assert rows[-1]["X/X0"] <= 0.4
    assert rows[-1]["A/A0"] < 0.9              # it shrank, so the geometry moved
    assert rows[-1]["solves"] >= 5
    assert max(abs(r["balance"]) for r in rows) < 1e-10
    # the geometry of the last solve still links each bead to its nearest shell only
    assert np.bincount(drying.bead_geometry(res["xy"])["pairs"].ravel()).max() == 6


def curves(result, keys=("t_h", "X/X0", "T_product", "surface_X/X0", "core_X/X0", "A/A0",
                          "EL/EL0", "balance", "solves")):
    return {k: np.array([r[k] for r in result["rows"]]) for k in keys}


@pytest.mark.parametrize("moving", [False, True], ids=["frozen", "FIRE"])
def test_engine_matches_oracle(tmp_path, moving):
    """cgms dry's engine, fix cgms/transport driven by drying.dry, gives the drying curve
    of the Python oracle (tests/drying_oracle.py: cgms.transport stepped the same way),
    row by row: the heat balance on, faces and outline in air, to X/X0 = 0.4 or the end
    of --hours (0.18 h, X/X0 = 0.03: a step cut short by it).

    Tolerances, from what each side guarantees. Both solve the same equations, by CG to
    a relative residual of 1e-14; the one difference is the product temperature: the
    oracle's Brent stops within 1e-6 K, the fix's bisection within 1e-10 K. 1e-6 K moves
    D_eff by E/(R T^2) = 7.5e-8 (58 kJ/mol at the wet bulb, 305 K) and the vapour density
    at the surface by 5.5e-8, so every flux by at most 7.5e-8 relative; the loss, X/X0's
    complement, by 7.5e-8 of it, and each step's length (dx_max over the largest change)
    by 1.5e-7. The row k of both is then at times 1.5e-7 relative apart, where X/X0
    moves at most rate x t: 7 /h x 0.18 h x 1.5e-7 = 2e-7. Asserted: X/X0, surface and
    core 1e-6, time 1e-6 relative, T_product 2e-6 K (Brent's 1e-6 K and the step).
    Moving (FIRE to 1e-13 N, each side its own LAMMPS): the shapes are two solves stopped
    anywhere in the ball test_drying_under_mpi derives for this tissue at that force,
    A 1.2e-7, P 8.6e-7, EL 1.1e-5 apart, and the water leaves through faces and edges
    off by that much: A/A0 1e-6, EL/EL0 3e-5, and X/X0 1e-6 more. The same solves at the
    same rows, unless a change falls within these of resolve. Measured: 4e-10 (X/X0),
    2.3e-7 K, 4e-10 (A/A0), 8e-8 (EL/EL0)."""
    xy, data = small_tissue(tmp_path)
    runs = {}
    for name, fn in (("engine", drying.dry), ("oracle", drying_oracle.dry)):
        mech = drying.Mechanics(data, APPLE, ftol=1e-13) if moving else None
        try:
            runs[name] = curves(fn(xy, PARAMS, dict(outline=True, heat=True),
                                   dict(layers=4, resolve=0.05), hours=0.18 if not moving else 2,
                                   stop=0.4 if moving else 0.0, mechanics=mech))
        finally:
            if mech:
                mech.close()
    a, b = runs["engine"], runs["oracle"]
    assert len(a["t_h"]) == len(b["t_h"]) > 20
    if moving:
        assert a["X/X0"][-1] <= 0.4 and a["solves"][-1] >= 5
    else:
        assert a["t_h"][-1] == pytest.approx(0.18, abs=1e-12)    # cut short by --hours
    assert np.all(a["solves"] == b["solves"])
    assert np.abs(a["t_h"] - b["t_h"]).max() <= 1e-6 * a["t_h"][-1]
    for key in ("X/X0", "surface_X/X0", "core_X/X0"):
        assert np.abs(a[key] - b[key]).max() < 1e-6, key
    assert np.abs(a["T_product"] - b["T_product"]).max() < 2e-6
    assert np.abs(a["A/A0"] - b["A/A0"]).max() < 1e-6
    assert np.abs(a["EL/EL0"] - b["EL/EL0"]).max() < 3e-5
    assert np.abs(a["balance"]).max() < 1e-10


def test_transport_neighbours_are_the_nearest_shell():
    """The transport links a bead to the beads within the pair style's cutoff factor
    times the median spacing: on a hexagonal lattice its six nearest, never the second
    shell at sqrt(3) spacings (the geometry of the oracle, and by
    test_engine_matches_oracle of fix cgms/transport, which it gives its cutoff)."""
    a = MAT["x_ref"]
    xy = tissue.hex_rectangle(6, 5, a)
    geo = drying.bead_geometry(xy)
    count = np.bincount(geo["pairs"].ravel(), minlength=len(xy))
    inner = np.hypot(*(xy - xy.mean(axis=0)).T) < a     # the beads around the centre
    assert count.max() == 6 and np.all(count[inner] == 6)
    assert np.allclose(geo["dist"], a, rtol=1e-12)


def test_uniform_field_equals_moisture_domain(tmp_path):
    """Faces only (impermeable outline) and the transport geometry of the fresh tissue:
    every column dries alike, the in-plane field stays uniform, and the shape is the
    moisture-domain steady state at that dryness (cgms study, solved from the lattice).
    The transport on the fresh geometry is a switch of the oracle only: with the geometry
    following the shape, as in cgms dry, the outline beads dry slower (their columns
    shrink less; doc/drying.md)."""
    xy, data = small_tissue(tmp_path)
    mech = drying.Mechanics(data, APPLE, ftol=1e-13)
    try:
        res = drying_oracle.dry(xy, PARAMS, dict(outline=False), dict(layers=4, resolve=0.1),
                         hours=3, stop=0.55, mechanics=mech, transport_geometry=False)
        s = res["x"].reshape(-1, 4).mean(axis=1) / PARAMS["X0"]
        assert np.ptp(s) < 1e-12 * s.mean()
        final = mech.solve(s)                   # the shape at exactly this field
        f = np.ctypeslib.as_array(mech.lmp.gather_atoms("f", 1, 3)).reshape(-1, 3)
        assert np.hypot(f[:, 0], f[:, 1]).max() < 1e-13     # FIRE stopped on its ftol
    finally:
        mech.close()
    ref = study.relax(data, APPLE, float(s[0]), tmp_path / "ref", method="quasistatic",
                      steady=dict(max_steps=20000))
    assert ref["converged"]
    # two FIRE solves to 1e-13 N per bead: residuals of at most 2 sqrt(86) 1e-13 N, which
    # move the elongation by at most 2.4e6 /N x that = 4.4e-6 relative (area, perimeter
    # less) and a bead by 8.8e6 x_ref/N x that = 1.6e-5 x_ref (|H+ grad m| and the largest
    # block row of the inverse stiffness at s = 0.55; tests/README.md)
    a, b = morphology.measures(final), morphology.measures(ref["xy"])
    for key in ("area", "perimeter", "elongation"):
        assert abs(a[key] / b[key] - 1) < 1e-5, key      # measured: 1e-6 at most
    # and bead by bead, after removing the rigid offset the two starts may leave
    d = (final - final.mean(0)) - (ref["xy"] - ref["xy"].mean(0))
    assert np.abs(d).max() < 1e-4 * MAT["x_ref"]         # measured: 2e-6


def cli(*args, cwd):
    env = lammps_env()
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "cgms", "dry", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def test_cli_outputs(tmp_path):
    xy, data = small_tissue(tmp_path)
    out = tmp_path / "res"
    proc = cli("--data", str(data), "--hours", "1", "--stop", "0.5", "--layers", "4",
               "--maps", "0.8,0.6", "--out", str(out), cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    for name in ("drying.csv", "drying.png", "moisture.png", "case-hardening.png",
                 "tissue.X0.8.dump", "tissue.X0.6.dump", "log.lammps"):
        assert (out / name).exists(), name
    assert "X/X0 = 0.5 after" in proc.stdout
    # nothing is overwritten: the same folder again is refused
    again = cli("--data", str(data), "--hours", "1", "--out", str(out), cwd=tmp_path)
    assert again.returncode != 0 and "exists and is not empty" in again.stderr


@pytest.mark.parametrize("args, message", [
    (["--humidity", "1.5"], "--humidity must be in"),
    (["--thickness", "0"], "--thickness must be positive"),
    (["--faces", "0", "--no-outline"], "no water can leave"),
    (["--data", "missing.data"], "missing.data"),
    (["--maps", "0.5,abc"], "'abc' is not a number"),
    (["--maps", "0.5,1.5"], "level 1.5 is outside (0, 1]"),
])
def test_cli_bad_input(tmp_path, args, message):
    proc = cli(*args, "--frozen", "--out", str(tmp_path / "o"), cwd=tmp_path)
    assert proc.returncode != 0
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "o").exists()   # stopped before the results folder was made



@pytest.mark.parametrize("atoms, message", [
    (["2 1 0 0 0", "3 1 1.5e-4 0 0", "4 1 0 1.5e-4 0"], "atom ids must be 1..N"),
    (["1 1 0 0 0", "2 1 abc 0 0", "3 1 0 1.5e-4 0"], "line 13: expected 'id type x y z'"),
])
def test_cli_bad_data_file(tmp_path, atoms, message):
    """--data goes through the package's one data-file reader: file and line named, and
    the ids the transport needs (1..N) checked, before any folder is made."""
    data = tmp_path / "bad.data"
    data.write_text("bad tissue\n\n3 atoms\n1 atom types\n\n-1 1 xlo xhi\n-1 1 ylo yhi\n"
                    "-1 1 zlo zhi\n\nAtoms\n\n" + "\n".join(atoms) + "\n")
    proc = cli("--data", str(data), "--frozen", "--out", str(tmp_path / "o"), cwd=tmp_path)
    assert proc.returncode != 0
    assert message in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
    assert not (tmp_path / "o").exists()

MPI_SCRIPT = """
import json, sys
from pathlib import Path
import numpy as np
sys.path.insert(0, {python!r})
from cgms import drying, material, tissue
folder = Path({folder!r})
xy = tissue.rectangle(1.25e-3, 1.5e-3, material.read({apple!r})["x_ref"])
mech = drying.Mechanics(folder / "tissue.data", {apple!r}, ftol={ftol!r},
                        overrides=sys.argv[2] if len(sys.argv) > 2 else "")
solve, fmax = mech.solve, []


def checked(*args, **kwargs):
    xy = solve(*args, **kwargs)
    # the largest force on a bead where the solve stopped: the premise of the tolerances
    f = np.ctypeslib.as_array(mech.lmp.gather_atoms("f", 1, 3)).reshape(-1, 3)
    fmax.append(float(np.hypot(f[:, 0], f[:, 1]).max()))
    return xy


mech.solve = checked
rows = drying.dry(xy, drying.read_params(), {{}}, dict(layers=4, resolve=0.05), hours=2,
                  stop=0.4, mechanics=mech)["rows"]
out = [(r["X/X0"], r["A/A0"], r["EL/EL0"], r["balance"]) for r in rows]
(folder / ("rows.%s.json" % sys.argv[1])).write_text(json.dumps(dict(rows=out, fmax=fmax)))
mech.close(finalize=True)
"""

# The mechanics solves of the MPI comparison: FIRE until the largest force on any bead is
# below MPI_FTOL (N). Its drying default, 1e-10 N, leaves A/A0 2e-5 and EL/EL0 2e-3 from
# the converged shape (measured against 1e-13), far above what ranks should change.
MPI_FTOL = 1e-13


@pytest.mark.mpi
def test_drying_under_mpi(tmp_path):
    """The moisture loop runs alike on every process and LAMMPS splits the beads: under
    mpirun -np 2 the drying curve and shape match the serial run and the water balance
    still closes.

    Tolerances, from the solver's stopping rule (tests/README.md, "Tolerances across
    configurations"). Each shape is a FIRE solve stopped when every bead's force is below
    ftol, so its residual r has |r|_2 <= sqrt(n) ftol, and a shape measure m is off the
    exact steady state by at most |H+ grad m| sqrt(n) ftol (H the stiffness matrix without
    the rigid motions, from cgms.solve.jacobian on this 86-bead tissue, the largest of
    s = 1, 0.6, 0.4: |H+ grad m| / m = 6.7e4 /N for the area, 4.7e5 /N for the perimeter,
    5.7e6 /N for the elongation, 7.4e3 /N for a bead's area). Two runs, each anywhere in
    that ball, with
    ftol = 1e-13 N: the area 1.2e-7, the perimeter 8.6e-7, the elongation 1.1e-5.
    - A/A0, a ratio of two solves: 2 x 1.2e-7, plus the shape's response (dA/A ds = 0.42)
      to the dryness, whose error is X/X0's below: 6e-7, asserted 1e-6;
    - X/X0: water leaves through the bead faces and the outline edges, whose lengths and
      areas are off by at most 8.6e-7 relative, so the loss by at most 8.6e-7 of the water
      lost: asserted 1e-6;
    - EL/EL0: 2 x 1.1e-5 (and 0.4 x 6e-7 from the dryness): asserted 3e-5.
    The moisture steps and the solves' triggers (resolve, stop) agree unless a value falls
    within these errors of a threshold: the same rows.
    Measured at the old ftol 1e-10: 1e-9 (X/X0), 3e-9 (A/A0), 3e-7 (EL/EL0) on a Xeon,
    1.3e-8 (A/A0) on an EPYC and on the Xeon with NumPy limited to AVX2 (EL/EL0 1.8e-6);
    at 1e-13: 2e-12, 3e-12, 1e-9 (2e-11, 2e-11, 7e-9 with NumPy on AVX2). A run at ftol 1e-10 against one at 1e-13 differs by
    2e-5 (A/A0) and fails, as does k_T changed by 1e-4 in one run (A/A0 2e-6 apart)."""
    import json
    small_tissue(tmp_path)
    script = tmp_path / "dry_mpi.py"
    script.write_text(MPI_SCRIPT.format(python=str(ROOT / "python"), folder=str(tmp_path),
                                        apple=APPLE, ftol=MPI_FTOL))
    env = lammps_env()
    for tag, cmd in (("serial", [sys.executable]),
                     ("np2", ["mpirun", "--oversubscribe", "-np", "2", sys.executable])):
        proc = subprocess.run(cmd + [str(script), tag], cwd=tmp_path, env=env,
                              capture_output=True, text=True, timeout=1800)
        assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    serial, parallel = (json.loads((tmp_path / f"rows.{tag}.json").read_text())
                        for tag in ("serial", "np2"))
    for run in (serial, parallel):       # every solve stopped on its force tolerance
        assert len(run["fmax"]) > 5 and max(run["fmax"]) < MPI_FTOL, run["fmax"]
    serial, parallel = np.array(serial["rows"]), np.array(parallel["rows"])
    assert serial.shape == parallel.shape and len(serial) > 10
    assert np.abs(serial[:, 0] - parallel[:, 0]).max() < 1e-6      # X/X0
    assert np.abs(serial[:, 1] - parallel[:, 1]).max() < 1e-6      # A/A0
    assert np.abs(serial[:, 2] - parallel[:, 2]).max() < 3e-5      # EL/EL0
    assert np.abs(parallel[:, 3]).max() < 1e-10
