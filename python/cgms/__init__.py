# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""CGMS: coarse-grained multiscale model of plant-tissue drying, on LAMMPS.

Plain functions on NumPy arrays: build tissues (:mod:`cgms.tissue`), read
material files (:mod:`cgms.material`), run LAMMPS with the CGMS plugin
(:mod:`cgms.run`). ``python3 -m cgms --help`` is the command line.
"""

__version__ = "0.1.0"
