# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""pair_style cgms/shaped's state travels: a restart file and a data file written by
LAMMPS in the middle of a minimisation carry F and the fresh tissue's fixed data, so that
the minimisation continues bit for bit from either (each ``minimize`` command starts its
conjugate directions afresh, so the continuation is a second ``minimize`` in every run;
the restart file holds the pair's settings and material, so no pair line is given again);
on two ranks too, where the files gather every rank's beads with their properties and
scatter them again. The fixed data comes back unchanged."""

import numpy as np
import pytest

import shapedlmp as sl
from cgms import shaped_data, shaped_tensor as st, tissue
from test_shaped_minimize import start

S = 0.6
STEP = "minimize 0 0 40 100000\n"
FIXED = ("i2_shaped_nb", "d2_shaped_bondx", "d2_shaped_bondy", "d2_shaped_wallx",
         "d2_shaped_wally", "i_shaped_nwall", "i_shaped_boundary", "d_shaped_area0")
# the per-atom columns of the final dump: the state and every fixed property
FINAL = ("write_dump all custom final.dump id x y fx fy d2_shaped_F[*] d2_shaped_fF[*] "
         + " ".join(f + "[*]" if f[1] == "2" else f for f in FIXED)
         + " modify format float %.17g sort id\n")
MIN = "min_style cg\nmin_modify dmax 1e-6 norm max line forcezero\n"


def read_final(path):
    lines = path.read_text().splitlines()
    k = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    return lines[k], lines[k + 1:]


@pytest.mark.lammps
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_restart_and_data_file_continue_bit_for_bit(tmp_path, nprocs):
    xy = tissue.rectangle(0.75e-3, 0.75e-3, sl.L)
    geo = st.build(xy, sl.MAT, sl.BEST)
    z0 = start(geo)
    physics = sl.physics(S, sl.BEST, sl.APPLE)
    sl.run(tmp_path, geo, z0, S, sl.BEST, sl.APPLE, nprocs=nprocs, commands=(
        MIN + STEP + "write_restart mid.restart\nwrite_data mid.data\n" + STEP + FINAL))
    whole = read_final(tmp_path / "final.dump")
    (tmp_path / "final.dump").unlink()

    restart = "\n".join([f"plugin load {sl.PLUGIN}",
                         f"processors {nprocs} 1 1" if nprocs > 1 else "", "read_restart mid.restart",
                         shaped_data.fix_command(geo), "neighbor 1.5e-5 bin",
                         "neigh_modify every 1 delay 0 check yes", ""])
    # the pair's settings and material come from the restart file: no pair lines
    sl.run_lmp(tmp_path, restart + MIN + STEP + FINAL, nprocs=nprocs)
    assert read_final(tmp_path / "final.dump") == whole
    (tmp_path / "final.dump").unlink()
    # and pair_style and pair_coeff given again as before give the same
    sl.run_lmp(tmp_path, restart + physics + MIN + STEP + FINAL, nprocs=nprocs)
    assert read_final(tmp_path / "final.dump") == whole
    (tmp_path / "final.dump").unlink()

    data = sl.header(geo, data="mid.data", nprocs=nprocs)
    sl.run_lmp(tmp_path, data + physics + MIN + STEP + FINAL, nprocs=nprocs)
    assert read_final(tmp_path / "final.dump") == whole

    # and the fixed data is the tissue's (the minimiser moved x and F only)
    columns, rows = whole
    names = columns.split()[2:]
    table = np.array([[float(w) for w in row.split()] for row in rows])
    b = shaped_data.per_bead(geo)
    got = {name: table[:, [k for k, c in enumerate(names) if c.split("[")[0] == name]]
           for name in FIXED}
    assert np.array_equal(got["i2_shaped_nb"], b["nb"])
    assert np.array_equal(got["d2_shaped_wallx"], b["wallx"])
    assert np.array_equal(got["d2_shaped_bondy"], b["bondy"])
    assert np.array_equal(got["d_shaped_area0"][:, 0], b["area0"])
    assert np.array_equal(got["i_shaped_boundary"][:, 0], b["boundary"])
    F0 = st.split(z0, geo["n"])[1].reshape(-1, 4)
    F = table[:, [k for k, c in enumerate(names) if c.startswith("d2_shaped_F[")]]
    assert np.abs(F - F0).max() > 1e-3        # the minimiser moved F
