/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "fix_cgms_transport.h"

#include "cgms_column_cg.h"
#include "cgms_parameter_file.h"
#include "cgms_store.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "math_const.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

using namespace LAMMPS_NS;
using namespace FixConst;
using MathConst::MY_PI;

namespace {
constexpr double R_GAS = 8.314462618;    // J/(mol K)
constexpr double M_WATER = 0.018015;     // kg/mol
constexpr double M_AIR = 0.028965;       // kg/mol
constexpr double KELVIN = 273.15;
constexpr double P_ATM = 101325.0;    // Pa
constexpr int NVECTOR = 16;
enum { MODE_STATE, MODE_DIRECTION, MODE_SHIFT };

// the fix property/atom that holds every bead's transport state, and its array
constexpr char STATE_FIX[] = "CGMS_TRANSPORT";
constexpr const char *STATE_PROPERTY = CGMS::TRANSPORT_PROPERTY;
// the columns of a bead's row there: first the run's global state, the same in
// every row (fix property/atom holds no global values, and so restart files, data
// files, migration, sorting and atom deletion carry it with the beads), then the
// bead's column (X of every layer, S, A0, L0). The layout leads, so that a row of
// another layer count still tells its layers.
enum Row {
  R_LAYERS,    // layout
  R_FACES,
  R_X0,          // X0 of the parameter file the columns started from
  R_TIME,        // drying time (s)
  R_WATER0,      // initial water of the tissue (kg)
  R_OUT_FACE,    // water out through the faces and the outline (kg)
  R_OUT_EDGE,
  R_OUT_GONE,    // water, and initial water, of the beads deleted so far (kg)
  R_GONE0,
  R_WATER,    // water, dry solid and beads of the tissue at the last moisture step
  R_SOLIDS,
  R_BEADS,
  R_TPRODUCT,    // product temperature at the start of the last step (output 11)
  R_DTMOVE,      // length of the next moisture step (s)
  R_NMOVES,
  R_RATE,
  NHEAD
};
// first value of this fix's restart record (an older layout began with its layers)
constexpr double RESTART_LAYOUT = -2.0;
// halvings of an adaptive step that would drive a node below zero moisture
constexpr int MAX_HALVINGS = 60;
constexpr int MAX_LAYERS = 1000;
// the Reynolds numbers of the flat-plate correlations: the highest of the mixed one,
// and the lowest at which a boundary layer (Re >> 1) can still be claimed
constexpr double RE_MAX = 1e8;
constexpr double RE_MIN = 1.0;

// a bead whose widest angular gap between neighbours exceeds this is on the outline:
// on a hexagonal lattice an interior bead's gaps are 60 deg, a concave corner's open
// gap 120, a straight edge's 180, a convex corner's 240; 100 deg lies between 60 and
// 120 with 40 deg to spare for the shear of a shrunken tissue on the side of the many
// interior gaps (python/cgms/transport.py OPEN_GAP)
constexpr double OPEN_GAP = 100.0 * MY_PI / 180.0;
// passes of the [1, 2, 1] / 4 smoothing along the outline: a Gaussian of 2 beads
constexpr int OUTLINE_PASSES = 8;

// the functions of python/cgms/transport.py, one to one (their docstrings cite the sources)
double saturation_pressure(double t)
{
  return 611.21 * exp((18.678 - t / 234.5) * (t / (257.14 + t)));
}

double vapour_density(double p, double t)
{
  return p * M_WATER / (R_GAS * (t + KELVIN));
}

double latent_heat(double t)
{
  return 2.501e6 - 2.44e3 * t;
}

// GAB isotherm inverted: water activity and d aw / dX at dry-basis moisture x
void gab_activity(double x, double xm, double c, double k, double &aw, double &slope)
{
  x = MAX(x, 1e-12);
  const double a = x * (c - 1);
  const double b = -(x * (c - 2) - xm * c);
  const double disc = sqrt(b * b + 4 * a * x);
  const double y = fabs(a) > 1e-300 ? (-b + disc) / (2 * a) : x / (b == 0.0 ? 1.0 : b);
  aw = y / k;
  const double u = 1 - k * aw;
  const double w = 1 - k * aw + c * k * aw;
  const double dxda =
      xm * c * k * (u * w + aw * k * w - aw * u * k * (c - 1)) / ((u * w) * (u * w));
  if (aw >= 1.0) {
    aw = 1.0;
    slope = 0.0;
  } else
    slope = 1.0 / dxda;
}

// share of the surface law that reaches a node through a half-cell conductance g
// (none when neither conducts: a node at zero diffusivity behind free water)
inline double series(double g, double alpha)
{
  return g + alpha > 0.0 ? g / (g + alpha) : 0.0;
}
}    // namespace

/* ---------------------------------------------------------------------- */

FixCGMSTransport::FixCGMSTransport(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), list(nullptr), istate(-1), out(nullptr), own(nullptr), nmax_own(0),
    nmax_bead(0), rho_s(nullptr), dz(nullptr), area(nullptr), spacing(nullptr), edge(nullptr),
    xn(nullptr), dn(nullptr), diag(nullptr), lower(nullptr), c1(nullptr), c0(nullptr), c1f(nullptr),
    c0f(nullptr), bn(nullptr), xnew(nullptr), xbegin(nullptr), xfull(nullptr), comm_vec(nullptr),
    cg(nullptr), along(nullptr), shift(nullptr), shift_new(nullptr)
{
  if (narg < 4)
    error->all(FLERR,
               "Illegal fix cgms/transport command: fix ID group cgms/transport <params file> "
               "keyword value ...");
  if (igroup != 0)
    error->all(FLERR, "Fix cgms/transport: group must be all (every bead holds moisture)");
  if (domain->dimension != 2)
    error->all(FLERR, "Fix cgms/transport requires dimension 2 (the tissue is a slice)");
  if (strcmp(update->unit_style, "si") != 0)
    error->all(FLERR, "Fix cgms/transport requires units si (its parameters are SI), not units {}",
               update->unit_style);

  set_defaults();

  params_file = arg[3];
  read_params(arg[3]);
  parse_keywords(narg, arg);

  // the linear law has no vapour pressure, so no heat balance: D at the air temperature
  if (linear_law) heat = 0;
  multiplicity = faces == 2 ? 2 : 1;
  dt_given = dt_move;
  air_coefficients();

  initialised = 0;
  time = water0 = water = solids = out_face = out_edge = out_gone = gone0 = rate = 0.0;
  beads = 0;
  t_product = t_air;
  nmoves = 0;
  cg_iterations = 0;
  halvings = 0;
  comm_mode = MODE_STATE;
  // the outputs before the first setup: nothing has dried yet
  for (double &v : vec) v = 0.0;
  vec[2] = vec[7] = vec[8] = 1.0;
  vec[10] = t_air;
  vec[11] = dt_move;

  nstore = NHEAD + layers + 3;
  vector_flag = 1;
  size_vector = NVECTOR;
  global_freq = 1;
  extvector = 0;
  peratom_flag = 1;
  size_peratom_cols = 4;
  peratom_freq = 1;
  // the state lives in the fix property/atom STATE_FIX; this fix's own restart
  // record only tells which layout wrote the file
  restart_global = 1;
  comm_forward = layers + 2;
  dynamic_group_allow = 0;
  create_attribute = 1;
  maxexchange = 5;    // the outputs and the own flag
  wd_section = 1;     // only to say in the data file that the columns are not in it

  // the solver's ghost exchange: this fix's forward communication of a node array
  cg = new CGMS::ColumnCG(world, [this](double *v) {
    exchange_nodes(v);
  });

  FixCGMSTransport::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  // the beads present now own their rows (fresh, or from a restart file or an earlier
  // fix); beads created later do not
  for (int i = 0; i < atom->nlocal; i++) {
    for (int m = 0; m < 4; m++) out[i][m] = 1.0;
    own[i] = 1;
  }
}

/* ----------------------------------------------------------------------
   the keywords' defaults (doc/fix_cgms_transport.rst)
------------------------------------------------------------------------- */

void FixCGMSTransport::set_defaults()
{
  layers = 10;
  faces = 2;
  inplane = outline = heat = shrink = 1;
  t_air = 70.0;
  humidity = 0.1;
  velocity = 1.5;
  plate = 0.04;
  thickness = 2e-3;
  linear_law = 0;
  hx = xeq = 0.0;
  cutoff_user = 0.0;
  s_min = 0.3;
  dt_move = 1.0;
  dx_max = dt_max = 0.0;
  cg_tol = 1e-14;
  cg_max = 2000;
  until = -1.0;
  nevery = 1;
}

/* ----------------------------------------------------------------------
   the keywords after the parameter file, each checked where it is read
------------------------------------------------------------------------- */

