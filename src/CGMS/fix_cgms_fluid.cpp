/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "fix_cgms_fluid.h"

#include "atom.h"
#include "atom_vec_cgms.h"
#include "cgms_laws.h"
#include "cgms_store.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "my_page.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "output.h"
#include "pair_cgms.h"
#include "update.h"
#include "variable.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <numeric>

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CGMS;

/* ----------------------------------------------------------------------
   entries a neighbour list holds since its last build: each thread's page
   counts what it stored and every build resets it (a copy list shares its
   parent's pages); a list without pages is counted bead by bead
------------------------------------------------------------------------- */

static bigint list_entries(const NeighList *list, int nthreads)
{
  bigint n = 0;
  if (list->ipage) {
    for (int t = 0; t < nthreads; t++) n += list->ipage[t].ndatum;
  } else {
    for (int ii = 0; ii < list->inum; ii++) n += list->numneigh[list->ilist[ii]];
  }
  return n;
}
/* ----------------------------------------------------------------------
   what depends on the dryness alone, recomputed when it changes from one bead
   to the next (the laws of cgms_laws.h)
------------------------------------------------------------------------- */

namespace {
struct DrynessLaws {
  double s = -1.0, beta = 1.0, inv_rho_ref = 0.0, P_ref = 0.0, Pi = 0.0, ld_factor = 0.0;
  double kS = 0.0;    // cell-shape stiffness k_S(s)

  void set(double s_new, const Material &mat, int periphery)
  {
    s = s_new;
    beta = periphery ? mat.beta(s) : 1.0;
    inv_rho_ref = 1.0 / (s * mat.rho0);
    P_ref = s * mat.P_f;
    Pi = s * mat.Pi_f;
    ld_factor = mat.perimeter_contraction(s);
    kS = mat.shape_stiffness(s);
  }
  // q^7 = (rho / rho_ref)^7 and the Tait pressure of eqn (4)
  double q7(double rho) const { return pow7(rho * inv_rho_ref); }
  double pressure(double q7, double K) const { return tait_pressure(q7, P_ref, K); }
};
}    // namespace

/* ----------------------------------------------------------------------
   the time-step limits (cgms_laws.h) of the forces the pair has switched on
------------------------------------------------------------------------- */

StepLimits FixCGMSFluid::step_limits() const
{
  const Material &mat = pair->material();
  return {pair->damping ? mat.k_d : 0.0, pair->turgor ? mat.k_T : 0.0, mat.K, mat.k_S, update->dt};
}

/* ----------------------------------------------------------------------
   a keyword with two values: 0 for the first, 1 for the second (the error
   lists them in this order)
------------------------------------------------------------------------- */

int FixCGMSFluid::choice(const std::string &key, const char *val, const char *zero, const char *one)
{
  if (strcmp(val, zero) == 0) return 0;
  if (strcmp(val, one) == 0) return 1;
  error->all(FLERR, "Fix cgms/fluid {} must be '{}' or '{}', not '{}'", key, zero, one, val);
  return 0;
}

/* ----------------------------------------------------------------------
   fix ID all cgms/fluid keyword value ...
------------------------------------------------------------------------- */

FixCGMSFluid::FixCGMSFluid(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), pair(nullptr), list(nullptr), dryness_value(1.0), dryness_var(nullptr),
    dryness_ivar(-1), dryness_given(0), diameter_value(0.0), diameter_var(nullptr),
    diameter_ivar(-1), dryness_every(0), density_rate(0), inertia_fluid(0), transfer(1),
    transfer_implicit(1), always_balance(0), minimize_balance(1), allow_isolated(0),
    dryness_changed(0), beads_added(0), natoms_known(-1), coef(nullptr), nmax_bead(0),
    sums(nullptr), outputs(nullptr), nmax_outputs(0), output_every(0), init_output_every(1),
    passes_done(0), rdist(nullptr), rdist_size(0), rdist_list(nullptr), rdist_valid(0),
    comm_column(-1), work(nullptr), nmax_work(0), energy_local(0.0), vector_step(-1), setup_done(0)
{
  if (igroup != 0) error->all(FLERR, "Fix cgms/fluid must be applied to group all");

  int iarg = 3;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Fix cgms/fluid keyword {} needs a value", key);
    const char *val = arg[iarg + 1];
    if (key == "dryness") {
      dryness_given = 1;
      if (utils::strmatch(val, "^v_")) {
        delete[] dryness_var;
        dryness_var = utils::strdup(val + 2);
      } else {
        dryness_value = utils::numeric(FLERR, val, false, lmp);
        if (!(dryness_value > 0.0 && dryness_value <= 1.0))
          error->all(FLERR, "Fix cgms/fluid dryness {} is out of range: it must be in (0, 1]",
                     dryness_value);
      }
    } else if (key == "diameter") {
      if (utils::strmatch(val, "^v_")) {
        delete[] diameter_var;
        diameter_var = utils::strdup(val + 2);
      } else {
        diameter_value = utils::numeric(FLERR, val, false, lmp);
        if (!(diameter_value > 0.0))
          error->all(FLERR, "Fix cgms/fluid diameter {} must be > 0", diameter_value);
      }
    } else if (key == "every") {
      dryness_every = utils::inumeric(FLERR, val, false, lmp);
      if (dryness_every < 0) error->all(FLERR, "Fix cgms/fluid every must be >= 0");
    } else if (key == "density") {
      density_rate = choice(key, val, "exact", "rate");
    } else if (key == "inertia") {
      inertia_fluid = choice(key, val, "fresh", "fluid");
    } else if (key == "transfer") {
      transfer = utils::logical(FLERR, val, false, lmp);
    } else if (key == "transfer/scheme") {
      transfer_implicit = 1 - choice(key, val, "implicit", "explicit");
    } else if (key == "minimize") {
      minimize_balance = 1 - choice(key, val, "balance", "state");
    } else if (key == "balance") {
      // P = -Pi in every force evaluation, also in runs: for external steady-state
      // solvers that drive LAMMPS with "run 0"
      always_balance = utils::logical(FLERR, val, false, lmp);
    } else if (key == "isolated") {
      allow_isolated = choice(key, val, "error", "allow");
    } else if (key == "output") {
      // the steps on which the per-atom array f_ID[1-14] is filled: every N, or
      // auto: the steps the run's thermo and dumps write (set_output_frequency)
      if (strcmp(val, "auto") == 0) {
        output_every = 0;
      } else {
        output_every = utils::inumeric(FLERR, val, false, lmp);
        if (output_every < 1)
          error->all(FLERR, "Fix cgms/fluid output must be 'auto' or a step count >= 1, not {}",
                     val);
      }
    } else {
      error->all(
          FLERR,
          "Unknown fix cgms/fluid keyword '{}' (known: dryness diameter every density inertia "
          "transfer transfer/scheme minimize balance isolated output)",
          key);
    }
    iarg += 2;
  }
  if (dryness_every > 0 && !dryness_var)
    error->all(FLERR, "Fix cgms/fluid every needs a variable dryness (dryness v_name)");

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  // the potential of the quasi-static problem (see update_fluid_state); counted in the
  // potential energy by default, as minimize needs it for its line search
  scalar_flag = 1;
  extscalar = 1;
  energy_global_flag = 1;
  thermo_energy = 1;
  peratom_flag = 1;
  size_peratom_cols = NOUTPUTS;
  peratom_freq = output_every > 0 ? output_every : 1;
  comm_forward = 1;
  comm_reverse = NSUMS;
  wd_section = 1;          // the fluid state travels with write_data
  create_attribute = 1;    // set_arrays() learns of beads created during a run

  maxexchange = NOUTPUTS + 2;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
}

