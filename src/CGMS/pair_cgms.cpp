/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "pair_cgms.h"

#include "atom.h"
#include "cgms_store.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

// default interaction cutoff in units of the pair's LJ radius r(s), the mean
// centroid distance at that dryness: it holds the first hexagonal shell and never
// the second at every dryness. (A fixed 1.35 x_ref lets the second shell in
// below s of about 0.2, and the tissue then collapses.)
static constexpr double CUTOFF_FACTOR = 1.35;

enum { LJ_REPULSION = 1, LJ_ATTRACTION = 2 };

/* ---------------------------------------------------------------------- */

PairCGMS::PairCGMS(LAMMPS *lmp) :
    Pair(lmp), turgor(1), perimeter(1), periphery(1), damping(1), repulsion(1), attraction(1),
    cut_user(0.0), cut_factor(CUTOFF_FACTOR), cut_scaled(1), cut_global(0.0), uniform_dryness(-1.0),
    dryness_changed(0), passes_run(0), energy_local(0.0), coef(nullptr), nmax_coef(0),
    rdist(nullptr), rdist_size(0)
{
  single_enable = 0;
  restartinfo = 1;
  one_coeff = 1;
  manybody_flag = 1;    // forces depend on the neighbours' neighbours through N_k and l_k
  centroidstressflag = CENTROID_NOTAVAIL;
  shape_k = nullptr;
  nmax_shape = 0;
  comm_forward = 1;              // the pair coefficients
  comm_reverse = CGMS::NSUMS;    // the neighbour sums
  // compute property/atom asks this style for the derived outputs
  CGMS::output_packer(lmp) = [this](int column, double *buf, int nvalues, int groupbit) {
    const int *mask = atom->mask;
    for_each_output([&](int i, const double *out) {
      buf[i * nvalues] = (mask[i] & groupbit) ? out[column] : 0.0;
    });
  };
}

/* ---------------------------------------------------------------------- */

PairCGMS::~PairCGMS()
{
  CGMS::output_packer(lmp) = nullptr;
  memory->destroy(shape_k);
  memory->destroy(coef);
  memory->destroy(rdist);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

/* ---------------------------------------------------------------------- */

void PairCGMS::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  memory->create(cutsq, n, n, "pair:cutsq");
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) setflag[i][j] = 0;
}

/* ----------------------------------------------------------------------
   pair_style cgms keyword value ...
------------------------------------------------------------------------- */

void PairCGMS::settings(int narg, char **arg)
{
  // checked here too so that the error comes before the material file is read
  if (strcmp(update->unit_style, "si") != 0)
    error->all(FLERR, "Pair style cgms requires units si (found units {})", update->unit_style);

  int iarg = 0;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair style cgms keyword {} needs a value", key);
    if (key == "cutoff") {
      cut_user = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (cut_user <= 0.0) error->all(FLERR, "Pair style cgms cutoff must be > 0");
      cut_scaled = 0;
    } else if (key == "cutoff/lj") {
      cut_factor = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (cut_factor <= 1.0)
        error->all(FLERR, "Pair style cgms cutoff/lj must be > 1 (it multiplies the LJ radius)");
      cut_scaled = 1;
    } else if (key == "turgor") {
      turgor = utils::logical(FLERR, arg[iarg + 1], false, lmp);
    } else if (key == "perimeter") {
      perimeter = utils::logical(FLERR, arg[iarg + 1], false, lmp);
    } else if (key == "periphery") {
      periphery = utils::logical(FLERR, arg[iarg + 1], false, lmp);
    } else if (key == "damping") {
      damping = utils::logical(FLERR, arg[iarg + 1], false, lmp);
    } else if (key == "repulsion") {
      repulsion = utils::logical(FLERR, arg[iarg + 1], false, lmp);
    } else if (key == "attraction") {
      attraction = utils::logical(FLERR, arg[iarg + 1], false, lmp);
    } else {
      error->all(FLERR,
                 "Unknown pair style cgms keyword '{}' (known: cutoff cutoff/lj turgor perimeter "
                 "periphery damping repulsion attraction)",
                 key);
    }
    iarg += 2;
  }
}

/* ----------------------------------------------------------------------
   pair_coeff * * material-file [name value ...]
------------------------------------------------------------------------- */

void PairCGMS::coeff(int narg, char **arg)
{
  if (narg < 3 || (narg - 3) % 2 != 0)
    error->all(FLERR, "Pair coeff for cgms: expected '* * material-file [name value ...]'");
  // LAMMPS itself insists on "* *" for a style with one_coeff set
  if (!allocated) allocate();

  mat = CGMS::Material();
  coeff_line = "* *";
  for (int iarg = 2; iarg < narg; iarg++) coeff_line += std::string(" ") + arg[iarg];
  mat.read_file(lmp, arg[2]);
  mat.require_model(lmp, "cgms", arg[2]);
  for (int iarg = 3; iarg < narg; iarg += 2) mat.set(lmp, arg[iarg], arg[iarg + 1], "pair_coeff");
  mat.finish(lmp, fmt::format("CGMS material {}", arg[2]));

  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = 1;
}

