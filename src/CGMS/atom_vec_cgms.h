/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_ATOM_VEC_CGMS_H
#define LMP_ATOM_VEC_CGMS_H

#include "atom_vec.h"

namespace LAMMPS_NS {

// One bead per plant cell: per-atom mass plus the per-bead array "cgms", the
// bead's state (dryness, fluid and solid mass, fresh state, density, area,
// mass rate: CGMS::State); the outputs fix cgms/fluid derives from it are
// named for compute property/atom here (CGMS::Output).
class AtomVecCGMS : public AtomVec {
 public:
  AtomVecCGMS(class LAMMPS *);

  void process_args(int, char **) override;
  void init() override;
  void grow_pointers() override;
  void create_atom_post(int) override;
  int unpack_restart(double *) override;
  void data_atom_post(int) override;
  int property_atom(const std::string &) override;
  void pack_property_atom(int, double *, int, int) override;

 private:
  double *rmass;
  double **cgms;
};

}    // namespace LAMMPS_NS

#endif