void FixCGMSTransport::parse_keywords(int narg, char **arg)
{
  int iarg = 4;
  auto need = [&](int n) {
    if (iarg + n >= narg)
      error->all(FLERR, "Fix cgms/transport keyword '{}' needs {} value(s)", arg[iarg], n);
  };
  // a number too large for a double reads as inf, and no keyword takes one
  auto number = [&](int k) {
    const double v = utils::numeric(FLERR, arg[k], false, lmp);
    if (!std::isfinite(v))
      error->all(FLERR, "Fix cgms/transport {} must be a finite number, got {}", arg[iarg], arg[k]);
    return v;
  };
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (key == "every") {
      need(1);
      nevery = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (nevery < 1) error->all(FLERR, "Fix cgms/transport every must be >= 1, got {}", nevery);
      iarg += 2;
    } else if (key == "dt") {
      need(1);
      dt_move = number(iarg + 1);
      if (!(dt_move > 0.0))
        error->all(FLERR, "Fix cgms/transport dt (s) must be > 0, got {}", dt_move);
      iarg += 2;
    } else if (key == "adapt") {
      need(2);
      dx_max = number(iarg + 1);
      dt_max = number(iarg + 2);
      if (!(dx_max > 0.0) || !(dt_max > 0.0))
        error->all(FLERR, "Fix cgms/transport adapt dx_max dt_max: both must be > 0, got {} {}",
                   dx_max, dt_max);
      iarg += 3;
    } else if (key == "layers") {
      need(1);
      layers = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (layers < 1 || layers > MAX_LAYERS)
        error->all(FLERR,
                   "Fix cgms/transport layers must be >= 1 and <= {} (finer than a cell is "
                   "not resolved by a tissue of cells), got {}",
                   MAX_LAYERS, layers);
      iarg += 2;
    } else if (key == "faces") {
      need(1);
      faces = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (faces < 0 || faces > 2)
        error->all(FLERR, "Fix cgms/transport faces must be 0, 1 or 2 (slice faces in air), got {}",
                   faces);
      iarg += 2;
    } else if (key == "inplane" || key == "outline" || key == "heat" || key == "shrink") {
      need(1);
      int v = utils::logical(FLERR, arg[iarg + 1], false, lmp);
      if (key == "inplane")
        inplane = v;
      else if (key == "outline")
        outline = v;
      else if (key == "heat")
        heat = v;
      else
        shrink = v;
      iarg += 2;
    } else if (key == "temperature" || key == "humidity" || key == "velocity" || key == "plate" ||
               key == "thickness" || key == "cutoff" || key == "smin") {
      need(1);
      set_number_keyword(key, number(iarg + 1));
      iarg += 2;
    } else if (key == "surface") {
      need(1);
      if (strcmp(arg[iarg + 1], "vapour") == 0) {
        linear_law = 0;
        iarg += 2;
      } else if (strcmp(arg[iarg + 1], "linear") == 0) {
        need(3);
        linear_law = 1;
        hx = number(iarg + 2);
        xeq = number(iarg + 3);
        if (!(hx > 0.0))
          error->all(FLERR,
                     "Fix cgms/transport surface linear: h_x must be > 0 kg/(m^2 s), got {} "
                     "(for a slice sealed from the air use faces 0 and outline no)",
                     hx);
        if (!(xeq >= 0.0))
          error->all(FLERR,
                     "Fix cgms/transport surface linear: X_eq is the equilibrium dry-basis "
                     "moisture (kg water per kg dry solid) and must be >= 0, got {}",
                     xeq);
        iarg += 4;
      } else
        error->all(FLERR,
                   "Fix cgms/transport surface must be 'vapour' or 'linear h_x X_eq', got '{}'",
                   arg[iarg + 1]);
    } else if (key == "until") {
      need(1);
      until = number(iarg + 1);
      if (!(until > 0.0))
        error->all(FLERR, "Fix cgms/transport until (s of drying) must be > 0, got {}", until);
      iarg += 2;
    } else if (key == "tolerance") {
      need(1);
      cg_tol = number(iarg + 1);
      if (!(cg_tol > 0.0 && cg_tol < 1.0))
        error->all(FLERR, "Fix cgms/transport tolerance must be in (0, 1), got {}", cg_tol);
      iarg += 2;
    } else
      error->all(FLERR,
                 "Unknown fix cgms/transport keyword '{}' (known: every dt adapt layers faces "
                 "inplane outline heat shrink temperature humidity velocity plate thickness "
                 "cutoff smin surface until tolerance)",
                 key);
  }
}

/* ----------------------------------------------------------------------
   the air and size keywords, one finite number each
------------------------------------------------------------------------- */

void FixCGMSTransport::set_number_keyword(const std::string &key, double v)
{
  if (key == "temperature") {
    if (!(v > -20.0 && v < 150.0))
      error->all(
          FLERR,
          "Fix cgms/transport temperature is the air temperature in deg C (-20 to 150), got {}", v);
    t_air = v;
  } else if (key == "humidity") {
    if (!(v >= 0.0 && v < 1.0))
      error->all(FLERR, "Fix cgms/transport humidity is a relative humidity, 0 <= RH < 1, got {}",
                 v);
    humidity = v;
  } else if (key == "velocity" && !(v > 0.0)) {
    error->all(FLERR,
               "Fix cgms/transport velocity must be > 0 m/s, got {}: the air-side "
               "coefficients come from forced convection over the slice (Sherwood number "
               "of a flat plate), which needs moving air; natural convection is not "
               "modelled. For a slice sealed from the air use faces 0 and outline no",
               v);
  } else if (key == "smin" && !(v > 0.0 && v <= 1.0)) {
    error->all(FLERR,
               "Fix cgms/transport smin is the lowest dryness handed to the mechanics, "
               "0 < smin <= 1 (fix cgms/fluid takes dryness in (0, 1]), got {}",
               v);
  } else {
    if (key != "smin" && !(v > 0.0))
      error->all(FLERR, "Fix cgms/transport {} (m) must be > 0, got {}", key, v);
    if (key == "velocity")
      velocity = v;
    else if (key == "plate")
      plate = v;
    else if (key == "thickness")
      thickness = v;
    else if (key == "cutoff")
      cutoff_user = v;
    else
      s_min = v;
  }
}

/* ----------------------------------------------------------------------
   the state store: a fix property/atom with a fixed ID, made by the first
   transport fix and kept when this fix is replaced or deleted, so that the
   tissue's moisture travels with its beads as its fluid state does (sorting,
   migration, deletion, restart files under any ID of this fix). After
   read_restart, defining it again (here) restores its rows. It stays out of
   data files: read_data reads at most 256 characters of a line, fewer than a
   row of full-precision values (check_not_dried guards that gap).
------------------------------------------------------------------------- */

void FixCGMSTransport::post_constructor()
{
  if (!modify->get_fix_by_id(STATE_FIX)) {
    const int stored = restart_store_size();
    if (stored > 0 && stored != nstore) refuse_store_size(stored);
    modify->add_fix(fmt::format("{} all property/atom d2_{} {} writedata no", STATE_FIX,
                                STATE_PROPERTY, nstore));
  }
  bind_state();
  check_state_layout();
  for (int i = 0; i < atom->nlocal; i++) set_output(i);
}

/* ---------------------------------------------------------------------- */

FixCGMSTransport::~FixCGMSTransport()
{
  if (modify->get_fix_by_id(id)) atom->delete_callback(id, Atom::GROW);
  memory->destroy(out);
  memory->destroy(own);
  for (double **p : {&rho_s, &dz, &area, &spacing, &edge, &xn, &dn, &diag, &lower, &c1, &c0, &c1f,
                     &c0f, &bn, &xnew, &xbegin, &xfull})
    memory->destroy(*p);
  delete cg;
  memory->destroy(shift);
  memory->destroy(shift_new);
  memory->destroy(along);
}

/* ---------------------------------------------------------------------- */

int FixCGMSTransport::setmask()
{
  return END_OF_STEP;
}

/* ----------------------------------------------------------------------
   the parameters file of python/cgms/drying.py read_params: "name value"
   lines, '#' comments; every name below is needed, others are refused
------------------------------------------------------------------------- */