/* ---------------------------------------------------------------------- */

void PairCGMS::init_style()
{
  CGMS::require_cgms_system(lmp, "Pair style cgms");
  // fix cgms/fluid prepares the per-bead state once per step, for one force level
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR,
               "Pair style cgms does not support run_style {}: CGMS forces have one time "
               "scale; use run_style verlet",
               update->integrate_style);
  if (modify->get_fix_by_style("^cgms/fluid$").empty())
    error->all(FLERR,
               "Pair style cgms requires fix cgms/fluid: it computes the virtual-cell geometry, "
               "pressure and dryness the forces use");
  if (damping && !comm->ghost_velocity)
    error->all(FLERR,
               "Pair style cgms with damping requires 'comm_modify vel yes' (ghost velocities)");

  // the LJ radius is largest for fresh beads (s = 1), r = r0
  cut_global = cut_scaled ? cut_factor * mat.r0 : cut_user;
  if (cut_global <= mat.x_ref)
    error->all(FLERR,
               "Pair style cgms cutoff {:.6g} m is not above the lattice spacing x_ref = {:.6g} m: "
               "beads would see no neighbours",
               cut_global, mat.x_ref);

  // LAMMPS's default skin in si units is 1 mm, several cells wide: every bead
  // would carry most of a small tissue in its neighbour list
  if (neighbor->skin > 0.5 * mat.x_ref && comm->me == 0)
    error->warning(FLERR,
                   "Neighbor skin {:.3g} m is large for CGMS beads {:.3g} m apart; "
                   "'neighbor {:.2g} bin' is a good choice",
                   neighbor->skin, mat.x_ref, 0.1 * mat.x_ref);

  // the material comes from a file (one_coeff), which LAMMPS data files cannot
  // hold: no Pair Coeffs section in write_data, so that data files stay readable
  // before pair_style; but write_coeff, which LAMMPS offers only through this
  // flag, does get the full pair_coeff line (write_data_all)
  writedata = input->command && strcmp(input->command, "write_coeff") == 0;

  neighbor->add_request(this);
}

/* ----------------------------------------------------------------------
   the pair_coeff line as it was given (material file and overrides)
------------------------------------------------------------------------- */

void PairCGMS::write_data_all(FILE *fp)
{
  if (coeff_line.empty())
    error->one(FLERR, "Pair cgms: write_coeff needs the pair_coeff line, which is not known");
  // write_coeff reads lines back through a 256-character buffer
  if (coeff_line.size() > 240)
    error->one(FLERR,
               "Pair cgms: the pair_coeff line ({} characters) is too long for write_coeff, "
               "which handles up to 240; put the overrides into a material file",
               coeff_line.size());
  fmt::print(fp, "{}\n", coeff_line);
}

/* ---------------------------------------------------------------------- */

double PairCGMS::init_one(int, int)
{
  return cut_global;
}

/* ---------------------------------------------------------------------- */

void PairCGMS::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  energy_local = 0.0;
  found = CGMS::Trouble();
  // with turgor, perimeter and mass transfer all off nothing reads the fluid state
  const int passes = passes_needed();
  if (passes) {
    geometry_pass();
    fluid_pass();
    passes_run = 1;
    if (pair_coefficient_needed()) comm->forward_comm(this);
  }
  force_loop(passes);
  // the quasi-static potential (fluid_pass), added after the pairs' LJ energy
  if (eflag_global) eng_vdwl += energy_local;
}

/* ----------------------------------------------------------------------
   every combination of effects gets its own loop, so a switched-off effect
   costs neither flops nor branches in the inner loop; cached: the geometry
   pass has stored the distance of every list entry
------------------------------------------------------------------------- */

