# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The contract layer, after LAMMPS's unittest/force-styles: one YAML per style and case
(tests/contract/*.yaml) holds a fixed small input and the frozen outputs of its first
evaluation (``init_*``, a ``run 0``) and after ``run_steps`` steps (``run_*``): the forces,
the global outputs (pair energy, virial, the fix's scalar and vector) and named per-atom
values. Only outputs are frozen (dumps and thermo), never how a style computes them.

One test per case runs it on 1 and 2 ranks (``mpirun -np 2``, ``processors 2 1 1``) with
``newton`` on and off, and reads the serial run's ``write_restart`` and ``write_data``
files back on 1 rank (``newton on``) and on 2 (``newton off``), those compared with
``init_*`` as LAMMPS compares its restart and data runs; everything against the YAML.
``./cgms test tests/contract --regenerate`` rewrites the frozen values from the serial
``newton on`` run (LAMMPS's ``-g``); then review the diff, and run the case's independent
check (the YAML's ``independent_check``) before committing.

Tolerances (tests/README.md, "summation order only"): every configuration adds the same
terms in another order (ghost atoms, reverse communication, a list rebuilt from a restart
or data file), so a value differs by at most ``terms_per_bead`` round-offs of the sum of the
absolute values of its terms, as LAMMPS's ``epsilon``. That sum is the largest value of the
output times the case's ``condition`` for the stage (the cancellation in its sums, derived
in each YAML from the oracle or the law, never from a run), so an output ``q`` is compared
as ``|q - q_yaml| <= epsilon max|q_yaml|``, ``epsilon = terms_per_bead * condition *
2**-52``; a global output, a sum over the beads, has ``natoms`` times the terms and is
compared to ``natoms * epsilon`` of its value (a tensor's components: of the largest).
After ``run_steps`` steps the errors of each step add (an integrator at a time step
inside its stability limit does not amplify them: tests/README.md), so ``run_*`` get
``run_steps + 1`` times their ``epsilon``, with the ``condition`` of the run's last state.
The restart and data-file runs read values written to 17 digits (restart: bit-exact) and
recompute the same sums: the same ``epsilon``.
A case with an iterative linear solve adds, per step, twice (one solve in each run) its
bound ``kappa * tol`` on a solution's relative error (tests/README.md, "iterative
solve"), ``kappa`` bounding the matrix's condition number (stated in its YAML)."""

import re
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pytest
import yaml

import reference
from cgmstest import CUTOFF, PLUGIN, ROOT, material, run_lmp

HERE = Path(__file__).resolve().parent
CASES = sorted(HERE.glob("*.yaml"))
ULP = 2.0 ** -52
#: the configurations compared with the YAML: (ranks, newton, how the input is read)
CONFIGS = [(1, "on", "input"), (1, "off", "input"), (2, "on", "input"), (2, "off", "input"),
           (1, "on", "restart"), (1, "on", "data"), (2, "off", "restart"), (2, "off", "data")]


def load(path):
    return yaml.safe_load(Path(path).read_text())


def epsilon(case, stage):
    """The relative tolerance of a stage (the module's docstring): summation order, plus,
    for a case with an iterative linear solve (``solver``: its relative residual tolerance
    and a bound on the matrix's condition number), two solves' error bound kappa tol."""
    factor = case["run_steps"] + 1 if stage == "run" else 1
    solver = case.get("solver", {"tolerance": 0.0, "condition": 0.0})
    return (case["terms_per_bead"] * case["condition"][stage] * ULP
            + 2 * solver["tolerance"] * solver["condition"]) * factor


def script(case, nprocs, newton, read):
    """The input for one configuration. ``input`` runs ``run 0``, writes the restart and
    data files, then ``run_steps`` steps; ``restart`` and ``data`` read those files back
    and run ``run 0``."""
    fill = dict(newton=newton, nprocs=nprocs, root=ROOT, timestep=case["timestep"])
    steps = case["run_steps"]
    lines = [f"plugin load {PLUGIN}", case[f"{read}_commands"].format(**fill),
             case["commands"].format(**fill),
             f"thermo_style custom step {' '.join(case['global'].values())}",
             "thermo_modify format float %.17g", f"thermo {max(steps, 1)}",
             f"dump d all custom {max(steps, 1)} values.dump id "
             + " ".join(case["per_atom"].values()),
             "dump_modify d format float %.17g sort id", "run 0"]
    if read == "input":
        lines += ["write_restart case.restart",
                  f"write_data case.data {case.get('write_data_options', '')}", f"run {steps}"]
    return "\n".join(lines) + "\n"


def frames(path):
    """Every frame of a text dump: {timestep: {column: array sorted by id}}."""
    out = {}
    for block in Path(path).read_text().split("ITEM: TIMESTEP\n")[1:]:
        lines = block.splitlines()
        start = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
        cols = lines[start].split()[2:]
        data = np.array([[float(w) for w in line.split()] for line in lines[start + 1:]])
        data = data[np.argsort(data[:, 0])]
        out[int(lines[0])] = {c: data[:, k] for k, c in enumerate(cols)}
    return out


def thermo_rows(stdout, ncols):
    """The thermo rows of a log: {step: values}, the last row of a step winning."""
    rows = {}
    for line in stdout.splitlines():
        words = line.split()
        if len(words) == ncols + 1 and re.fullmatch(r"\d+", words[0]):
            try:
                rows[int(words[0])] = [float(w) for w in words[1:]]
            except ValueError:
                continue
    return rows


def measure(case, folder, nprocs, newton, read):
    """Run one configuration; return {"init": outputs, "run": outputs} (``run`` only
    for ``input``), outputs being {"global": {name: value}, "per_atom": {name: array}}."""
    proc = run_lmp(folder, script(case, nprocs, newton, read), nprocs=nprocs)
    dumps = frames(folder / "values.dump")
    rows = thermo_rows(proc.stdout, len(case["global"]))
    out = {"version": re.search(r"LAMMPS \((.*?)\)", proc.stdout).group(1)}
    for stage, step in (("init", 0), ("run", case["run_steps"])):
        if step not in dumps or (stage == "run" and read != "input"):
            continue
        columns = dumps[step]
        out[stage] = {"global": dict(zip(case["global"], rows[step])),
                      "per_atom": {"id": columns["id"]} | {
                          name: columns[col] for name, col in case["per_atom"].items()}}
    return out


def per_atom_text(values, names):
    """The frozen per-atom block: one line per atom, id and the values in order."""
    ids = values["id"].astype(int)
    return "".join(f"{i:4d} " + " ".join(f"{values[n][k]: .17e}" for n in names) + "\n"
                   for k, i in enumerate(ids))


def per_atom_values(text, names):
    rows = np.array([[float(w) for w in line.split()] for line in text.strip().splitlines()])
    out = {"id": rows[:, 0]}
    out.update({n: rows[:, k + 1] for k, n in enumerate(names)})
    return out


class Literal(str):
    pass


yaml.SafeDumper.add_representer(
    Literal, lambda dumper, text: dumper.represent_scalar("tag:yaml.org,2002:str", text,
                                                          style="|"))


def regenerate(path, case, got):
    """Rewrite the frozen values of ``path`` from one configuration's outputs, keeping
    every hand-written key (inputs, tolerance derivation, independent check)."""
    case = dict(case)
    case["date_generated"] = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    case["lammps_version"] = got["version"]
    for stage in ("init", "run"):
        case[f"{stage}_global"] = {k: float(v) for k, v in got[stage]["global"].items()}
        case[f"{stage}_per_atom"] = Literal(per_atom_text(got[stage]["per_atom"],
                                                          list(case["per_atom"])))
    for key, value in case.items():
        if isinstance(value, str) and "\n" in value:
            case[key] = Literal(value)
    Path(path).write_text("---\n" + yaml.safe_dump(case, sort_keys=False, width=100))
    return case


def differences(case, got, stage, eps):
    """The outputs of one stage that differ from the YAML by more than allowed: a per-atom
    value by ``eps`` times the output's largest frozen value, a global (a sum over the
    beads of their sums: ``natoms`` times the terms) by ``natoms * eps`` times its own
    frozen value or, for the members of a ``global_groups`` entry (a tensor's
    components), the group's largest. [(name, error, allowed)]."""
    bad = []
    want = case[f"{stage}_global"]
    natoms = len(got["per_atom"]["id"])
    scale = {name: abs(value) for name, value in want.items()}
    for group in case.get("global_groups", []):
        scale.update({name: max(abs(want[m]) for m in group) for name in group})
    for name, value in got["global"].items():
        allowed = natoms * eps * scale[name] + 1e-300
        if not abs(value - want[name]) <= allowed:
            bad.append((name, abs(value - want[name]), allowed))
    frozen = per_atom_values(case[f"{stage}_per_atom"], case["per_atom"])
    assert np.array_equal(frozen["id"], got["per_atom"]["id"]), "another set of atoms"
    for name in case["per_atom"]:
        largest = np.max(np.abs(frozen[name]))
        err = np.max(np.abs(got["per_atom"][name] - frozen[name]))
        if not err <= eps * largest + 1e-300:
            bad.append((name, err, eps * largest))
    return bad


@pytest.mark.lammps
@pytest.mark.mpi
@pytest.mark.parametrize("path", CASES, ids=[p.stem for p in CASES])
def test_contract(path, tmp_path, request):
    case = load(path)
    # the restart and data files of the serial newton-on run are read by the last two
    folder = tmp_path / "run"
    folder.mkdir()
    for name in case.get("input_files", []):
        (folder / name).write_bytes((HERE / name).read_bytes())
    results = {}
    skip = case.get("skip", {})   # {read: why}, as LAMMPS's YAML skip_tests
    for nprocs, newton, read in CONFIGS:
        if read in skip:
            continue
        results[(nprocs, newton, read)] = measure(case, folder, nprocs, newton, read)
        if request.config.getoption("--regenerate") and len(results) == 1:
            case = regenerate(path, case, results[(1, "on", "input")])
    failures = []
    for config, got in results.items():
        assert "init" in got, f"{config}: no frame at step 0"
        for stage in ("init", "run"):
            if stage not in got:
                continue
            values = got[stage]
            allowed = epsilon(case, stage)
            failures += [f"{config} {stage} {name}: {err:.3e} > {tol:.3e}"
                         for name, err, tol in differences(case, values, stage, allowed)]
    assert not failures, f"{path.name}:\n" + "\n".join(failures)


#: the laws of pair cgms, one at a time (reference.pair_forces's switches)
LAWS = [dict(turgor=True, perimeter=True, damping=False, repulsion=False, attraction=False),
        dict(turgor=False, perimeter=False, damping=True, repulsion=False, attraction=False),
        dict(turgor=False, perimeter=False, damping=False, repulsion=True, attraction=False),
        dict(turgor=False, perimeter=False, damping=False, repulsion=False, attraction=True)]


def cancellation(xy, v, s, c, mat, got):
    """max_i sum_k sum_law |F_ik,law| / max_i |F_i|: the summed absolute terms of the
    force sums against the largest force, each pair term from the oracle on the pair alone
    (a pair's force depends on its two beads only: positions, velocities, dryness, c)."""
    adj = reference.pair_geometry(xy, s, mat, CUTOFF)[2]
    terms = np.zeros(len(xy))
    for i, k in zip(*np.nonzero(adj)):
        for law in LAWS:
            f = reference.pair_forces(xy[[i, k]], v[[i, k]], s[[i, k]], c[[i, k]], mat, CUTOFF,
                                      **law)[0]
            terms[i] += np.hypot(*f[0])
    return terms.max() / np.hypot(got["fx"], got["fy"]).max()


def test_pair_cgms_yaml_agrees_with_the_oracle():
    """The frozen initial forces, LJ energy, virial, pressure and pair coefficient of pair
    cgms (both materials) against the NumPy oracle tests/reference.py, evaluated on the
    frozen inputs of the same YAML (positions, velocities, dryness, fluid mass, turgid
    perimeter): the frozen numbers are derived independently, to 1e-10 of their largest
    value (the two implementations sum in different orders; test_reference.py's RTOL).
    And the YAML's ``condition`` covers the cancellation the oracle finds in the forces
    and the Tait law's amplification K / max|P| of a density's round-off in the pressure.
    The forces after the run are not recomputed here: velocity Verlet evaluated them with
    the half-step velocities, the dump holds the full-step ones (the cancellation uses
    those: damping is one of four laws); tests/plugin/test_reference.py checks forces
    after 300 steps with a ``run 0``, and the configurations here agree with each other."""
    for path in (HERE / "pair-cgms-apple.yaml", HERE / "pair-cgms-apple-mfc.yaml"):
        case = load(path)
        mat = material.read(ROOT / case["material"])
        for stage in ("init", "run"):
            got = per_atom_values(case[f"{stage}_per_atom"], case["per_atom"])
            xy, v = np.c_[got["x"], got["y"]], np.c_[got["vx"], got["vy"]]
            fluid = reference.fluid_state(xy, got["dryness"], got["mf"], got["l0p"], mat,
                                          CUTOFF, implicit_dt=case["timestep"])
            cond = max(cancellation(xy, v, got["dryness"], fluid["cgmscoef"], mat, got),
                       mat["K"] / np.max(np.abs(got["pressure"])))
            assert cond <= case["condition"][stage], \
                f"{path.name} {stage}: condition {cond:.2f}"
            if stage == "run":
                continue  # its forces used the half-step velocities, not the dumped ones
            f, pe, vir = reference.pair_forces(xy, v, got["dryness"], fluid["cgmscoef"], mat,
                                               CUTOFF)
            frozen = case[f"{stage}_global"]
            checks = {"fx": (got["fx"], f[:, 0]), "fy": (got["fy"], f[:, 1]),
                      "pressure": (got["pressure"], fluid["pressure"]),
                      "cgmscoef": (got["cgmscoef"], fluid["cgmscoef"]),
                      "pair energy": (frozen["pe"], pe),
                      "virial": (np.array([frozen[k] for k in ("wxx", "wyy", "wxy")]),
                                 np.array([vir[0, 0], vir[1, 1], vir[0, 1]]))}
            for name, (a, b) in checks.items():
                a, b = np.asarray(a, float), np.asarray(b, float)
                err, scale = np.max(np.abs(a - b)), np.max(np.abs(b))
                assert err <= 1e-10 * scale, \
                    f"{path.name} {stage} {name}: {err:.2e} of {scale:.2e}"


def test_balance_yaml_agrees_with_the_oracle():
    """fix-cgms-fluid-balance.yaml against tests/reference.py on its frozen inputs: every
    pressure is -Pi = s |Pi_f|, the geometry (neighbour count, perimeter, l_d) is the
    oracle's, the forces are the oracle's with the frozen pair coefficients (which the
    potential's gradient pins: tests/plugin/test_quasistatic.py), the fix's scalar is the
    potential of doc/fix_cgms_fluid.rst and the pair energy the LJ energy plus that potential (the pair owns the quasi-static
    energy, doc/pair_cgms.rst), to 1e-10 of
    their largest value; and the YAML's ``condition`` covers the oracle's cancellation."""
    case = load(HERE / "fix-cgms-fluid-balance.yaml")
    mat = material.read(ROOT / case["material"])
    for stage in ("init", "run"):
        got = per_atom_values(case[f"{stage}_per_atom"], case["per_atom"])
        xy, v, s = np.c_[got["x"], got["y"]], np.c_[got["vx"], got["vy"]], got["dryness"]
        cond = cancellation(xy, v, s, got["cgmscoef"], mat, got)
        assert cond <= case["condition"][stage], f"{stage}: condition {cond:.2f}"
        if stage == "run":
            continue  # the forces of the last step used other positions than the dumped ones
        geo = reference.fluid_state(xy, s, got["mf"], got["l0p"], mat, CUTOFF)
        f, pe, _ = reference.pair_forces(xy, v, s, got["cgmscoef"], mat, CUTOFF, damping=False)
        frozen = case[f"{stage}_global"]
        qs = reference.quasistatic_energy(xy, s, got["l0p"], mat, CUTOFF)
        checks = {"pressure": (got["pressure"], -s * mat["Pi_f"]),
                  "nneigh": (got["nneigh"], geo["nneigh"]),
                  "perim": (got["perim"], geo["perim"]),
                  "ldeq": (got["ldeq"], geo["ldeq"]),
                  "fx": (got["fx"], f[:, 0]), "fy": (got["fy"], f[:, 1]),
                  "pair energy": (frozen["pe"], pe + qs),
                  "potential": (frozen["quasistatic"], qs)}
        for name, (a, b) in checks.items():
            a, b = np.asarray(a, float), np.asarray(b, float)
            err, scale = np.max(np.abs(a - b)), np.max(np.abs(b))
            assert err <= 1e-10 * scale, f"{stage} {name}: {err:.2e} of {scale:.2e}"


def test_mfc_pressure_yaml_areas():
    """fix-mfc-pressure.yaml: each cell's frozen area is the shoelace sum of its frozen
    wall positions (ids 1-96 and 97-192 in ring order), to 1e-12, and its cancellation
    (sum of the absolute cross terms over twice the area) is the YAML's 1.57 at most."""
    case = load(HERE / "fix-mfc-pressure.yaml")
    for stage in ("init", "run"):
        got = per_atom_values(case[f"{stage}_per_atom"], case["per_atom"])
        rings = np.c_[got["x"], got["y"]].reshape(2, 96, 2)
        for c, ring in enumerate(rings):
            cross = ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1]
            area = 0.5 * cross.sum()
            assert area == pytest.approx(case[f"{stage}_global"][f"area{c + 1}"], rel=1e-12)
            assert np.abs(cross).sum() / (2 * area) <= 1.57


def test_sph_yaml_agrees_with_the_oracle():
    """pair-sph-taitwater-ap.yaml's frozen initial forces and density rates against the
    NumPy oracle of tests/mfc/test_mfc_sph.py on the frozen positions and densities (at
    rest: the viscous term and the rates vanish), to the oracle's 1e-6 (dW/dr by central
    differences); and the YAML's ``condition`` covers the cancellation of the force sums,
    max_i sum_j |F_ij| / max_i |F_i|, and of the density rates' sums, each pair's terms from
    the oracle on the pair alone
    (an SPH pair force depends on its two particles' positions, velocities, densities)."""
    from mfc.test_mfc_sph import oracle
    case = load(HERE / "pair-sph-taitwater-ap.yaml")
    types = np.array([int(line.split()[1]) for line in
                      (HERE / "sph-patch.data").read_text().split("Atoms # sph\n\n")[1]
                      .strip().splitlines()])
    for stage in ("init", "run"):
        got = per_atom_values(case[f"{stage}_per_atom"], case["per_atom"])
        x, v = np.c_[got["x"], got["y"]], np.c_[got["vx"], got["vy"]]
        terms = np.zeros((len(x), 2))   # summed |pair force|, |pair density rate|
        for i in range(len(x)):
            for j in range(len(x)):
                if i != j:
                    pair = [i, j]
                    f, drho = oracle(x[pair], v[pair], got["rho"][pair], types[pair], "lucy",
                                     0.3, 4)
                    terms[i] += np.hypot(*f[0]), abs(drho[0])
        cond = terms[:, 0].max() / np.hypot(got["fx"], got["fy"]).max()
        if np.abs(got["drho"]).max() > 0:
            cond = max(cond, terms[:, 1].max() / np.abs(got["drho"]).max())
        assert cond <= case["condition"][stage], f"{stage}: condition {cond:.2f}"
        if stage == "init":
            f, drho = oracle(x, v, got["rho"], types, "lucy", 0.3, 4)
            scale = np.abs(f).max()
            assert np.abs(np.c_[got["fx"], got["fy"]] - f).max() <= 1e-6 * scale
            assert np.abs(got["drho"] - drho).max() <= 1e-6 * np.abs(drho).max() + 1e-300
