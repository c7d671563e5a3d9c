/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(cgms/atom,ComputeCGMSAtom);
// clang-format on
#else

#ifndef LMP_COMPUTE_CGMS_ATOM_H
#define LMP_COMPUTE_CGMS_ATOM_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

// The per-bead outputs by name (CGMS::Output: the state columns and what
// pair_style cgms derives from them and its last geometry pass), as a
// per-atom vector (one name) or array (several, in the order given).
class ComputeCGMSAtom : public Compute {
 public:
  ComputeCGMSAtom(class LAMMPS *, int, char **);
  ~ComputeCGMSAtom() override;
  void init() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  std::vector<int> columns;    // CGMS::Output column of each value
  int nmax;
  double *vector;
  double **array;
};

}    // namespace LAMMPS_NS

#endif
#endif
