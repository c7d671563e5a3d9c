# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""fix cgms/transport (time-domain drying inside LAMMPS) against its Python oracle
(cgms.drying.transport stepped as cgms.drying.dry steps it), against Crank's slab series, and for
water balance, MPI, restart and bad input (doc/fix_cgms_transport.rst). The mechanics is
frozen here (pair_style zero, no integrator): the beads keep their positions."""

from pathlib import Path

import numpy as np
import pytest

import crank
from cgmstest import PLUGIN, ROOT, read_dump, run_lmp, slow
from cgms import tissue
from cgms.drying import transport

PARAMS_FILE = ROOT / "potentials" / "apple-drying.params"
A = 1.5e-4            # lattice spacing (m)
CUT = 1.35 * A        # transport cutoff: the nearest shell of the lattice only


def read_params(path=PARAMS_FILE):
    params = {}
    for raw in Path(path).read_text().splitlines():
        words = raw.split("#", 1)[0].split()
        if words:
            params[words[0]] = float(words[1])
    return params


def jittered(ncols=6, nrows=7, jitter=0.04, seed=3):
    rng = np.random.default_rng(seed)
    xy = tissue.hex_rectangle(ncols, nrows, A)
    return xy + rng.uniform(-jitter, jitter, xy.shape) * A


def script(fix_args, steps, params=PARAMS_FILE, thermo_every=1, extra="", processors=None,
           head=True, dump=True, cut=CUT):
    lines = [f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
             f"processors {processors} 1 1" if processors else "",
             "atom_style cgms", "atom_modify map array sort 0 0", "read_data t.data",
             f"pair_style zero {cut!r}", "pair_coeff * *", f"neighbor {0.1 * cut!r} bin"] if head else []
    lines += [f"fix tr all cgms/transport {params} {fix_args}",
              "thermo_style custom step " + " ".join(f"f_tr[{k}]" for k in range(1, 15)),
              "thermo_modify format float %.17g", f"thermo {thermo_every}", extra,
              f"run {steps}"]
    if dump:
        lines.append("write_dump all custom out.dump id x y f_tr[1] f_tr[2] f_tr[3] f_tr[4] "
                     "modify format float %.17g")
    return "\n".join(lines) + "\n"


def thermo(stdout):
    """Thermo rows (step and the 14 global outputs) of every run in ``stdout``."""
    rows = []
    for line in stdout.splitlines():
        words = line.split()
        if len(words) == 15 and words[0].isdigit():
            rows.append([float(w) for w in words])
    return np.array(rows)


def lammps(folder, xy, fix_args, steps, nprocs=1, **kw):
    tissue.write_data(folder / "t.data", xy, 3 * kw.get("cut", CUT) / 1.35, overwrite=True)
    proc = run_lmp(folder, script(fix_args, steps, **kw), nprocs=nprocs)
    return thermo(proc.stdout), read_dump(folder / "out.dump")


def oracle(xy, steps, dt, layers, faces=2, outline=True, inplane=True, heat=False,
           temperature=70.0, humidity=0.1, velocity=1.5, plate=0.04, thickness=2e-3,
           linear=None, adapt=None, params=None):
    """cgms.drying.transport stepped as cgms.drying.dry steps it (shape frozen, fixed or adaptive
    step), on the geometry of cgms.drying.transport.bead_geometry (its outline is the one the fix
    constructs). Returns the node moisture (n, layers), the product temperature, the water
    out through faces and outline, and the initial water."""
    p = params or read_params()
    n = len(xy)
    geo = transport.bead_geometry(xy, CUT)
    if not outline:
        geo["edge"] = np.zeros(n)
    if not inplane:
        geo = dict(geo, pairs=np.zeros((0, 2), int), dist=np.zeros(0), face=np.zeros(0))
    solids = p["solids_density"] * geo["area"] * thickness
    grid = transport.column_grid(geo, np.full(n, thickness), solids, layers, faces)
    gab = (p["GAB_Xm"], p["GAB_C"], p["GAB_K"])
    kc, h = transport.air_coefficients(temperature, velocity, plate)
    x = np.full(n * layers, p["X0"])
    w0 = transport.water(grid, x)

    def diffusivity(v, t_c):
        return transport.diffusivity(v, t_c, p["D_ref"], p["T_ref"], p["D_energy"],
                                     p["D_moisture"], p["X0"])

    def temperature_of(v):
        if not heat:
            return temperature
        return transport.product_temperature(kc, h, temperature, humidity, gab, grid, v,
                                             diffusivity, True)

    def coefficients(v):
        tp = temperature_of(v)
        law = transport.linear_surface(*linear) if linear else \
            transport.vapour_surface(kc, tp, temperature, humidity, gab)
        return (lambda u: diffusivity(u, tp)), law

    tp = temperature_of(x)
    out_face = out_edge = 0.0
    for _ in range(steps):
        tp = temperature_of(x)
        x_new, face, edge, _ = transport.extrapolated_step(grid, x, dt, coefficients,
                                                           outline=True)
        change = np.abs(x_new - x).max() / p["X0"]
        x = x_new
        out_face += face
        out_edge += edge
        if adapt:
            dt = min(adapt[1], dt * min(2.0, adapt[0] / max(change, 1e-12)))
    return x.reshape(n, layers), tp, out_face, out_edge, w0


def nodes(dump, layers=3):
    """Every node's X/X0 from the per-atom output of a 3-layer fix: mean, surface, core."""
    assert layers == 3
    mid = 3 * dump["f_tr[2]"] - dump["f_tr[3]"] - dump["f_tr[4]"]
    return np.column_stack([dump["f_tr[3]"], mid, dump["f_tr[4]"]])


