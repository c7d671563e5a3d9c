/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "compute_cgms_atom.h"

#include "atom.h"
#include "cgms_store.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "pair_cgms.h"
#include "update.h"

#include <cstring>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

ComputeCGMSAtom::ComputeCGMSAtom(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), vector(nullptr), array(nullptr)
{
  std::string names;
  for (int k = 0; k < CGMS::NOUTPUTS; k++) names += std::string(" ") + CGMS::column_names[k];
  if (narg < 4) error->all(FLERR, "Compute cgms/atom needs at least one output name:{}", names);
  for (int iarg = 3; iarg < narg; iarg++) {
    int column = -1;
    for (int k = 0; k < CGMS::NOUTPUTS; k++)
      if (strcmp(arg[iarg], CGMS::column_names[k]) == 0) column = k;
    if (column < 0)
      error->all(FLERR, "Compute cgms/atom: unknown output {}; the outputs are:{}", arg[iarg],
                 names);
    columns.push_back(column);
  }
  peratom_flag = 1;
  size_peratom_cols = columns.size() == 1 ? 0 : static_cast<int>(columns.size());
}

/* ---------------------------------------------------------------------- */

ComputeCGMSAtom::~ComputeCGMSAtom()
{
  memory->destroy(vector);
  memory->destroy(array);
}

/* ----------------------------------------------------------------------
   the derived outputs need the pair style that derives them; the state
   columns alone are read from the beads
------------------------------------------------------------------------- */

void ComputeCGMSAtom::init()
{
  CGMS::require_cgms_system(lmp, "Compute cgms/atom");
  if (dynamic_cast<PairCGMS *>(force->pair)) return;
  for (int column : columns) {
    bool stored = false;
    for (int k = 0; k < CGMS::NSTATE; k++) stored = stored || CGMS::STATE_OUTPUT[k] == column;
    if (!stored)
      error->all(FLERR,
                 "Compute cgms/atom {}: output {} is derived by pair_style cgms, which is not "
                 "defined (the state columns, e.g. mf, can be read without it)",
                 id, CGMS::column_names[column]);
  }
}

/* ----------------------------------------------------------------------
   one pass over the beads: pair_style cgms gives every output of a bead at
   once (PairCGMS::for_each_output), as for compute property/atom
------------------------------------------------------------------------- */

void ComputeCGMSAtom::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  const int nvalues = static_cast<int>(columns.size());
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    if (nvalues == 1) {
      memory->destroy(vector);
      memory->create(vector, nmax, "cgms/atom:vector");
      vector_atom = vector;
    } else {
      memory->destroy(array);
      memory->create(array, nmax, nvalues, "cgms/atom:array");
      array_atom = array;
    }
  }
  double *out = nvalues == 1 ? vector : (nmax > 0 ? array[0] : nullptr);
  const int *mask = atom->mask;
  const int *column = columns.data();
  const auto store = [&](int i, const double *outputs) {
    const bool in_group = mask[i] & groupbit;
    for (int m = 0; m < nvalues; m++) out[i * nvalues + m] = in_group ? outputs[column[m]] : 0.0;
  };

  const auto *pair = dynamic_cast<const PairCGMS *>(force->pair);
  if (pair) {
    pair->for_each_output(store);
    return;
  }
  // init() allowed the state columns only
  const CGMS::BeadState state = CGMS::bead_state(lmp);
  double outputs[CGMS::NOUTPUTS] = {};
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < CGMS::NSTATE; k++) outputs[CGMS::STATE_OUTPUT[k]] = state[i][k];
    store(i, outputs);
  }
}

/* ---------------------------------------------------------------------- */

double ComputeCGMSAtom::memory_usage()
{
  return static_cast<double>(nmax) * columns.size() * sizeof(double);
}
