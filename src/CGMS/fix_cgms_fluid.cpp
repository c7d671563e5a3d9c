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
    transfer_implicit(1), always_balance(0), minimize_balance(1), allow_isolated(0), beads_added(0),
    natoms_known(-1), outputs(nullptr), nmax_outputs(0), output_every(0), init_output_every(1),
    comm_column(DRYNESS), work(nullptr), nmax_work(0), setup_fresh(0), setup_loaded(0),
    vector_step(-1), setup_done(0)
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
  // the potential of the quasi-static problem, which pair_style cgms computes and counts
  // in its energy (evdwl, so pe: minimize needs it for its line search); the scalar
  // reports it. energy_global_flag keeps 'fix_modify ID energy' valid (see init).
  scalar_flag = 1;
  extscalar = 1;
  energy_global_flag = 1;
  thermo_energy = 0;
  peratom_flag = 1;
  size_peratom_cols = NOUTPUTS;
  peratom_freq = output_every > 0 ? output_every : 1;
  comm_forward = 1;        // the dryness of the ghosts
  wd_section = 1;          // the fluid state travels with write_data
  create_attribute = 1;    // set_arrays() learns of beads created during a run

  maxexchange = NOUTPUTS;
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
  memory->destroy(outputs);
}

/* ---------------------------------------------------------------------- */

double FixCGMSFluid::memory_usage()
{
  return sizeof(double) * ((double) NOUTPUTS * atom->nmax + nmax_work);
}

/* ---------------------------------------------------------------------- */