CASES = {
    "both faces and outline": dict(faces=2, outline=True),
    "one face, no outline": dict(faces=1, outline=False),
    "outline only": dict(faces=0, outline=True),
    "no in-plane flow": dict(faces=2, outline=True, inplane=False),
}


def switches(case):
    words = [f"faces {case.get('faces', 2)}",
             f"outline {'yes' if case.get('outline', True) else 'no'}",
             f"inplane {'yes' if case.get('inplane', True) else 'no'}"]
    return " ".join(words)


@pytest.mark.parametrize("name", list(CASES))
def test_matches_python_oracle(tmp_path, name):
    """Per-node moisture, water out and balance of the fix equal cgms.drying.transport on the same
    frozen jittered tissue and the same 25 steps (adaptive), to 1e-10 (measured: 4e-13 at
    most), half way through the drying, with the field far from uniform."""
    case = CASES[name]
    xy = jittered()
    rows, dump = lammps(tmp_path, xy, f"layers 3 dt 10 adapt 0.02 300 heat no {switches(case)}",
                        25)
    x, _, out_face, out_edge, w0 = oracle(xy, 25, 10.0, 3, adapt=(0.02, 300.0), **case)
    x0 = read_params()["X0"]
    assert np.abs(nodes(dump) - x / x0).max() < 1e-10
    assert np.ptp(x / x0) > 0.3                                # a real moisture field
    last = rows[-1]
    assert last[0] == 25 and last[14] == 25                   # 25 moisture steps
    assert abs(last[5] - out_face) <= 1e-10 * w0
    assert abs(last[6] - out_edge) <= 1e-10 * w0
    assert last[3] < 0.85                                      # it dried
    assert abs(last[7]) < 1e-10                                # water balance
    # the drying rate: the X/X0 lost in the last step over its length (h)
    prev = rows[-2]
    assert abs(last[4] - (prev[3] - last[3]) / (last[2] - prev[2])) < 1e-9 * last[4]


