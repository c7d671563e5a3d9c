# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The 3-D fine-model tissue (doc/mfc.md, "3-D tissue"): the triangulated truncated
octahedron and its facing walls, the lamella set at rest in the fresh state, single dried
cells against the equation of state and the virial, conservation, 1 against 2 ranks,
restart, the drying study's files and refusals."""

import json
import math

import numpy as np
import pytest

from cgmstest import PLUGIN, new_lammps, read_dump, run_lmp, run_then_dump

from cgms.mfc import cell3d, model as mfc_model, run3d, study3d, tissue3d

P = mfc_model.parameters()
K = P["K"]
D = P["diameter"]


# --------------------------------------------------------------------------- the mesh

@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_polyhedron_is_a_closed_outward_centrosymmetric_kelvin_cell(n):
    x, tri = tissue3d.polyhedron(n)
    edges, _ = cell3d.edges_and_hinges(tri)
    assert len(x) == 36 * n * n + 2 and len(tri) == 72 * n * n
    assert len(x) - len(edges) + len(tri) == 2
    v, grad = cell3d.volume(x, tri)
    assert v == pytest.approx(0.5, rel=1e-14)           # a BCC cell of a unit cube
    assert np.all(np.einsum("ij,ij->i", grad, x) > 0)
    # the node set is its own mirror through the centre: facing walls carry facing nodes
    key = {tuple(np.rint(p * 4 * n).astype(int)) for p in x}
    assert key == {tuple(np.rint(-p * 4 * n).astype(int)) for p in x}
    with pytest.raises(ValueError, match="integer 1..12"):
        tissue3d.polyhedron(0)


def test_built_walls_face_each_other_across_the_gap():
    """Every node of a shared hexagonal face has a node of the neighbour d_p away along the
    face normal (3 n (n + 1) + 1 of them), of a square face 2 d_p / sqrt(3) away
    (2 n (n + 1) + 1); the fluid's rest volume is the built wall's, pi D^3 / 6."""
    n = 3
    centres = tissue3d.block(P, 2)
    assert len(centres) == 16
    x, cell, w = tissue3d.walls(centres, P, n)
    assert w["mesh_volume"] == pytest.approx(w["fluid_volume"], rel=1e-13)
    assert w["fluid_volume"] == pytest.approx(math.pi * D ** 3 / 6, rel=1e-14)
    a = tissue3d.lattice_edge(P)
    for gap, count, step in ((P["pectin"], 3 * n * (n + 1) + 1, np.array([1, 1, 1]) / 2),
                             (2 * P["pectin"] / math.sqrt(3), 2 * n * (n + 1) + 1,
                              np.array([1, 0, 0]))):
        i = np.nonzero(np.all(np.isclose(centres, centres[0] + step * a, atol=1e-12), 1))[0]
        assert len(i) == 1
        mine, theirs = x[cell == 0], x[cell == i[0]]
        d = np.linalg.norm(mine[:, None] - theirs[None], axis=2)
        near = np.argwhere(np.abs(d - gap) < 1e-12 * D)
        assert len(near) == count
        normal = step / np.linalg.norm(step)
        assert np.allclose((theirs[near[:, 1]] - mine[near[:, 0]]) @ normal, gap, atol=1e-12 * D)
    pairs = tissue3d.lamella_pairs(x, cell, w, P)
    assert len(pairs) and np.all(cell[pairs[:, 0]] != cell[pairs[:, 1]])


def test_intrusions_find_a_particle_inside_another_wall():
    """The built block has no wall particle inside another cell; one moved to a
    neighbour's centre is found, and only that one."""
    centres = tissue3d.block(P, 2)
    x, cell, w = tissue3d.walls(centres, P, 2)
    assert run3d.intrusions(x, w) == []
    moved = x.copy()
    moved[5] = centres[3]
    assert run3d.intrusions(moved, w) == [(5, 3)]


# --------------------------------------------------------------------------- single cells

