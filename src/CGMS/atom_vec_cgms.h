/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_ATOM_VEC_CGMS_H
#define LMP_ATOM_VEC_CGMS_H

#include "atom_vec.h"
#include "cgms_store.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

namespace CGMS {
  // MF0 of a bead read from a data file whose CGMS section read_data hands to
  // fix CGMS: its line is still to come (<= 0: no fluid state yet)
  constexpr double AWAITS_DATA_LINE = -2.0;
  // MF0 of a data-file line that declares a bead without a fluid state (what
  // write_data writes for such a bead: every other column 0)
  constexpr double NO_STATE = -1.0;

  // what is wrong with a line (row) of the data file's CGMS section, in the
  // row's column order: "" if nothing, else the column, its value and the range
  // it needs
  std::string data_row_problem(const double *row);
}    // namespace CGMS

// One bead per plant cell: per-atom mass plus the bead's state (dryness, fluid
// and solid mass, fresh state, density, area, mass rate: CGMS::State), one
// custom per-atom vector d_NAME per column, which this style creates and
// carries; the outputs pair_style cgms derives from it are named for
// compute property/atom and dump custom here (CGMS::Output).
class AtomVecCGMS : public AtomVec {
 public:
  AtomVecCGMS(class LAMMPS *);
  ~AtomVecCGMS() override;

  void process_args(int, char **) override;
  void grow_pointers() override;
  void copy_bonus(int, int, int) override;
  int pack_exchange_bonus(int, double *) override;
  int unpack_exchange_bonus(int, double *) override;
  int size_restart_bonus() override;
  int pack_restart_bonus(int, double *) override;
  int unpack_restart_bonus(int, double *) override;
  double memory_usage_bonus() override;
  void create_atom_post(int) override;
  int unpack_restart(double *) override;
  void data_atom_post(int) override;
  void pack_data(double **) override;
  int property_atom(const std::string &) override;
  void pack_property_atom(int, double *, int, int) override;

 private:
  double *rmass;
  CGMS::BeadState state;

  // the read_data command whose data file was last looked at, and what it held
  std::vector<std::string> scanned_args;
  bigint scanned_natoms;
  bool scanned_awaits;

  void clear_custom_rows(int);
  bool data_file_brings_state();
  bool scan_data_file(const std::string &, const std::string &, bool);
};

}    // namespace LAMMPS_NS

#endif
