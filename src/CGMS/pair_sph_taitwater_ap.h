/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_SPH_TAITWATER_AP_H
#define LMP_PAIR_SPH_TAITWATER_AP_H

#include "pair.h"

namespace LAMMPS_NS {

// SPH fluid as pair sph/taitwater/morris (Tait EOS, Morris viscosity,
// continuity density) plus Monaghan's artificial pressure (J. Comput. Phys.
// 159, 2000, 290), which keeps particles in tension from pairing up (the
// tensile instability), and a choice of kernel: Lucy's, as LAMMPS's SPH
// package, or Wendland's C2, which does not pair (Dehnen and Aly, MNRAS 425,
// 2012, 1068). Optionally a range of atom types are walls whose pressure is
// extrapolated from the fluid next to them (Adami, Hu and Adams, J. Comput.
// Phys. 231, 2012, 7057), so the wall feels the fluid's tension as well as its
// compression.
class PairSPHTaitwaterAP : public Pair {
 public:
  PairSPHTaitwaterAP(class LAMMPS *);
  ~PairSPHTaitwaterAP() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;

 protected:
  enum { LUCY, WENDLAND };
  int kernel;            // LUCY or WENDLAND
  double epsilon;        // artificial pressure factor (0: off)
  int exponent;          // n of (W(r) / W(dp))^n
  int walllo, wallhi;    // atom types of the walls (Adami's boundary); 0 0: none

  double *wsum, *wnorm;    // per atom: sum_f P_f W_wf and sum_f W_wf of a wall
  double *pressure;        // per atom: the Tait pressure P of its density
  int nmax;

  double *rho0, *soundspeed, *B;    // per type: the EOS
  double **cut, **viscosity;        // per type pair: kernel support, mu
  double **spacing;                 // per type pair: particle spacing dp of the artificial pressure
  double **wdp_inv;                 // per type pair: 1 / W(dp), kernel shape only

  void allocate();
  double shape(double) const;
  double tait(int i) const;
  void tait_pressures(bool walls_only);
  int is_wall(int type) const { return type >= walllo && type <= wallhi; }
  void wall_densities();
  void check_densities();
};

}    // namespace LAMMPS_NS

#endif