/* ---------------------------------------------------------------------- */

FixCGMSFluid::~FixCGMSFluid()
{
  if (modify->get_fix_by_id(id)) atom->delete_callback(id, Atom::GROW);
  delete[] dryness_var;
  delete[] diameter_var;
  memory->destroy(work);
  memory->destroy(coef);
  memory->destroy(sums);
  memory->destroy(outputs);
  memory->destroy(rdist);
}

/* ---------------------------------------------------------------------- */

const double *FixCGMSFluid::distances_for(const NeighList *l) const
{
  return rdist_valid && rdist_list == l->firstneigh ? rdist : nullptr;
}

/* ---------------------------------------------------------------------- */

double FixCGMSFluid::memory_usage()
{
  return sizeof(double) *
      (nmax_bead + (2.0 + NOUTPUTS) * atom->nmax + (double) rdist_size + nmax_work);
}

/* ---------------------------------------------------------------------- */

int FixCGMSFluid::setmask()
{
  return PRE_FORCE | MIN_PRE_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixCGMSFluid::post_run()
{
  // between runs the per-atom array holds the last step's outputs, and any step
  // is compatible with it (write_dump, variables); the next run sets it again
  peratom_freq = output_every > 0 ? output_every : 1;
  if (update->whichflag == 2 && sums) warn_if_folded();
}

/* ---------------------------------------------------------------------- */

void FixCGMSFluid::init()
{
  require_cgms_system(lmp, "Fix cgms/fluid");
  if (modify->get_fix_by_style("^cgms/fluid$").size() > 1)
    error->all(FLERR, "Only one fix cgms/fluid may be defined");
  pair = dynamic_cast<PairCGMS *>(force->pair);
  if (!pair)
    error->all(FLERR,
               "Fix cgms/fluid requires pair_style cgms: the pair style holds the material "
               "parameters and applies the forces");

  dryness_ivar = find_variable(dryness_var, "dryness");
  diameter_ivar = find_variable(diameter_var, "diameter");

  // the fluid state is updated once per step in pre_force; rRESPA's inner levels
  // would compute forces from a state it never prepares
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR,
               "Fix cgms/fluid does not support run_style {}: CGMS forces have one time scale; "
               "use run_style verlet",
               update->integrate_style);
  if (update->whichflag == 1 && !(update->dt > 0.0))
    error->all(FLERR,
               "Fix cgms/fluid requires a positive time step (timestep is {:.6g} s): CGMS "
               "integrates forward in time",
               update->dt);
  if (update->whichflag == 2) limit_minimizer_step();
  peratom_freq = init_output_every = output_frequency();

  neighbor->add_request(this);
}

/* ----------------------------------------------------------------------
   index of the equal- or atom-style variable a keyword names, -1 for none
------------------------------------------------------------------------- */

int FixCGMSFluid::find_variable(const char *name, const char *keyword)
{
  if (!name) return -1;
  const int ivar = input->variable->find(name);
  if (ivar < 0)
    error->all(FLERR, "Variable {} for fix cgms/fluid {} does not exist", name, keyword);
  if (!input->variable->equalstyle(ivar) && !input->variable->atomstyle(ivar))
    error->all(FLERR, "Variable {} for fix cgms/fluid {} must be equal- or atom-style", name,
               keyword);
  return ivar;
}

/* ---------------------------------------------------------------------- */

void FixCGMSFluid::init_list(int, NeighList *ptr)
{
  list = ptr;
}

/* ---------------------------------------------------------------------- */

void FixCGMSFluid::grow_arrays(int nmax)
{
  const int nold = nmax_outputs;
  memory->grow(sums, nmax, "cgms/fluid:sums");
  memory->grow(outputs, nmax, NOUTPUTS, "cgms/fluid:outputs");
  for (int i = nold; i < nmax; i++) {
    sums[i] = {0.0, 0.0};
    for (int k = 0; k < NOUTPUTS; k++) outputs[i][k] = 0.0;
  }
  nmax_outputs = nmax;
  array_atom = outputs;
}

void FixCGMSFluid::copy_arrays(int i, int j, int)
{
  sums[j] = sums[i];
  for (int k = 0; k < NOUTPUTS; k++) outputs[j][k] = outputs[i][k];
}

int FixCGMSFluid::pack_exchange(int i, double *buf)
{
  buf[0] = sums[i].count;
  buf[1] = sums[i].distance;
  for (int k = 0; k < NOUTPUTS; k++) buf[2 + k] = outputs[i][k];
  return NOUTPUTS + 2;
}

int FixCGMSFluid::unpack_exchange(int nlocal, double *buf)
{
  sums[nlocal] = {buf[0], buf[1]};
  for (int k = 0; k < NOUTPUTS; k++) outputs[nlocal][k] = buf[2 + k];
  return NOUTPUTS + 2;
}