void FixCGMSTransport::read_params(const char *file)
{
  const char *names[] = {"X0",         "solids_density", "D_ref", "T_ref", "D_energy",
                         "D_moisture", "GAB_Xm",         "GAB_C", "GAB_K"};
  double *targets[] = {&x0,         &solids_density, &d_ref, &t_ref, &d_energy,
                       &d_moisture, &gab_xm,         &gab_c, &gab_k};
  const int n = 9;
  const auto where = fmt::format("Fix cgms/transport: {}", file);
  int given = 0;
  for (const auto &p : CGMS::read_parameter_file(
           lmp, file, where,
           fmt::format("Fix cgms/transport: cannot open parameter file {} (looked in the "
                       "current folder and LAMMPS_POTENTIALS)",
                       file))) {
    int k = 0;
    while (k < n && p.name != names[k]) k++;
    if (k == n) error->all(FLERR, "{} line {}: unknown parameter '{}'", where, p.line, p.name);
    if (!utils::is_double(p.value))
      error->all(FLERR, "{} line {}: '{}' is not a number", where, p.line, p.value);
    // strtod, not stod: a value beyond a double is inf, refused below, not an exception
    *targets[k] = strtod(p.value.c_str(), nullptr);
    if (!std::isfinite(*targets[k]))
      error->all(FLERR, "{} line {}: {} = {} is beyond a double", where, p.line, p.name, p.value);
    given |= 1 << k;
  }
  std::string missing;
  for (int k = 0; k < n; k++)
    if (!(given & (1 << k))) missing += std::string(missing.empty() ? "" : ", ") + names[k];
  if (!missing.empty()) error->all(FLERR, "{} misses {}", where, missing);
  if (!(x0 > 0.0) || !(solids_density > 0.0) || !(d_ref > 0.0) || !(t_ref > -KELVIN) ||
      !(gab_xm > 0.0) || !(gab_c > 1.0) || !(gab_k > 0.0 && gab_k < 1.0))
    error->all(FLERR,
               "Fix cgms/transport: {}: needs X0 > 0, solids_density > 0, D_ref > 0, "
               "T_ref above absolute zero (-273.15 C), GAB_Xm > 0, GAB_C > 1 and 0 < GAB_K < 1",
               file);
}

/* ----------------------------------------------------------------------
   k_c and h of a flat plate in air (python/cgms/transport.py air_coefficients:
   Sutherland viscosity, Marrero and Mason diffusivity, laminar or mixed
   Sherwood number, Chilton-Colburn for h)
------------------------------------------------------------------------- */

void FixCGMSTransport::air_coefficients()
{
  const double t = t_air + KELVIN;
  const double rho = P_ATM * M_AIR / (R_GAS * t);
  const double mu = 1.716e-5 * pow(t / 273.15, 1.5) * (273.15 + 110.4) / (t + 110.4);
  const double cp = 1007.0;
  const double k = 0.0241 * pow(t / 273.15, 0.81);
  const double dva = 1.87e-10 * pow(t, 2.072);
  const double nu = mu / rho;
  const double pr = mu * cp / k, sc = nu / dva;
  const double re = velocity * plate / nu;
  if (re > RE_MAX || re < RE_MIN)
    error->all(FLERR,
               "Fix cgms/transport: air at {} m/s over a plate of {} m has a Reynolds number of "
               "{:.3g}, outside {:g} to {:g}, the range of the flat-plate boundary-layer "
               "Sherwood correlations (Incropera et al. 2007, eqs. 7.30 and 7.38; a boundary "
               "layer needs Re >> 1): give another velocity or plate",
               velocity, plate, re, RE_MIN, RE_MAX);
  const double sh = re < 5e5 ? 0.664 * sqrt(re) * cbrt(sc)
                             : (0.037 * pow(re, 0.8) - 871.0) * cbrt(sc);
  kc = sh * dva / plate;
  hc = kc * rho * cp * pow(sc / pr, 2.0 / 3.0);
}

/* ---------------------------------------------------------------------- */

void FixCGMSTransport::init()
{
  if (!force->pair && cutoff_user <= 0.0)
    error->all(FLERR,
               "Fix cgms/transport needs a pair style or the cutoff keyword: its neighbours "
               "are the beads within that distance");
  // one transport state per system: two fixes would both step its columns (each bead
  // dried twice per step, and the water balance broken)
  for (auto *other : modify->get_fix_by_style("^cgms/transport$"))
    if (other != this)
      error->all(FLERR,
                 "Fix cgms/transport {}: fix {} dries this tissue already (both would step its "
                 "one set of moisture columns, fix {}): unfix {} first, or define fix {} again "
                 "to change its settings",
                 id, other->id, STATE_FIX, other->id, other->id);
  cutoff = cutoff_user > 0.0 ? cutoff_user : force->pair->cutforce;
  double ghost = comm->cutghostuser;
  if (force->pair) ghost = MAX(force->pair->cutforce + neighbor->skin, ghost);
  if (cutoff + neighbor->skin > ghost)
    error->all(FLERR,
               "Fix cgms/transport cutoff {} m plus skin exceeds the ghost range {} m: "
               "use comm_modify cutoff",
               cutoff, ghost);
  auto req = neighbor->add_request(this, NeighConst::REQ_FULL | NeighConst::REQ_OCCASIONAL);
  if (cutoff_user > 0.0) req->set_cutoff(cutoff_user + neighbor->skin);

  bind_state();
  if (!initialised) {
    int local = 0, any;
    for (int i = 0; i < atom->nlocal && !local; i++) local = has_column(i) ? 1 : 0;
    MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, world);
    if (!any) check_not_dried();
  }
}

