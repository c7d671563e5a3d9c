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

  // The pointer to the per-bead array, one per LAMMPS instance. Atom keeps
  // its address (Atom::add_peratom) and grows, copies and frees the array
  // through it, also after the AtomVec that registered it is gone (a second
  // atom_style command, read_restart, atom_style hybrid deleting its
  // sub-styles): so it cannot be a member of AtomVecCGMS, and LAMMPS's own
  // styles register members of Atom, which a plugin cannot add. A map keyed
  // by the instance keeps it alive as long as the process.
  double **&bead_array(LAMMPS *lmp);

  // stop with an ERROR unless the system is what CGMS styles need:
  // units si, dimension 2, atom_style cgms
  void require_cgms_system(LAMMPS *lmp, const char *who);

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