def free_cell(tmp_path, levels, n=2):
    """One free cell dried along the ramp to each level of ``levels``; per level its
    positions, forces, volume, pressure and the bond tensions."""
    data = tmp_path / "cell.data"
    x, cell, w = tissue3d.write_data(data, [(0.0, 0.0, 0.0)], P, n=n, overwrite=True)
    lmp = new_lammps()
    out = {}
    try:
        lmp.commands_list(run3d.setup_commands(data, w))
        previous = 1.0
        for s in levels:
            run3d.kick(lmp, 1e-7, 7 + round(1e4 * s))
            for stage in study3d.stages(previous, s):
                run3d.relax(lmp, P, w, stage, max_iterations=2000)
            r = run3d.relax(lmp, P, w, s, max_iterations=20000)
            xs = run3d.positions(lmp)
            f = np.array(lmp.gather_atoms("f", 1, 3)).reshape(-1, 3)
            v, p = (lmp.numpy.extract_fix("cell", 0, 2, 0, k) for k in range(2))
            e = w["edges"]
            length = np.linalg.norm(xs[e[:, 1]] - xs[e[:, 0]], axis=1)
            rest = w["rest_classes"][w["bond_type"] - 1] * mfc_model.level(P, s)["contraction"]
            out[s] = dict(x=xs, f=f, volume=v, pressure=p, length=length,
                          tension=w["k_bond"] * (length - rest), result=r)
            previous = s
    finally:
        lmp.close()
    return out, w


@pytest.mark.lammps
def test_fresh_free_cell_holds_the_turgor(tmp_path):
    """Laplace's law for the tissue's wall: the free fresh cell (n = 2), bending off, at
    rest, holds its fluid at P_T: the pre-stress was found for that, to 1e-5, on a
    relaxation of the same energy outside LAMMPS; LAMMPS's force test (1e-10 N, of a
    turgor load of 7e-5 N per particle) adds about 1e-6. With bending, the dihedrals (flat
    at rest, bent on the round cell) move it by a few 1e-3 (measured -4.3e-3 here, -8e-3
    at n = 5). The virial sum T l = 3 P V holds either way."""
    for bending, tol in ((False, 1e-4), (True, 1e-2)):
        data = tmp_path / "cell.data"
        x, cell, w = tissue3d.write_data(data, [(0.0, 0.0, 0.0)], P, n=2, overwrite=True)
        lmp = new_lammps()
        try:
            lmp.commands_list(run3d.setup_commands(data, w))
            if not bending:
                lmp.command("dihedral_coeff 1 0.0 1 1")
            run3d.kick(lmp, 1e-7, 5)
            r = run3d.relax(lmp, P, w, 1.0)
            xs = run3d.positions(lmp)
            v, p = (lmp.numpy.extract_fix("cell", 0, 2, 0, k) for k in range(2))
        finally:
            lmp.close()
        assert r["converged"]
        assert abs(p / P["P_f"] - 1) < tol, bending
        e = w["edges"]
        length = np.linalg.norm(xs[e[:, 1]] - xs[e[:, 0]], axis=1)
        tension = w["k_bond"] * (length - w["rest_classes"][w["bond_type"] - 1])
        assert np.sum(tension * length) == pytest.approx(3 * p * v, rel=1e-5)


