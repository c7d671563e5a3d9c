/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#include "fix_mfc_pressure3d.h"

#include "atom.h"
#include "atom_vec.h"
#include "cgms_laws.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "mfc_cells.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

// a closed wall's triangle area vectors sum to zero; this much of the total
// area is rounding (the sum runs over a few thousand terms)
static constexpr double CLOSED_TOL = 1.0e-9;

/* ----------------------------------------------------------------------
   fix ID group mfc/pressure3d modulus K turgor P_T volume V_f [triangles T]
------------------------------------------------------------------------- */

FixMFCPressure3d::FixMFCPressure3d(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), modulus(0.0), turgor(0.0), fluid_volume(0.0), triangle_type(1), ncell(0),
    sums(nullptr), pressure(nullptr), energy(0.0), nmax(0), fwall(nullptr)
{
  if (!atom->molecule_flag || !atom->molecular || !atom->avec->angles_allow)
    error->all(FLERR,
               "Fix mfc/pressure3d needs molecule IDs and angles (e.g. atom_style molecular): "
               "the wall triangles are angles");
  if (domain->dimension != 3)
    error->all(FLERR, "Fix mfc/pressure3d needs dimension 3 (fix mfc/pressure is the 2-D one)");

  int given[3] = {0, 0, 0};
  for (int iarg = 3; iarg < narg; iarg += 2) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Fix mfc/pressure3d keyword {} needs a value", key);
    if (key == "triangles") {
      triangle_type = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      continue;
    }
    const double value = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    if (!std::isfinite(value))
      error->all(FLERR, "Fix mfc/pressure3d {} must be a finite number, not {}", key,
                 arg[iarg + 1]);
    if (key == "modulus") {
      modulus = value;
      given[0] = 1;
    } else if (key == "turgor") {
      turgor = value;
      given[1] = 1;
    } else if (key == "volume") {
      fluid_volume = value;
      given[2] = 1;
    } else
      error->all(FLERR, "Unknown fix mfc/pressure3d keyword {}", key);
  }
  const char *names[3] = {"modulus", "turgor", "volume"};
  for (int k = 0; k < 3; k++)
    if (!given[k]) error->all(FLERR, "Fix mfc/pressure3d needs the keyword {}", names[k]);
  if (modulus <= 0.0) error->all(FLERR, "Fix mfc/pressure3d modulus must be > 0, not {}", modulus);
  if (fluid_volume <= 0.0)
    error->all(FLERR, "Fix mfc/pressure3d volume (fluid mass / rho0) must be > 0, not {}",
               fluid_volume);
  if (triangle_type < 1 || triangle_type > atom->nangletypes)
    error->all(FLERR,
               "Fix mfc/pressure3d triangles {}: the wall triangles' angle type must be one "
               "of 1..{} (the data file's angle types)",
               triangle_type, atom->nangletypes);

  if (group->count(igroup) == 0)
    error->all(FLERR,
               "Fix mfc/pressure3d group {} is empty: it must hold the cells' wall particles",
               group->names[igroup]);
  ncell = CGMS::max_cell_molecule(lmp, this);

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = 3;
  extvector = 0;
  array_flag = 1;
  size_array_rows = ncell;
  size_array_cols = 3;
  extarray = 0;
  energy_global_flag = 1;
  comm_reverse = 3;

  memory->create(sums, ncell, "mfc/pressure3d:sums");
  memory->create(pressure, ncell, "mfc/pressure3d:pressure");
  for (int c = 0; c < ncell; c++) sums[c] = {0.0, 0.0, 0.0};
  for (int c = 0; c < ncell; c++) pressure[c] = 0.0;
}

/* ---------------------------------------------------------------------- */

FixMFCPressure3d::~FixMFCPressure3d()
{
  memory->destroy(sums);
  memory->destroy(pressure);
  memory->destroy(fwall);
}

/* ---------------------------------------------------------------------- */

int FixMFCPressure3d::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixMFCPressure3d::init()
{
  if (domain->xperiodic || domain->yperiodic || domain->zperiodic)
    error->all(FLERR, "Fix mfc/pressure3d needs non-periodic boundaries (boundary f f f)");
  if (!force->angle)
    error->all(FLERR,
               "Fix mfc/pressure3d needs an angle style (e.g. angle_style zero): LAMMPS "
               "lists the wall triangles, which are angles, only when one is defined");
  if (CGMS::max_cell_molecule(lmp, this) > ncell)
    error->all(FLERR,
               "Fix mfc/pressure3d: the group has molecule IDs above {} (its cells when "
               "the fix was defined); define the fix again",
               ncell);
  CGMS::refuse_shared_walls(lmp, this);
}

/* ---------------------------------------------------------------------- */

void FixMFCPressure3d::setup(int vflag)
{
  post_force(vflag);
}

void FixMFCPressure3d::min_setup(int vflag)
{
  post_force(vflag);
}

