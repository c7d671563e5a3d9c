/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "atom_vec_cgms.h"

#include "atom.h"
#include "cgms_store.h"
#include "error.h"
#include "input.h"
#include "memory.h"
#include "modify.h"

#include <cmath>
#include <cstring>
#include <unordered_map>

using namespace LAMMPS_NS;

static constexpr char SUMS_FIELD[] = "cgms_sums";

/* ---------------------------------------------------------------------- */

AtomVecCGMS::AtomVecCGMS(LAMMPS *lmp) :
    AtomVec(lmp), rmass(nullptr), scanned_natoms(-1), scanned_awaits(false)
{
  CGMS::dropped_columns_note(lmp).clear();
  molecular = Atom::ATOMIC;
  mass_type = PER_ATOM;
  atom->rmass_flag = 1;

  // the state columns are LAMMPS custom vectors (d_mf, ...), so that set, dump custom,
  // compute property/atom, variables and extract_atom see them by name. Atom grows,
  // copies and sends only its own fields and those a fix property/atom owns: this
  // style carries the columns through its bonus hooks, which AtomVec calls wherever it
  // carries a bead (grow, copy, exchange, restart). Nothing goes to the ghosts: what
  // the loops read for ghosts, the dryness (when it is not uniform, fix cgms/fluid)
  // and the pair coefficient (pair_style cgms), is sent when it changes.
  int *index = CGMS::state_indices(lmp);
  for (int k = 0; k < CGMS::NSTATE; k++) index[k] = -1;    // none, until all are there
  for (int k = 0; k < CGMS::NSTATE; k++) {
    int flag, cols;
    if (atom->find_custom(CGMS::state_name(k), flag, cols) >= 0)
      error->all(FLERR,
                 "Atom style cgms: a custom per-atom property {} exists already (fix "
                 "property/atom?); atom_style cgms defines d_{} for its bead state: remove "
                 "the other one or give it another name",
                 CGMS::state_name(k), CGMS::state_name(k));
    index[k] = atom->add_custom(CGMS::state_name(k), 1, 0, 0);
  }
  bonus_flag = 1;

  // register the neighbour sums once per Atom instance; read_restart and a second
  // atom_style command construct this class again for the same Atom
  bool sums_registered = false;
  for (const auto &item : atom->peratom)
    if (item.name == SUMS_FIELD) sums_registered = true;
  if (!sums_registered)
    atom->add_peratom(SUMS_FIELD, &CGMS::sums_array(lmp), Atom::DOUBLE, CGMS::NSUMS);

  // the neighbour sums of the last geometry pass travel with a bead that changes rank
  // (not in restart files: every setup computes them)
  fields_grow = {"rmass", SUMS_FIELD};
  fields_copy = {"rmass", SUMS_FIELD};
  fields_border = {"rmass"};
  fields_border_vel = {"rmass"};
  fields_exchange = {"rmass", SUMS_FIELD};
  fields_restart = {"rmass"};
  fields_create = {"rmass", SUMS_FIELD};
  fields_data_atom = {"id", "type", "x"};
  fields_data_vel = {"id", "v"};

  setup_fields();
}

/* ----------------------------------------------------------------------
   the state columns go with this style: Atom::create_avec deletes it before
   it makes the next one, and ~Atom before it frees the custom vectors
------------------------------------------------------------------------- */

AtomVecCGMS::~AtomVecCGMS()
{
  int *index = CGMS::state_indices(lmp);
  for (int k = 0; k < CGMS::NSTATE; k++) {
    if (index[k] >= 0) atom->remove_custom(index[k], 1, 0);
    index[k] = -1;
  }
}

/* ----------------------------------------------------------------------
   the state columns, carried where AtomVec carries a bead's own fields
------------------------------------------------------------------------- */

void AtomVecCGMS::grow_pointers()
{
  rmass = atom->rmass;
  const int *index = CGMS::state_indices(lmp);
  for (int k = 0; k < CGMS::NSTATE; k++)
    memory->grow(atom->dvector[index[k]], nmax, "atom:dvector");
  state = CGMS::bead_state(lmp);
}

void AtomVecCGMS::copy_bonus(int i, int j, int)
{
  for (int k = 0; k < CGMS::NSTATE; k++) state.col[k][j] = state.col[k][i];
}

int AtomVecCGMS::pack_exchange_bonus(int i, double *buf)
{
  for (int k = 0; k < CGMS::NSTATE; k++) buf[k] = state.col[k][i];
  return CGMS::NSTATE;
}

int AtomVecCGMS::unpack_exchange_bonus(int ilocal, double *buf)
{
  for (int k = 0; k < CGMS::NSTATE; k++) state.col[k][ilocal] = buf[k];
  return CGMS::NSTATE;
}

// a restart record holds the columns right after rmass, in column order: the
// layout of the per-bead row of earlier builds, whose restart files read the same
int AtomVecCGMS::size_restart_bonus()
{
  return CGMS::NSTATE * atom->nlocal;
}

int AtomVecCGMS::pack_restart_bonus(int i, double *buf)
{
  return pack_exchange_bonus(i, buf);
}