@pytest.mark.lammps
def test_single_dried_cells_follow_their_fluid(tmp_path):
    """A free cell, fresh and dried to s = 0.8 and 0.3: at rest (largest force below the
    solver's 1e-10 N); its volume is its fluid's, s V_f, at the pressure the equation of
    state gives, V = s V_f (1 + (P - s P_T) / K)^(-1/7) (to rounding); within 2 % of s V_f
    (the fluid is nearly incompressible); and the virial of a uniform dilation, under which
    the dihedral angles do not change, sum T l = 3 P V, to the residual force's share. The
    dried wall has folded: its area is above the sphere's of that volume."""
    levels = (1.0, 0.8, 0.3)
    cells, w = free_cell(tmp_path, levels)
    for s in levels:
        c = cells[s]
        v, p = c["volume"], c["pressure"]
        assert c["result"]["converged"] and np.abs(c["f"]).max() < 1e-10
        vf = s * w["fluid_volume"]
        turgor = s * P["P_f"]
        assert v == pytest.approx(vf * (1 + (p - turgor) / K) ** (-1 / 7), rel=1e-12)
        assert abs(v / vf - 1) < 0.02
        assert cell3d.volume(c["x"], w["tri"])[0] == pytest.approx(v, rel=1e-12)
        virial = np.sum(c["tension"] * c["length"])
        r = c["x"] - c["x"].mean(axis=0)
        residual = np.abs(c["f"]).max() * np.abs(r).sum()
        assert abs(virial - 3 * p * v) <= 3 * residual + 1e-12 * abs(virial), s
    sphere = (36 * math.pi * (0.3 * w["fluid_volume"]) ** 2) ** (1 / 3)
    assert cell3d.area(cells[0.3]["x"], w["tri"]) > 1.2 * sphere


# --------------------------------------------------------------------------- two glued cells

def glued_pair(folder, n=2):
    """Two cells of the 1-cube block (hexagonal-face neighbours), the lamella set at rest
    in the built walls."""
    centres = tissue3d.block(P, 1)
    x, cell, w = tissue3d.walls(centres, P, n)
    lamella = tissue3d.fresh_lamella(x, cell, w, P)
    tissue3d.write_data(folder / "pair.data", centres, P, n=n, lamella=lamella,
                        overwrite=True)
    return w, lamella


def pair_script(w, nprocs=1, newton="on", steps=200, restart=None, read=None,
                damp=True, start_dump=False):
    """The glued pair at s = 0.8 (so the walls and fluid pull), kicked, under dynamics."""
    setup = run3d.setup_commands("pair.data", w, newton=newton,
                                 processors="2 1 1" if nprocs > 1 else None)
    lines = [f"plugin load {PLUGIN}"]
    if read:
        lines += ["units si", "dimension 3", f"newton {newton}", "atom_modify map array",
                  f"read_restart {read}", "angle_coeff *", *run3d.pair_commands(w)]
        lines += [s for s in setup if s.split()[0] in ("neigh_modify", "neighbor",
                                                     "comm_modify")]
        lines += [s for s in run3d.level_commands(P, w, 0.8) if s.startswith("fix")]
    else:
        lines += setup + run3d.level_commands(P, w, 0.8)
        lines += ["displace_atoms all random 1e-6 1e-6 1e-6 11 units box"]
    if start_dump:
        lines += ["run 0", "write_dump all custom start.dump id fx fy fz modify sort id "
                  "format float %.17g"]
    lines += ["fix nve all nve", "timestep 1e-9",
              "thermo_style custom step pe ke", "thermo 50"]
    if damp:
        lines.insert(-3, "fix damp all viscous 1e-9")
    return "\n".join(lines + run_then_dump(steps, restart)) + "\n"


@pytest.mark.lammps
def test_glued_pair_conserves_momentum_particles_and_fluid(tmp_path):
    """Without damping the glued pair's total momentum and angular momentum stay what they
    started as (zero), to the rounding of the forces' sum (each force pair and each cell's
    fluid forces sum to zero, and so do their torques), every particle stays, and each
    cell's fluid rest volume is s times fresh."""
    w, lamella = glued_pair(tmp_path)
    proc = run_lmp(tmp_path, pair_script(w, damp=False, steps=400))
    final = read_dump(tmp_path / "final.dump")
    m = len(w["x"])
    assert len(final["id"]) == 2 * m
    assert np.array_equal(final["mol"], np.repeat([1, 2], m))
    p = np.array([final[k] for k in ("vx", "vy", "vz")])
    scale = np.abs(p).sum()
    assert scale > 0 and np.abs(p.sum(axis=1)).max() < 1e-10 * scale
    r = np.array([final[k] for k in ("x", "y", "z")])
    r = r - r.mean(axis=1)[:, None]                  # one mass: the centre of mass
    spin = np.cross(r.T, p.T)
    assert np.abs(spin.sum(axis=0)).max() < 1e-10 * np.abs(spin).sum()
    fluid = [s for s in run3d.level_commands(P, w, 0.8) if "mfc/pressure3d" in s][0]
    assert float(fluid.split("volume")[1]) == pytest.approx(0.8 * math.pi * D ** 3 / 6,
                                                            rel=1e-14)
    assert "ERROR" not in proc.stdout and len(lamella[0]) > 0


