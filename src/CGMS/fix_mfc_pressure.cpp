/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#include "fix_mfc_pressure.h"

#include "atom.h"
#include "cgms_laws.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "memory.h"
#include "mfc_cells.h"
#include "modify.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group mfc/pressure height H modulus K turgor P_T area A_f
------------------------------------------------------------------------- */

FixMFCPressure::FixMFCPressure(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), height(0.0), modulus(0.0), turgor(0.0), fluid_area(0.0), ncell(0),
    sums(nullptr), area(nullptr), pressure(nullptr), energy(0.0)
{
  if (!atom->molecule_flag || !atom->molecular)
    error->all(FLERR, "Fix mfc/pressure needs molecule IDs and bonds (e.g. atom_style angle)");
  if (domain->dimension != 2) error->all(FLERR, "Fix mfc/pressure needs dimension 2");

  int given[4] = {0, 0, 0, 0};
  int iarg = 3;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Fix mfc/pressure keyword {} needs a value", key);
    const double value = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    if (!std::isfinite(value))
      error->all(FLERR, "Fix mfc/pressure {} must be a finite number, not {}", key, arg[iarg + 1]);
    if (key == "height") {
      height = value;
      given[0] = 1;
    } else if (key == "modulus") {
      modulus = value;
      given[1] = 1;
    } else if (key == "turgor") {
      turgor = value;
      given[2] = 1;
    } else if (key == "area") {
      fluid_area = value;
      given[3] = 1;
    } else
      error->all(FLERR, "Unknown fix mfc/pressure keyword {}", key);
    iarg += 2;
  }
  const char *names[4] = {"height", "modulus", "turgor", "area"};
  for (int k = 0; k < 4; k++)
    if (!given[k]) error->all(FLERR, "Fix mfc/pressure needs the keyword {}", names[k]);
  if (height <= 0.0) error->all(FLERR, "Fix mfc/pressure height must be > 0, not {}", height);
  if (modulus <= 0.0) error->all(FLERR, "Fix mfc/pressure modulus must be > 0, not {}", modulus);
  if (fluid_area <= 0.0)
    error->all(FLERR, "Fix mfc/pressure area (fluid mass / (rho0 height)) must be > 0, not {}",
               fluid_area);

  if (group->count(igroup) == 0)
    error->all(FLERR, "Fix mfc/pressure group {} is empty: it must hold the cells' wall particles",
               group->names[igroup]);
  ncell = CGMS::max_cell_molecule(lmp, this);

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = 3;
  extvector = 0;
  array_flag = 1;
  size_array_rows = ncell;
  size_array_cols = 2;
  extarray = 0;
  energy_global_flag = 1;

  memory->create(sums, ncell, "mfc/pressure:sums");
  memory->create(area, ncell, "mfc/pressure:area");
  memory->create(pressure, ncell, "mfc/pressure:pressure");
  for (int c = 0; c < ncell; c++) sums[c] = {0.0, 0.0, 0.0};
  for (int c = 0; c < ncell; c++) area[c] = pressure[c] = 0.0;
}

/* ---------------------------------------------------------------------- */

FixMFCPressure::~FixMFCPressure()
{
  memory->destroy(sums);
  memory->destroy(area);
  memory->destroy(pressure);
}

/* ---------------------------------------------------------------------- */

int FixMFCPressure::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

/* ---------------------------------------------------------------------- */

void FixMFCPressure::init()
{
  if (domain->xperiodic || domain->yperiodic)
    error->all(FLERR, "Fix mfc/pressure needs non-periodic x and y (boundary f f p)");
  if (CGMS::max_cell_molecule(lmp, this) > ncell)
    error->all(FLERR,
               "Fix mfc/pressure: the group has molecule IDs above {} (its cells when "
               "the fix was defined); define the fix again",
               ncell);
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "Fix mfc/pressure needs an atom map (atom_modify map)");
  CGMS::refuse_shared_walls(lmp, this);
}

/* ---------------------------------------------------------------------- */

void FixMFCPressure::setup(int vflag)
{
  post_force(vflag);
}

void FixMFCPressure::min_setup(int vflag)
{
  post_force(vflag);
}

