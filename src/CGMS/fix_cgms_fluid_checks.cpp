/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

// fix cgms/fluid: the checks of the user's input and of every step, and their
// messages (each names bead, step, cause and cure; tests and doc/errors.md match
// them). The passes they check are in fix_cgms_fluid.cpp.

#include "fix_cgms_fluid.h"

#include "atom.h"
#include "atom_vec_cgms.h"
#include "cgms_laws.h"
#include "cgms_store.h"
#include "comm.h"
#include "error.h"
#include "min.h"
#include "neigh_list.h"
#include "pair_cgms.h"
#include "update.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace CGMS;

/* ----------------------------------------------------------------------
   a minimizer may end on a tissue folded onto itself: beads inside each other's
   second shell. The dynamics stops there (the damping check of stop_if_unstable);
   a minimizer has no such limit and would hand the state on as a steady state.
------------------------------------------------------------------------- */

void FixCGMSFluid::warn_if_folded()
{
  const NeighbourSums *sums = neighbour_sums(lmp);
  double most_local = 0.0, most = 0.0;
  for (int i = 0; i < atom->nlocal; i++) most_local = MAX(most_local, sums[i].count);
  MPI_Allreduce(&most_local, &most, 1, MPI_DOUBLE, MPI_MAX, world);
  // a hexagonal tissue has 6 neighbours and 12 within its second shell
  if (most > 12.0 && comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/fluid: minimize ended on a tissue folded onto itself: a bead has "
                   "{:g} neighbours within the cutoff, where a hexagonal tissue has 6. This is "
                   "no steady state of a tissue; a cell-shape stiffness (k_S, doc/pair_cgms.rst) "
                   "or a stiffer perimeter law (k_PA) may prevent it",
                   most);
}

/* ----------------------------------------------------------------------
   LAMMPS's default largest move per minimizer step, dmax = 0.1, is meant for
   Angstroms; in SI units it is 0.1 m, a whole tissue, and the first line
   search throws the beads apart. A dmax above one cell is never meant for
   CGMS: bound it to 1 % of the lattice spacing (min_modify dmax sets it).
------------------------------------------------------------------------- */

namespace {
struct MinDmax : public LAMMPS_NS::Min {
  // Min::dmax is protected and has no accessor; a member pointer of a derived
  // class may read it
  static double get(LAMMPS_NS::Min *min) { return min->*(&MinDmax::dmax); }
};
}    // namespace