@pytest.mark.mpi
def test_one_and_two_ranks_agree(tmp_path_factory):
    """The glued pair, split across two ranks (lamella bonds, triangles and dihedrals
    cross the boundary): forces at the start agree to summation order (1e-12), positions
    after 200 damped steps to what that rounding grows to (1e-9 D), newton on and off."""
    runs = {}
    for name, nprocs, newton in (("np1", 1, "on"), ("np2", 2, "on"), ("np2off", 2, "off")):
        folder = tmp_path_factory.mktemp(name)
        w, _ = glued_pair(folder)
        run_lmp(folder, pair_script(w, nprocs, newton, start_dump=True), nprocs=nprocs)
        runs[name] = read_dump(folder / "start.dump"), read_dump(folder / "final.dump")
    s1, f1 = runs["np1"]
    fscale = max(np.abs(s1[k]).max() for k in ("fx", "fy", "fz"))
    assert np.abs(f1["vx"]).max() > 0
    for name in ("np2", "np2off"):
        s2, f2 = runs[name]
        for k in ("fx", "fy", "fz"):
            assert np.abs(s1[k] - s2[k]).max() < 1e-12 * fscale, (name, k)
        for k in ("x", "y", "z"):
            assert np.abs(f1[k] - f2[k]).max() < 1e-9 * D, (name, k)


@pytest.mark.lammps
def test_restart_continues_the_run(tmp_path_factory):
    """A run continued from a restart file (bonds, their coefficients and the lamella in
    it; the fix, pair and angle coefficients given again) ends where the uninterrupted one
    does."""
    a, b = tmp_path_factory.mktemp("straight"), tmp_path_factory.mktemp("restart")
    w, _ = glued_pair(a)
    glued_pair(b)
    run_lmp(a, pair_script(w, steps=200, restart="half.restart"))
    (b / "half.restart").write_bytes((a / "half.restart").read_bytes())
    run_lmp(b, pair_script(w, steps=100, read="half.restart"))
    straight, resumed = read_dump(a / "final.dump"), read_dump(b / "final.dump")
    for k in ("x", "y", "z"):
        assert np.abs(straight[k] - resumed[k]).max() < 1e-12 * D


# --------------------------------------------------------------------------- the study

