/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_FIX_CGMS_FLUID_H
#define LMP_FIX_CGMS_FLUID_H

#include "fix.h"

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
  double compute_scalar() override;
  double compute_vector(int) override;
  void grow_arrays(int) override;

  void write_data_section_size(int, int &, int &) override;
  void write_data_section_pack(int, double **) override;
  void write_data_section_keyword(int, FILE *) override;
  void write_data_section(int, FILE *, int, double **, int) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

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

  int comm_column;    // column sent by forward communication
  double *work;       // per-bead values of a keyword (dryness, diameter)
  int nmax_work;

  double energy_local;    // quasi-static potential of the local beads (J)

  bigint vector_step;    // step of the cached global outputs
  double vector_cache[5];
  int setup_done;        // this instance has computed the state once (global outputs valid)

  int choice(const std::string &, const char *, const char *, const char *);
  int find_variable(const char *, const char *);
  const double *per_bead_values(int, double);
  double shape_pair_energy(double) const;
  void apply_dryness();
  bigint load_data_file_state();
  bigint initialise_beads();
  void warn_if_dried(bigint);
  void update_fluid_state(int advance);
  void damping_limit_error(int);
  void limit_minimizer_step();
  void check_dryness_range(double, double);
  void check_setup_input();
  void check_setup_geometry(const double *);
  void isolated_error(int);
  void forward(int column);
  void refresh_vector();
};

}    // namespace LAMMPS_NS

#endif