void FixCGMSFluid::limit_minimizer_step()
{
  if (!update->minimize || !pair) return;
  const double x_ref = pair->material().x_ref;
  const double dmax = MinDmax::get(update->minimize);
  if (dmax <= x_ref) return;
  std::string value = fmt::format("{:.3g}", 0.01 * x_ref);
  char key[] = "dmax";
  char *args[2] = {key, value.data()};
  update->minimize->modify_params(2, args);
  if (comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/fluid: min_modify dmax {:g} m is larger than a cell (x_ref = {:.3g} "
                   "m; LAMMPS's default 0.1 is meant for Angstroms); minimizing with dmax {} m "
                   "(set min_modify dmax ~1e-6 to choose it yourself)",
                   dmax, x_ref, value);
}

/* ----------------------------------------------------------------------
   the model's dryness laws hold only where they stay positive: the LJ radius
   r0 (1 + lj_slope ln s) and the periphery factor beta_a + beta_b ln s. Both
   are monotonic in s, so the extremes of the range decide.
------------------------------------------------------------------------- */

void FixCGMSFluid::check_dryness_range(double s_min, double s_max)
{
  const Material &mat = pair->material();
  for (double s : {s_min, s_max}) {
    if (!(mat.lj_radius(s) > 0.0))
      error->all(FLERR,
                 "Fix cgms/fluid: at dryness {:.6g} the LJ radius r0 (1 + lj_slope ln s) = {:.4g} "
                 "m is not positive; this material (lj_slope {:g}) needs a dryness above "
                 "exp(-1/lj_slope) = {:.4g}",
                 s, mat.lj_radius(s), mat.lj_slope, exp(-1.0 / mat.lj_slope));
    if (pair->periphery && !(mat.beta(s) > 0.0)) {
      const std::string lowest = mat.beta_b > 0.0
          ? fmt::format("needs a dryness above exp(-beta_a/beta_b) = {:.4g}",
                        exp(-mat.beta_a / mat.beta_b))
          : std::string("gives no positive beta at this dryness; check beta_a and beta_b");
      error->all(FLERR,
                 "Fix cgms/fluid: at dryness {:.6g} the periphery factor beta = beta_a + "
                 "beta_b ln s = {:.4g} is not positive (boundary cells would get a negative "
                 "side); this material (beta_a {:g}, beta_b {:g}) {}",
                 s, mat.beta(s), mat.beta_a, mat.beta_b, lowest);
    }
  }
}

/* ----------------------------------------------------------------------
   a tissue read from a data file without the fluid state starts fresh at
   its dryness; if its beads sit much closer than the fresh cells they got,
   it was most likely dried before and written without the state
------------------------------------------------------------------------- */

void FixCGMSFluid::warn_if_dried(bigint fresh)
{
  const NeighbourSums *sums = neighbour_sums(lmp);
  if (!pair->pair_coefficient_needed() && !transfer) return;    // no geometry computed
  const Material &mat = pair->material();
  const BeadState cg = bead_state(lmp);
  // interior beads (six neighbours or more): their side against the reference side
  double local[2] = {0.0, 0.0}, global[2];
  for (int i = 0; i < atom->nlocal; i++) {
    if (sums[i].count < 6.0) continue;
    const double b_ref = cg[i][L0P] / (6.0 * mat.turgid_ratio);
    const double beta = pair->periphery ? mat.beta(cg[i][DRYNESS]) : 1.0;
    local[0] += cell_side(sums[i].count, sums[i].distance, beta, mat.pectin, mat.b_ref) / b_ref;
    local[1] += 1.0;
  }
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, world);
  if (global[1] == 0.0) return;
  const double ratio = global[0] / global[1];
  if (ratio < 0.9 && comm->me == 0)
    error->warning(FLERR,
                   "Fix cgms/fluid: {} beads start from the fresh reference cell, but the "
                   "cells are {:.0f} % smaller in side than that cell: if this tissue was dried "
                   "and written by write_data, its fluid state is lost; read the data file "
                   "with 'read_data FILE fix {} NULL {}' (files written by write_data with "
                   "fix cgms/fluid defined carry it)",
                   fresh, 100.0 * (1.0 - ratio), DATA_FIX, DATA_SECTION);
}

/* ---------------------------------------------------------------------- */

void FixCGMSFluid::fresh_bead_error(int fresh)
{
  error->one(FLERR,
             "Fix cgms/fluid: bead {} appeared during the run at step {} (e.g. from fix "
             "deposit or fix pour) and has no fluid state: CGMS gives beads their state at "
             "setup; add beads between runs (create_atoms, then run)",
             atom->tag[fresh], update->ntimestep);
}

/* ----------------------------------------------------------------------
   bead i has a line of a data file's state section that no setup took over
   yet: its state must be the one read_data left (data_atom_post), or a
   command between read_data and this setup changed it (set d_mf ..., the
   state's custom vectors), which taking the line over would silently undo
------------------------------------------------------------------------- */

void FixCGMSFluid::check_awaits_line(int i)
{
  const BeadState cg = bead_state(lmp);
  int changed = cg[i][MF0] != AWAITS_DATA_LINE ? MF0 : -1;
  for (int k = 0; k < NSTATE && changed < 0; k++)
    if (k != MF0 && cg[i][k] != 0.0) changed = k;
  if (changed >= 0)
    error->one(FLERR,
               "Fix cgms/fluid: bead {} has a line in the data file's {} section, which setup "
               "takes over, but its {} was changed after read_data (to {}, e.g. by 'set ... "
               "d_{}'): taking the line over would undo that. Give 'run 0' after read_data "
               "(the beads take their lines), then change the state",
               atom->tag[i], DATA_SECTION, state_name(changed), cg[i][changed],
               state_name(changed));
}

/* ----------------------------------------------------------------------
   the state every bead holds at setup, in the ranges of a data-file line
   (data_row_problem): a value changed between runs (set d_mf ...) must not
   surface later as a NaN or an unstable step
------------------------------------------------------------------------- */

void FixCGMSFluid::check_stored_state()
{
  const BeadState cg = bead_state(lmp);
  double row[NSTATE];
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < NSTATE; k++) row[k] = cg[i][k];
    const std::string problem = data_row_problem(row);
    if (!problem.empty())
      error->one(FLERR,
                 "Fix cgms/fluid: bead {} has {} (its state, the custom per-atom vectors "
                 "d_dryness ... d_dmdt, e.g. changed with set): give it a value in range",
                 atom->tag[i], problem);
  }
}