@pytest.mark.lammps
def test_study_dries_a_glued_pair(tmp_path):
    """``cgms.mfc.study3d`` on the two-cell block (n = 5, the study's mesh: at n = 2 the
    walls pass through each other and the study stops, test_mfc3d_crossing.py), levels 1
    and 0.8: every level at rest, no particle inside the other cell's wall, the cells'
    volume their fluid's, a wall dump per level; the lamella bonds set between
    different cells, each at its fresh length (within the 10 nm bin); a second run into the
    same folder refused with one line."""
    out = tmp_path / "pair"
    res = study3d.dry(out, P, cubes=1, n=5, levels=(1.0, 0.8), say=lambda *a: None)
    assert [r["s"] for r in res] == [1.0, 0.8]
    w = tissue3d.wall(P, 5)
    assert json.loads((out / "setup.json").read_text())["self_avoidance"] == dict(
        radius=w["self_r0"], E0=w["self_E0"], special=list(tissue3d.SELF_SPECIAL))
    for r in res:
        assert r["converged"] and r["fmax"] < 1e-10 and r["intrusions"] == 0
        assert abs(r["cell_volume_over_fluid"] - 1) < 0.02
        dump = (out / f"walls.s{r['s']:g}.dump").read_text().splitlines()
        assert dump[3] == "1804" and dump[8].split() == ["ITEM:", "ATOMS", "id", "mol", "x",
                                                         "y", "z"]
    assert res[1]["volume"] < res[0]["volume"]
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[0].split(",") == list(study3d.SUMMARY) and len(summary) == 3
    cells = np.loadtxt(out / "cells.s0.8.csv", delimiter=",", skiprows=1)
    assert cells.shape == (2, 6)
    fresh = np.loadtxt(out / "cells.s1.csv", delimiter=",", skiprows=1)
    # the fresh state relaxed from the built one, whose fluid rest volume it keeps
    x, cell, w = tissue3d.walls(tissue3d.block(P, 1), P, 5)
    assert np.allclose(fresh[:, 4], w["fluid_volume"], rtol=0.02)
    text = (out / "lamella.data").read_text()
    atoms = text.split("\nAtoms # molecular\n\n")[1].split("\n\n")[0].splitlines()
    xf = np.array([[float(v) for v in r.split()[3:6]] for r in atoms])
    mol = np.array([int(r.split()[1]) for r in atoms])
    bonds = text.split("\nBonds\n\n")[1].split("\n\n")[0].splitlines()
    bonds = np.array([[int(v) for v in r.split()[1:4]] for r in bonds])
    glue = bonds[bonds[:, 0] > len(w["rest_classes"])]
    assert len(glue) > 0 and np.all(mol[glue[:, 1] - 1] != mol[glue[:, 2] - 1])
    rest = np.loadtxt(out / "lamella.txt")
    rest = dict(zip(rest[:, 0].astype(int), rest[:, 1]))
    d = np.linalg.norm(xf[glue[:, 1] - 1] - xf[glue[:, 2] - 1], axis=1)
    binned = np.array([rest[t] for t in glue[:, 0]])
    assert np.abs(d - binned).max() <= tissue3d.REST_BIN / 2 * 1.0001
    with pytest.raises(SystemExit, match="cgms mfc3d: .*exists"):
        study3d.main([str(out), "--cubes", "1", "--subdivision", "2", "--levels", "1"])


@pytest.mark.mpi
def test_minimised_state_agrees_on_one_and_two_ranks(tmp_path_factory):
    """The glued pair at s = 0.8 minimised to the force test (largest force below 1e-10 N)
    on 1 and 2 ranks (newton on and off) reaches the same state: the runs may stop anywhere
    within the force test, a distance of at most ftol over the softest stiffness of a wall
    node, that of bending, K_dihedral / l^2 (the shortest edge l); the cell volumes then
    within 3 times that over the cell radius."""
    runs = {}
    for name, nprocs, newton in (("np1", 1, "on"), ("np2", 2, "on"), ("np2off", 2, "off")):
        folder = tmp_path_factory.mktemp(name)
        w, _ = glued_pair(folder)
        lines = [f"plugin load {PLUGIN}"] + run3d.setup_commands(
            "pair.data", w, newton=newton, processors="2 1 1" if nprocs > 1 else None)
        lines += run3d.level_commands(P, w, 0.8)
        lines += ["displace_atoms all random 1e-7 1e-7 1e-7 11 units box",
                  "min_style cg", "min_modify norm max dmax 1e-7 line quadratic",
                  "minimize 0 1e-10 20000 200000", 'print "FMAX $(fmax:%.17g)"',
                  "write_dump all custom final.dump id x y z modify sort id "
                  "format float %.17g"]
        proc = run_lmp(folder, "\n".join(lines) + "\n", nprocs=nprocs)
        assert float(proc.stdout.split("FMAX ")[-1].split()[0]) < 1e-10
        d = read_dump(folder / "final.dump")
        x = np.c_[d["x"], d["y"], d["z"]]
        runs[name] = x, run3d.cells(x, w)["volume"]
    shortest = w["rest_classes"].min()
    reach = 1e-10 / (w["k_dihedral"] / shortest ** 2)
    x1, v1 = runs["np1"]
    for name in ("np2", "np2off"):
        x2, v2 = runs[name]
        assert np.abs(x1 - x2).max() < reach, name
        assert np.abs(v2 / v1 - 1).max() < 3 * reach / w["radius"], name
