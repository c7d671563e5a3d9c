/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   The pressure, viscosity and density terms follow LAMMPS's
   pair sph/taitwater/morris (src/SPH); added here: Monaghan's artificial
   pressure, Wendland's C2 kernel and, as an option, walls whose pressure is
   extrapolated from the fluid next to them (Adami, Hu and Adams, J. Comput.
   Phys. 231, 2012, 7057, eqs. 27-28).
------------------------------------------------------------------------- */

#include "pair_sph_taitwater_ap.h"

#include "atom.h"
#include "cgms_laws.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "math_const.h"
#include "math_special.h"
#include "memory.h"
#include "neigh_list.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using MathConst::MY_PI;
using MathSpecial::powint;

/* ---------------------------------------------------------------------- */

PairSPHTaitwaterAP::PairSPHTaitwaterAP(LAMMPS *lmp) :
    Pair(lmp), kernel(LUCY), epsilon(0.2), exponent(4), walllo(0), wallhi(-1), wsum(nullptr),
    wnorm(nullptr), pressure(nullptr), nmax(0), rho0(nullptr), soundspeed(nullptr), B(nullptr),
    cut(nullptr), viscosity(nullptr), spacing(nullptr), wdp_inv(nullptr)
{
  if ((atom->esph_flag != 1) || (atom->rho_flag != 1) || (atom->vest_flag != 1))
    error->all(FLERR,
               "Pair sph/taitwater/ap requires atom attributes energy, density, and velocity "
               "estimates, e.g. in atom_style sph");

  restartinfo = 1;
  single_enable = 0;
  comm_forward = 1;    // the walls' densities
  comm_reverse = 2;    // the walls' sums over ghost fluid particles
}

/* ---------------------------------------------------------------------- */

PairSPHTaitwaterAP::~PairSPHTaitwaterAP()
{
  memory->destroy(wsum);
  memory->destroy(wnorm);
  memory->destroy(pressure);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);

    memory->destroy(rho0);
    memory->destroy(soundspeed);
    memory->destroy(B);
    memory->destroy(cut);
    memory->destroy(viscosity);
    memory->destroy(spacing);
    memory->destroy(wdp_inv);
  }
}

/* ----------------------------------------------------------------------
   the kernel's shape w(q), q = r/h, without its normalisation: the
   artificial pressure needs only the ratio W(r)/W(dp)
------------------------------------------------------------------------- */

double PairSPHTaitwaterAP::shape(double q) const
{
  const double u = 1.0 - q;
  if (kernel == WENDLAND) return (1.0 + 4.0 * q) * u * u * u * u;
  return (1.0 + 3.0 * q) * u * u * u;
}

/* ----------------------------------------------------------------------
   the Tait equation of state, P = B ((rho / rho0)^7 - 1), of atom i (the
   coarse model's law, eqn 4 of doc/model.md, with P_ref = 0)
------------------------------------------------------------------------- */

double PairSPHTaitwaterAP::tait(int i) const
{
  const int itype = atom->type[i];
  return CGMS::tait_pressure(CGMS::pow7(atom->rho[i] / rho0[itype]), 0.0, B[itype]);
}

/* ----------------------------------------------------------------------
   the pressure of every local and ghost atom (or of the walls only), once
   per atom rather than once per pair
------------------------------------------------------------------------- */

void PairSPHTaitwaterAP::tait_pressures(bool walls_only)
{
  const int *type = atom->type;
  const int nall = atom->nlocal + atom->nghost;
  for (int i = 0; i < nall; i++)
    if (!walls_only || is_wall(type[i])) pressure[i] = tait(i);
}

/* ----------------------------------------------------------------------
   Adami, Hu and Adams (2012), eqs. 27-28: a wall particle takes the pressure of
   the fluid around it, P_w = sum_f P_f W_wf / sum_f W_wf (their body-force and
   wall-acceleration term left out: no gravity here, and the walls move slowly
   against the sound speed), and the density of that pressure in its own
   type's EOS. Stored in rho, so that the pair loop treats walls as any
   particle; tension reaches the wall as compression does. A wall without fluid
   neighbours is at P = 0.
------------------------------------------------------------------------- */

