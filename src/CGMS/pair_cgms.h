/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_CGMS_H
#define LMP_PAIR_CGMS_H

#include "cgms_material.h"
#include "pair.h"

namespace LAMMPS_NS {

// The five pairwise forces of the CGMS model (doc/model.md, Forces): turgor and
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
  void write_data_all(FILE *) override;
  double memory_usage() override;

  // read by fix cgms/fluid
  const CGMS::Material &material() const { return mat; }
  double cutoff() const { return cut_global; }
  // LJ radius of a pair, r = r0 (1 + lj_slope ln s_ik); radi is the value for s_i,
  // reused when the dryness is uniform (one log per bead instead of per pair)
  double pair_radius(double si, double sj, double radi) const
  {
    return sj == si ? radi : mat.lj_radius(0.5 * (si + sj));
  }
  // squared interaction cutoff of a pair: fixed, or cut_factor times its LJ radius
  double pair_cutsq(double rad) const
  {
    return cut_scaled ? cut_factor * cut_factor * rad * rad : cut_global * cut_global;
  }
  bool cutoff_scaled() const { return cut_scaled; }
  // fix cgms/fluid tells the pair when every bead has the same dryness (value
  // > 0) or not (-1): the loops then use one LJ radius and cutoff for all pairs
  // and never read a neighbour's dryness
  void set_uniform_dryness(double s) { uniform_dryness = s; }
  double get_uniform_dryness() const { return uniform_dryness; }
  bool pair_coefficient_needed() const { return turgor || perimeter || mat.k_S > 0.0; }

  // effect switches (all on by default)
  int turgor, perimeter, periphery, damping, repulsion, attraction;

 protected:
  CGMS::Material mat;
  std::string coeff_line;    // the pair_coeff arguments as given (for write_coeff)
  double cut_user;           // fixed cutoff given in pair_style (m), 0 = scaled cutoff
  double cut_factor;         // scaled cutoff: cut_factor times the pair's LJ radius
  int cut_scaled;            // 1: scaled cutoff, 0: fixed cutoff cut_user
  double cut_global;         // largest cutoff, for the neighbour lists
  double uniform_dryness;
  class FixCGMSFluid *fluid;    // the fix that prepares coefficients and distances (init_style)
  // k_S(s_i) of every local and ghost bead, filled once per force call when the
  // stiffness differs from bead to bead (PAIRCOEF 2), so the pair loop takes no pow
  double *shape_k;
  int nmax_shape;

  void allocate();
  template <int EVFLAG, int PAIRCOEF, int LJ, int DAMP> void eval();
};

}    // namespace LAMMPS_NS

#endif