void FixMFCPressure3d::min_post_force(int vflag)
{
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   the cell index of triangle t = (a, b, c, type) of the angle list, or -1
   when it is not counted here: not a wall triangle, no atom in the group,
   or its middle atom owned by another rank (each triangle is counted by
   the owner of its middle atom, with newton_bond on or off)
------------------------------------------------------------------------- */

int FixMFCPressure3d::triangle_cell(const int *t)
{
  if (t[3] != triangle_type || t[1] >= atom->nlocal) return -1;
  const int *mask = atom->mask;
  const tagint *molecule = atom->molecule;
  const int inside = (mask[t[0]] & groupbit ? 1 : 0) + (mask[t[1]] & groupbit ? 1 : 0) +
      (mask[t[2]] & groupbit ? 1 : 0);
  if (inside == 0) return -1;
  if (inside != 3 || molecule[t[0]] != molecule[t[1]] || molecule[t[0]] != molecule[t[2]])
    error->one(FLERR,
               "Fix mfc/pressure3d: wall triangle {} {} {} (molecule IDs {} {} {}) is not "
               "whole in one cell of group {}: a cell's triangles join its own wall "
               "particles, and the group holds whole cells",
               atom->tag[t[0]], atom->tag[t[1]], atom->tag[t[2]], molecule[t[0]], molecule[t[1]],
               molecule[t[2]], group->names[igroup]);
  const int c = (int) molecule[t[1]] - 1;
  if (c >= ncell)
    error->one(FLERR, "Fix mfc/pressure3d: wall particle {} has molecule ID {} outside 1..{}",
               atom->tag[t[1]], molecule[t[1]], ncell);
  return c;
}

/* ----------------------------------------------------------------------
   enclosed volumes by the divergence theorem, V = sum (x_a . x_b x x_c) / 6
   over the triangles (positions from the box centre, for rounding), and
   wall areas; summed over ranks
------------------------------------------------------------------------- */

void FixMFCPressure3d::sum_volumes()
{
  double **x = atom->x;
  double centre[3];
  for (int d = 0; d < 3; d++) centre[d] = 0.5 * (domain->boxlo[d] + domain->boxhi[d]);
  for (int c = 0; c < ncell; c++) sums[c] = {0.0, 0.0, 0.0};
  for (int n = 0; n < neighbor->nanglelist; n++) {
    const int *t = neighbor->anglelist[n];
    const int c = triangle_cell(t);
    if (c < 0) continue;
    double a[3], b[3], e[3], cross[3], u[3], v[3];
    for (int d = 0; d < 3; d++) {
      a[d] = x[t[0]][d] - centre[d];
      b[d] = x[t[1]][d] - centre[d];
      e[d] = x[t[2]][d] - centre[d];
      u[d] = b[d] - a[d];
      v[d] = e[d] - a[d];
    }
    cross[0] = b[1] * e[2] - b[2] * e[1];
    cross[1] = b[2] * e[0] - b[0] * e[2];
    cross[2] = b[0] * e[1] - b[1] * e[0];
    sums[c].volume += (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0;
    sums[c].triangles += 1.0;
    const double nx = u[1] * v[2] - u[2] * v[1];
    const double ny = u[2] * v[0] - u[0] * v[2];
    const double nz = u[0] * v[1] - u[1] * v[0];
    sums[c].area += 0.5 * sqrt(nx * nx + ny * ny + nz * nz);
  }
  MPI_Allreduce(MPI_IN_PLACE, reinterpret_cast<double *>(sums), NSUM * ncell, MPI_DOUBLE, MPI_SUM,
                world);
}

/* ----------------------------------------------------------------------
   per cell: the pressure of the Tait law and the stored energy
------------------------------------------------------------------------- */

void FixMFCPressure3d::cell_pressures()
{
  energy = 0.0;
  for (int c = 0; c < ncell; c++) {
    pressure[c] = 0.0;
    if (sums[c].triangles == 0.0) continue;    // no such cell in the group
    const double volume = sums[c].volume;
    if (!(volume > 0.0))
      error->all(FLERR,
                 "Fix mfc/pressure3d: cell {} encloses volume {} <= 0 on step {}: its "
                 "triangles are ordered clockwise seen from outside, or its wall turned "
                 "inside out",
                 c + 1, volume, update->ntimestep);
    // the Tait law of the coarse model (eqn 4 of doc/model.md), density ratio V_f / V
    const double q = fluid_volume / volume;
    const double q6 = q * q * q * q * q * q;
    pressure[c] = CGMS::tait_pressure(CGMS::pow7(q), turgor, modulus);
    // -int_{V_f}^{V} P dV, zero at V = V_f
    const double stored =
        (modulus - turgor) * (volume - fluid_volume) + modulus * fluid_volume / 6.0 * (q6 - 1.0);
    if (!std::isfinite(pressure[c]) || !std::isfinite(stored))
      error->all(FLERR,
                 "Fix mfc/pressure3d: cell {} on step {}: its fluid of rest volume {} m^3 "
                 "in a wall of volume {} m^3 gives a pressure of {} Pa (the Tait law's "
                 "(V_f / V)^7 overflows): the volume keyword must be the fluid's rest "
                 "volume, of the order of the wall's",
                 c + 1, update->ntimestep, fluid_volume, volume, pressure[c]);
    energy += stored;
  }
}

/* ----------------------------------------------------------------------
   forces P dV/dx: on a closed wall dV/dx_i is a third of the area vectors
   of the triangles around particle i, so each triangle pushes its three
   corners by P N / 3 (N = its area vector, outward). Ghost corners get
   theirs by a reverse communication of this fix, since the force's own
   reverse communication is over by post_force.
------------------------------------------------------------------------- */

void FixMFCPressure3d::post_force(int /*vflag*/)
{
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    memory->destroy(fwall);
    memory->create(fwall, nmax, 3, "mfc/pressure3d:fwall");
  }
  const int nall = atom->nlocal + atom->nghost;
  for (int i = 0; i < nall; i++) fwall[i][0] = fwall[i][1] = fwall[i][2] = 0.0;

  sum_volumes();
  cell_pressures();

  double **x = atom->x;
  std::vector<double> closure(3 * ncell, 0.0);
  for (int n = 0; n < neighbor->nanglelist; n++) {
    const int *t = neighbor->anglelist[n];
    const int c = triangle_cell(t);
    if (c < 0) continue;
    double u[3], v[3];
    for (int d = 0; d < 3; d++) {
      u[d] = x[t[1]][d] - x[t[0]][d];
      v[d] = x[t[2]][d] - x[t[0]][d];
    }
    const double area_vector[3] = {0.5 * (u[1] * v[2] - u[2] * v[1]),
                                   0.5 * (u[2] * v[0] - u[0] * v[2]),
                                   0.5 * (u[0] * v[1] - u[1] * v[0])};
    const double third = pressure[c] / 3.0;
    for (int d = 0; d < 3; d++) {
      closure[3 * c + d] += area_vector[d];
      for (int k = 0; k < 3; k++) fwall[t[k]][d] += third * area_vector[d];
    }
  }
  // an open wall (a missing or flipped triangle) has no enclosed volume
  MPI_Allreduce(MPI_IN_PLACE, closure.data(), 3 * ncell, MPI_DOUBLE, MPI_SUM, world);
  for (int c = 0; c < ncell; c++) {
    const double *sum = &closure[3 * c];
    const double gap = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (sums[c].triangles > 0.0 && gap > CLOSED_TOL * sums[c].area)
      error->all(FLERR,
                 "Fix mfc/pressure3d: the wall of cell {} is not closed (its triangles' area "
                 "vectors sum to {:.3g} of its area {} m^2): a triangle is missing, doubled "
                 "or ordered the wrong way round",
                 c + 1, gap / sums[c].area, sums[c].area);
  }

  comm->reverse_comm(this);
  double **f = atom->f;
  for (int i = 0; i < atom->nlocal; i++)
    for (int d = 0; d < 3; d++) f[i][d] += fwall[i][d];
}

/* ---------------------------------------------------------------------- */

int FixMFCPressure3d::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    buf[m++] = fwall[i][0];
    buf[m++] = fwall[i][1];
    buf[m++] = fwall[i][2];
  }
  return m;
}