void PairSPHTaitwaterAP::wall_densities()
{
  double **x = atom->x;
  double *rho = atom->rho;
  int *type = atom->type;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  const int ntotal = newton_pair ? nlocal + atom->nghost : nlocal;
  for (int i = 0; i < ntotal; i++) wsum[i] = wnorm[i] = 0.0;

  // W = wnorm0 / h^dim * shape(q); the norm matters where pairs differ in h
  const int dim3 = domain->dimension == 3;
  double wnorm0;
  if (kernel == WENDLAND)
    wnorm0 = dim3 ? 21.0 / (2.0 * MY_PI) : 7.0 / MY_PI;
  else
    wnorm0 = dim3 ? 105.0 / (16.0 * MY_PI) : 5.0 / MY_PI;

  const int inum = list->inum;
  int *ilist = list->ilist;
  int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int itype = type[i];
    const int iwall = is_wall(itype);
    int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const int jtype = type[j];
      if (is_wall(jtype) == iwall) continue;
      const double delx = x[i][0] - x[j][0];
      const double dely = x[i][1] - x[j][1];
      const double delz = x[i][2] - x[j][2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      if (rsq >= cutsq[itype][jtype]) continue;

      const double h = cut[itype][jtype];
      double w = wnorm0 / (h * h) * shape(sqrt(rsq) / h);
      if (dim3) w /= h;
      const int wall = iwall ? i : j;
      const int fluid = iwall ? j : i;
      if (wall >= nlocal && !newton_pair) continue;
      wsum[wall] += pressure[fluid] * w;
      wnorm[wall] += w;
    }
  }
  if (newton_pair) comm->reverse_comm(this);

  for (int i = 0; i < nlocal; i++) {
    const int itype = type[i];
    if (!is_wall(itype)) continue;
    const double pw = wnorm[i] > 0.0 ? wsum[i] / wnorm[i] : 0.0;
    const double ratio = 1.0 + pw / B[itype];
    // a mean of fluid pressures is above -B of the fluid; a wall type's EOS may differ
    if (ratio <= 0.0)
      error->one(FLERR,
                 "Pair sph/taitwater/ap: wall atom {} takes the fluid's pressure {} beyond "
                 "the tension -B = {} its type's equation of state holds",
                 atom->tag[i], pw, -B[itype]);
    rho[i] = CGMS::tait_density(pw, 0.0, B[itype], 1.0 / rho0[itype]);
  }
  comm->forward_comm(this);
  tait_pressures(true);
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    memory->destroy(pressure);
    memory->destroy(wsum);
    memory->destroy(wnorm);
    memory->create(pressure, nmax, "pair:pressure");
    memory->create(wsum, nmax, "pair:wsum");
    memory->create(wnorm, nmax, "pair:wnorm");
  }
  // every atom's pressure from its density; the walls' then from the fluid's pressure
  check_densities();
  tait_pressures(false);
  if (walllo > 0) wall_densities();

  double **v = atom->vest;
  double **x = atom->x;
  double **f = atom->f;
  double *rho = atom->rho;
  double *mass = atom->mass;
  double *desph = atom->desph;
  double *drho = atom->drho;
  int *type = atom->type;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  const int dim3 = domain->dimension == 3;

  // dW/dr / r = norm (1 - q)^k / h^(dim+2): Lucy k = 2, Wendland C2 k = 3
  double norm;
  if (kernel == WENDLAND)
    norm = dim3 ? -210.0 / MY_PI : -140.0 / MY_PI;
  else
    norm = dim3 ? -315.0 / (4.0 * MY_PI) : -60.0 / MY_PI;

  const int inum = list->inum;
  int *ilist = list->ilist;
  int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double xtmp = x[i][0];
    const double ytmp = x[i][1];
    const double ztmp = x[i][2];
    const int itype = type[i];
    int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    const double imass = mass[itype];
    const int iwall = is_wall(itype);

    // P_i / rho_i^2; the artificial pressure R_i acts only in tension
    const double fi = pressure[i] / (rho[i] * rho[i]);
    const double ri = fi < 0.0 ? -epsilon * fi : 0.0;

    for (int jj = 0; jj < jnum; jj++) {
      int j = jlist[jj];
      j &= NEIGHMASK;

      const double delx = xtmp - x[j][0];
      const double dely = ytmp - x[j][1];
      const double delz = ztmp - x[j][2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      const int jtype = type[j];

      if (rsq >= cutsq[itype][jtype]) continue;
      // walls interact only with the fluid (Adami et al.: their pressure is the fluid's)
      const int jwall = is_wall(jtype);
      if (iwall && jwall) continue;

      const double jmass = mass[jtype];
      const double h = cut[itype][jtype];
      const double q = sqrt(rsq) / h;
      const double u = 1.0 - q;
      const double h2 = h * h;
      // the factor r that wfd lacks is recovered by using delx, not delx/r (as LAMMPS's SPH)
      double wfd = norm / (h2 * h2) * u * u;
      if (kernel == WENDLAND) wfd *= u;
      if (dim3) wfd /= h;

      const double fj = pressure[j] / (rho[j] * rho[j]);
      const double rj = fj < 0.0 ? -epsilon * fj : 0.0;

      // Monaghan's artificial pressure: (R_i + R_j) (W(r)/W(dp))^n
      double art = 0.0;
      if (ri + rj > 0.0) art = (ri + rj) * powint(shape(q) * wdp_inv[itype][jtype], exponent);

      const double velx = v[i][0] - v[j][0];
      const double vely = v[i][1] - v[j][1];
      const double velz = v[i][2] - v[j][2];
      const double delVdotDelR = delx * velx + dely * vely + delz * velz;

      // Morris viscosity (Morris, Fox and Zhu, J. Comput. Phys. 136, 1997, 214)
      const double fvisc = 2.0 * viscosity[itype][jtype] / (rho[i] * rho[j]) * imass * jmass * wfd;

      const double fpair = -imass * jmass * (fi + fj + art) * wfd;
      const double deltaE =
          -0.5 * (fpair * delVdotDelR + fvisc * (velx * velx + vely * vely + velz * velz));

      f[i][0] += delx * fpair + velx * fvisc;
      f[i][1] += dely * fpair + vely * fvisc;
      f[i][2] += delz * fpair + velz * fvisc;
      // a wall's density is its fluid's pressure, not a continuity density
      if (!iwall) drho[i] += jmass * delVdotDelR * wfd;
      desph[i] += deltaE;

      if (newton_pair || j < nlocal) {
        f[j][0] -= delx * fpair + velx * fvisc;
        f[j][1] -= dely * fpair + vely * fvisc;
        f[j][2] -= delz * fpair + velz * fvisc;
        if (!jwall) drho[j] += imass * delVdotDelR * wfd;
        desph[j] += deltaE;
      }

      // no potential energy (the fluid's energy is esph); viscous forces have no virial
      if (evflag) ev_tally(i, j, nlocal, newton_pair, 0.0, 0.0, fpair, delx, dely, delz);
    }
  }

  if (vflag_fdotr) virial_fdotr_compute();
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;

  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");

  memory->create(rho0, n + 1, "pair:rho0");
  memory->create(soundspeed, n + 1, "pair:soundspeed");
  memory->create(B, n + 1, "pair:B");
  for (int i = 0; i <= n; i++) rho0[i] = soundspeed[i] = B[i] = 0.0;
  memory->create(cut, n + 1, n + 1, "pair:cut");
  memory->create(viscosity, n + 1, n + 1, "pair:viscosity");
  memory->create(spacing, n + 1, n + 1, "pair:spacing");
  memory->create(wdp_inv, n + 1, n + 1, "pair:wdp_inv");
}