@pytest.mark.parametrize("b", [3.0, -2.0])
def test_moisture_dependent_d_matches_python(tmp_path, b):
    """D varying with moisture (D_moisture b: D ~ exp(b (X/X0 - 1)), the face D the mean of
    the two nodes' D): the fix's nodes, outflows and water balance equal cgms.drying.transport's
    (whose steady flow matches the Kirchhoff solution, test_drying_transport.py) to 1e-10,
    with both faces and the outline in air (measured: nodes 1.7e-13 for b = 3, 2.8e-14
    for b = -2; outflows 3e-14 of the initial water; balance 1.2e-15)."""
    params = dict(read_params(), D_moisture=b)
    (tmp_path / "dx.params").write_text("".join(f"{k} {v!r}\n" for k, v in params.items()))
    xy = jittered()
    rows, dump = lammps(tmp_path, xy, "layers 3 dt 10 adapt 0.02 300 heat no", 25,
                        params="dx.params")
    x, _, out_face, out_edge, w0 = oracle(xy, 25, 10.0, 3, adapt=(0.02, 300.0), params=params)
    assert np.ptp(x / params["X0"]) > 0.3          # D varies by exp(0.3 b) or more
    assert np.abs(nodes(dump) - x / params["X0"]).max() < 1e-10
    last = rows[-1]
    assert abs(last[5] - out_face) <= 1e-10 * w0
    assert abs(last[6] - out_edge) <= 1e-10 * w0
    assert abs(last[7]) < 1e-10                    # water balance
    # and the moisture dependence acts: the same run with D constant differs
    flat, *_ = oracle(xy, 25, 10.0, 3, adapt=(0.02, 300.0), params=dict(params, D_moisture=0.0))
    assert np.abs(flat - x).max() > 1e-3 * params["X0"]


def test_product_temperature_matches_python(tmp_path):
    """With the heat balance on: the product temperature and the moisture follow the
    Python side (whose Brent solve stops at 1e-6 K, so 1e-6 here)."""
    xy = jittered()
    rows, dump = lammps(tmp_path, xy, "layers 3 dt 30 heat yes", 20)
    x, tp, *_ = oracle(xy, 20, 30.0, 3, heat=True)
    assert abs(rows[-1][11] - tp) < 1e-5
    assert 32.0 < rows[1][11] < 45.0        # near the wet bulb while the surface is wet
    assert np.abs(nodes(dump) - x / read_params()["X0"]).max() < 1e-6


@pytest.mark.mpi
def test_water_balance_serial_and_two_ranks(tmp_path):
    """Water conserved to 1e-10 over a run, serially and on 2 ranks, and the two agree.
    The ranks add the same terms in another order, and each step's linear solve stops at
    a relative residual of 1e-14 on a well-conditioned (diagonally dominant) matrix: the
    runs differ by some 1e-14 per step (measured at 2 and 3 ranks: 9e-14 relative in the
    thermo columns, 1e-15 in the node moisture), against rtol 1e-9
    over 60 steps (tests/README.md, "Tolerances across configurations")."""
    xy = jittered(10, 9)
    args = "layers 5 dt 10 adapt 0.02 600 heat yes"
    results = []
    for nprocs in (1, 2):
        folder = tmp_path / f"np{nprocs}"
        folder.mkdir()
        results.append(lammps(folder, xy, args, 60, nprocs=nprocs,
                              processors=2 if nprocs == 2 else None))
    (r1, d1), (r2, d2) = results
    assert r1[-1][3] < 0.7                                 # it dried
    for rows in (r1, r2):
        assert np.abs(rows[:, 7]).max() < 1e-10
    assert np.allclose(r1[:, 1:], r2[:, 1:], rtol=1e-9, atol=1e-14)
    for key in ("f_tr[2]", "f_tr[3]", "f_tr[4]"):
        assert np.abs(d1[key] - d2[key]).max() < 1e-10


def test_slab_matches_crank(tmp_path):
    """Frozen mechanics, constant D, convective faces only (Crank's boundary condition,
    a linear surface law): X/X0(t) follows Crank's slab series (eq. 4.54) within 1 %."""
    p = read_params()
    assert p["D_moisture"] == 0.0                  # D independent of moisture
    d = p["D_ref"]                                 # at T_ref, as the fix runs at T_air = T_ref
    thick = 2e-3
    half = thick / 2
    biot = 2.0
    hx = biot * d / half * p["solids_density"]    # h rho_s, per unit X
    steps, fourier = 300, 0.3
    dt = fourier * half**2 / d / steps
    xy = tissue.hex_rectangle(4, 4, A)
    rows, _ = lammps(tmp_path, xy,
                     f"layers 20 dt {dt!r} faces 2 outline no temperature {p['T_ref']} "
                     f"thickness {thick} surface linear {hx!r} 0.0", steps, thermo_every=30)
    fo = rows[1:, 1] * d / half**2
    exact = crank.slab_mean(fo, biot)
    assert np.abs(rows[1:, 3] / exact - 1).max() < 0.01
    assert rows[-1][3] < 0.7                       # Crank: 0.681 at Fo = 0.3, Bi = 2


