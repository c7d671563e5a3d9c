/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_CGMS_H
#define LMP_PAIR_CGMS_H

#include "cgms_laws.h"
#include "cgms_material.h"
#include "cgms_store.h"
#include "pair.h"

#include <functional>

namespace LAMMPS_NS {

namespace CGMS {
  // the settings of fix cgms/fluid that the fluid pass follows (the fix sets them)
  struct FluidOptions {
    int density_rate = 0;         // 1: literal rate form of eqns (5)-(6); 0: rho = m_f / (h A)
    int transfer = 1;             // mass transfer on/off
    int transfer_implicit = 1;    // 1: linearised backward Euler; 0: explicit Euler (paper)
    int always_balance = 0;       // 1: P = -Pi in runs too (external quasi-static solvers)
    int minimize_balance = 1;     // 1: under minimize, P = -Pi (quasi-static solve)
    int allow_isolated = 0;       // a bead without neighbours: error (0) or reference cell (1)
    int inertia_fluid = 0;        // 1: rmass = m_f + m_s follows the fluid mass; 0: fresh mass
  };

  // the beads a fluid pass found beyond a limit (-1: none), first of each kind;
  // fix cgms/fluid's stability scan reports them
  struct Trouble {
    int emptied = -1, isolated = -1, nonfinite = -1, unstable = -1, shaky = -1;
    int stiff = -1;    // the worst turgor case, with:
    double stiff_ratio = 0.0, stiff_limit = 0.0;
    int after_change = 0;    // right after a change of dryness
  };
}    // namespace CGMS

// pair_style cgms owns the step of the CGMS model, as pair_style eam does its two
// passes: in compute() the geometry pass (neighbour count and distance sum of
// every bead, eqns 10-11), the reverse communication of the sums, the fluid pass
// (each bead's pressure, eqn 4, l_d, eqn 9, dm_f/dt, eqn 7, and pair coefficient
// c_i), the forward communication of c_i, and the force loop: turgor and
// perimeter (c_i + c_k), relative-velocity damping, LJ repulsion and attraction,
// cell shape (doc/model.md, Forces). The quasi-static energy is part of eng_vdwl.
// The fluid pass of a time step first applies the mass transfer of the previous step
// (m_f += dt dm_f/dt), in the same walk over the rows. fix cgms/fluid sets the dryness
// and the fluid options and reports the beads the pass found emptied or unstable.
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
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  // set by fix cgms/fluid
  void set_fluid_options(const CGMS::FluidOptions &o) { options = o; }
  void note_dryness_changed() { dryness_changed = 1; }

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
  // the geometry and fluid passes run: something reads the fluid state
  bool passes_needed() const { return pair_coefficient_needed() || options.transfer; }
  // what the last fluid pass found, and its quasi-static energy (this rank's beads)
  const CGMS::Trouble &trouble() const { return found; }
  double quasi_static_energy() const { return energy_local; }
  int passes_done() const { return passes_run; }
  // the outputs of every local bead i (CGMS::Output columns), handed to use(i, outputs):
  // its state, and what the fluid pass derives from the state and the neighbour sums
  void for_each_output(const std::function<void(int, const double *)> &use) const;
  CGMS::StepLimits step_limits() const;

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
  CGMS::FluidOptions options;
  int dryness_changed;    // a bead with a fluid state got a new dryness since the last pass
  int passes_run;         // the passes have run once (the sums are valid)
  CGMS::Trouble found;
  double energy_local;    // quasi-static potential of the local beads (J)

  // the pair coefficient of every local and ghost bead, sent to the ghosts
  double *coef;
  int nmax_coef;
  // the distance of every entry of the neighbour list (0: beyond the cutoff),
  // from the geometry pass for the force loop: no square root, no cutoff test
  double *rdist;
  bigint rdist_size;
  // k_S(s_i) of every local and ghost bead, filled once per force call when the
  // stiffness differs from bead to bead (PAIRCOEF 2), so the pair loop takes no pow
  double *shape_k;
  int nmax_shape;

  void allocate();
  void geometry_pass();
  void fluid_pass();
  double shape_pair_energy() const;
  void force_loop(int cached);
  template <int EVFLAG, int PAIRCOEF, int LJ, int DAMP> void eval(int cached);
};

}    // namespace LAMMPS_NS

#endif
