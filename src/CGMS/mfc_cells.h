/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

// What fix mfc/pressure (2-D rings) and fix mfc/pressure3d (closed triangulated
// walls) share: a wall particle's molecule ID names its cell, and a cell's fluid
// belongs to one fix.

#ifndef LMP_MFC_CELLS_H
#define LMP_MFC_CELLS_H

namespace LAMMPS_NS {

class Fix;
class LAMMPS;

namespace CGMS {

  // the largest molecule ID in the fix's group; refuses a particle without one
  int max_cell_molecule(LAMMPS *lmp, Fix *fix);

  // refuses a wall particle that another fix of the same style holds too
  void refuse_shared_walls(LAMMPS *lmp, Fix *fix);

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
