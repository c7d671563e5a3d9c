# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The MFC study gives every tissue its own results folder (the calibration against the MFC
reads them by tissue name: doc/calibration.md)."""

from cgms.tissue import MICROSCALE
from cgms.cli.mfc import SINGLE, folder_name


def test_every_named_tissue_has_its_own_folder():
    names = [*MICROSCALE, SINGLE]
    folders = [folder_name(n) for n in names]
    assert len(set(folders)) == len(names), dict(zip(names, folders))
    assert folder_name("2.0x2.5") == "2.0x2.5"


def test_a_data_file_gives_its_stem(tmp_path):
    assert folder_name(str(tmp_path / "my.tissue.data")) == "my.tissue"