/* ----------------------------------------------------------------------
   a bead created during a run (fix deposit, fix pour: Modify::create_attribute)
   has no fluid state; the next fluid pass looks for such beads
------------------------------------------------------------------------- */

void FixCGMSFluid::set_arrays(int i)
{
  beads_added = 1;
  sums[i].count = sums[i].distance = 0.0;
  for (int k = 0; k < NOUTPUTS; k++) outputs[i][k] = 0.0;
}

/* ----------------------------------------------------------------------
   setup: dryness from the keyword, fresh state for new beads, then the
   geometry and pressure the first force evaluation needs
------------------------------------------------------------------------- */

void FixCGMSFluid::setup_pre_force(int)
{
  // a run with 'pre no' skips init(): its first and last step count too, and
  // the consumers init() checked against its frequency must stay compatible
  peratom_freq = std::gcd(init_output_every, output_frequency());
  vector_step = -1;    // the state may have changed between runs at the same step
  check_setup_input();
  const bigint loaded = load_data_file_state();
  apply_dryness();
  const bigint fresh = initialise_beads();
  beads_added = 0;
  natoms_known = atom->natoms;
  update_fluid_state(0);
  if (fresh > 0 && loaded == 0) warn_if_dried(fresh);
  setup_done = 1;
}

void FixCGMSFluid::pre_force(int)
{
  if (dryness_every > 0 && update->ntimestep % dryness_every == 0)
    apply_dryness();
  else
    refresh_ghost_dryness();
  update_fluid_state(1);
}

void FixCGMSFluid::min_pre_force(int)
{
  refresh_ghost_dryness();
  update_fluid_state(0);
}

/* ----------------------------------------------------------------------
   ghosts carry no CGMS state from the atom style: after a re-neighbouring
   (new ghosts) send the dryness, which the loops read for ghosts only when
   it differs between beads
------------------------------------------------------------------------- */

void FixCGMSFluid::refresh_ghost_dryness()
{
  if (neighbor->ago == 0 && pair->get_uniform_dryness() <= 0.0) forward(DRYNESS);
}

/* ----------------------------------------------------------------------
   a constant (ivar < 0), or an equal- or atom-style variable, for every
   local bead; the values live in a work array until the next call
------------------------------------------------------------------------- */

const double *FixCGMSFluid::per_bead_values(int ivar, double constant)
{
  if (atom->nmax > nmax_work) {
    nmax_work = atom->nmax;
    memory->destroy(work);
    memory->create(work, nmax_work, "cgms/fluid:work");
  }
  const int nlocal = atom->nlocal;
  if (ivar >= 0 && input->variable->atomstyle(ivar)) {
    input->variable->compute_atom(ivar, igroup, work, 1, 0);
  } else {
    const double value = ivar >= 0 ? input->variable->compute_equal(ivar) : constant;
    for (int i = 0; i < nlocal; i++) work[i] = value;
  }
  return work;
}

/* ----------------------------------------------------------------------
   set the DRYNESS column of local beads and send it to the ghosts
------------------------------------------------------------------------- */

void FixCGMSFluid::apply_dryness()
{
  double **cg = bead_array(lmp);
  const int nlocal = atom->nlocal;

  if (!dryness_given) {
    // keep what the beads carry (e.g. from a restart file); new beads are fresh
    for (int i = 0; i < nlocal; i++)
      if (cg[i][MF0] <= 0.0) cg[i][DRYNESS] = 1.0;
  } else {
    const double *value = per_bead_values(dryness_ivar, dryness_value);
    for (int i = 0; i < nlocal; i++) {
      // a bead that already has a fluid state and gets a new dryness
      if (cg[i][MF0] > 0.0 && cg[i][DRYNESS] != value[i]) dryness_changed = 1;
      cg[i][DRYNESS] = value[i];
    }
  }

  int bad = -1;
  for (int i = 0; i < nlocal && bad < 0; i++)
    if (!(cg[i][DRYNESS] > 0.0 && cg[i][DRYNESS] <= 1.0)) bad = i;
  if (bad >= 0)
    error->one(FLERR, "Fix cgms/fluid: dryness {} of bead {} is out of range: it must be in (0, 1]",
               cg[bad][DRYNESS], atom->tag[bad]);

  double range[2] = {-2.0, 0.0};    // -min, max
  for (int i = 0; i < nlocal; i++) {
    range[0] = MAX(range[0], -cg[i][DRYNESS]);
    range[1] = MAX(range[1], cg[i][DRYNESS]);
  }
  double all[2];
  MPI_Allreduce(range, all, 2, MPI_DOUBLE, MPI_MAX, world);
  pair->set_uniform_dryness(-all[0] == all[1] ? all[1] : -1.0);
  check_dryness_range(-all[0], all[1]);

  forward(DRYNESS);
}

/* ----------------------------------------------------------------------
   beads read from a data file or created carry MF0 <= 0: give them the
   reference cell at their dryness (doc/model.md, Reference cell and initial state)
------------------------------------------------------------------------- */

