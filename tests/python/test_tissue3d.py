# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""3-D tissues (cgms.tissue3d, ``cgms tissue slab|block|cylinder``): BCC neighbours and
Kelvin cells, cell volumes tiling the body, surface cells, the data file read by LAMMPS
with ``dimension 3``, and the one-line refusals."""

import math

import numpy as np
import pytest

from cgmstest import PLUGIN, read_dump, run_cli, run_lmp

from cgms import material, tissue3d

A = tissue3d.cube_edge(material.read("apple")["diameter"])
KELVIN = A ** 3 / 2


def depth(t):
    """Each bead's distance inside the body (smallest over its faces)."""
    p = t["body"]["planes"]
    return -np.max(t["x"] @ p[:, :3].T + p[:, 3], axis=1)


@pytest.mark.parametrize("body", [tissue3d.box(1.2e-3, 1.0e-3, 0.9e-3),
                                  tissue3d.cylinder(0.6e-3, 0.8e-3)], ids=["block", "cylinder"])
@pytest.mark.parametrize("jitter", [0.0, 0.15])
def test_cells_tile_the_body_and_deep_cells_are_kelvin_cells(body, jitter):
    t = tissue3d.build(body, A, jitter, seed=4)
    n = len(t["x"])
    assert n > 50
    # the clipped Voronoi cells tile the body: volumes sum to it (rounding of n hulls),
    # their free faces to its surface
    assert abs(t["volume"].sum() / body["volume"] - 1) < 1e-12 * n
    # neighbours are mutual
    assert all(i in t["neighbours"][j] for i, js in enumerate(t["neighbours"]) for j in js)
    deep = depth(t) > 1.26 * A          # every lattice neighbour present (fill inset a/4)
    assert deep.sum() > 5 and not t["surface"][deep].any()
    counts = np.array([len(v) for v in t["neighbours"]])
    if jitter == 0:
        # BCC: 14 neighbours (8 at sqrt(3) a/2, 6 at a), a truncated octahedron of a^3/2
        # whose area is (6 + 12 sqrt 3) (a/(2 sqrt 2))^2
        assert np.all(counts[deep] == 14)
        assert np.allclose(t["volume"][deep], KELVIN, rtol=1e-12)
        edge = A / (2 * math.sqrt(2))
        assert np.allclose(t["area"][deep], (6 + 12 * math.sqrt(3)) * edge ** 2, rtol=1e-12)
        for i in np.flatnonzero(deep)[:5]:
            d = np.sort(np.linalg.norm(t["x"][t["neighbours"][i]] - t["x"][i], axis=1))
            assert np.allclose(d, [math.sqrt(3) * A / 2] * 8 + [A] * 6, rtol=1e-12)
    else:
        assert t["volume"][deep].std() > 0.01 * KELVIN     # jitter makes volumes differ
    # surface cells: exactly those with a free face, and together they cover the surface
    assert np.all(t["surface"] == (t["free"] > 0))
    assert np.all(t["surface"][depth(t) < 0.3 * A])


def test_box_surface_area_and_slab_layers():
    body = tissue3d.box(1e-3, 1e-3, 0.6e-3, kind="slab")
    t = tissue3d.build(body, A)
    assert t["free"].sum() == pytest.approx(2 * 1e-6 + 4 * 0.6e-6, rel=1e-12)
    layers = np.unique(np.round(t["x"][:, 2] / A, 9))
    assert len(layers) == math.floor(2 * 0.6e-3 / A)           # floor(2 T / a)
    assert np.all(depth(t) >= A / 4 * (1 - 1e-9))


def test_builder_refuses_impossible_sizes():
    with pytest.raises(ValueError, match="holds 0 bead"):
        tissue3d.build(tissue3d.box(1e-3, 1e-3, 0.4 * A, kind="slab"), A)
    with pytest.raises(ValueError, match="in one plane"):
        tissue3d.build(tissue3d.box(1e-3, 1e-3, 0.9 * A, kind="slab"), A)
    with pytest.raises(ValueError, match="jitter"):
        tissue3d.bcc(tissue3d.box(1e-3, 1e-3, 1e-3), A, jitter=0.3)
    with pytest.raises(ValueError, match="positive"):
        tissue3d.box(1e-3, -1e-3, 1e-3)


@pytest.mark.parametrize("args,message", [
    (["slab", "1", "1", "0.05"], "holds 0 bead(s)"),
    (["slab", "1", "1", "0.1"], "in one plane"),
    (["block", "100", "100", "100"], "limit"),
    (["cylinder", "0.5", "-1"], "height must be positive"),
    (["block", "1", "1", "1", "--jitter", "0.5"], "--jitter must be in"),
])
def test_cli_refuses_in_one_line(tmp_path, capsys, args, message):
    status, err, out = run_cli(capsys, "tissue", *args, "--out", str(tmp_path / "t.data"))
    assert status == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "t.data").exists()


@pytest.mark.lammps
def test_data_file_is_read_by_lammps_in_3d(tmp_path, capsys):
    out = tmp_path / "slab.data"
    status, err, text = run_cli(capsys, "tissue", "slab", "0.8", "0.9", "0.5", "--jitter",
                                "0.1", "--cv", "0.15", "--seed", "2", "--out", str(out))
    assert status == 0, err
    read = text.split("read with: ")[1].rstrip(")\n").split("; ")
    nb = int(read[4].split()[-1])
    script = [f"plugin load {PLUGIN}", "units si"] + [
        line.replace(str(out), "slab.data") for line in read]
    props = " ".join(f"i2_nb3d[{k}]" for k in range(1, nb + 1))
    script += [f"write_dump all custom read.dump id x y z i_surface3d d_volume3d d_free3d "
               f"d_diameter {props} modify sort id format float %.17g"]
    run_lmp(tmp_path, "\n".join(script) + "\n")
    d = read_dump(tmp_path / "read.dump")
    body = tissue3d.box(0.8e-3, 0.9e-3, 0.5e-3)
    t = tissue3d.build(body, A, 0.1, seed=2)
    assert len(d["id"]) == len(t["x"])
    assert np.allclose(np.c_[d["x"], d["y"], d["z"]], t["x"], rtol=0, atol=1e-18)
    assert np.array_equal(d["i_surface3d"], t["surface"].astype(int))
    assert np.allclose(d["d_volume3d"], t["volume"], rtol=1e-14)
    assert d["d_volume3d"].sum() == pytest.approx(body["volume"], rel=1e-12)
    for i, js in enumerate(t["neighbours"]):
        row = [d[f"i2_nb3d[{k}]"][i] for k in range(1, nb + 1)]
        assert sorted(v for v in row if v) == [j + 1 for j in js]
    assert np.all(d["d_diameter"] > 0)
