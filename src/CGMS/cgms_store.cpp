/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "cgms_store.h"

#include "atom.h"
#include "atom_vec_cgms.h"
#include "domain.h"
#include "error.h"
#include "lammps.h"
#include "update.h"

#include <cstring>
#include <map>

using namespace LAMMPS_NS;

const char *const CGMS::column_names[CGMS::NOUTPUTS] = {
    "cgmscoef", "dryness", "nneigh",   "side", "mf",    "ms",   "mf0",
    "l0p",      "rho",     "pressure", "area", "perim", "ldeq", "dmdt"};

/* ---------------------------------------------------------------------- */

int *CGMS::state_indices(LAMMPS *lmp)
{
  struct Indices {
    int index[NSTATE];
    Indices()
    {
      for (int &k : index) k = -1;
    }
  };
  static std::map<LAMMPS *, Indices> indices;
  return indices[lmp].index;
}

CGMS::BeadState CGMS::bead_state(LAMMPS *lmp)
{
  const int *index = state_indices(lmp);
  BeadState state;
  for (int k = 0; k < NSTATE; k++)
    state.col[k] = index[k] >= 0 ? lmp->atom->dvector[index[k]] : nullptr;
  return state;
}

/* ----------------------------------------------------------------------
   std::map nodes never move, so the address handed to Atom::add_peratom()
   stays valid for the life of the process
------------------------------------------------------------------------- */

double **&CGMS::sums_array(LAMMPS *lmp)
{
  static std::map<LAMMPS *, double **> arrays;
  return arrays[lmp];
}

// memory->grow allocates a 2d array's rows as one block: row 0 is its start
CGMS::NeighbourSums *CGMS::neighbour_sums(LAMMPS *lmp)
{
  double **array = sums_array(lmp);
  return array ? reinterpret_cast<NeighbourSums *>(array[0]) : nullptr;
}

/* ---------------------------------------------------------------------- */

CGMS::OutputPacker &CGMS::output_packer(LAMMPS *lmp)
{
  static std::map<LAMMPS *, OutputPacker> packers;
  return packers[lmp];
}

/* ---------------------------------------------------------------------- */

std::string &CGMS::dropped_columns_note(LAMMPS *lmp)
{
  static std::map<LAMMPS *, std::string> notes;
  return notes[lmp];
}

/* ---------------------------------------------------------------------- */

void CGMS::require_cgms_system(LAMMPS *lmp, const char *who)
{
  if (strcmp(lmp->update->unit_style, "si") != 0)
    lmp->error->all(FLERR, "{} requires units si (found units {})", who, lmp->update->unit_style);
  if (lmp->domain->dimension != 2) lmp->error->all(FLERR, "{} requires dimension 2", who);
  if (!dynamic_cast<AtomVecCGMS *>(lmp->atom->avec))
    lmp->error->all(FLERR, "{} requires atom_style cgms (found atom_style {})", who,
                    lmp->atom->atom_style);
}