void FixCGMSFluid::emptied_error(int emptied)
{
  error->one(FLERR,
             "Fix cgms/fluid: fluid mass of bead {} became {} at step {}: mass transfer is "
             "unstable; reduce the time step (now {:.6g} s)",
             atom->tag[emptied], bead_state(lmp)[emptied][MF], update->ntimestep, update->dt);
}

/* ----------------------------------------------------------------------
   the first bead (of each kind, in this order) that pair_style cgms's fluid
   pass found beyond a limit stops the run
------------------------------------------------------------------------- */

void FixCGMSFluid::stop_if_unstable(const Trouble &t)
{
  const Material &mat = pair->material();
  const BeadState cg = bead_state(lmp);
  const double *rmass = atom->rmass;
  const NeighbourSums *sums = neighbour_sums(lmp);
  const double dt = update->dt;
  const int isolated = t.isolated, nonfinite = t.nonfinite, unstable = t.unstable;
  const int shaky = t.shaky, stiff = t.stiff;

  if (t.emptied >= 0) emptied_error(t.emptied);
  if (isolated >= 0) isolated_error(isolated);
  if (nonfinite >= 0)
    error->one(FLERR,
               "Fix cgms/fluid: bead {} has a non-finite pressure at step {}: the simulation "
               "became unstable; reduce the time step (now {:.6g} s)",
               atom->tag[nonfinite], update->ntimestep, dt);
  if (unstable >= 0) damping_limit_error(unstable);
  if (shaky >= 0)
    error->one(FLERR,
               "Fix cgms/fluid: time step {:.4g} s is above the stability limit of the cell-shape "
               "stiffness k_S = {:g} N/m at step {}, about {:.4g} s = sqrt(m / (2 k_S N)) for "
               "bead {} (m = {:.4g} kg, N = {:g}): use a smaller timestep or k_S",
               dt, mat.k_S, update->ntimestep,
               pair->step_limits().shape(rmass[shaky], sums[shaky].count), atom->tag[shaky],
               rmass[shaky], sums[shaky].count);
  if (stiff >= 0 && t.after_change)
    error->one(FLERR,
               "Fix cgms/fluid: the change of dryness at step {} compresses bead {} to {:.4g} "
               "times its new reference density, and its turgor force is then above the "
               "stability limit, about {:.4g} s = 2 / omega (omega dt = {:.3g} at dt = {:.4g} "
               "s): change the dryness in smaller steps (e.g. a ramp with 'every'; when the "
               "dryness comes from fix cgms/transport, a shorter moisture step: its keywords "
               "dt or adapt), or use a smaller timestep",
               update->ntimestep, atom->tag[stiff],
               cg[stiff][RHO] / (cg[stiff][DRYNESS] * mat.rho0), t.stiff_limit,
               2.0 * sqrt(t.stiff_ratio), dt);
  if (stiff >= 0)
    error->one(
        FLERR,
        "Fix cgms/fluid: time step {:.4g} s is above the stability limit of the turgor "
        "force at step {}, about {:.4g} s = 2 / omega (omega dt = {:.3g}) for bead {}, whose "
        "fluid is compressed to {:.4g} times its reference density: use a smaller "
        "timestep",
        dt, update->ntimestep, t.stiff_limit, 2.0 * sqrt(t.stiff_ratio), atom->tag[stiff],
        cg[stiff][RHO] / (cg[stiff][DRYNESS] * mat.rho0));
}

/* ----------------------------------------------------------------------
   positions and velocities come from the user (data file, set, velocity):
   a non-finite one would surface later as a pressure or time-step error
------------------------------------------------------------------------- */

void FixCGMSFluid::check_setup_input()
{
  double **x = atom->x;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    for (int d = 0; d < 2; d++) {
      if (!std::isfinite(x[i][d]))
        error->one(FLERR, "Fix cgms/fluid: bead {} has a non-finite position ({} = {}) at setup",
                   atom->tag[i], d ? "y" : "x", x[i][d]);
      if (!std::isfinite(v[i][d]))
        error->one(FLERR,
                   "Fix cgms/fluid: bead {} has a non-finite velocity (v{} = {}) at setup; "
                   "check the data file's Velocities section and any set or velocity command",
                   atom->tag[i], d ? "y" : "x", v[i][d]);
    }
  }
}

