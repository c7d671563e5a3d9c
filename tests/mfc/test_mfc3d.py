# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The 3-D fine-model cell (doc/mfc.md, "3-D cell"): the icosphere wall, fix mfc/pressure3d
against a NumPy oracle and finite differences of its energy, Newton's third law, Laplace's
law for a free fresh cell, volume under rigid motion, 1 against 2 ranks, restart, and the
refusals."""

import math

import numpy as np
import pytest

from cgmstest import PLUGIN, new_lammps, read_dump, run_lmp, run_then_dump

from cgms.mfc import cell3d, model as mfc_model

P = mfc_model.parameters()
K, P_T = P["K"], P["P_f"]
EPS = np.finfo(float).eps


def tait(v, vf):
    """The Tait law on volume and its stored energy -int_{V_f}^{V} P dV (written here,
    independent of the fix)."""
    q = vf / v
    return P_T + K * (q ** 7 - 1), (K - P_T) * (v - vf) + K * vf / 6 * (q ** 6 - 1)


def open_cells(folder, centres, level=2, jitter=0.0, seed=1, extra=(), bending=True):
    data = folder / "cells.data"
    w = cell3d.write_data(data, centres, P, level=level, overwrite=True)
    lmp = new_lammps()
    lmp.commands_list(cell3d.commands(data, w, P, bending=bending))
    lmp.commands_list(list(extra))
    if jitter:
        lmp.command(f"displace_atoms all random {jitter} {jitter} {jitter} {seed} units box")
    return lmp, w


def state(lmp):
    lmp.command("run 0")
    n = lmp.get_natoms()
    x = np.array(lmp.gather_atoms("x", 1, 3)).reshape(n, 3)
    f = np.array(lmp.gather_atoms("f", 1, 3)).reshape(n, 3)
    return x, f, lmp.get_thermo("pe")


FIX_ONLY = ["bond_coeff * 0.0 1e-6", "dihedral_coeff 1 0.0 1 1"]


# --------------------------------------------------------------------------- the mesh

@pytest.mark.parametrize("level", [0, 1, 2, 3])
def test_icosphere_is_a_closed_outward_sphere(level):
    x, tri = cell3d.icosphere(level)
    edges, hinges = cell3d.edges_and_hinges(tri)
    assert len(x) == 10 * 4 ** level + 2
    assert len(x) - len(edges) + len(tri) == 2        # Euler: a sphere
    assert np.allclose(np.linalg.norm(x, axis=1), 1, atol=1e-15)
    v, grad = cell3d.volume(x, tri)
    assert 0 < v < 4 * math.pi / 3
    # the volume's gradient points outward at every vertex
    assert np.all(np.einsum("ij,ij->i", grad, x) > 0)
    assert len(hinges) == len(edges) and np.all(hinges[:, 0] != hinges[:, 3])


def test_icosphere_refuses_bad_levels_and_open_meshes():
    with pytest.raises(ValueError, match="integer 0..6"):
        cell3d.icosphere(1.5)
    _, tri = cell3d.icosphere(1)
    with pytest.raises(ValueError, match="closed surface"):
        cell3d.edges_and_hinges(tri[1:])


# --------------------------------------------------------------------------- the fix

@pytest.mark.lammps
def test_fix_force_is_p_dv_dx_and_minus_its_energy_gradient(tmp_path):
    """Forces of the fix alone (bonds, bending zeroed) on two jittered cells: equal to
    P dV/dx of the NumPy oracle (divergence-theorem volume), their energy to the Tait
    energy, and to minus the central difference of the energy; the fluid's force on its
    own wall sums to zero, and so does its torque."""
    centres = [(0, 0, 0), (2.2 * P["diameter"] / 2, 0.3e-4, 0)]
    lmp, w = open_cells(tmp_path, centres, level=2, jitter=6e-6, seed=3, extra=FIX_ONLY)
    try:
        x, f, pe = state(lmp)
        n = len(w["x"])
        energy, scale = 0.0, np.abs(f).max()
        for c in range(2):
            xc, fc = x[c * n:(c + 1) * n], f[c * n:(c + 1) * n]
            v, grad = cell3d.volume(xc, w["tri"])
            p, e = tait(v, w["fluid_volume"])
            energy += e
            assert lmp.numpy.extract_fix("cell", 0, 2, c, 0) == pytest.approx(v, rel=1e-12)
            assert lmp.numpy.extract_fix("cell", 0, 2, c, 1) == pytest.approx(p, rel=1e-9)
            assert abs(p - P_T) > 0.1 * P_T            # far from rest: the check has teeth
            assert np.abs(fc - p * grad).max() < 1e-12 * scale
            assert np.abs(fc.sum(axis=0)).max() < 1e-12 * np.abs(fc).sum()
            r = xc - xc.mean(axis=0)
            assert np.abs(np.cross(r, fc).sum(axis=0)).max() < 1e-12 * np.abs(fc).sum() * w["radius"]
        assert pe == pytest.approx(energy, rel=1e-10)
        h = 1e-9
        rng = np.random.default_rng(1)
        for i in rng.choice(len(f), 8, replace=False):
            for d in range(3):
                shift = [0.0, 0.0, 0.0]
                shift[d] = h
                lmp.command(f"group one id {i + 1}")
                lmp.command("displace_atoms one move {} {} {}".format(*shift))
                ep = state(lmp)[2]
                lmp.command("displace_atoms one move {} {} {}".format(*(-2 * s for s in shift)))
                em = state(lmp)[2]
                lmp.commands_list(["displace_atoms one move {} {} {}".format(*shift),
                                   "group one delete"])
                # central difference: truncation (h^2 f'''), rounding (eps E / h)
                assert abs(-(ep - em) / (2 * h) - f[i, d]) < 1e-6 * scale, (i, d)
    finally:
        lmp.close()


@pytest.mark.lammps
def test_volume_is_kept_by_a_rigid_motion(tmp_path):
    """Translated by 3 cell radii and turned by 37 degrees about a skew axis, the jittered
    cell encloses the same volume: to rounding of the ~1e3 triangle terms, whose size is
    set by the distance from the box centre (a few radii)."""
    lmp, w = open_cells(tmp_path, [(0, 0, 0)], level=3, jitter=3e-6)
    try:
        lmp.command("change_box all x final -1e-3 1e-3 y final -1e-3 1e-3 z final -1e-3 1e-3")
        v0 = (state(lmp), lmp.numpy.extract_fix("cell", 0, 2, 0, 0))[1]
        r = w["radius"]
        lmp.command(f"displace_atoms all move {3 * r} {-2 * r} {r} units box")
        v1 = (state(lmp), lmp.numpy.extract_fix("cell", 0, 2, 0, 0))[1]
        lmp.command(f"displace_atoms all rotate {r} {r} 0 1 2 3 37 units box")
        x, f, _ = state(lmp)
        v2 = lmp.numpy.extract_fix("cell", 0, 2, 0, 0)
        tol = 4 * len(w["tri"]) * EPS * 10
        assert abs(v1 - v0) < tol * v0 and abs(v2 - v0) < tol * v0
        # the rotated volume equals the oracle's of the rotated positions
        assert cell3d.volume(x, w["tri"])[0] == pytest.approx(v2, rel=1e-12)
    finally:
        lmp.close()


def relaxed(tmp_path, level, bending=True):
    """A free fresh cell, kicked, minimised to the force test; its bond tensions."""
    lmp, w = open_cells(tmp_path, [(0, 0, 0)], level=level, jitter=1e-7, bending=bending)
    try:
        lmp.commands_list(["thermo_style custom step pe fmax", "min_modify dmax 1e-7",
                           "minimize 0 1e-14 20000 100000"])
        x, f, _ = state(lmp)
        v, p, a = (lmp.numpy.extract_fix("cell", 0, 2, 0, k) for k in range(3))
    finally:
        lmp.close()
    e = w["edges"]
    length = np.linalg.norm(x[e[:, 1]] - x[e[:, 0]], axis=1)
    tension = w["k_bond"] * (length - w["rest"])
    return dict(x=x, fmax=np.abs(f).max(), volume=v, pressure=p, area=a, length=length,
                tension=tension, w=w)


@pytest.mark.lammps
@pytest.mark.parametrize("level,bending", [(2, True), (3, True), (3, False)])
def test_fresh_cell_obeys_laplace(tmp_path, level, bending):
    """Laplace's law for a free fresh cell. Exact for the mesh (virial of a uniform
    dilation, under which the dihedral angles do not change): sum T l = 3 P V, to the
    residual force sum |f.x|. With the wall tension of the net, gamma = sum T l / (2 A),
    and R = (3 V / 4 pi)^(1/3), that is P R / (2 gamma) = A / (4 pi R^2): Laplace's law
    P = 2 gamma / R up to the mesh's excess area over the sphere of its volume, which
    falls as h^2 (4x per level)."""
    c = relaxed(tmp_path, level, bending)
    v, p, a = c["volume"], c["pressure"], c["area"]
    virial = np.sum(c["tension"] * c["length"])
    residual = c["fmax"] * np.abs(c["x"] - c["x"].mean(axis=0)).sum()
    assert c["fmax"] < 1e-9 * p * a / len(c["x"])     # converged: 1e-9 of the turgor load
    assert abs(virial - 3 * p * v) <= 10 * residual + 1e-12 * virial
    radius = (3 * v / (4 * math.pi)) ** (1 / 3)
    gamma = virial / (2 * a)
    excess = a / (4 * math.pi * radius ** 2) - 1
    assert 0 < excess < {2: 5e-3, 3: 1.2e-3}[level]
    assert p * radius / (2 * gamma) - 1 == pytest.approx(excess, rel=1e-6, abs=1e-10)
    # the cell keeps its fluid's rest volume: P within the Tait law of P_T
    assert abs(v / c["w"]["fluid_volume"] - 1) < 0.05 * P_T / K


# --------------------------------------------------------------------------- ranks, restart

def cells_script(nprocs=1, newton="on", steps=200, restart=None, read=None):
    """Two jittered cells under damped dynamics, straddling the middle of the box."""
    w = cell3d.wall(P, 2)
    lines = [f"plugin load {PLUGIN}"]
    setup = cell3d.commands("cells.data", w, P, newton=newton,
                            processors="2 1 1" if nprocs > 1 else None)
    if read:
        lines += ["units si", "dimension 3", f"newton {newton}", "atom_modify map array",
                  f"read_restart {read}", "angle_coeff *"]
        lines += [s for s in setup if s.split()[0] in ("neighbor", "neigh_modify",
                                                     "comm_modify", "fix", "fix_modify")]
    else:
        lines += setup + ["displace_atoms all random 2e-6 2e-6 2e-6 11 units box"]
    lines += ["fix nve all nve", "fix damp all viscous 1e-9", "timestep 2e-9",
              "thermo_style custom step pe ke f_cell[3]", "thermo 50"]
    return "\n".join(lines + run_then_dump(steps, restart)) + "\n"


def cells_folder(path):
    r = P["diameter"] / 2
    # side by side along y, the box split along x: both cells straddle the two ranks
    cell3d.write_data(path / "cells.data", [(0, 0, 0), (0.3 * r, 2.2 * r, 0)], P,
                      level=2, overwrite=True)
    return path


@pytest.mark.mpi
def test_one_and_two_ranks_agree(tmp_path_factory):
    """Forces at the start (run 0 of the kicked cells) and positions after 200 steps agree
    on 1 and 2 ranks (newton_bond on and off): the cells straddle the ranks' boundary, so
    triangles and dihedrals cross it. Forces sum the same terms in another order; the
    positions after 200 steps of damped dynamics differ by what that rounding grows to."""
    runs = {}
    for name, nprocs, newton in (("np1", 1, "on"), ("np2", 2, "on"), ("np2off", 2, "off")):
        folder = cells_folder(tmp_path_factory.mktemp(name))
        script = cells_script(nprocs, newton).replace(
            "fix nve all nve", "run 0\nwrite_dump all custom start.dump id fx fy fz modify "
            "sort id format float %.17g\nfix nve all nve")
        run_lmp(folder, script, nprocs=nprocs)
        runs[name] = read_dump(folder / "start.dump"), read_dump(folder / "final.dump")
    (s1, f1) = runs["np1"]
    fscale = max(np.abs(s1[k]).max() for k in ("fx", "fy", "fz"))
    assert np.hypot(f1["vx"], f1["vy"]).max() > 0
    for name in ("np2", "np2off"):
        s2, f2 = runs[name]
        for k in ("fx", "fy", "fz"):
            assert np.abs(s1[k] - s2[k]).max() < 1e-12 * fscale, (name, k)
        for k in ("x", "y", "z"):
            assert np.abs(f1[k] - f2[k]).max() < 1e-9 * P["diameter"], (name, k)


@pytest.mark.lammps
def test_restart_continues_the_run(tmp_path_factory):
    """The fix holds no state (the volume comes from the positions every step): a run
    continued from a restart file, with the fix defined again, ends where the
    uninterrupted one does."""
    a = cells_folder(tmp_path_factory.mktemp("straight"))
    b = cells_folder(tmp_path_factory.mktemp("restart"))
    run_lmp(a, cells_script(steps=200, restart="half.restart"))
    (b / "half.restart").write_bytes((a / "half.restart").read_bytes())
    run_lmp(b, cells_script(steps=100, read="half.restart"))
    straight, resumed = read_dump(a / "final.dump"), read_dump(b / "final.dump")
    for k in ("x", "y", "z"):
        assert np.abs(straight[k] - resumed[k]).max() < 1e-12 * P["diameter"]


# --------------------------------------------------------------------------- refusals

def refused(tmp_path, edit=None, after=(), before=()):
    folder = cells_folder(tmp_path)
    if edit:
        text = (folder / "cells.data").read_text()
        (folder / "cells.data").write_text(edit(text))
    w = cell3d.wall(P, 2)
    lines = [f"plugin load {PLUGIN}", *before] + cell3d.commands("cells.data", w, P)
    lines += list(after) + ["run 0"]
    proc = run_lmp(folder, "\n".join(lines) + "\n", check=False)
    assert proc.returncode != 0
    return (proc.stdout + proc.stderr).replace("\n", " ")


def drop_angle(text):
    head, tail = text.split("\nAngles\n\n")
    rows = tail.split("\n")
    return head + "\nAngles\n\n" + "\n".join(rows[1:])


def flip_angles(text):
    head, tail = text.split("\nAngles\n\n")
    angles, rest = tail.split("\n\nDihedrals\n\n")
    rows = [r.split() for r in angles.split("\n")]
    flipped = "\n".join(f"{r[0]} {r[1]} {r[4]} {r[3]} {r[2]}" for r in rows)
    return head + "\nAngles\n\n" + flipped + "\n\nDihedrals\n\n" + rest


@pytest.mark.lammps
@pytest.mark.parametrize("case,message", [
    ("open", "is not closed"),
    ("clockwise", "encloses volume"),
    ("periodic", "needs non-periodic boundaries"),
    ("keyword", "needs the keyword volume"),
])
def test_fix_refuses_bad_walls_and_input(tmp_path, case, message):
    if case == "open":
        out = refused(tmp_path, edit=lambda t: drop_angle(t).replace(
            f"{2 * 320} angles", f"{2 * 320 - 1} angles"))
    elif case == "clockwise":
        out = refused(tmp_path, edit=flip_angles)
    elif case == "periodic":
        out = refused(tmp_path, after=["change_box all boundary p f f"])
    else:
        out = refused(tmp_path, after=["unfix cell", "fix bad all mfc/pressure3d modulus 2e7 "
                                       "turgor 2e5"])
    assert "ERROR" in out and message in out, out[-2000:]


@pytest.mark.lammps
def test_fix_mfc_pressure3d_example_runs_as_written(tmp_path):
    """The Examples of doc/fix_mfc_pressure3d.rst: the Python block writes the cell, the
    LAMMPS block (its plugin path made this build's, its volume the builder's) minimises
    it to a steady state."""
    from errors.test_mfc_styles_errors import example_script
    script = example_script("doc/fix_mfc_pressure3d.rst", tmp_path)
    w = cell3d.wall(P, 3)
    assert f"volume {w['fluid_volume']:.15e}" in script
    proc = run_lmp(tmp_path, script + '\nprint "FMAX $(fmax:%.17g)"\n')
    fmax = float(proc.stdout.split("FMAX ")[1].split()[0])
    assert fmax < 1e-9 * P_T * cell3d.area(w["x"], w["tri"]) / len(w["x"])