bigint FixCGMSFluid::initialise_beads()
{
  const Material &mat = pair->material();
  double **cg = bead_array(lmp);
  double *rmass = atom->rmass;
  const int nlocal = atom->nlocal;
  const double *diameter =
      per_bead_values(diameter_ivar, diameter_value > 0.0 ? diameter_value : mat.diameter);

  int bad = -1;
  bigint fresh = 0;
  for (int i = 0; i < nlocal; i++) {
    double *c = cg[i];
    if (c[MF0] <= 0.0) {
      fresh++;
      // the reference cell of doc/model.md, for this bead's cell diameter
      const double d = diameter[i];
      if (!(d > 0.0) && bad < 0) bad = i;
      const ReferenceCell cell = reference_cell(d, mat.pectin);
      const double mf0 = mat.rho0 * mat.height * cell.A_ref;
      const double s = c[DRYNESS];
      c[MF0] = mf0;
      c[L0P] = mat.turgid_ratio * cell.l_ref;
      c[MF] = s * mf0;
      c[MS] = mat.solid_ratio * s * mf0;
      c[RHO] = s * mat.rho0;
      c[AREA] = 0.0;    // no previous area: the rate form starts from m_f / (h A)
      c[DMDT] = 0.0;
    }
    rmass[i] = inertia_fluid ? c[MF] + c[MS] : (1.0 + mat.solid_ratio) * c[MF0];
  }
  if (bad >= 0)
    error->one(FLERR, "Fix cgms/fluid: cell diameter {} of bead {} must be > 0", diameter[bad],
               atom->tag[bad]);
  bigint all = 0;
  MPI_Allreduce(&fresh, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  return all;
}

/* ----------------------------------------------------------------------
   beads without a fluid state take the one a data file brought (read_data
   ... fix CGMS NULL CGMS), each line checked first: a value out of range, or
   a bead of such a file without a line, stops here rather than giving the
   bead the fresh state or surfacing later as an unstable step. Returns how
   many beads took a state, over all ranks.
------------------------------------------------------------------------- */

bigint FixCGMSFluid::load_data_file_state()
{
  int flag, cols;
  const int index = atom->find_custom(DATA_PROPERTY, flag, cols);
  bigint loaded = 0;
  if (index >= 0 && flag == 1 && cols == NDATA) {
    double **data = atom->darray[index];
    double **cg = bead_array(lmp);
    for (int i = 0; i < atom->nlocal; i++) {
      if (cg[i][MF0] > 0.0) continue;
      bool line = false;    // no line leaves the row at 0 (NaN != 0 counts as a line)
      for (int k = 0; k < NDATA; k++) line = line || data[i][k] != 0.0;
      if (!line) {
        if (cg[i][MF0] == AWAITS_DATA_LINE)
          error->one(FLERR,
                     "Fix cgms/fluid: bead {} has no line in the data file's {} section: "
                     "give every bead of the file exactly one line 'id dryness mf ms mf0 l0p "
                     "rho area dmdt' (write_data writes them so)",
                     atom->tag[i], DATA_SECTION);
        continue;
      }
      const std::string problem = data_row_problem(data[i]);
      if (!problem.empty())
        error->one(FLERR,
                   "Fix cgms/fluid: the line of bead {} in the data file's {} section has {}; "
                   "correct the line (columns: id dryness mf ms mf0 l0p rho area dmdt) or write "
                   "the file again with write_data",
                   atom->tag[i], DATA_SECTION, problem);
      // the section holds the row, column by column; a declared fresh bead keeps none
      if (data[i][MF0] != NO_STATE) {
        for (int k = 0; k < NDATA; k++) cg[i][k] = data[i][k];
        loaded++;
      } else
        cg[i][MF0] = NO_STATE;
      for (int k = 0; k < NDATA; k++) data[i][k] = 0.0;    // the bead's own state rules now
    }
  }
  bigint all = 0;
  MPI_Allreduce(&loaded, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  return all;
}

/* ----------------------------------------------------------------------
   write_data: the section DATA_SECTION, one line "id value ..." per bead with
   its state row, at full precision
------------------------------------------------------------------------- */

void FixCGMSFluid::write_data_section_size(int, int &nx, int &ny)
{
  nx = atom->nlocal;
  ny = NDATA + 1;
}

void FixCGMSFluid::write_data_section_pack(int, double **buf)
{
  double **cg = bead_array(lmp);
  int flag, cols;
  const int index = atom->find_custom(DATA_PROPERTY, flag, cols);
  double **data = index >= 0 && flag == 1 && cols == NDATA ? atom->darray[index] : nullptr;
  for (int i = 0; i < atom->nlocal; i++) {
    buf[i][0] = ubuf(atom->tag[i]).d;
    // a bead without a state yet: the one a data file brought for it, not yet taken over
    // at a setup, or the line of a bead without one
    const double *row = cg[i];
    if (cg[i][MF0] <= 0.0) row = data && data[i][MF0] > 0.0 ? data[i] : nullptr;
    for (int k = 0; k < NDATA; k++) buf[i][k + 1] = row ? row[k] : 0.0;
    if (!row) buf[i][MF0 + 1] = NO_STATE;
  }
}

void FixCGMSFluid::write_data_section_keyword(int, FILE *fp)
{
  std::string hint;
  for (int k = 0; k < NDATA; k++) hint += std::string(" ") + column_names[STATE_OUTPUT[k]];
  fmt::print(fp, "\n{} # id{}\n\n", DATA_SECTION, hint);
}

void FixCGMSFluid::write_data_section(int, FILE *fp, int n, double **buf, int)
{
  for (int i = 0; i < n; i++) {
    std::string line = fmt::format("{}", (tagint) ubuf(buf[i][0]).i);
    for (int k = 1; k <= NDATA; k++) line += fmt::format(" {}", buf[i][k]);
    fmt::print(fp, "{}\n", line);
  }
}

/* ----------------------------------------------------------------------
   geometry (eqns 10-11), density, pressure (eqn 4), l_d (eqn 9), the mass
   rate (eqn 7) and the pair coefficient, for every local bead.
   advance = 1 (a time step): first the mass transfer of the previous step,
   m_f(n+1) = m_f(n) + dt dm_f/dt(n), and one step of the rate form of the
   density, eqns (5)-(6). advance = 0 (setup, minimize): neither.
   The mass transfer of step n is applied at the start of step n+1 rather
   than at its end: the same update, but the state at the end of a step (and
   so in a restart file) is the one its forces were computed from, so a
   restarted run recomputes the same forces at setup.
   transfer/scheme implicit stores dm_f/dt / (1 + dt lambda): a linearised
   backward Euler step, stable at any dt; the explicit step (the paper's) is
   unstable once dt lambda > 2, which a bead compressed by a third reaches at
   dt = 1e-7 s since lambda grows as (rho/rho_ref)^7. Same fixed point.
------------------------------------------------------------------------- */

void FixCGMSFluid::update_fluid_state(int advance)
{
  energy_local = 0.0;
  // with turgor, perimeter and mass transfer all off nothing reads this state
  if (!pair->pair_coefficient_needed() && !transfer) {
    if (output_step()) fill_outputs();
    return;
  }

  geometry_pass();
  // before the stability checks, which would blame the time step
  if (update->setupflag) check_setup_geometry();
  Trouble trouble;
  fluid_pass(advance, trouble);
  stop_if_unstable(trouble);
  passes_done = 1;
  if (output_step()) fill_outputs();
  if (pair->pair_coefficient_needed()) forward(-1);
}

/* ----------------------------------------------------------------------
   geometry: neighbour count and sum of centre distances of every bead (the
   compact sums, summed over ranks with newton on), and the distance of every
   neighbour-list entry for the pair's force loop
------------------------------------------------------------------------- */

void FixCGMSFluid::geometry_pass()
{
  const Material &mat = pair->material();
  double **x = atom->x;
  double **cg = bead_array(lmp);
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int newton_pair = force->newton_pair;
  const double cut = pair->cutoff();
  const double cutsq_fixed = cut * cut;
  const int scaled = pair->cutoff_scaled();
  const double s_uniform = pair->get_uniform_dryness();
  const int uniform = s_uniform > 0.0;
  const double cutsq_uniform = scaled && uniform ? pair->pair_cutsq(mat.lj_radius(s_uniform))
                                                 : cutsq_fixed;
  const int per_pair_cutoff = scaled && !uniform;

  if (atom->nmax > nmax_bead) {
    nmax_bead = atom->nmax;
    memory->destroy(coef);
    memory->create(coef, nmax_bead, "cgms/fluid:coef");
  }
  // the list's length, read every pass: neighbor->ncalls cannot tell one build from
  // another (Verlet and Min set it to 0 after their setup build, so the builds of
  // consecutive runs, e.g. the 'run 0' of every Newton force evaluation, repeat its values)
  // and a list that grows between runs would overrun rdist
  const bigint npairs = list_entries(list, comm->nthreads);
  if (npairs > rdist_size) {
    rdist_size = npairs + npairs / 4;
    memory->destroy(rdist);
    memory->create(rdist, rdist_size, "cgms/fluid:rdist");
  }
  // local copies: the loops then keep them in registers
  NeighbourSums *const sums = this->sums;
  double *const rdist = this->rdist;
  bigint k = 0;
  const int nclear = newton_pair ? nall : nlocal;
  for (int i = 0; i < nclear; i++) sums[i] = {0.0, 0.0};

  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  double s_last = -1.0, rad_last = 0.0;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double xtmp = x[i][0];
    const double ytmp = x[i][1];
    // the per-bead row only for a cutoff that varies by pair (a cache line per bead
    // on large tissues); there one log per change of s, not per bead
    const double si = per_pair_cutoff ? cg[i][DRYNESS] : 0.0;
    if (per_pair_cutoff && si != s_last) {
      s_last = si;
      rad_last = mat.lj_radius(si);
    }
    const double radi = rad_last;
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    double n = 0.0, sum = 0.0;
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double delx = xtmp - x[j][0];
      const double dely = ytmp - x[j][1];
      const double rsq = delx * delx + dely * dely;
      if (rsq >= (per_pair_cutoff ? pair->pair_cutsq(pair->pair_radius(si, cg[j][DRYNESS], radi))
                                  : cutsq_uniform)) {
        rdist[k++] = 0.0;
        continue;
      }
      const double r = sqrt(rsq);
      rdist[k++] = r;
      n += 1.0;
      sum += r;
      if (newton_pair || j < nlocal) {
        sums[j].count += 1.0;
        sums[j].distance += r;
      }
    }
    sums[i].count += n;
    sums[i].distance += sum;
  }
  rdist_list = list->firstneigh;
  rdist_valid = 1;
  if (newton_pair) comm->reverse_comm(this);
}

