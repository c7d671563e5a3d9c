/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_FIX_MFC_PRESSURE_H
#define LMP_FIX_MFC_PRESSURE_H

#include "fix.h"

namespace LAMMPS_NS {

// The fluid of every cell of the fine-scale (MFC) model at rest: one pressure
// per cell from the equation of state of the area its closed wall ring
// encloses, P = P_T + K [(A_f / A)^7 - 1], acting on the wall particles as
// P H dA/dx_i. Conservative (energy -H int P dA), so minimize finds steady
// states. One cell = one molecule ID; the ring = the group's atoms, each
// bonded to its two neighbours, numbered counter-clockwise.
class FixMFCPressure : public Fix {
 public:
  FixMFCPressure(class LAMMPS *, int, char **);
  ~FixMFCPressure() override;

  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  double compute_array(int, int) override;

 private:
  double height;        // slab height H (m): 2-D areas to volumes, pressures to forces
  double modulus;       // K of the equation of state (Pa)
  double turgor;        // P_T: the pressure at A = A_f (Pa)
  double fluid_area;    // A_f: fluid mass / (rho0 H), the area at rest density (m^2)

  int ncell;    // largest molecule ID in the group at creation
  // per cell, summed over ranks as NSUM doubles
  struct CellSums {
    double area;        // enclosed area (shoelace)
    double walls;       // wall particle count
    double wrapping;    // ring edges to a lower ID: 1 for one closed ring
  };
  static constexpr int NSUM = sizeof(CellSums) / sizeof(double);
  CellSums *sums;
  double *area;        // per cell: enclosed area (m^2)
  double *pressure;    // per cell: pressure (Pa)
  double energy;       // sum over cells of -H int_{A_f}^{A} P dA (J)

  void ring_partners(int, int &, int &);
};

}    // namespace LAMMPS_NS

#endif