void FixCGMSTransport::init_list(int, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   first run: every bead's column gets the fresh moisture X0, its dry solid
   from the current geometry (the fresh state) and the fresh thickness
------------------------------------------------------------------------- */

void FixCGMSTransport::setup(int)
{
  bind_state();
  check_state_layout();
  check_beads();
  if (!initialised) {
    bigint with = 0, local = 0;
    for (int i = 0; i < atom->nlocal; i++) local += has_column(i) ? 1 : 0;
    MPI_Allreduce(&local, &with, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    if (with == 0)
      initialise_columns();
    else
      load_globals();
    initialised = 1;
  }
  check_columns();
  account_removed();
  for (int i = 0; i < atom->nlocal; i++) set_output(i);
  refresh_vector();
  save_globals();
  if (until > 0.0 && time >= until - 1e-9 && comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/transport {}: the tissue has dried for {:.6g} s, at or past until "
                   "{:.6g} s: this run makes no moisture step",
                   id, time, until);
}

/* ----------------------------------------------------------------------
   a run needs beads to dry: with none (all deleted) the tissue's X/X0 and
   drying rate are 0/0
------------------------------------------------------------------------- */

void FixCGMSTransport::check_beads()
{
  if (atom->natoms == 0)
    error->all(FLERR,
               "Fix cgms/transport {}: the system has no beads (none read, or all deleted): "
               "there is no tissue to dry; unfix {} for a run without beads",
               id, id);
}

/* ----------------------------------------------------------------------
   the rows of the state store, and bead i's column in them
------------------------------------------------------------------------- */

double **FixCGMSTransport::rows() const
{
  return atom->darray[istate];
}

double *FixCGMSTransport::column(int i) const
{
  return atom->darray[istate][i] + NHEAD;
}

// the row is this bead's own: a bead created later may find the row of a deleted
// one in its slot, so the fix marks the beads it knows (own)
bool FixCGMSTransport::has_column(int i) const
{
  return own[i] && atom->darray[istate][i][NHEAD + layers] > 0.0;
}

void FixCGMSTransport::bind_state()
{
  Fix *holder = modify->get_fix_by_id(STATE_FIX);
  if (!holder || strcmp(holder->style, "property/atom") != 0)
    error->all(FLERR,
               "Fix cgms/transport keeps the moisture columns in fix {} (property/atom), "
               "which {}; unfix {} and define this fix again",
               STATE_FIX, holder ? "has another style" : "was deleted", id);
  int flag, cols;
  istate = atom->find_custom(STATE_PROPERTY, flag, cols);
  if (istate < 0 || flag != 1 || cols < 0)
    error->all(FLERR, "Fix cgms/transport: fix {} must hold the per-atom array d2_{}", STATE_FIX,
               STATE_PROPERTY);
  if (cols != nstore) refuse_store_size(cols);
}

void FixCGMSTransport::refuse_store_size(int cols)
{
  error->all(FLERR,
             "Fix cgms/transport: fix {} holds the tissue's moisture columns with {} values "
             "per bead, the state of {} layers; this fix has layers {}: give layers {} (or "
             "unfix {} to start the tissue afresh at X0)",
             STATE_FIX, cols, cols - NHEAD - 3, layers, cols - NHEAD - 3, STATE_FIX);
}

/* ----------------------------------------------------------------------
   after read_restart the store's rows wait in atom->extra, one set per fix
   of the restart file, each [count, values...]. LAMMPS hands a new fix
   property/atom as many values as it holds, whatever the set's count, so a
   store of another size would read past its set: find the set by its
   layout (a count that matches the layers its row records) and refuse
   another size before the store is made. -1: no such set.
------------------------------------------------------------------------- */

int FixCGMSTransport::restart_store_size() const
{
  int local = -1;
  if (modify->nfix_restart_peratom > 0 && atom->extra && atom->nlocal > 0) {
    const double *set = atom->extra[0];
    int m = 0;
    for (int j = 0; j < modify->nfix_restart_peratom; j++) {
      const int count = static_cast<int>(set[m]);
      if (count < 1 || m + count > atom->nextra_store) break;
      const double stored_layers = count > 1 + NHEAD ? set[m + 1 + R_LAYERS] : 0.0;
      if (stored_layers >= 1.0 && stored_layers <= MAX_LAYERS &&
          count == 1 + NHEAD + static_cast<int>(stored_layers) + 3)
        local = count - 1;
      m += count;
    }
  }
  int size;
  MPI_Allreduce(&local, &size, 1, MPI_INT, MPI_MAX, world);
  return size;
}

/* ----------------------------------------------------------------------
   the columns the beads carry (from a restart file or an earlier fix) must have been made with this fix's layers, faces and X0
------------------------------------------------------------------------- */

void FixCGMSTransport::check_state_layout()
{
  double **row = rows();
  int bad = -1;
  for (int i = 0; i < atom->nlocal && bad < 0; i++) {
    if (!(row[i][NHEAD + layers] > 0.0)) continue;
    if (row[i][R_LAYERS] != layers || row[i][R_FACES] != faces || row[i][R_X0] != x0) bad = i;
  }
  const tagint mine = bad >= 0 ? atom->tag[bad] : MAXTAGINT;
  tagint first;
  MPI_Allreduce(&mine, &first, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (first == MAXTAGINT) {
    check_thickness();
    return;
  }
  double found[3] = {0.0, 0.0, 0.0}, all[3];
  if (bad >= 0 && atom->tag[bad] == first)
    for (int k = 0; k < 3; k++) found[k] = row[bad][R_LAYERS + k];
  MPI_Allreduce(found, all, 3, MPI_DOUBLE, MPI_SUM, world);
  error->all(FLERR,
             "Fix cgms/transport: the tissue's moisture columns (from a restart file or an "
             "earlier fix) hold {} layers and faces {} from X0 {}; this fix has "
             "layers {} faces {} and X0 {} ({}): give the same (or unfix {} to start the "
             "tissue afresh at X0)",
             all[0], all[1], all[2], layers, faces, x0, params_file, STATE_FIX);
}

/* ----------------------------------------------------------------------
   every column keeps the fresh thickness L0 and the dry solid S = rho_s A0 L0
   it was set up with: a fix with another thickness or solids_density would
   run on as if it had not been given them
------------------------------------------------------------------------- */

void FixCGMSTransport::check_thickness()
{
  // the relative change of rho_s that S / (A0 L0) carries: a few roundings
  constexpr double ROUNDING = 1e-12;
  double local[2] = {0.0, 0.0}, stored[2];
  for (int i = 0; i < atom->nlocal; i++) {
    if (!has_column(i)) continue;
    const double *col = column(i);
    if (col[layers + 2] != thickness) local[0] = col[layers + 2];
    const double rho = col[layers] / (col[layers + 1] * col[layers + 2]);
    if (fabs(rho / solids_density - 1.0) > ROUNDING) local[1] = rho;
  }
  MPI_Allreduce(local, stored, 2, MPI_DOUBLE, MPI_MAX, world);
  if (stored[0] != 0.0)
    error->all(FLERR,
               "Fix cgms/transport {}: the tissue's moisture columns (from a restart file or "
               "an earlier fix) were set up for a slice thickness of {} m, this fix has "
               "thickness {} m; a drying slice keeps its fresh thickness: give thickness {} "
               "(or unfix {} to start the tissue afresh at X0)",
               id, stored[0], thickness, stored[0], STATE_FIX);
  if (stored[1] != 0.0)
    error->all(FLERR,
               "Fix cgms/transport {}: the tissue's moisture columns (from a restart file or "
               "an earlier fix) hold the dry solid of solids_density {:.10g} kg/m^3, {} has "
               "{:.10g}; the dry solid of a column does not change: give the parameter file "
               "the columns started from (or unfix {} to start the tissue afresh at X0)",
               id, stored[1], params_file, solids_density, STATE_FIX);
}

/* ----------------------------------------------------------------------
   every bead has its own column once the tissue's columns exist
------------------------------------------------------------------------- */

void FixCGMSTransport::check_columns()
{
  tagint bare = MAXTAGINT, first;
  for (int i = 0; i < atom->nlocal; i++)
    if (!has_column(i)) bare = MIN(bare, atom->tag[i]);
  MPI_Allreduce(&bare, &first, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (first != MAXTAGINT)
    error->all(FLERR,
               "Fix cgms/transport: bead {} has no moisture column: it was added after the "
               "tissue's columns were set up (create_atoms, fix deposit, read_data add). "
               "Create every bead before the first run of fix cgms/transport, or delete the "
               "new ones",
               first);
}

/* ----------------------------------------------------------------------
   a tissue without columns starts at X0; refuse that for one the fluid state
   shows dried (its dryness below 1, e.g. from a data file, which cannot carry
   the columns), which would silently undo its drying. Checked at init, before
   fix cgms/fluid takes the dryness of this fix's (fresh) output.
------------------------------------------------------------------------- */

void FixCGMSTransport::check_not_dried()
{
  if (!utils::strmatch(atom->atom_style, "^cgms")) return;
  const CGMS::BeadState cg = CGMS::bead_state(lmp);
  int flag, cols;
  const int index = atom->find_custom(CGMS::DATA_PROPERTY, flag, cols);
  double **data = index >= 0 && flag == 1 && cols == CGMS::NDATA ? atom->darray[index] : nullptr;
  tagint dried = MAXTAGINT;
  for (int i = 0; i < atom->nlocal; i++) {
    const bool held = cg && cg[i][CGMS::MF0] > 0.0 && cg[i][CGMS::DRYNESS] < 1.0;
    const bool read = data && data[i][CGMS::MF0] > 0.0 && data[i][CGMS::DRYNESS] < 1.0;
    if (held || read) dried = MIN(dried, atom->tag[i]);
  }
  // the data file said where the columns were dropped (every rank that read it)
  const std::string &note = CGMS::dropped_columns_note(lmp);
  int local = note.empty() ? 0 : 1, noted;
  MPI_Allreduce(&local, &noted, 1, MPI_INT, MPI_MAX, world);
  if (noted && !note.empty())
    error->one(FLERR,
               "Fix cgms/transport: the tissue was read from a data file written after fix "
               "cgms/transport had dried it ({} says its moisture columns are not in the "
               "file): starting them at X0 would undo its drying. Continue a dried tissue "
               "from a restart file (write_restart, read_restart); to start its drying "
               "afresh at X0 on purpose, delete that line from the data file",
               note);
  else if (noted)
    error->all(FLERR,
               "Fix cgms/transport: the tissue was read from a data file written after "
               "fix cgms/transport had dried it, without its moisture columns: continue "
               "it from a restart file");
  tagint first;
  MPI_Allreduce(&dried, &first, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (first != MAXTAGINT)
    error->all(FLERR,
               "Fix cgms/transport: bead {} has a dryness below 1 (a dried tissue) but the "
               "tissue has no moisture columns: starting them at X0 would undo its drying. "
               "Data files cannot carry the columns (read_data reads at most 256 characters "
               "of a line); continue a dried tissue from a restart file (write_restart, "
               "read_restart). To start drying a tissue held at a lower dryness, give it "
               "dryness 1 first",
               first);
}

/* ----------------------------------------------------------------------
   the global state from the rows (the same in every bead's row), and back
------------------------------------------------------------------------- */

void FixCGMSTransport::load_globals()
{
  int first = -1;
  for (int i = 0; i < atom->nlocal && first < 0; i++)
    if (has_column(i)) first = i;
  int mine = first >= 0 ? comm->me : comm->nprocs, root;
  MPI_Allreduce(&mine, &root, 1, MPI_INT, MPI_MIN, world);
  double head[NHEAD];
  if (comm->me == root)
    for (int k = 0; k < NHEAD; k++) head[k] = rows()[first][k];
  MPI_Bcast(head, NHEAD, MPI_DOUBLE, root, world);
  time = head[R_TIME];
  water0 = head[R_WATER0];
  out_face = head[R_OUT_FACE];
  out_edge = head[R_OUT_EDGE];
  out_gone = head[R_OUT_GONE];
  gone0 = head[R_GONE0];
  water = head[R_WATER];
  solids = head[R_SOLIDS];
  beads = (bigint) head[R_BEADS];
  t_product = head[R_TPRODUCT];
  // an adaptive step continues at its length; a fixed one is the dt keyword
  dt_move = dx_max > 0.0 ? MIN(head[R_DTMOVE], dt_max) : dt_given;
  nmoves = (bigint) head[R_NMOVES];
  rate = head[R_RATE];
}

void FixCGMSTransport::save_globals()
{
  double head[NHEAD];
  head[R_LAYERS] = layers;
  head[R_FACES] = faces;
  head[R_X0] = x0;
  head[R_TIME] = time;
  head[R_WATER0] = water0;
  head[R_OUT_FACE] = out_face;
  head[R_OUT_EDGE] = out_edge;
  head[R_OUT_GONE] = out_gone;
  head[R_GONE0] = gone0;
  head[R_WATER] = water;
  head[R_SOLIDS] = solids;
  head[R_BEADS] = (double) beads;
  head[R_TPRODUCT] = t_product;
  head[R_DTMOVE] = dt_move;
  head[R_NMOVES] = (double) nmoves;
  head[R_RATE] = rate;
  double **row = rows();
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < NHEAD; k++) row[i][k] = head[k];
}

/* ----------------------------------------------------------------------
   beads deleted since the last moisture step (delete_atoms, lost atoms) took
   their water out of the tissue: it leaves the balance as output 15, and the
   tissue's X/X0 is over the initial water of the beads that remain
------------------------------------------------------------------------- */

void FixCGMSTransport::account_removed()
{
  if (atom->natoms == beads) return;
  double w, surf, core, s;
  totals(w, surf, core, s);
  const double gone = water - w;
  out_gone += gone;
  gone0 += x0 * (solids - s);
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "Fix cgms/transport {}: {} beads deleted took {:.6g} kg of water out of the "
                   "tissue (output 15)\n",
                   id, beads - atom->natoms, gone);
  water = w;
  solids = s;
  beads = atom->natoms;
}

void FixCGMSTransport::initialise_columns()
{
  geometry();
  for (int i = 0; i < atom->nlocal; i++) {
    own[i] = 1;
    column(i)[layers] = solids_density * area[i] * thickness;
    column(i)[layers + 1] = area[i];
    column(i)[layers + 2] = thickness;
    for (int l = 0; l < layers; l++) column(i)[l] = x0;
  }
  double surf, core;
  totals(water0, surf, core, solids);
  water = water0;
  beads = atom->natoms;
  t_product = t_air;
  geometry();
  t_product = product_temperature();
}

/* ---------------------------------------------------------------------- */

void FixCGMSTransport::end_of_step()
{
  move();
}

/* ---------------------------------------------------------------------- */

void FixCGMSTransport::set_output(int i)
{
  if (!has_column(i)) {
    for (int m = 0; m < 4; m++) out[i][m] = 1.0;
    return;
  }
  double mean = 0.0;
  for (int l = 0; l < layers; l++) mean += column(i)[l];
  mean /= layers;
  out[i][1] = mean / x0;
  out[i][0] = MIN(1.0, MAX(s_min, out[i][1]));
  out[i][2] = column(i)[0] / x0;
  out[i][3] = column(i)[layers - 1] / x0;
}

/* ---------------------------------------------------------------------- */

double FixCGMSTransport::sum_all(double v) const
{
  double all;
  MPI_Allreduce(&v, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

// water in the tissue (kg, whole columns), the solids-weighted surface and core X/X0,
// and the dry solid (kg)
void FixCGMSTransport::totals(double &w, double &surf, double &core, double &dry) const
{
  double local[4] = {0.0, 0.0, 0.0, 0.0}, all[4];
  for (int i = 0; i < atom->nlocal; i++) {
    const double s = column(i)[layers];
    double col = 0.0;
    for (int l = 0; l < layers; l++) col += column(i)[l];
    local[0] += s / layers * col;
    local[1] += s * column(i)[0];
    local[2] += s * column(i)[layers - 1];
    local[3] += s;
  }
  MPI_Allreduce(local, all, 4, MPI_DOUBLE, MPI_SUM, world);
  w = all[0];
  dry = all[3];
  surf = all[3] > 0.0 ? all[1] / all[3] / x0 : 1.0;
  core = all[3] > 0.0 ? all[2] / all[3] / x0 : 1.0;
}

// the global outputs, with the water totals (once per moisture step)
void FixCGMSTransport::refresh_vector()
{
  double surf, core;
  totals(water, surf, core, solids);
  beads = atom->natoms;
  const double w = water;
  const double w0 = water0 > 0.0 ? water0 : w;
  // the initial water of the beads that remain (all of it unless some were deleted)
  const double w0_here = w0 - gone0;
  vec[0] = time;
  vec[1] = time / 3600.0;
  vec[2] = w0_here > 0.0 ? w / w0_here : 1.0;
  vec[3] = rate;
  vec[4] = out_face;
  vec[5] = out_edge;
  vec[6] = w0 > 0.0 ? (w0 - w - out_face - out_edge - out_gone) / w0 : 0.0;
  vec[7] = surf;
  vec[8] = core;
  vec[9] = core - surf;
  vec[10] = t_product;
  vec[11] = dt_move;
  vec[12] = cg_iterations;
  vec[13] = (double) nmoves;
  vec[14] = out_gone;
  vec[15] = halvings;
}

double FixCGMSTransport::compute_vector(int n)
{
  return vec[n];
}

/* ---------------------------------------------------------------------- */

void FixCGMSTransport::grow_beads()
{
  const int nall = atom->nlocal + atom->nghost;
  if (nall <= nmax_bead) return;
  nmax_bead = atom->nmax;
  for (double **p : {&rho_s, &dz, &area, &spacing, &edge})
    memory->grow(*p, nmax_bead, "cgms/transport:bead");
  for (double **p : {&xn, &dn, &diag, &c1, &c0, &c1f, &c0f, &bn, &xnew, &xbegin, &xfull})
    memory->grow(*p, (bigint) nmax_bead * layers, "cgms/transport:node");
  memory->grow(lower, (bigint) nmax_bead * MAX(layers - 1, 1), "cgms/transport:column");
  memory->grow(shift, nmax_bead, 2, "cgms/transport:shift");
  memory->grow(shift_new, nmax_bead, 2, "cgms/transport:shift");
  memory->grow(along, nmax_bead, 2, "cgms/transport:along");
}

/* ----------------------------------------------------------------------
   the in-plane finite-volume geometry from the current positions
   (python/cgms/transport.py bead_geometry): neighbours within the cutoff,
   a = mean neighbour distance, area (sqrt 3 / 2) a^2; the outline (below).
   Then each column's thickness, solid density and layer depth, sent with the
   moisture to the ghost beads.
------------------------------------------------------------------------- */

void FixCGMSTransport::geometry()
{
  grow_beads();
  neighbor->build_one(list);
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  const double cutsq = cutoff * cutoff;
  pair_start.assign(nlocal + 1, 0);
  pair_j.clear();
  pair_dist.clear();
  tagint lonely = MAXTAGINT;
  std::vector<std::pair<double, int>> around;
  for (int i = 0; i < nlocal; i++) {
    pair_start[i] = (int) pair_j.size();
    around.clear();
    const int *jlist = list->firstneigh[i];
    const int jnum = list->numneigh[i];
    double sum = 0.0;
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1];
      const double rsq = dx * dx + dy * dy;
      if (rsq >= cutsq) continue;
      const double r = sqrt(rsq);
      pair_j.push_back(j);
      pair_dist.push_back(r);
      around.emplace_back(atan2(-dy, -dx), j);
      sum += r;
    }
    const int count = (int) pair_j.size() - pair_start[i];
    if (count == 0) {
      lonely = MIN(lonely, atom->tag[i]);
      spacing[i] = area[i] = edge[i] = 0.0;
      continue;
    }
    spacing[i] = sum / count;
    area[i] = 0.5 * sqrt(3.0) * spacing[i] * spacing[i];
    // the widest gap between neighbours sorted by angle (the first of equal ones)
    std::sort(around.begin(), around.end());
    double widest = -1.0;
    for (int k = 0; k < count; k++) {
      const int next = (k + 1) % count;
      const double gap = around[next].first - around[k].first + (next == 0 ? 2.0 * MY_PI : 0.0);
      if (gap > widest) {
        widest = gap;
        // counter-clockwise along the outline (air on the right): the neighbour where the
        // open gap starts comes before the bead, the one where it ends after it
        along[i][0] = around[k].second;
        along[i][1] = around[next].second;
      }
    }
    if (!outline || widest <= OPEN_GAP) along[i][0] = along[i][1] = -1;
  }
  pair_start[nlocal] = (int) pair_j.size();
  tagint first;
  MPI_Allreduce(&lonely, &first, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (first != MAXTAGINT)
    error->all(FLERR,
               "Fix cgms/transport: bead {} has no neighbour within the transport cutoff {} m: "
               "moisture cannot move in or out of it (a tissue that came apart, or set cutoff)",
               first, cutoff);

  // before the columns exist (first setup) only the area is needed
  if (initialised) check_columns();

  outline_edges();

  for (int i = 0; i < nlocal; i++) {
    const double s = column(i)[layers];
    const double thick = shrink ? column(i)[layers + 2] * sqrt(area[i] / column(i)[layers + 1])
                                : column(i)[layers + 2];
    // before the columns exist (first setup) only the area is needed
    rho_s[i] = s > 0.0 ? s / (area[i] * thick) : 0.0;
    dz[i] = thick / multiplicity / layers;
    for (int l = 0; l < layers; l++) xn[i * layers + l] = column(i)[l];
  }
  comm_mode = MODE_STATE;
  comm->forward_comm(this, layers + 2);
}

/* ----------------------------------------------------------------------
   the length of outline each local bead exposes to air (edge), found from its
   own neighbours (python/cgms/transport.py outline_edge, one to one): the two
   neighbours bounding a bead's open gap (along) are its neighbours along the
   outline polygon; that polygon smoothed OUTLINE_PASSES times, each vertex to
   (prev + 2 self + next) / 4 (a lattice outline is a staircase 10 % longer
   than the curve it follows), a bead's share half of its two edges, offset
   outwards by a/2 times the turning angle (pi a over a closed outline). The
   smoothing shifts go to the ghosts after every pass (periodic images keep
   their own coordinates).
------------------------------------------------------------------------- */

void FixCGMSTransport::outline_edges()
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  double **x = atom->x;
  for (int i = 0; i < nall; i++) shift[i][0] = shift[i][1] = 0.0;
  for (int pass = 0; pass < OUTLINE_PASSES; pass++) {
    for (int i = 0; i < nlocal; i++) {
      shift_new[i][0] = shift_new[i][1] = 0.0;
      if (along[i][0] < 0) continue;
      const int a = along[i][0], b = along[i][1];
      for (int d = 0; d < 2; d++)
        shift_new[i][d] =
            0.25 * (x[a][d] + shift[a][d] + 2.0 * (x[i][d] + shift[i][d]) + x[b][d] + shift[b][d]) -
            x[i][d];
    }
    for (int i = 0; i < nlocal; i++) {
      shift[i][0] = shift_new[i][0];
      shift[i][1] = shift_new[i][1];
    }
    comm_mode = MODE_SHIFT;
    comm->forward_comm(this, 2);
  }
  for (int i = 0; i < nlocal; i++) {
    edge[i] = 0.0;
    if (along[i][0] < 0) continue;
    const int a = along[i][0], b = along[i][1];
    double back[2], ahead[2];
    for (int d = 0; d < 2; d++) {
      back[d] = x[i][d] + shift[i][d] - x[a][d] - shift[a][d];
      ahead[d] = x[b][d] + shift[b][d] - x[i][d] - shift[i][d];
    }
    const double cross = back[0] * ahead[1] - back[1] * ahead[0];
    const double dot = back[0] * ahead[0] + back[1] * ahead[1];
    // the tip of a one-bead chain turns back: +pi (the outline goes round it)
    const double turn = (cross == 0.0 && dot < 0.0) ? MY_PI : atan2(cross, dot);
    edge[i] = 0.5 *
            (sqrt(back[0] * back[0] + back[1] * back[1]) +
             sqrt(ahead[0] * ahead[0] + ahead[1] * ahead[1])) +
        0.5 * spacing[i] * turn;
    // a sharp concave corner cannot take in air
    edge[i] = MAX(edge[i], 0.0);
  }
}

/* ---------------------------------------------------------------------- */

double FixCGMSTransport::diffusivity(double x, double t) const
{
  const double arrhenius = exp(-d_energy / R_GAS * (1.0 / (t + KELVIN) - 1.0 / (t_ref + KELVIN)));
  return d_ref * arrhenius * exp(d_moisture * (x / x0 - 1.0));
}

// the surface law linearised at x: N = alpha X + beta (kg/(m^2 s))
void FixCGMSTransport::surface_law(double x, double rho_sat_p, double rho_air, double &alpha,
                                   double &beta) const
{
  if (linear_law) {
    alpha = hx;
    beta = -hx * xeq;
    return;
  }
  double aw, slope;
  gab_activity(x, gab_xm, gab_c, gab_k, aw, slope);
  alpha = kc * rho_sat_p * slope;
  beta = kc * (rho_sat_p * (aw - slope * x) - rho_air);
}

/* ----------------------------------------------------------------------
   heat balance of the slice at product temperature tp (W): what the air
   brings to every exchanging surface minus the latent heat of what
   evaporates there (python/cgms/drying/transport.py product_temperature),
   the half-node resistance with the diffusivity at tp
------------------------------------------------------------------------- */

double FixCGMSTransport::evaporation(double tp)
{
  const double rho_sat_p = vapour_density(saturation_pressure(tp), tp);
  const double rho_air = humidity * vapour_density(saturation_pressure(t_air), t_air);
  double local[2] = {0.0, 0.0}, all[2];
  auto add = [&](int n, double a, double g) {
    double alpha, beta;
    surface_law(xn[n], rho_sat_p, rho_air, alpha, beta);
    local[0] += a * series(g, alpha) * (alpha * xn[n] + beta);
    local[1] += a;
  };
  for (int i = 0; i < atom->nlocal; i++) {
    const int top = i * layers;
    if (faces) add(top, area[i], diffusivity(xn[top], tp) * rho_s[i] / (0.5 * dz[i]));
    if (edge[i] > 0.0)
      for (int n = top; n < top + layers; n++)
        add(n, edge[i] * dz[i], diffusivity(xn[n], tp) * rho_s[i] / (0.5 * spacing[i]));
  }
  MPI_Allreduce(local, all, 2, MPI_DOUBLE, MPI_SUM, world);
  return hc * (t_air - tp) * all[1] - latent_heat(tp) * all[0];
}

double FixCGMSTransport::product_temperature()
{
  if (!heat) return t_air;
  if (evaporation(t_air) >= 0.0) return t_air;
  double lo = -20.0, hi = t_air;
  if (evaporation(lo) <= 0.0)
    error->all(FLERR,
               "Fix cgms/transport: no product temperature above -20 C balances the "
               "evaporation (air at {} C, humidity {}): the evaporation would cool the "
               "surface below the range of the model's water properties; give warmer or "
               "more humid air (temperature, humidity), or heat no",
               t_air, humidity);
  // bisection to 1e-10 K: each probe is one sum over the surface nodes
  while (hi - lo > 1e-10) {
    const double mid = 0.5 * (lo + hi);
    if (evaporation(mid) > 0.0)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

/* ----------------------------------------------------------------------
   one moisture step of length dt_move (python/cgms/drying/transport.py
   extrapolated_step, and the loop of tests/drying_oracle.py): the Richardson
   extrapolation of the linearised backward Euler step, twice the result of
   two half steps minus that of one whole step. Each is first order with an
   error expansion in the step, so the combination is second order; as the
   step grows its amplification goes to zero (L-stable). The water out is
   combined alike, so the balance closes as each Euler step's does. The
   coefficients (product temperature, D, surface law) are those at the start
   of each Euler step: of the whole one and the first half at the step's
   start, of the second half at the midpoint.
------------------------------------------------------------------------- */

void FixCGMSTransport::move()
{
  check_beads();
  account_removed();
  // the drying ends at 'until' (1e-9 s: below any step the adaptive rule makes)
  if (until > 0.0 && time >= until - 1e-9) return;
  const int nlocal = atom->nlocal;
  const int nn = nlocal * layers;
  const int nall = nlocal + atom->nghost;
  double dt = until > 0.0 ? MIN(dt_move, until - time) : dt_move;
  geometry();
  std::copy(xn, xn + (bigint) nall * layers, xbegin);

  const double before = water;    // the totals of the last refresh_vector
  double face, edge_out, t_start;
  for (halvings = 0;; halvings++) {
    cg_iterations = 0;
    coefficients();
    t_start = t_product;
    double face_whole, edge_whole, face1, edge1, face2, edge2;
    euler(dt, face_whole, edge_whole);
    std::copy(xnew, xnew + nn, xfull);
    euler(0.5 * dt, face1, edge1);
    if (!drained(dt, halvings)) {
      std::copy(xnew, xnew + nn, xn);
      exchange_nodes(xn);
      coefficients();
      euler(0.5 * dt, face2, edge2);
      for (int n = 0; n < nn; n++) xnew[n] = 2.0 * xnew[n] - xfull[n];
      face = 2.0 * (face1 + face2) - face_whole;
      edge_out = 2.0 * (edge1 + edge2) - edge_whole;
      if (!drained(dt, halvings)) break;
    }
    std::copy(xbegin, xbegin + (bigint) nall * layers, xn);
    dt *= 0.5;
  }
  // the output is the product temperature at the start of the step
  t_product = t_start;

  double change = 0.0, local = 0.0;
  for (int n = 0; n < nn; n++) local = MAX(local, fabs(xnew[n] - xbegin[n]) / x0);
  MPI_Allreduce(&local, &change, 1, MPI_DOUBLE, MPI_MAX, world);
  out_face += face;
  out_edge += edge_out;

  for (int i = 0; i < nlocal; i++) {
    for (int l = 0; l < layers; l++) column(i)[l] = xnew[i * layers + l];
    set_output(i);
  }
  time += dt;
  nmoves++;
  if (dx_max > 0.0) {
    dt_move = MIN(dt_max, dt * MIN(2.0, dx_max / MAX(change, 1e-12)));
    if (!std::isnormal(dt_move))
      error->all(FLERR,
                 "Fix cgms/transport: the adaptive moisture step shrank to {:.3g} s: a change of "
                 "X/X0 of dx_max = {:g} per step is below what a step resolves (keyword adapt)",
                 dt_move, dx_max);
  }
  refresh_vector();
  rate = (before - water) / (water0 - gone0) / (dt / 3600.0);
  vec[3] = rate;
  save_globals();
}

/* ----------------------------------------------------------------------
   the coefficients at the node moisture xn (local and ghost): the product
   temperature, then the diffusivity of every node at it
------------------------------------------------------------------------- */

void FixCGMSTransport::coefficients()
{
  t_product = product_temperature();
  const int nall = atom->nlocal + atom->nghost;
  for (int n = 0; n < nall * layers; n++) dn[n] = diffusivity(xn[n], t_product);
  check_diffusivity();
}

/* ----------------------------------------------------------------------
   one linearised backward Euler step of length dt from xn with the
   coefficients of coefficients(), into xnew; the water out through the
   faces and through the outline over it (kg, whole columns)
------------------------------------------------------------------------- */

void FixCGMSTransport::euler(double dt, double &face, double &edge_out)
{
  assemble(dt);
  cg_iterations += solve();
  double local[2] = {0.0, 0.0}, all[2];
  for (int n = 0; n < atom->nlocal * layers; n++) {
    local[0] += c1[n] * xnew[n] + c0[n];
    local[1] += c1f[n] * xnew[n] + c0f[n];
  }
  MPI_Allreduce(local, all, 2, MPI_DOUBLE, MPI_SUM, world);
  face = multiplicity * dt * all[1];
  edge_out = multiplicity * dt * (all[0] - all[1]);
}

// the ghost entries of a node array from their owners
void FixCGMSTransport::exchange_nodes(double *v)
{
  comm_vec = v;
  comm_mode = MODE_DIRECTION;
  comm->forward_comm(this, layers);
}

/* ----------------------------------------------------------------------
   D_eff = D_ref Arrhenius exp(D_moisture (X/X0 - 1)) must be a positive
   double at every node: extreme D_energy or D_moisture make it 0 or inf
------------------------------------------------------------------------- */

void FixCGMSTransport::check_diffusivity()
{
  int at = -1;
  for (int n = 0; n < atom->nlocal * layers && at < 0; n++)
    if (!(dn[n] > 0.0) || !std::isfinite(dn[n])) at = n;
  const tagint mine = at >= 0 ? atom->tag[at / layers] : MAXTAGINT;
  tagint bead;
  MPI_Allreduce(&mine, &bead, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (bead == MAXTAGINT) return;
  double local[3] = {-1.0, 0.0, 0.0}, all[3];
  if (mine == bead) {
    local[0] = at % layers;
    local[1] = xn[at] / x0;
    local[2] = dn[at];
  }
  MPI_Allreduce(local, all, 3, MPI_DOUBLE, MPI_MAX, world);
  error->all(FLERR,
             "Fix cgms/transport: the diffusivity of bead {} layer {} is {:.3g} m^2/s at X/X0 = "
             "{:.3g} and {:.4g} C: D_ref exp(-D_energy/R (1/T - 1/T_ref)) exp(D_moisture "
             "(X/X0 - 1)) must be a positive number; check D_energy and D_moisture in {}",
             bead, (int) all[0] + 1, all[2], all[1], t_product, params_file);
}

/* ----------------------------------------------------------------------
   xnew (the step's midpoint or its result) holds a node below zero moisture:
   the surface law is linearised at the start of each Euler step, and at free
   water (a_w = 1) it is a constant evaporation, which a long step carries past
   the water the node holds. An adaptive step (length dt) is halved (returns
   1); a fixed one is refused.
------------------------------------------------------------------------- */

int FixCGMSTransport::drained(double dt, int halving)
{
  const int nn = atom->nlocal * layers;
  double low = 0.0, all;
  int at = -1;
  for (int n = 0; n < nn; n++)
    if (xnew[n] < low) {
      low = xnew[n];
      at = n;
    }
  MPI_Allreduce(&low, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  if (all >= 0.0) return 0;
  if (dx_max > 0.0 && halving < MAX_HALVINGS) return 1;
  // name the bead and layer of the lowest node
  tagint mine = (at >= 0 && low == all) ? atom->tag[at / layers] : MAXTAGINT, bead;
  MPI_Allreduce(&mine, &bead, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  int layer = (mine == bead && at >= 0) ? at % layers : -1, where;
  MPI_Allreduce(&layer, &where, 1, MPI_INT, MPI_MAX, world);
  if (dx_max > 0.0)
    error->all(FLERR,
               "Fix cgms/transport: even halved {} times, to {:.3g} s, the moisture step drives "
               "bead {} layer {} to X/X0 = {:.3g} < 0; the surface law or the parameters "
               "(file {}) are out of the range this fix can step",
               MAX_HALVINGS, dt, bead, where + 1, all / x0, params_file);
  error->all(FLERR,
             "Fix cgms/transport: the moisture step of {:.6g} s (keyword dt) drives bead {} "
             "layer {} to X/X0 = {:.3g} < 0. The surface law is linearised at the start of each "
             "step, and at free water (a_w = 1) it is a constant evaporation, which a step this "
             "long carries past the water the node holds. Give a shorter dt, or let the fix "
             "choose its steps with 'adapt dx_max dt_max' (it halves such a step)",
             dt, bead, where + 1, all / x0);
  return 0;
}

/* ----------------------------------------------------------------------
   the matrix of the step: diag (mass/dt + surface + all couplings), the
   column couplings (lower), the in-plane couplings per pair and layer; the
   right-hand side bn; the surface flow c1 X + c0 per node (faces: c1f, c0f)
------------------------------------------------------------------------- */

void FixCGMSTransport::assemble(double dt)
{
  const int nlocal = atom->nlocal;
  const double rho_sat_p = vapour_density(saturation_pressure(t_product), t_product);
  const double rho_air = humidity * vapour_density(saturation_pressure(t_air), t_air);
  const double root3 = sqrt(3.0);
  pair_g.assign(pair_j.size() * layers, 0.0);
  for (int i = 0; i < nlocal; i++) {
    const double mass = column(i)[layers] / multiplicity / layers;
    if (!std::isfinite(mass / dt))
      error->one(FLERR,
                 "Fix cgms/transport: a moisture step of {:.3g} s is too short to hold the "
                 "water of bead {} (its storage mass / dt overflows): give a longer dt",
                 dt, atom->tag[i]);
    double *const d = &dn[i * layers];
    for (int l = 0; l < layers; l++) {
      const int n = i * layers + l;
      diag[n] = mass / dt;
      bn[n] = mass / dt * xn[n];
      c1[n] = c0[n] = c1f[n] = c0f[n] = 0.0;
    }
    if (inplane)
      for (int k = pair_start[i]; k < pair_start[i + 1]; k++) {
        const int j = pair_j[k];
        const double r = pair_dist[k];
        for (int l = 0; l < layers; l++) {
          const double dm = 0.5 * (d[l] + dn[j * layers + l]);
          const double g =
              dm * 0.5 * (rho_s[i] + rho_s[j]) * (r / root3) * 0.5 * (dz[i] + dz[j]) / r;
          pair_g[(size_t) k * layers + l] = g;
          diag[i * layers + l] += g;
        }
      }
    for (int l = 0; l + 1 < layers; l++) {
      const double g = 0.5 * (d[l] + d[l + 1]) * rho_s[i] * area[i] / dz[i];
      lower[i * (layers - 1) + l] = g;
      diag[i * layers + l] += g;
      diag[i * layers + l + 1] += g;
    }
    double alpha, beta;
    if (faces) {
      const int n = i * layers;
      surface_law(xn[n], rho_sat_p, rho_air, alpha, beta);
      const double share = series(d[0] * rho_s[i] / (0.5 * dz[i]), alpha) * area[i];
      c1[n] += share * alpha;
      c0[n] += share * beta;
      c1f[n] += share * alpha;
      c0f[n] += share * beta;
    }
    if (edge[i] > 0.0)
      for (int l = 0; l < layers; l++) {
        const int n = i * layers + l;
        surface_law(xn[n], rho_sat_p, rho_air, alpha, beta);
        const double share = series(d[l] * rho_s[i] / (0.5 * spacing[i]), alpha) * edge[i] * dz[i];
        c1[n] += share * alpha;
        c0[n] += share * beta;
      }
    for (int l = 0; l < layers; l++) {
      const int n = i * layers + l;
      diag[n] += c1[n];
      bn[n] -= c0[n];
    }
  }
  CGMS::ColumnMatrix matrix;
  matrix.nlocal = nlocal;
  matrix.layers = layers;
  matrix.diag = diag;
  matrix.lower = lower;
  matrix.pair_start = pair_start.data();
  matrix.pair_j = pair_j.data();
  matrix.pair_g = inplane ? pair_g.data() : nullptr;
  const int singular = cg->factor(matrix);
  tagint mine = singular >= 0 ? atom->tag[singular] : MAXTAGINT, bead;
  MPI_Allreduce(&mine, &bead, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (bead == MAXTAGINT) return;
  // the Fourier number of a layer: its coupling over its storage
  double local[2] = {0.0, 0.0}, all[2];
  if (mine == bead) {
    local[0] = dz[singular];
    local[1] = dn[singular * layers] * dt / (dz[singular] * dz[singular]);
  }
  MPI_Allreduce(local, all, 2, MPI_DOUBLE, MPI_MAX, world);
  error->all(FLERR,
             "Fix cgms/transport: the moisture equations of bead {} are singular to rounding: "
             "over a step of {:.6g} s its layers, {:.3g} m deep (thickness {:.3g} m over {} "
             "layers), couple {:.3g} times more strongly than they store water (D dt / dz^2). "
             "Give a thicker slice (keyword thickness), fewer layers, or a shorter step (dt, "
             "adapt)",
             bead, dt, all[0], thickness, layers, all[1]);
}

/* ----------------------------------------------------------------------
   the step's linear system solved by CGMS::ColumnCG (cgms_column_cg.cpp);
   its ghost exchange is this fix's forward communication of a node array.
   Returns the iterations.
------------------------------------------------------------------------- */

int FixCGMSTransport::solve()
{
  double residual;
  const int it = cg->solve(bn, xnew, atom->nlocal + atom->nghost, cg_tol, cg_max, residual);
  if (residual <= cg_tol) return it;
  if (!std::isfinite(residual))
    error->all(FLERR,
               "Fix cgms/transport: the moisture step's conjugate gradients broke down after {} "
               "iterations (a residual that is not a number): the system is not positive "
               "definite to rounding; check the parameter file and the keywords thickness, "
               "layers and dt",
               it);
  if (!(residual <= 1e-8))
    error->all(FLERR,
               "Fix cgms/transport: the moisture step did not converge in {} CG "
               "iterations (residual {:.3g} of the right-hand side)",
               cg_max, residual);
  if (comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/transport: CG stopped at a residual of {:.3g} of the "
                   "right-hand side (tolerance {:.3g})",
                   residual, cg_tol);
  return it;
}

/* ---------------------------------------------------------------------- */

int FixCGMSTransport::pack_forward_comm(int n, int *list_send, double *buf, int, int *)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list_send[k];
    if (comm_mode == MODE_STATE) {
      buf[m++] = rho_s[j];
      buf[m++] = dz[j];
      for (int l = 0; l < layers; l++) buf[m++] = xn[j * layers + l];
    } else if (comm_mode == MODE_SHIFT) {
      buf[m++] = shift[j][0];
      buf[m++] = shift[j][1];
    } else
      for (int l = 0; l < layers; l++) buf[m++] = comm_vec[j * layers + l];
  }
  return m;
}

void FixCGMSTransport::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    if (comm_mode == MODE_STATE) {
      rho_s[i] = buf[m++];
      dz[i] = buf[m++];
      for (int l = 0; l < layers; l++) xn[i * layers + l] = buf[m++];
    } else if (comm_mode == MODE_SHIFT) {
      shift[i][0] = buf[m++];
      shift[i][1] = buf[m++];
    } else
      for (int l = 0; l < layers; l++) comm_vec[i * layers + l] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   the per-atom outputs travel with the beads; the state travels in the fix
   property/atom STATE_FIX
------------------------------------------------------------------------- */

void FixCGMSTransport::grow_arrays(int nmax)
{
  memory->grow(out, nmax, 4, "cgms/transport:out");
  memory->grow(own, nmax, "cgms/transport:own");
  for (int i = nmax_own; i < nmax; i++) own[i] = 0;
  nmax_own = nmax;
  array_atom = out;
}

// delflag: slot i is freed (delete_atoms, migration), and whatever lands there later
// is not the bead whose row it holds
void FixCGMSTransport::copy_arrays(int i, int j, int delflag)
{
  for (int m = 0; m < 4; m++) out[j][m] = out[i][m];
  own[j] = own[i];
  if (delflag) own[i] = 0;
}

// a bead created during a run (fix deposit, fix pour): no column of its own, an
// ERROR at the next moisture step
void FixCGMSTransport::set_arrays(int i)
{
  for (int m = 0; m < 4; m++) out[i][m] = 1.0;
  own[i] = 0;
}

int FixCGMSTransport::pack_exchange(int i, double *buf)
{
  for (int m = 0; m < 4; m++) buf[m] = out[i][m];
  buf[4] = own[i];
  return 5;
}

int FixCGMSTransport::unpack_exchange(int nlocal, double *buf)
{
  for (int m = 0; m < 4; m++) out[nlocal][m] = buf[m];
  own[nlocal] = (int) buf[4];
  return 5;
}

/* ----------------------------------------------------------------------
   write_data: the columns cannot go into a data file (a row is longer than
   the 256 characters read_data reads of a line), so no section, but a
   warning and a comment in the file, where the loss is made
------------------------------------------------------------------------- */

void FixCGMSTransport::write_data_section_size(int, int &nx, int &ny)
{
  nx = 0;
  ny = 1;
  if (initialised && comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/transport {}: data files cannot carry the tissue's moisture "
                   "columns (read_data reads at most 256 characters of a line): a run from "
                   "this data file starts them at X0, refused if the fluid state shows the "
                   "tissue dried; write_restart keeps them",
                   id);
}

void FixCGMSTransport::write_data_section_pack(int, double **) {}

void FixCGMSTransport::write_data_section_keyword(int, FILE *fp)
{
  if (initialised)
    fmt::print(fp,
               "\n{} {}: the moisture columns ({:.6g} s of drying, X/X0 {:.6g}) are not in "
               "this file; a restart file carries them\n",
               CGMS::DROPPED_COLUMNS_NOTE, id, time, vec[2]);
}

void FixCGMSTransport::write_data_section(int, FILE *, int, double **, int) {}

/* ----------------------------------------------------------------------
   restart: the rows of STATE_FIX hold the state; this record only marks the
   layout, so that a file of an older CGMS (which kept the columns under this
   fix's ID, the first value its layer count) is refused rather than
   silently started afresh
------------------------------------------------------------------------- */

void FixCGMSTransport::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  double list_out[3] = {RESTART_LAYOUT, (double) layers, (double) faces};
  int size = sizeof(list_out);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(list_out, sizeof(list_out), 1, fp);
}

void FixCGMSTransport::restart(char *buf)
{
  auto *list_in = (double *) buf;
  if (list_in[0] != RESTART_LAYOUT)
    error->all(FLERR,
               "Fix cgms/transport {}: the restart file was written by an older CGMS, which kept "
               "the moisture columns in another form; continue that run with the CGMS that "
               "wrote it",
               id);
}

/* ---------------------------------------------------------------------- */

double FixCGMSTransport::memory_usage()
{
  return sizeof(double) *
      ((double) atom->nmax * 4.5 + 9.0 * nmax_bead + 16.0 * nmax_bead * layers +
       (double) pair_g.size() + (double) pair_dist.size()) +
      sizeof(int) * ((double) pair_j.size() + pair_start.size());
}