/* ----------------------------------------------------------------------
   what the material, the switches and the time step fix for a whole fluid
   pass, hoisted out of its loop, and the pass's parts for one bead.
   Divisions are the cost here: quantities that depend only on the dryness are
   recomputed when it changes from one bead to the next (DrynessLaws), and one
   reciprocal of the area serves the density and the implicit mass update.
------------------------------------------------------------------------- */

namespace {
struct FluidPassConstants {
  double dt, kT, kPA, kS, P_f, K, pectin, b_ref, height, inv_h, L_p;
  double conductance;    // membrane area l h times L_p, per l
  int advance, transfer, implicit, density_rate;
  // the quasi-static solve: every bead holds the pressure of the steady state
  int balance;
};

// the density: under a quasi-static solve the one of P = -Pi (doc/model.md, Steady
// state), with the fluid mass that fills the current cell with it; else the rate form of
// eqns (5)-(6) (density rate), or m_f / (h A)
inline double bead_density(const FluidPassConstants &p, const DrynessLaws &at, double *c,
                           double area, double inv_area)
{
  if (p.balance) {
    const double rho = tait_density(-at.Pi, at.P_ref, p.K, at.inv_rho_ref);
    c[MF] = rho * p.height * area;
    return rho;
  }
  if (p.density_rate && c[AREA] > 0.0) {
    if (!p.advance) return c[RHO];
    const double inv_area_old = 1.0 / c[AREA];
    return c[RHO] - c[RHO] * (area - c[AREA]) * inv_area_old +
        p.dt * c[DMDT] * p.inv_h * inv_area_old;
  }
  return c[MF] * p.inv_h * inv_area;
}

// eqn (7); the implicit scheme divides it by 1 + dt lambda when lambda > 0 (transfer_rate)
inline double bead_mass_rate(const FluidPassConstants &p, const DrynessLaws &at, double perim,
                             double inv_area, double rho, double press, double q7)
{
  if (!p.transfer || p.balance) return 0.0;
  double dmdt = mass_rate(perim, p.conductance, rho, press, at.Pi);
  if (p.implicit) {
    const double lambda = transfer_rate(p.L_p, perim, inv_area, press, at.Pi, p.K, q7);
    if (lambda > 0.0) dmdt /= 1.0 + p.dt * lambda;
  }
  return dmdt;
}

// the stability checks of one bead; stop_if_unstable() reports what they found
struct StabilityScan {
  StepLimits limits;
  double dt, pectin;
  int turgor, shape;
  // (omega dt)^2 allowed for the turgor force: right after a change of dryness, beads
  // keep the fluid of the old level against the reference of the new one: a large change
  // compresses them at once, the pressure spikes, and a step with omega dt > 2 blows up
  // (s from 1 to 0.5: omega dt 2.7 for a bead with one neighbour). There the strict
  // explicit limit applies.
  double turgor_bound;

