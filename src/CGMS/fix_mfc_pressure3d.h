/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_FIX_MFC_PRESSURE3D_H
#define LMP_FIX_MFC_PRESSURE3D_H

#include "fix.h"

namespace LAMMPS_NS {

// The fluid of every cell of a 3-D fine-scale (MFC) model at rest: one
// pressure per cell from the equation of state of the volume its closed
// triangulated wall encloses, P = P_T + K [(V_f / V)^7 - 1], acting on the
// wall particles as P dV/dx_i. Conservative (energy -int P dV), so minimize
// finds steady states. One cell = one molecule ID; its triangles are the
// angles of one angle type (atoms a b c counter-clockwise seen from outside),
// so LAMMPS's own topology carries them across ranks.
class FixMFCPressure3d : public Fix {
 public:
  FixMFCPressure3d(class LAMMPS *, int, char **);
  ~FixMFCPressure3d() override;

  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  double compute_array(int, int) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

 private:
  double modulus;         // K of the equation of state (Pa)
  double turgor;          // P_T: the pressure at V = V_f (Pa)
  double fluid_volume;    // V_f: fluid mass / rho0, the volume at rest density (m^3)
  int triangle_type;      // the angle type whose angles are the wall triangles

  int ncell;    // largest molecule ID in the group at creation
  // per cell, summed over ranks as NSUM doubles
  struct CellSums {
    double volume;       // enclosed volume (divergence theorem)
    double triangles;    // triangle count
    double area;         // wall area
  };
  static constexpr int NSUM = sizeof(CellSums) / sizeof(double);
  CellSums *sums;
  double *pressure;    // per cell: pressure (Pa)
  double energy;       // sum over cells of -int_{V_f}^{V} P dV (J)
  int nmax;
  double **fwall;    // per owned and ghost atom: the pressure force before reverse comm

  int triangle_cell(const int *);
  void sum_volumes();
  void cell_pressures();
};

}    // namespace LAMMPS_NS

#endif