def disc_error(folder, spacing, biot=2.0, fourier=0.2, steps=300):
    """Largest relative error of X/X0(t) of a disc (outline only, one layer, constant D,
    Crank's convective boundary) against Crank's series for the cylinder (eq. 5.52)."""
    p = read_params()
    d = p["D_ref"]                                     # the fix runs at T_air = T_ref
    xy = tissue.disc(1.5e-3, spacing)
    # the disc the beads tile: each owns a hexagonal cell of the lattice
    radius = np.sqrt(len(xy) * 0.5 * np.sqrt(3) * spacing**2 / np.pi)
    hx = biot * d / radius * p["solids_density"]      # h rho_s, per unit X
    dt = fourier * radius**2 / d / steps
    rows, _ = lammps(folder, xy, f"layers 1 dt {dt!r} faces 0 outline yes inplane yes "
                     f"temperature {p['T_ref']} surface linear {hx!r} 0.0", steps,
                     thermo_every=15, cut=1.35 * spacing)
    fo = rows[1:, 1] * d / radius**2
    assert abs(fo[-1] - fourier) < 1e-9
    return np.abs(rows[1:, 3] / crank.disc_mean(fo, biot) - 1).max(), rows[-1][3]


def test_disc_matches_crank(tmp_path):
    """Frozen mechanics, constant D, water out through the outline only (the outline the
    fix constructs from each bead's neighbours): X/X0(t) follows Crank's series for the
    disc within 1 % at every size, and the error falls as the beads get smaller (367, 823 and 3259
    beads; measured 7.3e-3, 1.8e-3, 2.8e-4)."""
    errors = []
    for spacing in (1.5e-4, 1e-4, 0.5e-4):
        folder = tmp_path / f"a{spacing}"
        folder.mkdir()
        error, last = disc_error(folder, spacing)
        assert last < 0.6                             # Crank: 0.573 at Fo = 0.2, Bi = 2
        errors.append(error)
    assert max(errors) < 0.01 and errors[0] > errors[1] > errors[2]


@slow
def test_disc_matches_crank_fine(tmp_path):
    """The same with 13 057 beads (spacing 25 um): measured 1.3e-4 with backward Euler
    steps (before the second-order step; not re-measured)."""
    error, _ = disc_error(tmp_path, 0.25e-4)
    assert error < 5e-4


def test_uniform_field_stays_uniform(tmp_path):
    """Uniform moisture, impermeable outline, faces in air on a jittered tissue: every
    column dries alike, so the in-plane field stays uniform (in-plane flows are zero)."""
    xy = jittered(8, 8, jitter=0.08)
    rows, dump = lammps(tmp_path, xy, "layers 3 dt 20 adapt 0.05 600 outline no", 30)
    mean = dump["f_tr[2]"]
    assert rows[-1][3] < 0.9
    assert np.ptp(mean) < 1e-12 * mean.mean()