  void bead(FixCGMSFluid::Trouble &t, int i, double nn, double sum_r, double q7, double press,
            const double *rmass, const NeighbourSums *sums) const
  {
    if (!std::isfinite(press) && t.nonfinite < 0) t.nonfinite = i;
    // turgor stiffness: eqn (4) makes a compressed bead a stiff spring. A neighbour
    // distance change dx changes P by 14 K q^7 dx / sum_k (x_k - d_p); for a bead pair
    // (reduced mass m/2) that gives omega^2 = 56 k_T K q^7 / (m sum_k (x_k - d_p)), and
    // the explicit update needs omega dt < 2. The estimate is rough: a squeezed pair at
    // omega dt = 2.8 relaxes before it can blow up, so the run stops only past 4, which
    // the blow-ups seen (a pair squeezed to 0.4 x_ref, a dryness jump) reach within a step.
    // Not under a quasi-static solve: there the pressure does not follow the geometry.
    if (turgor && nn > 0.0) {
      // (omega dt)^2 > 16 without a division in the common case
      const double sum_gap = sum_r - nn * pectin;
      if (limits.turgor_suspect(q7, rmass[i], sum_gap, turgor_bound)) {
        const double omega2 = limits.turgor_omega2(q7, rmass[i], sum_gap);
        const double ratio = dt * dt * omega2 / 4.0;    // (omega dt / 2)^2
        if (ratio > t.stiff_ratio) {
          t.stiff = i;
          t.stiff_ratio = ratio;
          t.stiff_limit = 2.0 / sqrt(omega2);
        }
      }
    }
    // the cell-shape term is a spring network of stiffness about 2 k_S per pair: omega^2
    // up to 8 k_S N / m, so the explicit step needs 2 k_S N dt^2 < m (the largest stable
    // k_S measured on a fresh 10 x 12 tissue at 1e-7 s lies between 1000 and 1200 N/m;
    // this gives 970: the damping uses up part of the margin)
    if (shape && limits.shape_exceeded(rmass[i], nn) &&
        (t.shaky < 0 || rmass[i] * sums[t.shaky].count < rmass[t.shaky] * nn))
      t.shaky = i;
    // damping stability (see damping_limit_error): the smallest m / N fails first
    if (limits.damping_exceeded(rmass[i], nn) &&
        (t.unstable < 0 || rmass[i] * sums[t.unstable].count < rmass[t.unstable] * nn))
      t.unstable = i;
  }
};
}    // namespace

/* ----------------------------------------------------------------------
   beads without a fluid state (MF0 <= 0) can appear only where beads were
   created during the run (set_arrays) or the atom count changed: looked for
   only then, not for every bead in every step. Returns the first, or -1.
------------------------------------------------------------------------- */

int FixCGMSFluid::bead_without_state()
{
  if (!beads_added && atom->natoms == natoms_known) return -1;
  double **cg = bead_array(lmp);
  for (int i = 0; i < atom->nlocal; i++)
    if (cg[i][MF0] <= 0.0) return i;
  beads_added = 0;
  natoms_known = atom->natoms;
  return -1;
}

/* ----------------------------------------------------------------------
   fluid state of every local bead: eqns (10-11), density, eqn (4), eqn (9),
   eqn (7), the pair coefficient, the quasi-static energy, and the beads that
   break a stability limit (stop_if_unstable() reports them)
------------------------------------------------------------------------- */

void FixCGMSFluid::fluid_pass(int advance, Trouble &trouble)
{
  const Material &mat = pair->material();
  double **cg = bead_array(lmp);
  double *rmass = atom->rmass;
  const int nlocal = atom->nlocal;

  FluidPassConstants p;
  p.dt = update->dt;
  p.kT = pair->turgor ? mat.k_T : 0.0;
  p.kPA = pair->perimeter ? mat.k_PA : 0.0;
  p.kS = mat.k_S;
  p.P_f = mat.P_f;
  p.K = mat.K;
  p.pectin = mat.pectin;
  p.b_ref = mat.b_ref;
  p.height = mat.height;
  p.inv_h = 1.0 / mat.height;
  p.conductance = mat.height * mat.L_p;
  p.L_p = mat.L_p;
  p.advance = advance;
  p.transfer = transfer;
  p.implicit = transfer_implicit;
  p.density_rate = density_rate;
  p.balance = always_balance || (minimize_balance && update->whichflag == 2);
  const int advance_mass = advance && transfer;
  // its energy is needed only where LAMMPS tallies energies (a second walk over the list)
  const int shape_energy = p.kS > 0.0 && (p.balance || update->eflag_global == update->ntimestep);
  StabilityScan scan{step_limits(), p.dt, p.pectin, 0, 0, 0.0};
  scan.turgor = p.kT > 0.0 && !p.balance;
  scan.shape = p.kS > 0.0 && !p.balance;
  scan.turgor_bound = dryness_changed ? 4.0 : 16.0;

  trouble.fresh = bead_without_state();
  if (trouble.fresh >= 0) return;
  // found beads in a local during the loop, into trouble after it
  Trouble found;
  found.after_change = dryness_changed;
  dryness_changed = 0;
  const NeighbourSums *const sums = this->sums;
  double *const coef = this->coef;
  double energy = 0.0;
  DrynessLaws at;
  const int periphery = pair->periphery;
  for (int i = 0; i < nlocal; i++) {
    double *c = cg[i];

    // mass transfer of the previous step, m_f(n+1) = m_f(n) + dt dm_f/dt(n)
    if (advance_mass) {
      c[MF] += p.dt * c[DMDT];
      if (!(c[MF] > 0.0) && found.emptied < 0) found.emptied = i;
      if (inertia_fluid) rmass[i] = c[MF] + c[MS];
    }

    if (c[DRYNESS] != at.s) at.set(c[DRYNESS], mat, periphery);
    const double nn = sums[i].count;
    const double sum_r = sums[i].distance;
    if (!(nn > 0.0) && !allow_isolated && found.isolated < 0) found.isolated = i;
    const double b = cell_side(nn, sum_r, at.beta, p.pectin, p.b_ref);
    const double area = HEX_AREA * b * b;
    const double inv_area = 1.0 / area;
    const double perim = 6.0 * b;
    const double rho = bead_density(p, at, c, area, inv_area);
    const double q7 = at.q7(rho);
    const double press = at.pressure(q7, p.K);
    const double ldeq = c[L0P] * at.ld_factor;

    // the state row only (one cache line); the outputs (N, side, perimeter,
    // pressure, l_d, the coefficient) are derived from it and the sums when an
    // output asks (for_each_output)
    c[DMDT] = bead_mass_rate(p, at, perim, inv_area, rho, press, q7);
    c[AREA] = area;
    c[RHO] = rho;
    coef[i] = pair_coefficient(p.kT, p.kPA, p.P_f, press, perim, ldeq);
    // the cell-shape term's share of bead i, k_S xbar_i (xbar_i = sum_k x_ik / N);
    // the per-atom output keeps the paper's turgor and perimeter coefficient
    if (p.kS > 0.0 && nn > 0.0) coef[i] += at.kS * sum_r / nn;
    // with the pressures held, turgor and perimeter forces are the gradient of the
    // quasi-static potential, as long as no neighbour crosses the cutoff: so minimize
    // can do line searches on them
    if (p.balance && nn > 0.0)
      energy += quasi_static_energy(p.kT, p.kPA, p.P_f, press, sum_r, perim, ldeq,
                                    perimeter_gradient(nn, at.beta));
    // The cell-shape energy k_S(s_i)/2 sum_k (x_ik - xbar_i)^2 does not depend on the
    // pressures: it is a potential in any run. Its -k_S(s_i)/2 N xbar_i^2 here, its
    // sum over pairs of (k_S(s_i) + k_S(s_k))/2 x^2 in shape_pair_energy()
    if (shape_energy && nn > 0.0) energy -= 0.5 * at.kS * sum_r * sum_r / nn;
    scan.bead(found, i, nn, sum_r, q7, press, rmass, sums);
  }

  energy_local += energy;
  if (shape_energy) energy_local += shape_pair_energy();
  trouble = found;
}