void PairCGMS::force_loop(int cached)
{
  const int lj = (repulsion ? LJ_REPULSION : 0) | (attraction ? LJ_ATTRACTION : 0);
  // 2: the cell-shape stiffness differs between beads, k_S(s_i) with s_i varying
  const int pc = !pair_coefficient_needed()                                ? 0
      : mat.k_S > 0.0 && mat.k_S_exponent != 0.0 && uniform_dryness <= 0.0 ? 2
                                                                           : 1;

#define CGMS_DISPATCH(EV, PC, LJ, DAMP)                        \
  if (evflag == EV && pc == PC && lj == LJ && damping == DAMP) \
    return eval<EV, PC, LJ, DAMP>(cached);
#define CGMS_DISPATCH_LJ(EV, PC, DAMP) \
  CGMS_DISPATCH(EV, PC, 0, DAMP)       \
  CGMS_DISPATCH(EV, PC, 1, DAMP)       \
  CGMS_DISPATCH(EV, PC, 2, DAMP)       \
  CGMS_DISPATCH(EV, PC, 3, DAMP)
#define CGMS_DISPATCH_ALL(EV) \
  CGMS_DISPATCH_LJ(EV, 0, 0)  \
  CGMS_DISPATCH_LJ(EV, 0, 1)  \
  CGMS_DISPATCH_LJ(EV, 1, 0)  \
  CGMS_DISPATCH_LJ(EV, 1, 1)  \
  CGMS_DISPATCH_LJ(EV, 2, 0)  \
  CGMS_DISPATCH_LJ(EV, 2, 1)
  CGMS_DISPATCH_ALL(0)
  CGMS_DISPATCH_ALL(1)
#undef CGMS_DISPATCH_ALL
#undef CGMS_DISPATCH_LJ
#undef CGMS_DISPATCH
}

/* ----------------------------------------------------------------------
   force on bead i from neighbour k, n = (x_i - x_k)/|x_i - x_k|:
     turgor + perimeter: (c_i + c_k) n, c from the fluid pass
     LJ:                 f0 [(r/x)^8 - (r/x)^4] / x^2 (x_i - x_k)
     damping:           -k_d (v_i - v_k)
     cell shape:        -(k_S,i (x - xbar_i) + k_S,k (x - xbar_k)) n, k_S,i xbar_i
                        inside c_i; k_S,i = k_S s_i^n
   PAIRCOEF 0: no coefficient, 1: one k_S(s) for all beads, 2: k_S(s_i) per bead
   the LJ energy U = f0 [(r/x)^8/8 - (r/x)^4/4] plus constants that keep it
   continuous at x = r
------------------------------------------------------------------------- */

template <int EVFLAG, int PAIRCOEF, int LJ, int DAMP> void PairCGMS::eval(int cached)
{
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  const CGMS::BeadState cg = CGMS::bead_state(lmp);
  const double *coef = this->coef;
  const double *rdist = this->rdist;
  bigint k = 0;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;

  const int scaled = cut_scaled;
  const double cutsq_fixed = cut_global * cut_global;
  const int uniform = uniform_dryness > 0.0;
  const double rad_uniform = uniform ? mat.lj_radius(uniform_dryness) : 0.0;
  const double cutsq_uniform = scaled ? pair_cutsq(rad_uniform) : cutsq_fixed;
  const double f0r = mat.f0_r;
  const double f0a = mat.f0_a;
  const double kd = mat.k_d;
  // cell-shape stiffness: -(k_S,i (x - xbar_i) + k_S,k (x - xbar_k)) n, of which the
  // fix puts k_S,i xbar_i into the pair coefficient of bead i; one k_S(s) for all
  // pairs unless PAIRCOEF == 2 (any bead's dryness then gives its k_S(s_i))
  const double shape_spring = 2.0 * mat.shape_stiffness(uniform ? uniform_dryness : 1.0);
  // constant added inside x <= r so that U is continuous at x = r
  // (U there is -f0_a/8 with attraction on, 0 without; U is not shifted at the cutoff)
  const double e_in =
      (LJ & LJ_REPULSION ? 0.125 * f0r : 0.0) - (LJ & LJ_ATTRACTION ? 0.125 * f0a : 0.0);

  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  double s_last = -1.0, rad_last = 0.0;
  if (PAIRCOEF == 2) {
    const int nall = atom->nlocal + atom->nghost;
    if (atom->nmax > nmax_shape) {
      nmax_shape = atom->nmax;
      memory->destroy(shape_k);
      memory->create(shape_k, nmax_shape, "pair:shape_k");
    }
    // one pow per change of s along the beads, as for the LJ radius below
    double kS_last = 0.0;
    for (int i = 0; i < nall; i++) {
      const double s = cg[i][CGMS::DRYNESS];
      if (s != s_last) {
        s_last = s;
        kS_last = mat.shape_stiffness(s);
      }
      shape_k[i] = kS_last;
    }
    s_last = -1.0;
  }

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double xtmp = x[i][0];
    const double ytmp = x[i][1];
    const double ci = PAIRCOEF ? coef[i] : 0.0;
    const double vxi = v[i][0];
    const double vyi = v[i][1];
    // with a uniform dryness the loop never touches the per-bead row (a cache
    // line per bead on large tissues); else one log per change of s, not per bead
    double si = 0.0, radi = rad_uniform, kSi = 0.0;
    if (!uniform) {
      si = cg[i][CGMS::DRYNESS];
      if (si != s_last) {
        s_last = si;
        rad_last = mat.lj_radius(si);
      }
      radi = rad_last;
      if (PAIRCOEF == 2) kSi = shape_k[i];
    }
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    double fxtmp = 0.0, fytmp = 0.0;

    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double delx = xtmp - x[j][0];
      const double dely = ytmp - x[j][1];
      double rad = 0.0, r1inv, r2inv;
      if (cached) {
        const double r = rdist[k++];
        if (r == 0.0) continue;    // beyond the cutoff
        r1inv = 1.0 / r;
        r2inv = r1inv * r1inv;
        if (LJ) rad = uniform ? rad_uniform : pair_radius(si, cg[j][CGMS::DRYNESS], radi);
      } else {
        const double rsq = delx * delx + dely * dely;
        double cutsq = cutsq_fixed;
        if (uniform) {
          rad = rad_uniform;
          cutsq = cutsq_uniform;
        } else if (LJ || scaled) {
          rad = pair_radius(si, cg[j][CGMS::DRYNESS], radi);
          if (scaled) cutsq = pair_cutsq(rad);
        }
        if (rsq >= cutsq) continue;
        // one division per pair: everything else multiplies by 1/x^2 or 1/x
        r2inv = 1.0 / rsq;
        r1inv = sqrt(r2inv);
      }

      double fpair = 0.0;
      double evdwl = 0.0;
      if (PAIRCOEF == 1) fpair += (ci + coef[j]) * r1inv - shape_spring;
      if (PAIRCOEF == 2) fpair += (ci + coef[j]) * r1inv - kSi - shape_k[j];
      if (LJ) {
        const double q2 = rad * rad * r2inv;
        const double q4 = q2 * q2;
        const double q8 = q4 * q4;
        if (q2 >= 1.0) {
          if (LJ & LJ_REPULSION) fpair += f0r * (q8 - q4) * r2inv;
          if (EVFLAG && eflag_either)
            evdwl = (LJ & LJ_REPULSION ? f0r * (0.125 * q8 - 0.25 * q4) : 0.0) + e_in;
        } else if (LJ & LJ_ATTRACTION) {
          fpair += f0a * (q8 - q4) * r2inv;
          if (EVFLAG && eflag_either) evdwl = f0a * (0.125 * q8 - 0.25 * q4);
        }
      }

      double fx = fpair * delx;
      double fy = fpair * dely;
      if (DAMP) {
        fx -= kd * (vxi - v[j][0]);
        fy -= kd * (vyi - v[j][1]);
      }

      fxtmp += fx;
      fytmp += fy;
      if (newton_pair || j < nlocal) {
        f[j][0] -= fx;
        f[j][1] -= fy;
      }
      if (EVFLAG) ev_tally_xyz(i, j, nlocal, newton_pair, evdwl, 0.0, fx, fy, 0.0, delx, dely, 0.0);
    }
    f[i][0] += fxtmp;
    f[i][1] += fytmp;
  }

  if (vflag_fdotr) virial_fdotr_compute();
}

