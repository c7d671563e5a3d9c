/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_FIX_CGMS_FLUID_H
#define LMP_FIX_CGMS_FLUID_H

#include "fix.h"
#include "pair_cgms.h"

#include <functional>

namespace LAMMPS_NS {

// The fluid phase of the CGMS model around pair_style cgms, which computes it
// (the previous step's mass transfer m_f += dt dm_f/dt, geometry, pressure, l_d,
// dm_f/dt, c_i; doc/model.md) in its compute(): the dryness (keyword, variable,
// schedule), the start-up of new beads, the fluid options the pair follows, the
// data-file section, the stability scan of what the pair's pass found, and the
// outputs.
class FixCGMSFluid : public Fix {
 public:
  FixCGMSFluid(class LAMMPS *, int, char **);
  ~FixCGMSFluid() override;

  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup_pre_force(int) override;
  void setup(int) override;
  void min_setup(int) override;
  void pre_force(int) override;
  void min_pre_force(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
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

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

 private:
  class PairCGMS *pair;
  class NeighList *list;    // for the setup checks and the messages (nearest beads)

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
  int beads_added;          // set_arrays: a bead was created during the run (fix deposit ...)
  bigint natoms_known;      // atom count when the beads were last known to have a fluid state

  // the per-atom output array f_ID[1-14] (CGMS::Output columns), filled from
  // the state and the neighbour sums on the steps an output may read it (output_step)
  double **outputs;
  int nmax_outputs;         // rows of outputs
  int output_every;         // the keyword output: N, or 0 for auto (init)
  int init_output_every;    // peratom_freq set by init()

  int comm_column;    // row column sent by forward communication
  double *work;       // per-bead values of a keyword (dryness, diameter)
  int nmax_work;
  bigint setup_fresh, setup_loaded;    // beads the setup started fresh, took from a data file

  bigint vector_step;    // step of the cached global outputs
  double vector_cache[5];
  int setup_done;    // this instance has computed the state once (global outputs valid)

  int choice(const std::string &, const char *, const char *, const char *);
  int find_variable(const char *, const char *);
  void pass_options_to_pair();
  const double *per_bead_values(int, double);
  void apply_dryness();
  void refresh_ghost_dryness();
  bigint load_data_file_state();
  void check_awaits_line(int);
  void check_stored_state();
  bigint initialise_beads();
  int bead_without_state();
  void forward(int column);
  void refresh_vector();
  int output_frequency() const;
  int output_step() const;
  void for_each_output(const std::function<void(int, const double *)> &) const;
  void fill_outputs();

  // the checks and their messages (fix_cgms_fluid_checks.cpp)
  void check_setup_input();
  void check_dryness_range(double, double);
  void check_setup_geometry();
  void limit_minimizer_step();
  void warn_if_dried(bigint);
  void warn_if_folded();
  void fresh_bead_error(int);
  void emptied_error(int);
  void stop_if_unstable(const CGMS::Trouble &);
  void isolated_error(int);
  void damping_limit_error(int);
};

}    // namespace LAMMPS_NS

#endif
