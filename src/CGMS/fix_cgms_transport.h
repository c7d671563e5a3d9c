/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_FIX_CGMS_TRANSPORT_H
#define LMP_FIX_CGMS_TRANSPORT_H

#include "fix.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {
namespace CGMS {
  class ColumnCG;
}

// Time-domain drying: moisture transport through a tissue slice and out into
// the air (doc/drying.md, doc/fix_cgms_transport.rst). Every bead carries a
// column of `layers` moisture nodes across the slice thickness; every N MD
// steps the fix advances the moisture by one step of its own length (seconds of
// drying): the Richardson extrapolation of linearised backward Euler steps
// (one of the whole length, two of half of it; second order in the step), each
// solved by conjugate gradients preconditioned by the columns. The same
// equations as python/cgms/drying/transport.py.
class FixCGMSTransport : public Fix {
 public:
  FixCGMSTransport(class LAMMPS *, int, char **);
  ~FixCGMSTransport() override;

  void post_constructor() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void end_of_step() override;
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
  void write_restart(FILE *) override;
  void restart(char *) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

  double memory_usage() override;

 private:
  class NeighList *list;

  // parameters of the material file (python/cgms/drying.py read_params)
  std::string params_file;
  double x0, solids_density, d_ref, t_ref, d_energy, d_moisture, gab_xm, gab_c, gab_k;
  // conditions and switches
  int layers, faces, multiplicity;
  int inplane, outline, heat, shrink;
  double t_air, humidity, velocity, plate, thickness;
  double kc, hc;     // air-side mass (m/s) and heat (W/(m^2 K)) coefficients
  int linear_law;    // 1: N = hx (X - xeq) (Crank's boundary condition)
  double hx, xeq;
  double cutoff, cutoff_user;
  double s_min;             // lowest dryness handed to the mechanics
  double dt_move;           // length of the next moisture step (s)
  double dt_given;          // the dt keyword (s)
  double dx_max, dt_max;    // adaptive step (dx_max <= 0: fixed)
  double cg_tol;
  int cg_max;
  double until;    // drying time (s) the steps stop at (<= 0: none)

  // state of the run (global; a copy rides in every bead's row of the state store)
  int initialised;    // 1: this fix holds the tissue's state (made or taken over)
  double time, water0, out_face, out_edge, rate, t_product;
  double out_gone, gone0;    // water, and initial water, of the beads deleted so far (kg)
  double water;              // water in the tissue at the last refresh_vector (kg)
  double solids;             // dry solid of the tissue then (kg)
  bigint beads;              // beads then
  bigint nmoves;
  int cg_iterations;    // of the last step's three solves
  int halvings;         // how often the last step was halved to keep every node >= 0
  double vec[16];       // the global outputs, refreshed after every moisture step

  // per bead, in the per-atom array of the fix property/atom STATE_FIX (it
  // travels with the bead, into restart and data files and past this fix's
  // re-definition): the global state, then X of every layer, dry solid S (kg,
  // whole column), fresh area A0 (m^2), fresh thickness L0 (m)
  int istate;      // index of that array in Atom::darray
  int nstore;      // columns per bead: the global state, layers, S, A0, L0
  double **out;    // per-atom output: dryness, mean, surface, core X/X0
  int *own;        // 1: the bead's row in the state store is its own
  int nmax_own;

  // per bead, local and ghost, rebuilt every moisture step
  int nmax_bead;
  double *rho_s, *dz, *area, *spacing, *edge;
  double *xn, *dn;    // node moisture and diffusivity (layers per bead)
  double *diag, *lower, *c1, *c0, *c1f, *c0f, *bn, *xnew;    // the step's system
  double *xbegin, *xfull;         // the step's start (local and ghost), its whole-length result
  double *comm_vec;               // the node array MODE_DIRECTION sends
  CGMS::ColumnCG *cg;             // its solver
  int **along;                    // an outline bead's neighbours before and after it
  double **shift, **shift_new;    // the smoothing of the outline polygon
  std::vector<int> pair_start, pair_j;    // in-plane neighbours of each local bead
  std::vector<double> pair_dist;          // their centre distance
  std::vector<double> pair_g;             // their conductance per layer

  int comm_mode;

  double **rows() const;
  double *column(int i) const;
  bool has_column(int i) const;
  void bind_state();
  int restart_store_size() const;
  void refuse_store_size(int cols);
  void check_state_layout();
  void check_thickness();
  void check_beads();
  void check_columns();
  void check_not_dried();
  void load_globals();
  void save_globals();
  void account_removed();
  void read_params(const char *);
  void set_defaults();
  void parse_keywords(int narg, char **arg);
  void set_number_keyword(const std::string &key, double v);
  void air_coefficients();
  void set_output(int);
  void initialise_columns();
  void grow_beads();
  void geometry();
  void outline_edges();
  double diffusivity(double, double) const;
  void surface_law(double, double, double, double &, double &) const;
  double product_temperature();
  double evaporation(double);
  void move();
  void coefficients();
  void euler(double, double &, double &);
  void exchange_nodes(double *);
  void assemble(double);
  int solve();
  int drained(double, int);
  void check_diffusivity();
  double sum_all(double) const;
  void totals(double &, double &, double &, double &) const;
  void refresh_vector();
};

}    // namespace LAMMPS_NS

#endif
