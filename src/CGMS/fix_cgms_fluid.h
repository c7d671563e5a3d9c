/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_FIX_CGMS_FLUID_H
#define LMP_FIX_CGMS_FLUID_H

#include "cgms_laws.h"
#include "cgms_store.h"
#include "fix.h"

#include <functional>

namespace LAMMPS_NS {

// The fluid phase of the CGMS model: each step the virtual-cell geometry
// (eqns 10-11), density, turgor pressure (eqn 4), equilibrium perimeter
// (eqn 9), mass transfer through the virtual membrane (eqn 7) and the
// per-bead pair coefficient used by pair_style cgms.
class FixCGMSFluid : public Fix {
 public:
  FixCGMSFluid(class LAMMPS *, int, char **);
  ~FixCGMSFluid() override;

  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup_pre_force(int) override;
  void pre_force(int) override;
  void min_pre_force(int) override;
  void post_run() override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;

  void write_data_section_size(int, int &, int &) override;
  void write_data_section_pack(int, double **) override;
  void write_data_section_keyword(int, FILE *) override;
  void write_data_section(int, FILE *, int, double **, int) override;

  double memory_usage() override;

  // The contract with pair_style cgms, which reads each step: the pair
  // coefficient of every bead (local and ghost), and the distance of every
  // entry of the neighbour list the force loop walks, when this fix's geometry
  // pass walked that very list in this step (nullptr otherwise; 0 marks an
  // entry beyond the cutoff). The force loop then needs neither a square root
  // nor a cutoff test; it calls distances_used() when done.
  const double *pair_coefficients() const { return coef; }
  const double *distances_for(const class NeighList *) const;
  void distances_used() { rdist_valid = 0; }

  // column (CGMS::Output) of every local bead's outputs for compute
  // property/atom, computed now from its state and the last geometry pass
  void pack_output(int column, double *buf, int nvalues, int groupbit);

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  // the beads a fluid pass found beyond a limit (-1: none), first of each kind
  struct Trouble {
    int fresh = -1, emptied = -1, isolated = -1, nonfinite = -1, unstable = -1, shaky = -1;
    int stiff = -1;    // the worst turgor case, with:
    double stiff_ratio = 0.0, stiff_limit = 0.0;
    int after_change = 0;    // right after a change of dryness
  };

 private:
  class PairCGMS *pair;
  class NeighList *list;

  double dryness_value;    // constant dryness, or
  char *dryness_var;       // name of an equal- or atom-style variable
  int dryness_ivar;
  int dryness_given;        // 0: keep each bead's stored dryness (new beads: 1)
  double diameter_value;    // cell diameter of new beads (0: the material's), or
  char *diameter_var;       // name of an equal- or atom-style variable
  int diameter_ivar;
  int dryness_every;        // re-evaluate the variable every this many steps (0: at setup)
  int density_rate;         // 1: literal rate form of eqns (5)-(6); 0: rho = m_f / (h A)
  int inertia_fluid;        // 1: rmass = m_f + m_s (paper); 0: fresh mass (stable default)
  int transfer;             // mass transfer on/off
  int transfer_implicit;    // 1: linearised backward Euler; 0: explicit Euler (paper)
  int always_balance;       // 1: P = -Pi in runs too (external quasi-static solvers)
  int minimize_balance;     // 1: under minimize, P = -Pi (quasi-static solve); 0: from m_f
  int allow_isolated;       // a bead without neighbours: error (0) or reference cell (1)
  int dryness_changed;      // a bead with a fluid state got a new dryness since the last pass
  int beads_added;          // set_arrays: a bead was created during the run (fix deposit ...)
  bigint natoms_known;      // atom count when the beads were last known to have a fluid state

  // compact per-bead copies of what the per-pair loops touch, so that a
  // neighbour costs 8 or 16 bytes instead of a 64-byte row
  double *coef;     // pair coefficient (local and ghost beads)
  int nmax_bead;    // length of coef
  // geometry pass: neighbour count and sum of distances (2 per bead, local and
  // ghost; per-atom, they travel with the beads: outputs derive from them)
  CGMS::NeighbourSums *sums;
  // the per-atom output array f_ID[1-14] (CGMS::Output columns), filled from
  // the state and the sums on the steps an output may read it (output_step)
  double **outputs;
  int nmax_outputs;         // rows of outputs (and beads of sums)
  int output_every;         // the keyword output: N, or 0 for auto (init)
  int init_output_every;    // peratom_freq set by init()
  int passes_done;          // the geometry and fluid passes have run (sums valid)
  double *rdist;            // distance per neighbour-list entry (see distances_for)
  bigint rdist_size;
  int **rdist_list;    // firstneigh of the list rdist follows
  int rdist_valid;     // set by the geometry pass, cleared by the pair after use

  int comm_column;    // row column sent by forward communication (-1: the pair coefficients)
  double *work;       // per-bead values of a keyword (dryness, diameter)
  int nmax_work;

  double energy_local;    // quasi-static potential of the local beads (J)

  bigint vector_step;    // step of the cached global outputs
  double vector_cache[5];
  int setup_done;    // this instance has computed the state once (global outputs valid)

  int choice(const std::string &, const char *, const char *, const char *);
  int find_variable(const char *, const char *);
  const double *per_bead_values(int, double);
  double shape_pair_energy() const;
  void apply_dryness();
  void refresh_ghost_dryness();
  bigint load_data_file_state();
  bigint initialise_beads();
  void warn_if_dried(bigint);
  void update_fluid_state(int advance);
  void geometry_pass();
  int bead_without_state();
  void fluid_pass(int advance, Trouble &);
  void stop_if_unstable(const Trouble &);
  void warn_if_folded();
  CGMS::StepLimits step_limits() const;
  void damping_limit_error(int);
  void limit_minimizer_step();
  void check_dryness_range(double, double);
  void check_setup_input();
  void check_setup_geometry();
  void isolated_error(int);
  void forward(int column);
  void refresh_vector();
  int output_frequency() const;
  int output_step() const;
  void for_each_output(const std::function<void(int, const double *)> &) const;
  void fill_outputs();
};

}    // namespace LAMMPS_NS

#endif