int AtomVecCGMS::unpack_restart_bonus(int ilocal, double *buf)
{
  return unpack_exchange_bonus(ilocal, buf);
}

double AtomVecCGMS::memory_usage_bonus()
{
  return static_cast<double>(CGMS::NSTATE) * nmax * sizeof(double);
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
  // atom_style hybrid would carry the state columns without the bonus hooks' sizes
  if (atom->avec != this)
    error->all(FLERR, "Atom style cgms cannot be used as a sub-style of atom_style hybrid");
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

/* ----------------------------------------------------------------------
   a new bead has no fluid state yet: fix cgms/fluid fills it from the
   material parameters and its dryness at the next setup (MF0 <= 0 marks it).
   The placeholder mass keeps LAMMPS's mass checks quiet until then. Its row
   of fix CGMS may hold what a deleted bead left there: cleared, so that the
   bead cannot take over another one's state.
------------------------------------------------------------------------- */

void AtomVecCGMS::create_atom_post(int ilocal)
{
  rmass[ilocal] = 1.0;
  for (int k = 0; k < CGMS::NSTATE; k++) state[ilocal][k] = 0.0;
  state[ilocal][CGMS::MF0] = CGMS::NO_STATE;
  for (int k = 0; k < CGMS::NSUMS; k++) CGMS::sums_array(lmp)[ilocal][k] = 0.0;
  clear_custom_rows(ilocal);
}

/* ----------------------------------------------------------------------
   a bead of a data file whose CGMS section read_data hands to fix CGMS
   awaits its line: fix cgms/fluid names a bead that got none at setup
------------------------------------------------------------------------- */

void AtomVecCGMS::data_atom_post(int ilocal)
{
  create_atom_post(ilocal);
  if (data_file_brings_state()) state[ilocal][CGMS::MF0] = CGMS::AWAITS_DATA_LINE;
}

/* ----------------------------------------------------------------------
   write_data: a data file of the same name may be read again afterwards
------------------------------------------------------------------------- */

void AtomVecCGMS::pack_data(double **buf)
{
  scanned_natoms = -1;
  AtomVec::pack_data(buf);
}

/* ---------------------------------------------------------------------- */

void AtomVecCGMS::clear_custom_rows(int ilocal)
{
  for (const char *name : {CGMS::DATA_PROPERTY, CGMS::TRANSPORT_PROPERTY}) {
    int flag, cols;
    const int index = atom->find_custom(name, flag, cols);
    if (index < 0 || flag != 1) continue;
    for (int k = 0; k < cols; k++) atom->darray[index][ilocal][k] = 0.0;
  }
}

/* ----------------------------------------------------------------------
   read_data reads the Atoms section before the sections write_data puts
   after it, and a section no fix was named for stops it with "Unknown
   identifier in data file", which cannot say how to read it: so the data
   file is looked at here, once per read_data command (by each processor
   that receives beads; one that cannot open the file skips the checks).
   Returns whether the file's CGMS section goes to fix CGMS.
------------------------------------------------------------------------- */

bool AtomVecCGMS::data_file_brings_state()
{
  if (!input->command || strcmp(input->command, "read_data") != 0 || input->narg < 1) return false;
  // called for every bead: the same command as last time, without a copy
  bool same = atom->natoms == scanned_natoms && input->narg == (int) scanned_args.size();
  for (int iarg = 0; same && iarg < input->narg; iarg++)
    same = scanned_args[iarg] == input->arg[iarg];
  if (same) return scanned_awaits;
  std::vector<std::string> args(input->arg, input->arg + input->narg);

  // the section 'fix CGMS header section' hands to fix CGMS, if any
  std::string section = CGMS::DATA_SECTION;
  bool routed = false;
  for (int iarg = 1; iarg + 3 < input->narg; iarg++)
    if (strcmp(input->arg[iarg], "fix") == 0 && strcmp(input->arg[iarg + 1], CGMS::DATA_FIX) == 0) {
      section = input->arg[iarg + 3];
      routed = true;
    }
  scanned_awaits = scan_data_file(input->arg[0], section, routed);
  scanned_args = args;
  scanned_natoms = atom->natoms;
  return scanned_awaits;
}

/* ----------------------------------------------------------------------
   whether the data file has the section; stop if it has one that read_data
   was not told to hand to fix CGMS, or one with two lines for a bead
------------------------------------------------------------------------- */

bool AtomVecCGMS::scan_data_file(const std::string &file, const std::string &section, bool routed)
{
  const bool compressed = platform::has_compress_extension(file);
  FILE *fp = compressed ? platform::compressed_read(file) : fopen(file.c_str(), "r");
  if (!fp) return false;
  const auto close = [&]() {
    compressed ? platform::pclose(fp) : fclose(fp);
  };

  constexpr int MAXLINE = 256;    // longer lines are not section names or read whole
  char line[MAXLINE];
  bigint number = 0;
  bool found = false;
  // the first line is the title; a section starts at a line of its name alone (plus a
  // comment). Most lines are numbers: compared as characters, without a copy
  const char *blank = " \t\r\n";
  std::string &note = CGMS::dropped_columns_note(lmp);
  note.clear();
  const auto look_for_note = [&](const char *start) {
    if (*start == '#' &&
        strncmp(start, CGMS::DROPPED_COLUMNS_NOTE, strlen(CGMS::DROPPED_COLUMNS_NOTE)) == 0)
      note = fmt::format("{} line {}", file, number);
  };
  while (utils::fgets_trunc(line, MAXLINE, fp)) {
    number++;
    if (number == 1) continue;
    const char *start = line + strspn(line, blank);
    look_for_note(start);
    if (strncmp(start, section.c_str(), section.size()) != 0) continue;
    const char *rest = start + section.size();
    rest += strspn(rest, blank);
    if (*rest == '\0' || *rest == '#') {
      found = true;
      break;
    }
  }
  if (found && !routed) {
    close();
    error->one(FLERR,
               "Data file {} has a {} section (the beads' fluid state, written by write_data "
               "with fix cgms/fluid defined) at line {}; read_data can read it only into fix "
               "{}, which atom_style cgms defines: read the file with 'read_data {} fix {} "
               "NULL {}' (without it the beads would lose the state)",
               file, section, number, CGMS::DATA_FIX, file, CGMS::DATA_FIX, section);
  }

  // the section's lines: a bead with two lines leaves another without one
  std::unordered_map<tagint, bigint> first_line;
  if (found && utils::fgets_trunc(line, MAXLINE, fp)) {    // the blank line after the name
    number++;
    while (utils::fgets_trunc(line, MAXLINE, fp)) {
      number++;
      char *end = nullptr;
      const auto id = static_cast<tagint>(strtoll(line, &end, 10));
      if (end == line || !strchr(blank, *end)) break;    // not a bead's line: the section ended
      const auto seen = first_line.emplace(id, number);
      if (!seen.second) {
        close();
        error->one(FLERR,
                   "Data file {}: bead {} has two lines in the {} section (lines {} and {}), so "
                   "another bead has none: give every bead exactly one line (write_data "
                   "writes them so)",
                   file, id, section, seen.first->second, number);
      }
    }
    // the rest of the file, for the transport's note after the section
    while (utils::fgets_trunc(line, MAXLINE, fp)) {
      number++;
      look_for_note(line + strspn(line, blank));
    }
  }
  close();
  return found;
}

/* ----------------------------------------------------------------------
   the column ranges of a CGMS section line (doc/atom_style_cgms.rst):
   every value finite; dryness in (0, 1]; masses, turgid perimeter and
   density positive (the solid mass may be 0), the area of the last step
   0 (none yet) or positive. The line 'id 0 0 0 -1 0 0 0 0' is a bead
   without a fluid state.
------------------------------------------------------------------------- */

std::string CGMS::data_row_problem(const double *row)
{
  const auto name = [](int k) {
    return std::string(column_names[STATE_OUTPUT[k]]);
  };
  for (int k = 0; k < NSTATE; k++)
    if (!std::isfinite(row[k])) return fmt::format("{} = {}, not a finite number", name(k), row[k]);
  if (row[MF0] == NO_STATE) {
    for (int k = 0; k < NSTATE; k++)
      if (k != MF0 && row[k] != 0.0)
        return fmt::format("mf0 = -1 (no fluid state) but {} = {}: a bead without a state "
                           "has 0 in every other column",
                           name(k), row[k]);
    return "";
  }
  struct Range {
    int column;
    bool zero_allowed;
  };
  static constexpr Range positive[] = {{MF, false},  {MS, true},   {MF0, false},
                                       {L0P, false}, {RHO, false}, {AREA, true}};
  if (!(row[DRYNESS] > 0.0 && row[DRYNESS] <= 1.0))
    return fmt::format("dryness = {}, outside (0, 1]", row[DRYNESS]);
  for (const auto &r : positive) {
    const double value = row[r.column];
    if (value > 0.0 || (r.zero_allowed && value == 0.0)) continue;
    if (r.column == MF0)
      return fmt::format("mf0 = {}: it must be > 0 (or -1 for a bead without a fluid state)",
                         value);
    return fmt::format("{} = {}: it must be {}", name(r.column), value,
                       r.zero_allowed ? ">= 0" : "> 0");
  }
  return "";
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
   others from pair_style cgms, which derives them now from the state and its
   last geometry pass (0 without the pair style)
------------------------------------------------------------------------- */

void AtomVecCGMS::pack_property_atom(int index, double *buf, int nvalues, int groupbit)
{
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  int column = -1;
  for (int k = 0; k < CGMS::NSTATE; k++)
    if (CGMS::STATE_OUTPUT[k] == index) column = k;
  const auto &packer = CGMS::output_packer(lmp);
  if (column < 0 && packer) {
    packer(index, buf, nvalues, groupbit);
    return;
  }
  int n = 0;
  for (int i = 0; i < nlocal; i++) {
    buf[n] = (mask[i] & groupbit) && column >= 0 ? state[i][column] : 0.0;
    n += nvalues;
  }
}