/* ----------------------------------------------------------------------
   what a user's tissue can get wrong from the start, seen at setup where it
   can be named: two beads closer than the pectin layer (their cell side
   would be negative), and far more neighbours than a hexagonal tissue has
   (the cutoff or the spacing does not fit the material)
------------------------------------------------------------------------- */

void FixCGMSFluid::check_setup_geometry()
{
  const NeighbourSums *sums = neighbour_sums(lmp);
  const Material &mat = pair->material();
  double **x = atom->x;
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;

  // the closest pair of this rank's list
  double closest = HUGE_VAL;
  int ci = -1, cj = -1;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = x[i][0] - x[j][0];
      const double dy = x[i][1] - x[j][1];
      const double rsq = dx * dx + dy * dy;
      if (rsq < closest) {
        closest = rsq;
        ci = i;
        cj = j;
      }
    }
  }
  closest = sqrt(closest);
  // a hexagonal tissue has 6 neighbours and 12 within its second shell
  int crowded = -1;
  for (int i = 0; i < nlocal; i++)
    if (sums[i].count > 12.0 && (crowded < 0 || sums[i].count > sums[crowded].count)) crowded = i;
  if (crowded >= 0)
    error->one(FLERR,
               "Fix cgms/fluid: bead {} has {:g} neighbours within the pair cutoff at setup, "
               "where a hexagonal tissue has 6: the cutoff ({:.4g} m) does not fit the bead "
               "spacing of this tissue (nearest beads {:.4g} m apart here; the material's "
               "lattice spacing x_ref = sqrt(3) b_ref + d_p = {:.4g} m). Check pair_style "
               "cutoff, the material's diameter and pectin, and the data file's units",
               tag[crowded], sums[crowded].count, pair->cutoff(), closest, mat.x_ref);

  if (closest <= mat.pectin)
    error->one(FLERR,
               "Fix cgms/fluid: beads {} and {} are {:.4g} m apart at setup, {} the pectin "
               "layer d_p = {:.4g} m that separates two cells (lattice spacing x_ref = {:.4g} "
               "m): check the data file for overlapping or duplicated beads",
               tag[ci], tag[cj], closest,
               closest == 0.0 ? "at the same position, inside" : "closer than", mat.pectin,
               mat.x_ref);
}

/* ----------------------------------------------------------------------
   a bead without neighbours: say how far its nearest bead is, and whether
   the dryness-scaled cutoff shrank below the spacing (low dryness)
------------------------------------------------------------------------- */

void FixCGMSFluid::isolated_error(int i)
{
  const Material &mat = pair->material();
  double **x = atom->x;
  const double s = bead_state(lmp)[i][DRYNESS];
  double nearest = HUGE_VAL;
  for (int ii = 0; ii < list->inum; ii++) {
    const int a = list->ilist[ii];
    const int *jlist = list->firstneigh[a];
    for (int jj = 0; jj < list->numneigh[a]; jj++) {
      const int b = jlist[jj] & NEIGHMASK;
      if (a != i && b != i) continue;
      const double dx = x[a][0] - x[b][0];
      const double dy = x[a][1] - x[b][1];
      nearest = MIN(nearest, sqrt(dx * dx + dy * dy));
    }
  }
  const std::string where = nearest < HUGE_VAL
      ? fmt::format("its nearest bead is {:.4g} m away", nearest)
      : std::string("no bead lies within the cutoff plus the neighbor skin");
  std::string why;
  const double rad = mat.lj_radius(s);
  const double cut = sqrt(pair->pair_cutsq(rad));
  // a scaled cutoff that has shrunk to about the fresh spacing (jittered tissues
  // have neighbours up to 15 % beyond x_ref)
  if (pair->cutoff_scaled() && cut < 1.15 * mat.x_ref) {
    // a fresh tissue (spacing x_ref) keeps its neighbours while cut(s) > x_ref
    const double fresh_lowest =
        exp((mat.x_ref / sqrt(pair->pair_cutsq(mat.r0)) - 1.0) / mat.lj_slope);
    why = fmt::format(
        "; at dryness {:.4g} the cutoff is {:.4g} m (cutoff/lj times the LJ radius r0 (1 + "
        "lj_slope ln s) = {:.4g} m), which shrinks with the dryness faster than a tissue "
        "that has not dried yet (a fresh tissue keeps its neighbours down to a dryness of "
        "about {:.3g}): start from a tissue dried closer to this level, or lower the dryness "
        "gradually (a variable ramp with 'every')",
        s, cut, rad, fresh_lowest);
  } else if (update->whichflag == 2) {
    why = fmt::format("; the minimizer moved it away from the tissue (cutoff {:.4g} m): use "
                      "min_style fire or cg with min_modify dmax ~1e-6, which move beads in "
                      "small steps",
                      cut);
  }
  error->one(FLERR,
             "Fix cgms/fluid: bead {} has no neighbour within the pair cutoff (use 'isolated "
             "allow' to give isolated beads the reference cell) at step {}: {}{}",
             atom->tag[i], update->ntimestep, where, why);
}