/* ---------------------------------------------------------------------- */

double FixCGMSFluid::shape_pair_energy() const
{
  // sum over neighbour pairs of (k_S(s_i) + k_S(s_k))/2 x^2 (x counted once from
  // each end), from the distances pass 1 cached per entry of the half list (0:
  // beyond the cutoff); without newton_pair a pair with a ghost is in the lists of
  // both of its ranks. k_S(s) differs between beads only with an exponent and a
  // dryness that varies (then forwarded to the ghosts, see pre_force)
  const Material &mat = pair->material();
  const double s_uniform = pair->get_uniform_dryness();
  const int by_bead = mat.k_S_exponent != 0.0 && s_uniform <= 0.0;
  const double kS = by_bead ? 0.0 : mat.shape_stiffness(s_uniform > 0.0 ? s_uniform : 1.0);
  double **cg = bead_array(lmp);
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  double energy = 0.0;
  bigint k = 0;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    const double kSi = by_bead ? mat.shape_stiffness(cg[i][DRYNESS]) : kS;
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const double r = rdist[k++];
      const int j = jlist[jj] & NEIGHMASK;
      const double kS_pair = by_bead ? 0.5 * (kSi + mat.shape_stiffness(cg[j][DRYNESS])) : kS;
      energy += (newton_pair || j < nlocal ? 1.0 : 0.5) * kS_pair * r * r;
    }
  }
  return energy;
}

/* ----------------------------------------------------------------------
   the quasi-static potential (J) of the last force evaluation while the
   pressures are held at -Pi (minimize, or balance yes); 0 otherwise, when
   turgor and perimeter forces have no potential
------------------------------------------------------------------------- */

double FixCGMSFluid::compute_scalar()
{
  double energy = 0.0;
  MPI_Allreduce(&energy_local, &energy, 1, MPI_DOUBLE, MPI_SUM, world);
  return energy;
}

/* ----------------------------------------------------------------------
   global outputs: 1 residual max|P + Pi|/|Pi_f|, 2 X/X0 = sum m_f / sum m_f0,
   3 largest bead speed, 4 kinetic energy, 5 estimated largest stable time
   step (0: no limit)
------------------------------------------------------------------------- */

double FixCGMSFluid::compute_vector(int n)
{
  // the outputs summarise the state this instance computes at setup; before
  // that (no run yet, or the fix was just defined again) there is none
  if (!setup_done)
    error->all(FLERR,
               "Fix cgms/fluid {}: its global outputs f_{}[1-5] exist only after this fix "
               "has been set up by a run: use them after 'run 0' or a run",
               id, id);
  if (vector_step != update->ntimestep) refresh_vector();
  return vector_cache[n];
}

void FixCGMSFluid::refresh_vector()
{
  const Material &mat = pair->material();
  double **cg = bead_array(lmp);
  double **v = atom->v;
  double *rmass = atom->rmass;

  // the explicit stability limits of the fluid pass (damping, turgor, cell shape),
  // from the neighbour sums of the last geometry pass; reduced as rates 1/dt^2
  const StepLimits limits = step_limits();
  double local_max[3] = {0.0, 0.0, 0.0}, local_sum[3] = {0.0, 0.0, 0.0};
  for_each_output([&](int i, const double *out) {
    const double *c = cg[i];
    local_max[0] = MAX(local_max[0], fabs(out[OUT_PRESS] + c[DRYNESS] * mat.Pi_f) / fabs(mat.Pi_f));
    const double nn = out[OUT_NNEIGH];
    if (nn > 0.0) {
      const double q7 = pow7(c[RHO] / (c[DRYNESS] * mat.rho0));
      const double limit = limits.smallest(rmass[i], nn, q7, sums[i].distance - nn * mat.pectin);
      local_max[2] = MAX(local_max[2], 1.0 / (limit * limit));
    }
    const double v2 = v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2];
    local_max[1] = MAX(local_max[1], v2);
    local_sum[0] += c[MF];
    local_sum[1] += c[MF0];
    local_sum[2] += 0.5 * rmass[i] * v2;
  });
  double global_max[3], global_sum[3];
  MPI_Allreduce(local_max, global_max, 3, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(local_sum, global_sum, 3, MPI_DOUBLE, MPI_SUM, world);

  vector_cache[0] = global_max[0];
  vector_cache[1] = global_sum[1] > 0.0 ? global_sum[0] / global_sum[1] : 0.0;
  vector_cache[2] = sqrt(global_max[1]);
  vector_cache[3] = global_sum[2];
  vector_cache[4] = global_max[2] > 0.0 ? 1.0 / sqrt(global_max[2]) : 0.0;
  vector_step = update->ntimestep;
}

