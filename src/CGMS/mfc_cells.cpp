/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "mfc_cells.h"

#include "atom.h"
#include "error.h"
#include "fix.h"
#include "group.h"
#include "lammps.h"
#include "modify.h"

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   the largest molecule ID in the group; every wall particle's ID names its
   cell, so it must be positive
------------------------------------------------------------------------- */

int CGMS::max_cell_molecule(LAMMPS *lmp, Fix *fix)
{
  Atom *atom = lmp->atom;
  tagint local = 0, global = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & fix->groupbit)) continue;
    if (atom->molecule[i] <= 0)
      lmp->error->one(FLERR,
                      "Fix {}: wall particle {} has molecule ID {}: every particle of group {} "
                      "needs the positive molecule ID of its cell",
                      fix->style, atom->tag[i], atom->molecule[i], lmp->group->names[fix->igroup]);
    local = MAX(local, atom->molecule[i]);
  }
  MPI_Allreduce(&local, &global, 1, MPI_LMP_TAGINT, MPI_MAX, lmp->world);
  if (global > MAXSMALLINT)
    lmp->error->all(FLERR, "Fix {}: molecule IDs up to {} are too large", fix->style, global);
  return (int) global;
}

/* ----------------------------------------------------------------------
   a wall particle in two fixes of one style has its cell's fluid pushing
   on it twice
------------------------------------------------------------------------- */

void CGMS::refuse_shared_walls(LAMMPS *lmp, Fix *fix)
{
  const int *mask = lmp->atom->mask;
  const int nlocal = lmp->atom->nlocal;
  for (auto *other : lmp->modify->get_fix_by_style(fmt::format("^{}$", fix->style))) {
    if (other == fix) continue;
    int local = 0, shared;
    for (int i = 0; i < nlocal && !local; i++)
      if ((mask[i] & fix->groupbit) && (mask[i] & other->groupbit)) local = 1;
    MPI_Allreduce(&local, &shared, 1, MPI_INT, MPI_MAX, lmp->world);
    if (shared)
      lmp->error->all(FLERR,
                      "Fix {} {}: fix {} holds wall particles of group {} too, so their cells' "
                      "fluid would push twice; each cell belongs to one fix (unfix {}, or give "
                      "the fixes groups without a common particle)",
                      fix->style, fix->id, other->id, lmp->group->names[fix->igroup], other->id);
  }
}
