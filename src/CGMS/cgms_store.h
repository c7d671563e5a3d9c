/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_STORE_H
#define LMP_CGMS_STORE_H

#include "lmptype.h"

#include <functional>
#include <string>

namespace LAMMPS_NS {

class LAMMPS;

namespace CGMS {

  // Columns of a bead's state carried by atom_style cgms: what must survive
  // migration, restarts and data files. The fluid pass reads and writes each
  // once per step; the outputs below are derived from them.
  enum State {
    DRYNESS = 0,    // prescribed dryness s = (X/X0)_i
    MF,             // fluid-phase mass m_f (kg)
    MS,             // solid-phase mass m_s (kg)
    MF0,            // fresh fluid mass m_f0 (kg); <= 0 marks a bead not yet initialised
    L0P,            // turgid perimeter l0' (m)
    RHO,            // fluid density (kg/m^3); state in the rate form of eqns (5)-(6)
    AREA,           // virtual-cell area A (m^2) of the last fluid pass
    DMDT,           // fluid mass rate dm_f/dt (kg/s), eqn (7), of the last fluid pass
    NSTATE
  };

  // Columns of a bead's outputs, in the order of fix cgms/fluid's per-atom array
  // (f_ID[1] to f_ID[14]) and with the names compute property/atom knows. The
  // state columns are copies of the row; the others pair_style cgms derives
  // from the row and the neighbour sums of its last geometry pass when an
  // output asks for them (PairCGMS::for_each_output).
  enum Output {
    OUT_COEF = 0,    // pair coefficient c_i = (k_T (P - P_f) - k_PA (l - l_d)) / 2 (N)
    OUT_DRYNESS,
    OUT_NNEIGH,    // neighbour count N
    OUT_SIDE,      // virtual-cell side b_avg (m)
    OUT_MF,
    OUT_MS,
    OUT_MF0,
    OUT_L0P,
    OUT_RHO,
    OUT_PRESS,    // turgor pressure P (Pa), eqn (4)
    OUT_AREA,
    OUT_PERIM,    // virtual-cell perimeter l (m)
    OUT_LDEQ,     // equilibrium perimeter l_d (m), eqn (9)
    OUT_DMDT,
    NOUTPUTS
  };

  // What pair_style cgms's geometry pass sums per bead (local and ghost; summed
  // over ranks by reverse communication): the neighbours within the cutoff, N,
  // and the sum of their centre distances, sum_k x_ik (eqn 10). Two doubles, so
  // that the communication packs them as such. The per-atom array "cgms_sums"
  // of atom_style cgms holds them: they move with the beads, so that the
  // outputs derived from them stay right after a sort or a migration.
  struct NeighbourSums {
    double count;       // N
    double distance;    // sum_k x_ik (m)
  };
  constexpr int NSUMS = sizeof(NeighbourSums) / sizeof(double);
  double **&sums_array(LAMMPS *lmp);
  // the array as NeighbourSums, one per local and ghost bead (nullptr before any bead);
  // valid until the atom arrays grow
  NeighbourSums *neighbour_sums(LAMMPS *lmp);

  // The outputs of every local bead for compute property/atom: column (CGMS::Output)
  // into buf[i * nvalues] for beads in the group, 0 elsewhere. pair_style cgms,
  // which derives them, sets it while it exists; atom_style cgms calls it, if set.
  using OutputPacker = std::function<void(int column, double *buf, int nvalues, int groupbit)>;
  OutputPacker &output_packer(LAMMPS *lmp);

  // Names of the output columns for dump custom, compute property/atom and the
  // fix's per-atom array, in output order.
  extern const char *const column_names[NOUTPUTS];
  // the output column of each state column
  constexpr int STATE_OUTPUT[NSTATE] = {OUT_DRYNESS, OUT_MF,  OUT_MS,   OUT_MF0,
                                        OUT_L0P,     OUT_RHO, OUT_AREA, OUT_DMDT};
  inline const char *state_name(int k)
  {
    return column_names[STATE_OUTPUT[k]];
  }

  // The fluid state a data file carries (write_data writes it as the section
  // DATA_SECTION through fix cgms/fluid; read_data reads it into the per-atom
  // array DATA_PROPERTY of the fix property/atom DATA_FIX that atom_style cgms
  // defines, as 'read_data file fix CGMS NULL CGMS'): the whole row, in row
  // order; the outputs are recomputed at setup from it and the positions
  constexpr int NDATA = NSTATE;
  constexpr char DATA_SECTION[] = "CGMS";
  constexpr char DATA_FIX[] = "CGMS";
  constexpr char DATA_PROPERTY[] = "cgms_data";

  // The per-atom array of fix cgms/transport's state store (a fix property/atom
  // that outlives the transport fix): a bead created into a freed slot while no
  // transport fix is defined would find a deleted bead's row there, so atom_style
  // cgms clears it, as the data row, for every new bead
  constexpr char TRANSPORT_PROPERTY[] = "cgms_transport";

  // The state columns are LAMMPS custom per-atom vectors (Atom::add_custom), one
  // per column, named state_name(k) (the output's name): LAMMPS's own commands
  // see them as d_NAME (dump custom, compute property/atom, set, variables, the
  // library's extract_atom). atom_style cgms creates them and carries them with
  // the beads (growth, copies, migration, restart files), as its own fields.

  // one bead's state columns: row[k] is column k (CGMS::State) of bead i
  class BeadRow {
   public:
    BeadRow(double *const *columns, int i) : col(columns), i(i) {}
    double &operator[](int k) const { return col[k][i]; }

   private:
    double *const *col;
    int i;
  };

  // the state columns of every local and ghost bead (ghosts hold only what is
  // forwarded to them), read as rows: state[i][k]. Valid until the atom arrays
  // grow; all columns nullptr while atom_style cgms is not defined.
  class BeadState {
   public:
    double *col[NSTATE];
    BeadRow operator[](int i) const { return {col, i}; }
    explicit operator bool() const { return col[0] != nullptr; }
  };
  BeadState bead_state(LAMMPS *lmp);
  // the indices of the state columns in Atom::dvector, one per LAMMPS instance
  // (-1: not defined); atom_style cgms sets them
  int *state_indices(LAMMPS *lmp);

  // The comment write_data leaves where fix cgms/transport's moisture columns
  // would be (no data-file line can hold a column); read_data's scan of the
  // file (atom_style cgms) records where it found one, "file line N", or ""
  // when the file had none, so that the transport does not restart such a
  // tissue at X0 without a word. One per LAMMPS instance, reset with the
  // atom style (clear, atom_style) and by every read_data.
  constexpr char DROPPED_COLUMNS_NOTE[] = "# fix cgms/transport";
  std::string &dropped_columns_note(LAMMPS *lmp);

  // stop with an ERROR unless the system is what CGMS styles need:
  // units si, dimension 2, atom_style cgms
  void require_cgms_system(LAMMPS *lmp, const char *who);

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
