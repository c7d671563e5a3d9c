/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

// pair_style cgms: the per-bead passes of its compute() (geometry, then the
// fluid state of every bead), their communication, and the outputs derived
// from the state and the neighbour sums. The force loop is in pair_cgms.cpp.

#include "pair_cgms.h"

#include "atom.h"
#include "comm.h"
#include "force.h"
#include "memory.h"
#include "my_page.h"
#include "neigh_list.h"
#include "update.h"

#include <cmath>

using namespace LAMMPS_NS;
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
   geometry: neighbour count and sum of centre distances of every bead (the
   compact sums, summed over ranks with newton on), and the distance of every
   neighbour-list entry for the pair's force loop
------------------------------------------------------------------------- */

void PairCGMS::geometry_pass()
{
  double **x = atom->x;
  const BeadState cg = bead_state(lmp);
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int newton_pair = force->newton_pair;
  const double cut = cut_global;
  const double cutsq_fixed = cut * cut;
  const int scaled = cut_scaled;
  const double s_uniform = uniform_dryness;
  const int uniform = s_uniform > 0.0;
  const double cutsq_uniform = scaled && uniform ? pair_cutsq(mat.lj_radius(s_uniform))
                                                 : cutsq_fixed;
  const int per_pair_cutoff = scaled && !uniform;

  if (atom->nmax > nmax_coef) {
    nmax_coef = atom->nmax;
    memory->destroy(coef);
    memory->create(coef, nmax_coef, "pair:coef");
  }
  // the list's length, read every pass: neighbor->ncalls cannot tell one build from
  // another (Verlet and Min set it to 0 after their setup build, so the builds of
  // consecutive runs, e.g. the 'run 0' of every Newton force evaluation, repeat its values)
  // and a list that grows between runs would overrun rdist
  const bigint npairs = list_entries(list, comm->nthreads);
  if (npairs > rdist_size) {
    rdist_size = npairs + npairs / 4;
    memory->destroy(rdist);
    memory->create(rdist, rdist_size, "pair:rdist");
  }
  // local copies: the loops then keep them in registers
  NeighbourSums *const sums = neighbour_sums(lmp);
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
      if (rsq >=
          (per_pair_cutoff ? pair_cutsq(pair_radius(si, cg[j][DRYNESS], radi)) : cutsq_uniform)) {
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
inline double bead_density(const FluidPassConstants &p, const DrynessLaws &at, const BeadRow &c,
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

  void bead(Trouble &t, int i, double nn, double sum_r, double q7, double press,
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
   fluid state of every local bead: in a time step first the mass transfer
   of the previous step, m_f(n+1) = m_f(n) + dt dm_f/dt(n) (doc/model.md, When
   the mass transfer is applied), then eqns (10-11), density, eqn (4), eqn (9),
   eqn (7), the pair coefficient, the quasi-static energy, and the beads that
   emptied or break a stability limit (fix cgms/fluid's stop_if_unstable()
   reports them). The update is done here, in the walk over the rows the pass
   makes anyway: a separate pass in the fix streamed every row once more per
   step (doc/results/performance.md, 2026-12-03).
------------------------------------------------------------------------- */

void PairCGMS::fluid_pass()
{
  const BeadState cg = bead_state(lmp);
  double *rmass = atom->rmass;
  const int nlocal = atom->nlocal;

  FluidPassConstants p;
  p.dt = update->dt;
  p.kT = turgor ? mat.k_T : 0.0;
  p.kPA = perimeter ? mat.k_PA : 0.0;
  p.kS = mat.k_S;
  p.P_f = mat.P_f;
  p.K = mat.K;
  p.pectin = mat.pectin;
  p.b_ref = mat.b_ref;
  p.height = mat.height;
  p.inv_h = 1.0 / mat.height;
  p.conductance = mat.height * mat.L_p;
  p.L_p = mat.L_p;
  // a time step (not a setup, not a minimizer's evaluation) advances the rate form
  p.advance = update->whichflag == 1 && !update->setupflag;
  p.transfer = options.transfer;
  p.implicit = options.transfer_implicit;
  p.density_rate = options.density_rate;
  p.balance = options.always_balance || (options.minimize_balance && update->whichflag == 2);
  const int advance_mass = p.advance && p.transfer;
  const int inertia_fluid = options.inertia_fluid;
  // its energy is needed only where LAMMPS tallies energies (a second walk over the list)
  const int shape_energy = p.kS > 0.0 && (p.balance || eflag_global);
  StabilityScan scan{step_limits(), p.dt, p.pectin, 0, 0, 0.0};
  scan.turgor = p.kT > 0.0 && !p.balance;
  scan.shape = p.kS > 0.0 && !p.balance;
  scan.turgor_bound = dryness_changed ? 4.0 : 16.0;

  // found beads in a local during the loop, into the member after it
  Trouble found;
  found.after_change = dryness_changed;
  dryness_changed = 0;
  const NeighbourSums *const sums = neighbour_sums(lmp);
  double *const coef = this->coef;
  double energy = 0.0;
  DrynessLaws at;
  for (int i = 0; i < nlocal; i++) {
    const BeadRow c = cg[i];

    if (advance_mass) {
      c[MF] += p.dt * c[DMDT];
      if (!(c[MF] > 0.0) && found.emptied < 0) found.emptied = i;
      if (inertia_fluid) rmass[i] = c[MF] + c[MS];
    }

    if (c[DRYNESS] != at.s) at.set(c[DRYNESS], mat, periphery);
    const double nn = sums[i].count;
    const double sum_r = sums[i].distance;
    if (!(nn > 0.0) && !options.allow_isolated && found.isolated < 0) found.isolated = i;
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
      energy += CGMS::quasi_static_energy(p.kT, p.kPA, p.P_f, press, sum_r, perim, ldeq,
                                          perimeter_gradient(nn, at.beta));
    // The cell-shape energy k_S(s_i)/2 sum_k (x_ik - xbar_i)^2 does not depend on the
    // pressures: it is a potential in any run. Its -k_S(s_i)/2 N xbar_i^2 here, its
    // sum over pairs of (k_S(s_i) + k_S(s_k))/2 x^2 in shape_pair_energy()
    if (shape_energy && nn > 0.0) energy -= 0.5 * at.kS * sum_r * sum_r / nn;
    scan.bead(found, i, nn, sum_r, q7, press, rmass, sums);
  }

  energy_local += energy;
  if (shape_energy) energy_local += shape_pair_energy();
  this->found = found;
}

/* ---------------------------------------------------------------------- */

double PairCGMS::shape_pair_energy() const
{
  // sum over neighbour pairs of (k_S(s_i) + k_S(s_k))/2 x^2 (x counted once from
  // each end), from the distances pass 1 cached per entry of the half list (0:
  // beyond the cutoff); without newton_pair a pair with a ghost is in the lists of
  // both of its ranks. k_S(s) differs between beads only with an exponent and a
  // dryness that varies (then forwarded to the ghosts, see pre_force)
  const double s_uniform = uniform_dryness;
  const int by_bead = mat.k_S_exponent != 0.0 && s_uniform <= 0.0;
  const double kS = by_bead ? 0.0 : mat.shape_stiffness(s_uniform > 0.0 ? s_uniform : 1.0);
  const BeadState cg = bead_state(lmp);
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
   the outputs of every local bead i (CGMS::Output columns), handed to use(i,
   outputs): its state, and what the fluid pass derived from the state and the
   neighbour sums, recomputed by the same formulas; 0 where no pass has
   computed them yet (or the pair style that holds the material is gone)
------------------------------------------------------------------------- */

void PairCGMS::for_each_output(const std::function<void(int, const double *)> &use) const
{
  const BeadState cg = bead_state(lmp);
  const int nlocal = atom->nlocal;
  const NeighbourSums *sums = neighbour_sums(lmp);
  const int derived = passes_run;
  DrynessLaws at;
  double out[NOUTPUTS];
  for (int i = 0; i < nlocal; i++) {
    const BeadRow c = cg[i];
    for (int k = 0; k < NSTATE; k++) out[STATE_OUTPUT[k]] = c[k];
    out[OUT_COEF] = out[OUT_NNEIGH] = out[OUT_SIDE] = 0.0;
    out[OUT_PRESS] = out[OUT_PERIM] = out[OUT_LDEQ] = 0.0;
    if (derived && c[MF0] > 0.0) {
      if (c[DRYNESS] != at.s) at.set(c[DRYNESS], mat, periphery);
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
      out[OUT_COEF] = pair_coefficient(turgor ? mat.k_T : 0.0, perimeter ? mat.k_PA : 0.0, mat.P_f,
                                       press, perim, ldeq);
    }
    use(i, out);
  }
}

/* ----------------------------------------------------------------------
   the time-step limits (cgms_laws.h) of the forces that are switched on
------------------------------------------------------------------------- */

StepLimits PairCGMS::step_limits() const
{
  return {damping ? mat.k_d : 0.0, turgor ? mat.k_T : 0.0, mat.K, mat.k_S, update->dt};
}

/* ----------------------------------------------------------------------
   the pair coefficients to the ghosts; the ghosts' neighbour sums to their
   owners (newton on)
------------------------------------------------------------------------- */

int PairCGMS::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  for (int i = 0; i < n; i++) buf[i] = coef[list[i]];
  return n;
}

void PairCGMS::unpack_forward_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) coef[first + i] = buf[i];
}

int PairCGMS::pack_reverse_comm(int n, int first, double *buf)
{
  const NeighbourSums *sums = neighbour_sums(lmp);
  for (int i = 0; i < n; i++) {
    buf[NSUMS * i] = sums[first + i].count;
    buf[NSUMS * i + 1] = sums[first + i].distance;
  }
  return NSUMS * n;
}

void PairCGMS::unpack_reverse_comm(int n, int *list, double *buf)
{
  NeighbourSums *sums = neighbour_sums(lmp);
  for (int i = 0; i < n; i++) {
    sums[list[i]].count += buf[NSUMS * i];
    sums[list[i]].distance += buf[NSUMS * i + 1];
  }
}