/* ----------------------------------------------------------------------
   the relative-velocity damping is explicit: stable while
   k_d lambda_max dt / m < 2, lambda_max the largest eigenvalue of the bead
   graph's Laplacian. It is 9 for the hexagonal lattice (N = 6); the check
   uses 1.5 N_i per bead, which is that value and grows with denser
   neighbourhoods. (doc/model.md, Time integration: s = 0.3 with the paper's inertia explodes at
   dt = 5e-8 s and runs at 3e-8 s; this gives 3.9e-8 s at the start.)
   Checked at setup and, since masses and neighbour counts change, every step.
------------------------------------------------------------------------- */

void FixCGMSFluid::damping_limit_error(int i)
{
  const NeighbourSums *sums = neighbour_sums(lmp);
  const double m = atom->rmass[i];
  const double nn = sums[i].count;
  // more neighbours than a hexagonal lattice has: the tissue is folding onto itself (a
  // second-shell bead crossed the cutoff), which a smaller time step does not cure; the
  // paper's forces give the lattice no shear stiffness (doc/results/validation.md), k_S does;
  // with k_S(s) it is the dried cells' stiffness, far below k_S, that may be too weak
  const Material &mat = pair->material();
  const double kS = mat.k_S;
  if (nn > 6.0 && update->setupflag)
    error->one(FLERR,
               "Fix cgms/fluid: bead {} has {:g} neighbours within the pair cutoff ({:.4g} m) "
               "at setup, more than the 6 of a hexagonal tissue, and the damping is unstable "
               "with them at dt = {:.4g} s: the cutoff does not fit the bead spacing (material "
               "lattice spacing x_ref = {:.4g} m); check pair_style cutoff, the material's "
               "diameter and pectin, and the data file",
               atom->tag[i], nn, pair->cutoff(), update->dt, pair->material().x_ref);
  if (nn > 6.0)
    error->one(FLERR,
               "Fix cgms/fluid: bead {} has {:g} neighbours within the cutoff at step {}, more "
               "than the 6 of a hexagonal tissue: the tissue is collapsing (beads crowding "
               "past the weak LJ repulsion), and the damping is unstable at dt = {:.4g} s; a "
               "smaller time step does not cure this. The paper's forces do not resist shear; "
               "{} prevent it (doc/pair_cgms.rst, doc/results/validation.md hard cases)",
               atom->tag[i], nn, update->ntimestep, update->dt,
               kS > 0.0 && mat.k_S_exponent != 0.0
                   ? fmt::format("a larger cell-shape stiffness of the dried cells, k_S(s) = "
                                 "max(k_S s^n, k_S_floor) with k_S = {:g} N/m, n = {:g}, "
                                 "k_S_floor = {:g} N/m, may",
                                 kS, mat.k_S_exponent, mat.k_S_floor)
                   : kS > 0.0
                   ? fmt::format("a cell-shape stiffness above k_S = {:g} N/m may", kS)
                   : std::string("a cell-shape stiffness (e.g. k_S 0.5 on the pair_coeff "
                                 "line) may"));
  error->one(FLERR,
             "Fix cgms/fluid: time step {:.4g} s is above the stability limit of the damping at "
             "step {}, about {:.4g} s = 2 m / (1.5 N k_d) for bead {} (m = {:.4g} kg, N = {:g}): "
             "use a smaller timestep{}",
             update->dt, update->ntimestep, pair->step_limits().damping(m, nn), atom->tag[i], m, nn,
             inertia_fluid ? " or 'inertia fresh'" : "");
}