/* ----------------------------------------------------------------------
   the per-atom array f_ID[1-14] is read by LAMMPS (dumps, fix ave/atom,
   variables, compute reduce, the library) without asking the fix first, and
   filling it costs a stream over every bead: it is filled only on the steps
   that are multiples of peratom_freq, and LAMMPS refuses a read at any other
   step during a run ("not computed at compatible time"). 'output auto' takes
   the largest step count that every thermo and dump step of this run, and its
   first and last step, are multiples of; 'output N' takes N (1: every step).
   Under minimize every step (the minimizer's iterations are its outputs).
------------------------------------------------------------------------- */

int FixCGMSFluid::output_frequency() const
{
  if (output_every > 0 || update->whichflag != 1) return output_every > 0 ? output_every : 1;
  bigint every = 0;
  auto include = [&every](bigint step) {
    if (step > 0) every = std::gcd(every, step);
  };
  include(update->firststep);
  include(update->laststep);
  if (output->var_thermo) every = 1;
  include(output->thermo_every);
  for (int i = 0; i < output->ndump; i++) {
    if (output->mode_dump[i] != 0 || output->every_dump[i] <= 0) every = 1;
    include(output->every_dump[i]);
  }
  if (every <= 0 || every > MAXSMALLINT) every = 1;
  return static_cast<int>(every);
}

int FixCGMSFluid::output_step() const
{
  return update->setupflag || update->whichflag != 1 || update->ntimestep % peratom_freq == 0 ||
      update->ntimestep == update->laststep;
}

/* ----------------------------------------------------------------------
   the outputs of every local bead i (CGMS::Output columns), handed to use(i,
   outputs): its state, and what the fluid pass derived from the state and the
   neighbour sums, recomputed by the same formulas; 0 where no pass has
   computed them yet (or the pair style that holds the material is gone)
------------------------------------------------------------------------- */

void FixCGMSFluid::for_each_output(const std::function<void(int, const double *)> &use) const
{
  const auto *pair = dynamic_cast<const PairCGMS *>(force->pair);
  double **cg = bead_array(lmp);
  const int nlocal = atom->nlocal;
  const int derived = passes_done && pair;
  DrynessLaws at;
  double out[NOUTPUTS];
  for (int i = 0; i < nlocal; i++) {
    const double *c = cg[i];
    for (int k = 0; k < NSTATE; k++) out[STATE_OUTPUT[k]] = c[k];
    out[OUT_COEF] = out[OUT_NNEIGH] = out[OUT_SIDE] = 0.0;
    out[OUT_PRESS] = out[OUT_PERIM] = out[OUT_LDEQ] = 0.0;
    if (derived && c[MF0] > 0.0) {
      const Material &mat = pair->material();
      if (c[DRYNESS] != at.s) at.set(c[DRYNESS], mat, pair->periphery);
      const double nn = sums[i].count;
      const double b = cell_side(nn, sums[i].distance, at.beta, mat.pectin, mat.b_ref);
      const double perim = 6.0 * b;
      const double press = at.pressure(at.q7(c[RHO]), mat.K);
      const double ldeq = c[L0P] * at.ld_factor;
      out[OUT_NNEIGH] = nn;
      out[OUT_SIDE] = b;
      out[OUT_PERIM] = perim;
      out[OUT_PRESS] = press;
      out[OUT_LDEQ] = ldeq;
      out[OUT_COEF] =
          pair_coefficient(pair->turgor ? mat.k_T : 0.0, pair->perimeter ? mat.k_PA : 0.0, mat.P_f,
                           press, perim, ldeq);
    }
    use(i, out);
  }
}

void FixCGMSFluid::fill_outputs()
{
  for_each_output([this](int i, const double *out) {
    for (int k = 0; k < NOUTPUTS; k++) outputs[i][k] = out[k];
  });
}

void FixCGMSFluid::pack_output(int column, double *buf, int nvalues, int groupbit)
{
  const int *mask = atom->mask;
  for_each_output([&](int i, const double *out) {
    buf[i * nvalues] = (mask[i] & groupbit) ? out[column] : 0.0;
  });
}

/* ----------------------------------------------------------------------
   column >= 0: that column of the state row; -1: the pair coefficients
------------------------------------------------------------------------- */

void FixCGMSFluid::forward(int column)
{
  comm_column = column;
  comm->forward_comm(this);
}

int FixCGMSFluid::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  if (comm_column < 0) {
    for (int i = 0; i < n; i++) buf[i] = coef[list[i]];
  } else {
    double **cg = bead_array(lmp);
    for (int i = 0; i < n; i++) buf[i] = cg[list[i]][comm_column];
  }
  return n;
}

void FixCGMSFluid::unpack_forward_comm(int n, int first, double *buf)
{
  if (comm_column < 0) {
    for (int i = 0; i < n; i++) coef[first + i] = buf[i];
  } else {
    double **cg = bead_array(lmp);
    for (int i = 0; i < n; i++) cg[first + i][comm_column] = buf[i];
  }
}

int FixCGMSFluid::pack_reverse_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) {
    buf[NSUMS * i] = sums[first + i].count;
    buf[NSUMS * i + 1] = sums[first + i].distance;
  }
  return NSUMS * n;
}

void FixCGMSFluid::unpack_reverse_comm(int n, int *list, double *buf)
{
  for (int i = 0; i < n; i++) {
    sums[list[i]].count += buf[NSUMS * i];
    sums[list[i]].distance += buf[NSUMS * i + 1];
  }
}
