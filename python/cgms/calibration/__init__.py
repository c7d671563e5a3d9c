# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Calibration (doc/calibration.md): fit material parameters to reference centroids by
eqn (2), and the paper's sensitivity study."""
