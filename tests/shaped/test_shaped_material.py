# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A material file calibrated for one pair style is refused by the other. The first line of
a calibrated file says which style its fitted values are for (``MODEL: cgms``, written by
cgms.material.write); a file of measured values (apple.cgms) has no MODEL tag and serves
both. pair_style cgms/shaped given apple-mfc.cgms (pair cgms's fit) and pair_style cgms
given a file fitted for cgms/shaped stop with one ERROR naming the file, the style it is
for and the cure."""

import pytest

import shapedlmp as sl
from cgms import material, positions, tissue
from cgmstest import PLUGIN, run_lmp
from test_shaped_errors import error_line, tissue_geo
from test_shaped_minimize import start

S = 0.6


@pytest.mark.lammps
def test_the_calibrated_files_name_their_model():
    for name in ("apple-mfc", "potato-mfc"):
        assert "MODEL: cgms" in material.find(name).read_text().splitlines()[0], name
    for name in ("apple", "potato"):
        assert "MODEL:" not in material.find(name).read_text().splitlines()[0], name


@pytest.mark.lammps
def test_the_shaped_pair_refuses_the_paper_models_calibrated_file(tmp_path):
    xy, geo = tissue_geo()
    line = error_line(sl.run(tmp_path, geo, start(geo), S, sl.BEST,
                             str(material.find("apple-mfc")), check=False))
    for words in ["Pair style cgms/shaped", "apple-mfc.cgms", "calibrated for pair_style cgms",
                  "MODEL: cgms", "apple.cgms", "calibrated for cgms/shaped"]:
        assert words in line, line


def shaped_fit(folder):
    """apple.cgms as cgms.material.write marks a fit for the shaped model."""
    return material.write(folder / "shaped-fit.cgms", "apple", {"lj_slope": 0.1}, "a test fit",
                          model="cgms/shaped")


@pytest.mark.lammps
def test_the_paper_pair_refuses_a_file_calibrated_for_the_shaped_model(tmp_path):
    shaped_fit(tmp_path)
    positions.write_data(tmp_path / "t.data", tissue.rectangle(0.6e-3, 0.6e-3, sl.L), 4 * sl.L)
    script = "\n".join([f"plugin load {PLUGIN}", "units si", "dimension 2", "boundary f f p",
                        "atom_style cgms", "comm_modify vel yes", "read_data t.data", "pair_style cgms",
                        "pair_coeff * * shaped-fit.cgms", "fix fl all cgms/fluid dryness 0.6",
                        "run 0", ""])
    line = error_line(run_lmp(tmp_path, script, check=False))
    for words in ["Pair style cgms:", "shaped-fit.cgms", "calibrated for pair_style cgms/shaped",
                  "MODEL: cgms/shaped"]:
        assert words in line, line


@pytest.mark.lammps
def test_the_shaped_pair_reads_a_file_calibrated_for_it(tmp_path):
    """The same file passes the shaped pair's check (it runs to the end)."""
    fit = shaped_fit(tmp_path)
    xy, geo = tissue_geo()
    sl.run(tmp_path, geo, start(geo), S, sl.BEST, str(fit))