def test_restart_continues_the_run(tmp_path):
    """40 moisture steps in one go equal 20, write_restart, read_restart and 20 more."""
    xy = jittered()
    args = "layers 4 dt 10 adapt 0.05 600 heat yes"
    one = tmp_path / "one"
    one.mkdir()
    rows_a, dump_a = lammps(one, xy, args, 40)
    two = tmp_path / "two"
    two.mkdir()
    tissue.write_data(two / "t.data", xy, 3 * A, overwrite=True)
    run_lmp(two, script(args, 20, dump=False) + "write_restart r.restart\n")
    head = [f"plugin load {PLUGIN}", "read_restart r.restart", f"pair_style zero {CUT}",
            "pair_coeff * *", "neighbor 1.5e-5 bin"]
    proc = run_lmp(two, "\n".join(head) + "\n" + script(args, 20, head=False))
    rows_b = thermo(proc.stdout)
    dump_b = read_dump(two / "out.dump")
    assert rows_b[0][0] == 20 and rows_b[-1][14] == 40
    assert np.allclose(rows_b[-1][1:], rows_a[-1][1:], rtol=1e-12, atol=1e-16)
    for key in ("f_tr[2]", "f_tr[3]", "f_tr[4]"):
        assert np.abs(dump_a[key] - dump_b[key]).max() < 1e-13
    # a fix with other columns than the file's is refused, naming both (before its store
    # is made: test_fix_transport_state.py::test_restart_with_other_layers_is_refused_first)
    proc = run_lmp(two, "\n".join(head) + "\n" + script(args.replace("layers 4", "layers 5"), 2,
                                                        head=False), check=False)
    error = next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")
    assert "the state of 4 layers" in error and "this fix has layers 5" in error, \
        proc.stdout[-2000:]


@pytest.mark.parametrize("fix_args, params, message", [
    ("", "missing.params", "cannot open parameter file missing.params"),
    ("", "short", "misses GAB_C"),
    ("", "bad", "line 2: 'abc' is not a number"),
    ("", "unknown", "unknown parameter 'D_typo'"),
    ("", "twice", "parameter D_ref given twice"),
    ("", "blank", "line 4: 'abc' is not a number"),   # blank and comment lines count
    ("faces 3", None, "faces must be 0, 1 or 2"),
    ("layers 0", None, "layers must be >= 1"),
    ("humidity 1.5", None, "humidity is a relative humidity"),
    ("dt", None, "keyword 'dt' needs 1 value"),
    ("colour blue", None, "Unknown fix cgms/transport keyword 'colour'"),
    ("surface wet", None, "surface must be 'vapour' or 'linear h_x X_eq'"),
    ("cutoff 1e-5", None, "bead 1 has no neighbour within the transport cutoff"),
    ("until 0", None, "until (s of drying) must be > 0"),
])
def test_bad_input_names_the_cause(tmp_path, fix_args, params, message):
    good = PARAMS_FILE.read_text()
    files = {"short": good.replace("GAB_C ", "# GAB_C "),
             "bad": "X0 5.94\nD_ref abc\n",
             "unknown": good + "D_typo 1.0\n",
             "twice": good + "D_ref 1e-9\n",
             "blank": "X0 5.94\n\n# a note\nD_ref abc\n"}
    if params in files:
        (tmp_path / f"{params}.params").write_text(files[params])
        params = f"{params}.params"
    tissue.write_data(tmp_path / "t.data", jittered(), 3 * A, overwrite=True)
    proc = run_lmp(tmp_path, script(fix_args, 2, params=params or PARAMS_FILE), check=False)
    assert proc.returncode != 0
    error = next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")
    assert message in error, proc.stdout[-2000:]