/* ----------------------------------------------------------------------
   pair_style sph/taitwater/ap [kernel lucy|wendland] [epsilon eps] [exponent n]
     [wall I*J]
------------------------------------------------------------------------- */

void PairSPHTaitwaterAP::settings(int narg, char **arg)
{
  kernel = LUCY;
  epsilon = 0.2;
  exponent = 4;
  walllo = 0;
  wallhi = -1;
  int iarg = 0;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair sph/taitwater/ap keyword {} needs a value", key);
    const std::string value = arg[iarg + 1];
    if (key == "kernel") {
      if (value == "lucy")
        kernel = LUCY;
      else if (value == "wendland")
        kernel = WENDLAND;
      else
        error->all(FLERR, "Pair sph/taitwater/ap kernel must be lucy or wendland, not {}", value);
    } else if (key == "epsilon") {
      epsilon = utils::numeric(FLERR, value, false, lmp);
      if (!std::isfinite(epsilon) || epsilon < 0.0)
        error->all(FLERR, "Pair sph/taitwater/ap epsilon must be >= 0, not {}", value);
    } else if (key == "exponent") {
      exponent = utils::inumeric(FLERR, value, false, lmp);
      if (exponent < 1)
        error->all(FLERR, "Pair sph/taitwater/ap exponent must be an integer >= 1, not {}", value);
    } else if (key == "wall") {
      utils::bounds(FLERR, value, 1, atom->ntypes, walllo, wallhi, error);
    } else
      error->all(FLERR, "Unknown pair sph/taitwater/ap keyword {}", key);
    iarg += 2;
  }
}

