# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The fine-scale MFC model (doc/mfc.md): cell-resolved tissues whose cells are rings of
wall particles around their fluid, dried to steady state to make reference centroids."""
