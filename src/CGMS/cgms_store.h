/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_STORE_H
#define LMP_CGMS_STORE_H

#include "lmptype.h"

namespace LAMMPS_NS {

class LAMMPS;

namespace CGMS {

  // Columns of the per-bead array "cgms" carried by atom_style cgms.
  // The first four are read for every neighbour pair in the pair and fix
  // loops and sit together so that a neighbour costs one cache line; then the
  // state that must survive migration and restarts; then values recomputed
  // every step by fix cgms/fluid and kept for output.
  enum Column {
    COEF = 0,    // pair coefficient c_i = (k_T (P - P_f) - k_PA (l - l_d)) / 2 (N)
    DRYNESS,     // prescribed dryness s = (X/X0)_i
    NNEIGH,      // neighbour count N
    SIDE,        // virtual-cell side b_avg (m)
    MF,          // fluid-phase mass m_f (kg)
    MS,          // solid-phase mass m_s (kg)
    MF0,         // fresh fluid mass m_f0 (kg); <= 0 marks a bead not yet initialised
    L0P,         // turgid perimeter l0' (m)
    RHO,         // fluid density (kg/m^3); state in the rate form of eqns (5)-(6)
    PRESS,       // turgor pressure P (Pa)
    AREA,        // virtual-cell area A (m^2)
    PERIM,       // virtual-cell perimeter l (m)
    LDEQ,        // equilibrium perimeter l_d (m), eqn (9)
    DMDT,        // fluid mass rate dm_f/dt (kg/s), eqn (7)
    NCOLUMNS
  };

  // Names of the columns for dump custom, compute property/atom and the fix's
  // per-atom array, in column order.
  extern const char *const column_names[NCOLUMNS];

  // The fluid state a data file carries (write_data writes it as the section
  // DATA_SECTION through fix cgms/fluid; read_data reads it into the per-atom
  // array DATA_PROPERTY of the fix property/atom DATA_FIX that atom_style cgms
  // defines, as 'read_data file fix CGMS NULL CGMS'); the other columns are
  // recomputed at setup from these and the positions
  constexpr int DATA_COLUMNS[] = {DRYNESS, MF, MS, MF0, L0P, RHO, AREA, DMDT};
  constexpr int NDATA = sizeof(DATA_COLUMNS) / sizeof(DATA_COLUMNS[0]);
  constexpr char DATA_SECTION[] = "CGMS";
  constexpr char DATA_FIX[] = "CGMS";
  constexpr char DATA_PROPERTY[] = "cgms_data";

  // Storage for the per-bead array, one per LAMMPS instance. It must live
  // outside the AtomVec object: LAMMPS keeps the address of the pointer and
  // frees through it after the AtomVec is gone (atom_style changes, restarts).
  struct Store {
    double **cgms = nullptr;
    // compact copies of what the per-pair loops touch, so that a neighbour
    // costs 8 or 16 bytes instead of a 112-byte row: the pair coefficient
    // (local and ghost beads) and the pass-1 sums (neighbour count, sum of
    // distances). Owned and grown by fix cgms/fluid.
    double *coef = nullptr;
    double *sums = nullptr;
    int nmax = 0;
    // the distance x of every entry of the neighbour list (0 beyond the
    // cutoff), written by fix cgms/fluid's geometry pass and read by the
    // pair's force loop of the same step when both walk the same list: the
    // force loop then needs neither a square root nor a cutoff test
    double *rdist = nullptr;
    bigint rdist_size = 0;
    int **rdist_list = nullptr;    // firstneigh of the list rdist follows
    int rdist_valid = 0;           // set by the fix, cleared by the pair after use
  };
  Store &store(LAMMPS *lmp);

  // stop with an ERROR unless the system is what CGMS styles need:
  // units si, dimension 2, atom_style cgms
  void require_cgms_system(LAMMPS *lmp, const char *who);

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
