/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#include "cgms_store.h"

#include <map>

using namespace LAMMPS_NS;

const char *const CGMS::column_names[CGMS::NCOLUMNS] = {
    "mf",     "ms",   "dryness", "mf0",   "l0p",  "rho",  "pressure",
    "nneigh", "side", "area",    "perim", "ldeq", "dmdt", "cgmscoef"};

/* ----------------------------------------------------------------------
   std::map nodes never move, so the address handed to Atom::add_peratom()
   stays valid for the life of the process
------------------------------------------------------------------------- */

CGMS::Store &CGMS::store(LAMMPS *lmp)
{
  static std::map<LAMMPS *, Store> stores;
  return stores[lmp];
}
