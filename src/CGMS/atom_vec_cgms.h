/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_ATOM_VEC_CGMS_H
#define LMP_ATOM_VEC_CGMS_H

#include "atom_vec.h"

namespace LAMMPS_NS {

// One bead per plant cell: per-atom mass plus the per-bead array "cgms"
// (fluid and solid mass, dryness, fresh state, and the per-step virtual-cell
// geometry, density and pressure written by fix cgms/fluid).
class AtomVecCGMS : public AtomVec {
 public:
  AtomVecCGMS(class LAMMPS *);

  void process_args(int, char **) override;
  void init() override;
  void grow_pointers() override;
  void create_atom_post(int) override;
  void data_atom_post(int) override;
  int property_atom(const std::string &) override;
  void pack_property_atom(int, double *, int, int) override;

 private:
  double *rmass;
  double **cgms;
};

}    // namespace LAMMPS_NS

#endif