/* ----------------------------------------------------------------------
   pair_coeff I J rho0 c0 mu h dp: as sph/taitwater/morris plus the particle
   spacing dp of the artificial pressure
------------------------------------------------------------------------- */

void PairSPHTaitwaterAP::coeff(int narg, char **arg)
{
  if (narg != 7)
    error->all(FLERR,
               "Incorrect args for pair sph/taitwater/ap coefficients: I J rho0 c0 viscosity "
               "h dp");
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  const char *names[5] = {"rho0", "c0", "viscosity", "h", "dp"};
  double value[5];
  for (int k = 0; k < 5; k++) {
    value[k] = utils::numeric(FLERR, arg[k + 2], false, lmp);
    if (!std::isfinite(value[k]) || value[k] < 0.0 || (value[k] == 0.0 && k != 2))
      error->all(FLERR, "Pair sph/taitwater/ap {} must be {}, not {}", names[k],
                 k == 2 ? ">= 0" : "> 0", arg[k + 2]);
  }
  const double rho0_one = value[0], c0_one = value[1], mu_one = value[2];
  const double cut_one = value[3], dp_one = value[4];
  if (dp_one >= cut_one)
    error->all(FLERR,
               "Pair sph/taitwater/ap spacing dp = {} must be smaller than the kernel support "
               "h = {} (W(dp) = 0)",
               dp_one, cut_one);

  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    rho0[i] = rho0_one;
    soundspeed[i] = c0_one;
    B[i] = c0_one * c0_one * rho0_one / 7.0;
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      viscosity[i][j] = mu_one;
      cut[i][j] = cut_one;
      spacing[i][j] = dp_one;
      setflag[i][j] = 1;
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients");
}

/* ----------------------------------------------------------------------
   the density of a fluid particle (a wall's is computed) must be finite and
   positive: at setup it comes from the user (the data file's Atoms section,
   the set command), later from the continuity equation of the run
------------------------------------------------------------------------- */

void PairSPHTaitwaterAP::check_densities()
{
  const double *rho = atom->rho;
  const int *type = atom->type;
  for (int i = 0; i < atom->nlocal; i++) {
    if (is_wall(type[i]) || (std::isfinite(rho[i]) && rho[i] > 0.0)) continue;
    if (update->setupflag)
      error->one(FLERR,
                 "Pair sph/taitwater/ap: atom {} has density {} at setup (step {}); every "
                 "fluid particle needs a finite density > 0 (check the data file's Atoms "
                 "section and any set density command)",
                 atom->tag[i], rho[i], update->ntimestep);
    error->one(FLERR,
               "Pair sph/taitwater/ap: the density of atom {} became {} at step {}: the run is "
               "unstable; use a smaller timestep (now {:.6g} s)",
               atom->tag[i], rho[i], update->ntimestep, update->dt);
  }
}