void FixMFCPressure::min_post_force(int vflag)
{
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   local indices of the previous and next wall particle of local atom i
   (closest images): the ring is numbered counter-clockwise with consecutive
   IDs, so a partner one ID up is the next, one down the previous, and the
   bond that closes the ring (first-last) goes the other way. Bond partners
   in other cells (a bonded middle lamella) are not part of the ring. The
   ring must lie in the group as a whole: the area of a part of it depends
   on where the origin is.
------------------------------------------------------------------------- */

void FixMFCPressure::ring_partners(int i, int &prev, int &next)
{
  const tagint me = atom->tag[i];
  prev = next = -1;
  int own = 0;
  for (int k = 0; k < atom->nspecial[i][0]; k++) {
    const tagint other = atom->special[i][k];
    int j = atom->map(other);
    if (j < 0)
      error->one(FLERR,
                 "Fix mfc/pressure: bond partner {} of wall particle {} is missing: it was "
                 "deleted (a ring needs every particle: delete whole cells, e.g. "
                 "'group gone molecule 5' and 'delete_atoms group gone bond yes'), or it is "
                 "beyond this processor's ghost region (comm_modify cutoff)",
                 other, me);
    j = domain->closest_image(i, j);
    if (atom->molecule[j] != atom->molecule[i]) continue;
    if (!(atom->mask[j] & groupbit))
      error->one(FLERR,
                 "Fix mfc/pressure: cell (molecule ID) {} is only partly in group {}: its wall "
                 "particle {} is, its ring neighbour {} is not; the group must hold whole rings",
                 atom->molecule[i], group->names[igroup], me, other);
    own++;
    const bool is_next = (other == me + 1) || (other < me - 1);
    if (is_next)
      next = j;
    else
      prev = j;
  }
  if (own != 2)
    error->one(FLERR,
               "Fix mfc/pressure: wall particle {} has {} bond partner(s) in its own cell "
               "(molecule ID {}); each must be bonded to exactly its two ring neighbours, in a "
               "closed ring of at least 3 particles",
               me, own, atom->molecule[i]);
  if (prev < 0 || next < 0)
    error->one(FLERR,
               "Fix mfc/pressure: the ring of wall particle {} (molecule ID {}) is not "
               "numbered with consecutive IDs",
               me, atom->molecule[i]);
}

/* ----------------------------------------------------------------------
   enclosed areas by the shoelace sum, each directed wall edge i -> next
   counted by the owner of i; pressures; forces P H dA/dx_i.
   A ring numbered with consecutive IDs has exactly one edge to a lower ID
   (last -> first): more under one molecule ID are more rings, which would
   be summed into one cell.
------------------------------------------------------------------------- */

void FixMFCPressure::post_force(int /*vflag*/)
{
  double **x = atom->x;
  double **f = atom->f;
  const int *mask = atom->mask;
  const tagint *molecule = atom->molecule;
  const int nlocal = atom->nlocal;

  for (int c = 0; c < ncell; c++) sums[c] = {0.0, 0.0, 0.0};
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    int prev, next;
    ring_partners(i, prev, next);
    const int c = (int) molecule[i] - 1;
    if (c < 0 || c >= ncell)
      error->one(FLERR, "Fix mfc/pressure: wall particle {} has molecule ID {} outside 1..{}",
                 atom->tag[i], molecule[i], ncell);
    sums[c].area += 0.5 * (x[i][0] * x[next][1] - x[next][0] * x[i][1]);
    sums[c].walls += 1.0;
    if (atom->tag[next] < atom->tag[i]) sums[c].wrapping += 1.0;
  }
  MPI_Allreduce(MPI_IN_PLACE, reinterpret_cast<double *>(sums), NSUM * ncell, MPI_DOUBLE, MPI_SUM,
                world);

  energy = 0.0;
  for (int c = 0; c < ncell; c++) {
    area[c] = sums[c].area;
    pressure[c] = 0.0;
    if (sums[c].walls == 0.0) continue;    // no such cell in the group
    if (sums[c].wrapping != 1.0)
      error->all(FLERR,
                 "Fix mfc/pressure: molecule ID {} holds {:.0f} rings of wall particles; each "
                 "cell needs its own molecule ID (one closed ring per ID)",
                 c + 1, sums[c].wrapping);
    if (!(area[c] > 0.0))
      error->all(FLERR,
                 "Fix mfc/pressure: cell {} encloses area {} <= 0 on step {}: its wall "
                 "is numbered clockwise or has turned inside out",
                 c + 1, area[c], update->ntimestep);
    // the Tait law of the coarse model (eqn 4 of doc/model.md), density ratio A_f / A
    const double q = fluid_area / area[c];
    const double q6 = q * q * q * q * q * q;
    pressure[c] = CGMS::tait_pressure(CGMS::pow7(q), turgor, modulus);
    // -H int_{A_f}^{A} P dA, zero at A = A_f
    const double stored = height *
        ((modulus - turgor) * (area[c] - fluid_area) + modulus * fluid_area / 6.0 * (q6 - 1.0));
    // a fluid squeezed far below its rest area: (A_f / A)^7 overflows
    if (!std::isfinite(pressure[c]) || !std::isfinite(stored))
      error->all(FLERR,
                 "Fix mfc/pressure: cell {} on step {}: its fluid of rest area {} m^2 in a ring "
                 "of area {} m^2 gives a pressure of {} Pa (the Tait law's (A_f / A)^7 "
                 "overflows): the area keyword must be the fluid's rest area, of the order of "
                 "the ring's",
                 c + 1, update->ntimestep, fluid_area, area[c], pressure[c]);
    energy += stored;
  }

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    int prev, next;
    ring_partners(i, prev, next);
    const double ph = 0.5 * pressure[molecule[i] - 1] * height;
    f[i][0] += ph * (x[next][1] - x[prev][1]);
    f[i][1] += ph * (x[prev][0] - x[next][0]);
  }
}

/* ----------------------------------------------------------------------
   the potential energy of the cell fluids (J), for fix_modify energy yes
------------------------------------------------------------------------- */

double FixMFCPressure::compute_scalar()
{
  return energy;
}

/* ----------------------------------------------------------------------
   1: number of cells, 2: their total area (m^2), 3: their mean pressure (Pa)
------------------------------------------------------------------------- */

double FixMFCPressure::compute_vector(int n)
{
  double count = 0.0, total = 0.0, mean = 0.0;
  for (int c = 0; c < ncell; c++)
    if (sums[c].walls > 0.0) {
      count += 1.0;
      total += area[c];
      mean += pressure[c];
    }
  if (n == 0) return count;
  if (n == 1) return total;
  return count > 0.0 ? mean / count : 0.0;
}

/* ----------------------------------------------------------------------
   row c (cell = molecule c + 1): enclosed area (m^2), pressure (Pa)
------------------------------------------------------------------------- */

double FixMFCPressure::compute_array(int c, int col)
{
  return col == 0 ? area[c] : pressure[c];
}