def test_coupled_to_fix_cgms_fluid(tmp_path):
    """The coupling of in.transport on a small tissue: fix cgms/fluid takes each bead's
    dryness from the fix (f_tr[1]), the dynamics shrinks the tissue between moisture
    steps, the transport geometry follows it, and the water balance still closes."""
    from cgmstest import APPLE, XREF
    xy = tissue.hex_rectangle(6, 7, XREF)
    tissue.write_data(tmp_path / "t.data", xy, 4 * XREF, overwrite=True)
    lines = [f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
             "atom_style cgms", "atom_modify map array sort 0 0", "comm_modify vel yes",
             "read_data t.data", "neighbor 1.5e-5 bin", "neigh_modify every 1 delay 0 check yes",
             "pair_style cgms", f"pair_coeff * * {APPLE}", "fix fluid all cgms/fluid dryness 1.0",
             "fix nve all nve", "fix 2d all enforce2d", "timestep 1e-7",
             "compute area all reduce sum f_fluid[11]", "thermo_style custom step c_area",
             "run 30000", "variable A0 equal c_area", "variable A0 equal ${A0}",
             f"fix tr all cgms/transport {PARAMS_FILE} layers 4 dt 10 adapt 0.02 600 "
             "outline no every 500",
             "variable s atom f_tr[1]", "fix fluid all cgms/fluid dryness v_s every 500",
             "run 25000", "run 0",
             'print "AREA $(c_area/v_A0:%.12g) X $(f_tr[3]:%.12g) BALANCE $(f_tr[7]:%.3e) '
             'STEPS $(f_tr[14])"',
             "write_dump all custom out.dump id f_tr[1] f_fluid[2] modify format float %.17g"]
    proc = run_lmp(tmp_path, "\n".join(lines) + "\n")
    words = next(line for line in proc.stdout.splitlines() if line.startswith("AREA")).split()
    area, moisture, balance, steps = (float(words[k]) for k in (1, 3, 5, 7))
    assert steps == 50                       # one moisture step every 500 MD steps
    assert moisture < 0.8                    # it dried
    assert area < 0.95                       # and shrank: the geometry moved
    assert abs(balance) < 1e-10
    dump = read_dump(tmp_path / "out.dump")
    assert dump["f_tr[1]"].min() < 0.9
    assert np.array_equal(dump["f_fluid[2]"], dump["f_tr[1]"])    # the dryness handed over


def test_until_ends_the_drying_there(tmp_path):
    """until T: the step that would pass T is cut short to end there (the end of cgms
    dry's --hours), and later MD steps make none; the cut step is the oracle's of the
    same length (10 fixed steps of 2 s and one of 1 s to T = 21 s)."""
    xy = jittered()
    rows, dump = lammps(tmp_path, xy, "layers 3 dt 2 heat no until 21", 14)
    last = rows[-1]
    assert last[1] == 21.0 and last[14] == 11          # drying time (s), moisture steps
    assert np.all(rows[-3:, 1] == 21.0)                 # no step after the end
    # the oracle's 10 steps of 2 s, then one of 1 s
    x10, *_ = oracle(xy, 10, 2.0, 3)
    x0 = read_params()["X0"]
    assert np.abs(nodes(dump) - x10 / x0).max() > 1e-6   # the cut step moved the field
    xs, *_ = oracle_tail(xy, x10)
    assert np.abs(nodes(dump) - xs / x0).max() < 1e-10


def oracle_tail(xy, x, dt=1.0, layers=3):
    """One step of ``dt`` from node moisture ``x`` (n, layers), as :func:`oracle` steps."""
    p = read_params()
    geo = transport.bead_geometry(xy, CUT)
    solids = p["solids_density"] * geo["area"] * 2e-3
    grid = transport.column_grid(geo, np.full(len(xy), 2e-3), solids, layers, 2)
    gab = (p["GAB_Xm"], p["GAB_C"], p["GAB_K"])
    kc, _ = transport.air_coefficients(70.0, 1.5, 0.04)
    law = transport.vapour_surface(kc, 70.0, 70.0, 0.1, gab)
    diff = lambda v: transport.diffusivity(v, 70.0, p["D_ref"], p["T_ref"], p["D_energy"],
                                           p["D_moisture"], p["X0"])
    x_new, *_ = transport.extrapolated_step(grid, np.ravel(x), dt, lambda v: (diff, law),
                                            outline=True)
    return (x_new.reshape(len(xy), layers),)


def test_bead_without_column_is_named(tmp_path):
    """A bead created after the fix's first run has no moisture column: an ERROR names it
    (not a zero row in the matrix)."""
    xy = jittered()
    tissue.write_data(tmp_path / "t.data", xy, 3 * A, overwrite=True)
    x, y = xy[0] - (A, 0.0)
    extra = f"create_atoms 1 single {x!r} {y!r} 0.0 units box\nrun 2\n"
    proc = run_lmp(tmp_path, script("", 2, dump=False) + extra, check=False)
    error = next((line for line in proc.stdout.splitlines() if "ERROR" in line), "")
    assert f"bead {len(xy) + 1} has no moisture column" in error, proc.stdout[-2000:]