/* ---------------------------------------------------------------------- */

double PairSPHTaitwaterAP::init_one(int i, int j)
{
  if (setflag[i][j] == 0) error->all(FLERR, "All pair sph/taitwater/ap coeffs are not set");
  if (rho0[i] <= 0.0 || rho0[j] <= 0.0)
    error->all(FLERR,
               "Pair sph/taitwater/ap: no equation of state for atom type {} (a type's EOS "
               "comes from a pair_coeff line whose first type range holds it)",
               rho0[i] <= 0.0 ? i : j);

  cut[j][i] = cut[i][j];
  viscosity[j][i] = viscosity[i][j];
  spacing[j][i] = spacing[i][j];
  wdp_inv[i][j] = wdp_inv[j][i] = 1.0 / shape(spacing[i][j] / cut[i][j]);
  return cut[i][j];
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    fwrite(&rho0[i], sizeof(double), 1, fp);
    fwrite(&soundspeed[i], sizeof(double), 1, fp);
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) {
        fwrite(&viscosity[i][j], sizeof(double), 1, fp);
        fwrite(&cut[i][j], sizeof(double), 1, fp);
        fwrite(&spacing[i][j], sizeof(double), 1, fp);
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();

  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    if (me == 0) {
      utils::sfread(FLERR, &rho0[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &soundspeed[i], sizeof(double), 1, fp, nullptr, error);
    }
    MPI_Bcast(&rho0[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&soundspeed[i], 1, MPI_DOUBLE, 0, world);
    B[i] = soundspeed[i] * soundspeed[i] * rho0[i] / 7.0;
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) {
          utils::sfread(FLERR, &viscosity[i][j], sizeof(double), 1, fp, nullptr, error);
          utils::sfread(FLERR, &cut[i][j], sizeof(double), 1, fp, nullptr, error);
          utils::sfread(FLERR, &spacing[i][j], sizeof(double), 1, fp, nullptr, error);
        }
        MPI_Bcast(&viscosity[i][j], 1, MPI_DOUBLE, 0, world);
        MPI_Bcast(&cut[i][j], 1, MPI_DOUBLE, 0, world);
        MPI_Bcast(&spacing[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::write_restart_settings(FILE *fp)
{
  fwrite(&kernel, sizeof(int), 1, fp);
  fwrite(&epsilon, sizeof(double), 1, fp);
  fwrite(&exponent, sizeof(int), 1, fp);
  fwrite(&walllo, sizeof(int), 1, fp);
  fwrite(&wallhi, sizeof(int), 1, fp);
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::read_restart_settings(FILE *fp)
{
  if (comm->me == 0) {
    utils::sfread(FLERR, &kernel, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &epsilon, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &exponent, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &walllo, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &wallhi, sizeof(int), 1, fp, nullptr, error);
  }
  MPI_Bcast(&kernel, 1, MPI_INT, 0, world);
  MPI_Bcast(&epsilon, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&exponent, 1, MPI_INT, 0, world);
  MPI_Bcast(&walllo, 1, MPI_INT, 0, world);
  MPI_Bcast(&wallhi, 1, MPI_INT, 0, world);
}

/* ---------------------------------------------------------------------- */

int PairSPHTaitwaterAP::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                          int * /*pbc*/)
{
  double *rho = atom->rho;
  for (int k = 0; k < n; k++) buf[k] = rho[list[k]];
  return n;
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::unpack_forward_comm(int n, int first, double *buf)
{
  double *rho = atom->rho;
  for (int k = 0; k < n; k++) rho[first + k] = buf[k];
}

/* ---------------------------------------------------------------------- */

int PairSPHTaitwaterAP::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    buf[m++] = wsum[i];
    buf[m++] = wnorm[i];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void PairSPHTaitwaterAP::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    wsum[list[k]] += buf[m++];
    wnorm[list[k]] += buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

double PairSPHTaitwaterAP::memory_usage()
{
  return Pair::memory_usage() + 3.0 * nmax * sizeof(double);
}
