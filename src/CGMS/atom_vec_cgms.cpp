/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "atom_vec_cgms.h"

#include "atom.h"
#include "cgms_store.h"
#include "error.h"
#include "fix_cgms_fluid.h"
#include "modify.h"

#include <cstring>

using namespace LAMMPS_NS;

static constexpr char FIELD[] = "cgms";

/* ---------------------------------------------------------------------- */

AtomVecCGMS::AtomVecCGMS(LAMMPS *lmp) : AtomVec(lmp), rmass(nullptr), cgms(nullptr)
{
  molecular = Atom::ATOMIC;
  mass_type = PER_ATOM;
  atom->rmass_flag = 1;

  // register the per-bead array once per Atom instance; read_restart and a
  // second atom_style command construct this class again for the same Atom
  bool registered = false;
  for (const auto &item : atom->peratom)
    if (item.name == FIELD) registered = true;
  if (!registered) atom->add_peratom(FIELD, &CGMS::bead_array(lmp), Atom::DOUBLE, CGMS::NSTATE);

  // the row (the bead's state, one cache line) travels with a bead that changes
  // rank. Ghosts get none of it here: what is read for ghosts, the dryness (when
  // it is not uniform) and the pair coefficient, fix cgms/fluid sends itself
  // when they change (forward communication).
  fields_grow = {"rmass", FIELD};
  fields_copy = {"rmass", FIELD};
  fields_border = {"rmass"};
  fields_border_vel = {"rmass"};
  fields_exchange = {"rmass", FIELD};
  fields_restart = {"rmass", FIELD};
  fields_create = {"rmass", FIELD};
  fields_data_atom = {"id", "type", "x"};
  fields_data_vel = {"id", "v"};

  setup_fields();
}

/* ----------------------------------------------------------------------
   a restart file holds each bead as one record of doubles in the layout of
   the build that wrote it; one written with another layout of the row (it
   held 14 columns before the 8-column state row) would be read shifted,
   without a sign. Each record must have the length this build writes, plus
   at most the per-atom values the file's fixes declared.
------------------------------------------------------------------------- */

int AtomVecCGMS::unpack_restart(double *buf)
{
  // the record's length, x (3), tag, type, mask, image, v (3), rmass, the row
  constexpr int OWN = 1 + 10 + 1 + CGMS::NSTATE;
  const int length = static_cast<int>(buf[0]);
  if ((length < OWN) || (length > OWN + atom->nextra_store))
    error->one(FLERR,
               "Restart file has {} values per bead where atom_style cgms reads {} (+ up to {} "
               "of fixes): it was written by another CGMS version. Read it with that version "
               "and write_data; a data file keeps the bead state across versions",
               length, OWN, atom->nextra_store);
  return AtomVec::unpack_restart(buf);
}

/* ----------------------------------------------------------------------
   read_data can hand a data-file section only to a fix that exists before
   the box, and LAMMPS allows that only for fix property/atom: define one that
   receives the fluid state section (read_data file fix CGMS NULL CGMS).
   fix cgms/fluid writes that section and takes the values over at setup.
------------------------------------------------------------------------- */

void AtomVecCGMS::process_args(int narg, char **arg)
{
  AtomVec::process_args(narg, arg);
  if (modify->get_fix_by_id(CGMS::DATA_FIX)) return;    // atom_style given again

  // fix property/atom records the atom style's name, which Atom::create_avec sets
  // only after this call returns: lend it the name meanwhile (create_avec then
  // replaces the pointer without freeing it)
  static char style_name[] = "cgms";
  atom->atom_style = style_name;
  try {
    modify->add_fix(fmt::format("{} all property/atom d2_{} {} writedata no", CGMS::DATA_FIX,
                                CGMS::DATA_PROPERTY, CGMS::NDATA));
  } catch (...) {
    atom->atom_style = nullptr;
    throw;
  }
  atom->atom_style = nullptr;
}

/* ---------------------------------------------------------------------- */

void AtomVecCGMS::init()
{
  AtomVec::init();
  if (atom->avec != this)
    error->all(FLERR, "Atom style cgms cannot be used as a sub-style of atom_style hybrid");
}

/* ---------------------------------------------------------------------- */

void AtomVecCGMS::grow_pointers()
{
  rmass = atom->rmass;
  cgms = CGMS::bead_array(lmp);
}

/* ----------------------------------------------------------------------
   a new bead has no fluid state yet: fix cgms/fluid fills it from the
   material parameters and its dryness at the next setup (MF0 <= 0 marks it).
   The placeholder mass keeps LAMMPS's mass checks quiet until then.
------------------------------------------------------------------------- */

void AtomVecCGMS::create_atom_post(int ilocal)
{
  rmass[ilocal] = 1.0;
  for (int k = 0; k < CGMS::NSTATE; k++) cgms[ilocal][k] = 0.0;
  cgms[ilocal][CGMS::MF0] = -1.0;
}

void AtomVecCGMS::data_atom_post(int ilocal)
{
  create_atom_post(ilocal);
}

/* ---------------------------------------------------------------------- */

int AtomVecCGMS::property_atom(const std::string &name)
{
  for (int k = 0; k < CGMS::NOUTPUTS; k++)
    if (name == CGMS::column_names[k]) return k;
  return -1;
}

/* ----------------------------------------------------------------------
   index is a CGMS::Output column: the state columns come from the row, the
   others from fix cgms/fluid, which derives them now from the state and its
   last geometry pass (0 without the fix)
------------------------------------------------------------------------- */

void AtomVecCGMS::pack_property_atom(int index, double *buf, int nvalues, int groupbit)
{
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  int column = -1;
  for (int k = 0; k < CGMS::NSTATE; k++)
    if (CGMS::STATE_OUTPUT[k] == index) column = k;
  if (column < 0) {
    const auto fixes = modify->get_fix_by_style("^cgms/fluid$");
    if (!fixes.empty()) {
      dynamic_cast<FixCGMSFluid *>(fixes.front())->pack_output(index, buf, nvalues, groupbit);
      return;
    }
  }
  int n = 0;
  for (int i = 0; i < nlocal; i++) {
    buf[n] = (mask[i] & groupbit) && column >= 0 ? cgms[i][column] : 0.0;
    n += nvalues;
  }
}