/* ---------------------------------------------------------------------- */

void PairCGMS::write_restart_settings(FILE *fp)
{
  int flags[7] = {turgor, perimeter, periphery, damping, repulsion, attraction, cut_scaled};
  fwrite(&cut_user, sizeof(double), 1, fp);
  fwrite(&cut_factor, sizeof(double), 1, fp);
  fwrite(flags, sizeof(int), 7, fp);
}

void PairCGMS::read_restart_settings(FILE *fp)
{
  int flags[7];
  if (comm->me == 0) {
    utils::sfread(FLERR, &cut_user, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &cut_factor, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, flags, sizeof(int), 7, fp, nullptr, error);
  }
  MPI_Bcast(&cut_user, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&cut_factor, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(flags, 7, MPI_INT, 0, world);
  turgor = flags[0];
  perimeter = flags[1];
  periphery = flags[2];
  damping = flags[3];
  repulsion = flags[4];
  attraction = flags[5];
  cut_scaled = flags[6];
}

/* ----------------------------------------------------------------------
   the material record (CGMS::Material::write_record) with the pair_coeff
   arguments
------------------------------------------------------------------------- */

void PairCGMS::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  mat.write_record(fp, "pair_coeff", coeff_line);
}

void PairCGMS::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  if (!mat.read_record(lmp, fp, "pair_coeff", coeff_line))
    error->all(FLERR,
               "Pair cgms: this restart file was written by another version of the CGMS "
               "plugin (its material record does not match this version's format); start "
               "from a data file, or read it with the plugin that wrote it");
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = 1;
}

/* ---------------------------------------------------------------------- */

double PairCGMS::memory_usage()
{
  const double n = atom->ntypes + 1;
  return Pair::memory_usage() + n * n * (sizeof(int) + sizeof(double)) +
      ((double) nmax_shape + nmax_coef + rdist_size) * sizeof(double);
}

/* ---------------------------------------------------------------------- */

void *PairCGMS::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "cut_global") == 0) return (void *) &cut_global;
  return nullptr;
}
