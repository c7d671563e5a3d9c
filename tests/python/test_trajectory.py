# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""cgms.trajectory: the tissue shape in every frame of a dump that LAMMPS wrote with the
plugin, read with MDAnalysis, against the same frames parsed here as plain text."""

import numpy as np
import pytest

from cgmstest import header, make_tissue, physics, run_lmp
from cgms import morphology, trajectory

EVERY, STEPS = 500, 3000


@pytest.fixture(scope="module")
def drying_run(tmp_path_factory):
    """A 90-bead tissue drying at s = 0.5 from the fresh lattice, dumped as text with and
    without z, unsorted (dump custom writes beads in the order they are stored)."""
    folder = tmp_path_factory.mktemp("trajectory")
    make_tissue(folder, jitter=0.02, seed=4, s=0.5)
    run_lmp(folder, header() + physics() + "\n".join([
        f"dump text all custom {EVERY} traj.dump id type x y z vx vy",
        f"dump flat all custom {STEPS} flat.dump id x y",
        f"run {STEPS}",
    ]) + "\n")
    return folder


def text_frames(path):
    """(step, xy sorted by id) of every frame, parsed without MDAnalysis."""
    lines = path.read_text().splitlines()
    frames = []
    for i, line in enumerate(lines):
        if line.startswith("ITEM: TIMESTEP"):
            step, n = int(lines[i + 1]), int(lines[i + 3])
            cols = lines[i + 8].split()[2:]
            rows = np.array([[float(w) for w in r.split()] for r in lines[i + 9:i + 9 + n]])
            rows = rows[np.argsort(rows[:, cols.index("id")])]
            frames.append((step, rows[:, [cols.index("x"), cols.index("y")]]))
    return frames


def test_shapes_of_every_frame_match_the_text(drying_run):
    frames = text_frames(drying_run / "traj.dump")
    assert [s for s, _ in frames] == list(range(0, STEPS + 1, EVERY))
    want = [morphology.measures(xy) for _, xy in frames]
    got = trajectory.shapes(trajectory.universe(drying_run / "traj.dump"))
    assert got["step"].tolist() == [s for s, _ in frames]
    for key in ("area", "perimeter", "elongation"):
        # MDAnalysis keeps float32 positions: 6e-8 relative
        np.testing.assert_allclose(got[key], [m[key] for m in want], rtol=1e-6, err_msg=key)
    np.testing.assert_allclose(got["A/A0"], [m["area"] / want[0]["area"] for m in want],
                               rtol=1e-6)
    # the run dries the tissue: its area falls from frame to frame
    assert np.all(np.diff(got["area"]) < 0), got["area"]
    assert got["A/A0"][-1] < 0.99


def test_fresh_reference_and_frame_slices(drying_run):
    u = trajectory.universe(drying_run / "traj.dump")
    every = trajectory.shapes(u)
    fresh = morphology.measures(text_frames(drying_run / "traj.dump")[1][1])
    part = trajectory.shapes(u, fresh=fresh, start=1, step=2)
    assert part["step"].tolist() == every["step"][1::2].tolist()
    np.testing.assert_allclose(part["area"], every["area"][1::2], rtol=1e-12)
    np.testing.assert_allclose(part["A/A0"], every["area"][1::2] / fresh["area"], rtol=1e-6)
    assert part["A/A0"][0] == pytest.approx(1.0, rel=1e-6)    # frame 1 is the reference


def test_the_data_file_as_topology(drying_run):
    text = trajectory.shapes(trajectory.universe(drying_run / "traj.dump"))
    with_data = trajectory.universe(drying_run / "traj.dump", topology=drying_run / "tissue.data")
    assert len(with_data.atoms) == 90
    got = trajectory.shapes(with_data)
    for key in ("step", "area", "perimeter", "elongation"):
        np.testing.assert_allclose(got[key], text[key], rtol=1e-12, err_msg=key)


def test_a_dump_without_z_is_refused_with_the_reason(drying_run):
    with pytest.raises(ValueError, match=r"lacks type, x y z \(ITEM: ATOMS id x y\)"):
        trajectory.universe(drying_run / "flat.dump")
