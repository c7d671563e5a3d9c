/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_CGMS_H
#define LMP_PAIR_CGMS_H

#include "cgms_material.h"
#include "pair.h"

namespace LAMMPS_NS {

// The five pairwise forces of the CGMS model (MODEL.md section 6): turgor and
// perimeter adjustment (through the per-bead coefficient that fix cgms/fluid
// computes), relative-velocity damping, and LJ repulsion and attraction.
class PairCGMS : public Pair {
 public:
  PairCGMS(class LAMMPS *);
  ~PairCGMS() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void *extract(const char *, int &) override;

  // read by fix cgms/fluid
  const CGMS::Material &material() const { return mat; }
  double cutoff() const { return cut_global; }
  bool pair_coefficient_needed() const { return turgor || perimeter; }

  // effect switches (all on by default)
  int turgor, perimeter, periphery, damping, repulsion, attraction;

 protected:
  CGMS::Material mat;
  double cut_user;      // cutoff given in pair_style, 0 = default 1.35 x_ref
  double cut_global;    // cutoff in use

  void allocate();
  template <int EVFLAG, int PAIRCOEF, int LJ, int DAMP> void eval();
};

}    // namespace LAMMPS_NS

#endif