int FixCGMSFluid::setmask()
{
  return PRE_FORCE | MIN_PRE_FORCE | POST_FORCE | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixCGMSFluid::post_run()
{
  // between runs the per-atom array holds the last step's outputs, and any step
  // is compatible with it (write_dump, variables); the next run sets it again
  peratom_freq = output_every > 0 ? output_every : 1;
  if (update->whichflag == 2 && neighbour_sums(lmp)) warn_if_folded();
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
  pass_options_to_pair();

  neighbor->add_request(this);
}

/* ----------------------------------------------------------------------
   pair_style cgms computes the fluid state with this fix's settings, and
   counts the quasi-static energy in its own (evdwl, pe); this fix reports it
   as its scalar and adds nothing to pe: 'fix_modify ID energy yes' (which
   once added it here) would count it twice and is dropped with a warning
------------------------------------------------------------------------- */

void FixCGMSFluid::pass_options_to_pair()
{
  FluidOptions o;
  o.density_rate = density_rate;
  o.transfer = transfer;
  o.transfer_implicit = transfer_implicit;
  o.always_balance = always_balance;
  o.minimize_balance = minimize_balance;
  o.allow_isolated = allow_isolated;
  o.inertia_fluid = inertia_fluid;
  pair->set_fluid_options(o);
  if (thermo_energy && comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/fluid: fix_modify {} energy yes is not needed: pair_style cgms "
                   "counts the quasi-static energy in pe (evdwl) itself",
                   id);
  thermo_energy = 0;
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
  memory->grow(outputs, nmax, NOUTPUTS, "cgms/fluid:outputs");
  for (int i = nold; i < nmax; i++) {
    for (int k = 0; k < NOUTPUTS; k++) outputs[i][k] = 0.0;
  }
  nmax_outputs = nmax;
  array_atom = outputs;
}

void FixCGMSFluid::copy_arrays(int i, int j, int)
{
  for (int k = 0; k < NOUTPUTS; k++) outputs[j][k] = outputs[i][k];
}

int FixCGMSFluid::pack_exchange(int i, double *buf)
{
  for (int k = 0; k < NOUTPUTS; k++) buf[k] = outputs[i][k];
  return NOUTPUTS;
}

int FixCGMSFluid::unpack_exchange(int nlocal, double *buf)
{
  for (int k = 0; k < NOUTPUTS; k++) outputs[nlocal][k] = buf[k];
  return NOUTPUTS;
}

/* ----------------------------------------------------------------------
   a bead created during a run (fix deposit, fix pour: Modify::create_attribute)
   has no fluid state; the next fluid pass looks for such beads
------------------------------------------------------------------------- */

void FixCGMSFluid::set_arrays(int i)
{
  beads_added = 1;
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
  setup_loaded = load_data_file_state();
  apply_dryness();
  setup_fresh = initialise_beads();
  check_stored_state();
  beads_added = 0;
  natoms_known = atom->natoms;
}

/* ----------------------------------------------------------------------
   after the pair's passes of the setup: the checks of the user's geometry
   (before the stability checks, which would blame the time step), then as
   after every force evaluation
------------------------------------------------------------------------- */

void FixCGMSFluid::setup(int)
{
  if (pair->passes_needed()) check_setup_geometry();
  post_force(0);
  if (setup_fresh > 0 && setup_loaded == 0) warn_if_dried(setup_fresh);
  setup_done = 1;
}

void FixCGMSFluid::min_setup(int vflag)
{
  setup(vflag);
}

/* ----------------------------------------------------------------------
   a time step: the dryness schedule, before pair_style cgms applies the mass
   transfer of the previous step and computes the fluid state (its fluid pass)
------------------------------------------------------------------------- */

void FixCGMSFluid::pre_force(int)
{
  if (dryness_every > 0 && update->ntimestep % dryness_every == 0)
    apply_dryness();
  else
    refresh_ghost_dryness();
  const int fresh = bead_without_state();
  if (fresh >= 0) fresh_bead_error(fresh);
}

void FixCGMSFluid::min_pre_force(int)
{
  refresh_ghost_dryness();
  const int fresh = bead_without_state();
  if (fresh >= 0) fresh_bead_error(fresh);
}

/* ----------------------------------------------------------------------
   after every force evaluation: what the pair's fluid pass found beyond a
   limit stops the run; the per-atom outputs on the steps that write them
------------------------------------------------------------------------- */

void FixCGMSFluid::post_force(int)
{
  if (pair->passes_needed()) stop_if_unstable(pair->trouble());
  if (output_step()) fill_outputs();
}

void FixCGMSFluid::min_post_force(int vflag)
{
  post_force(vflag);
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
  const BeadState cg = bead_state(lmp);
  const int nlocal = atom->nlocal;

  if (!dryness_given) {
    // keep what the beads carry (e.g. from a restart file); new beads are fresh
    for (int i = 0; i < nlocal; i++)
      if (cg[i][MF0] <= 0.0) cg[i][DRYNESS] = 1.0;
  } else {
    const double *value = per_bead_values(dryness_ivar, dryness_value);
    for (int i = 0; i < nlocal; i++) {
      // a bead that already has a fluid state and gets a new dryness
      if (cg[i][MF0] > 0.0 && cg[i][DRYNESS] != value[i]) pair->note_dryness_changed();
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
  const BeadState cg = bead_state(lmp);
  double *rmass = atom->rmass;
  const int nlocal = atom->nlocal;
  const double *diameter =
      per_bead_values(diameter_ivar, diameter_value > 0.0 ? diameter_value : mat.diameter);

  int bad = -1;
  bigint fresh = 0;
  for (int i = 0; i < nlocal; i++) {
    const BeadRow c = cg[i];
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
    const BeadState cg = bead_state(lmp);
    for (int i = 0; i < atom->nlocal; i++) {
      bool line = false;    // no line leaves the row at 0 (NaN != 0 counts as a line)
      for (int k = 0; k < NDATA; k++) line = line || data[i][k] != 0.0;
      // a line is taken over once, by a bead that awaits it: then the bead's own state
      // rules. One whose state was changed meanwhile (set d_mf ...) would lose that.
      if (line) check_awaits_line(i);
      if (cg[i][MF0] > 0.0) continue;
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
  const BeadState cg = bead_state(lmp);
  int flag, cols;
  const int index = atom->find_custom(DATA_PROPERTY, flag, cols);
  double **data = index >= 0 && flag == 1 && cols == NDATA ? atom->darray[index] : nullptr;
  for (int i = 0; i < atom->nlocal; i++) {
    buf[i][0] = ubuf(atom->tag[i]).d;
    // a bead without a state yet: the one a data file brought for it, not yet taken over
    // at a setup, or the line of a bead without one
    const bool own = cg[i][MF0] > 0.0;
    const bool read = !own && data && data[i][MF0] > 0.0;
    for (int k = 0; k < NDATA; k++) buf[i][k + 1] = own ? cg[i][k] : read ? data[i][k] : 0.0;
    if (!own && !read) buf[i][MF0 + 1] = NO_STATE;
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
   beads without a fluid state (MF0 <= 0) can appear only where beads were
   created during the run (set_arrays) or the atom count changed: looked for
   only then, not for every bead in every step. Returns the first, or -1.
------------------------------------------------------------------------- */

int FixCGMSFluid::bead_without_state()
{
  if (!beads_added && atom->natoms == natoms_known) return -1;
  const BeadState cg = bead_state(lmp);
  for (int i = 0; i < atom->nlocal; i++)
    if (cg[i][MF0] <= 0.0) return i;
  beads_added = 0;
  natoms_known = atom->natoms;
  return -1;
}

/* ----------------------------------------------------------------------
   the quasi-static potential (J) of the last force evaluation while the
   pressures are held at -Pi (minimize, or balance yes); 0 otherwise, when
   turgor and perimeter forces have no potential
------------------------------------------------------------------------- */

double FixCGMSFluid::compute_scalar()
{
  const double local = pair ? pair->quasi_static_energy() : 0.0;
  double energy = 0.0;
  MPI_Allreduce(&local, &energy, 1, MPI_DOUBLE, MPI_SUM, world);
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
  const BeadState cg = bead_state(lmp);
  double **v = atom->v;
  double *rmass = atom->rmass;

  // the explicit stability limits of the fluid pass (damping, turgor, cell shape),
  // from the neighbour sums of the last geometry pass; reduced as rates 1/dt^2
  const StepLimits limits = pair->step_limits();
  const NeighbourSums *sums = neighbour_sums(lmp);
  double local_max[3] = {0.0, 0.0, 0.0}, local_sum[3] = {0.0, 0.0, 0.0};
  for_each_output([&](int i, const double *out) {
    const BeadRow c = cg[i];
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
   the outputs of every local bead, from pair_style cgms, which derives them
   (PairCGMS::for_each_output); the state alone when that style is gone
------------------------------------------------------------------------- */

void FixCGMSFluid::for_each_output(const std::function<void(int, const double *)> &use) const
{
  const auto *current = dynamic_cast<const PairCGMS *>(force->pair);
  if (current) return current->for_each_output(use);
  const BeadState cg = bead_state(lmp);
  double out[NOUTPUTS];
  for (int k = 0; k < NOUTPUTS; k++) out[k] = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < NSTATE; k++) out[STATE_OUTPUT[k]] = cg[i][k];
    use(i, out);
  }
}

void FixCGMSFluid::fill_outputs()
{
  for_each_output([this](int i, const double *out) {
    for (int k = 0; k < NOUTPUTS; k++) outputs[i][k] = out[k];
  });
}

/* ----------------------------------------------------------------------
   a column of the state row to the ghosts
------------------------------------------------------------------------- */

void FixCGMSFluid::forward(int column)
{
  comm_column = column;
  comm->forward_comm(this);
}

int FixCGMSFluid::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  const BeadState cg = bead_state(lmp);
  for (int i = 0; i < n; i++) buf[i] = cg[list[i]][comm_column];
  return n;
}

void FixCGMSFluid::unpack_forward_comm(int n, int first, double *buf)
{
  const BeadState cg = bead_state(lmp);
  for (int i = 0; i < n; i++) cg[first + i][comm_column] = buf[i];
}