void FixMFCPressure3d::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    fwall[j][0] += buf[m++];
    fwall[j][1] += buf[m++];
    fwall[j][2] += buf[m++];
  }
}

/* ----------------------------------------------------------------------
   the potential energy of the cell fluids (J), for fix_modify energy yes
------------------------------------------------------------------------- */

double FixMFCPressure3d::compute_scalar()
{
  return energy;
}

/* ----------------------------------------------------------------------
   1: number of cells, 2: their total volume (m^3), 3: their mean pressure (Pa)
------------------------------------------------------------------------- */

double FixMFCPressure3d::compute_vector(int n)
{
  double count = 0.0, total = 0.0, mean = 0.0;
  for (int c = 0; c < ncell; c++)
    if (sums[c].triangles > 0.0) {
      count += 1.0;
      total += sums[c].volume;
      mean += pressure[c];
    }
  if (n == 0) return count;
  if (n == 1) return total;
  return count > 0.0 ? mean / count : 0.0;
}

/* ----------------------------------------------------------------------
   row c (cell = molecule c + 1): enclosed volume (m^3), pressure (Pa),
   wall area (m^2)
------------------------------------------------------------------------- */

double FixMFCPressure3d::compute_array(int c, int col)
{
  if (col == 0) return sums[c].volume;
  if (col == 1) return pressure[c];
  return sums[c].area;
}
