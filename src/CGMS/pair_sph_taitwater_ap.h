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
// 2012, 1068).
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

 protected:
  enum { LUCY, WENDLAND };
  int kernel;        // LUCY or WENDLAND
  double epsilon;    // artificial pressure factor (0: off)
  int exponent;      // n of (W(r) / W(dp))^n

  double *rho0, *soundspeed, *B;    // per type: the EOS
  double **cut, **viscosity;        // per type pair: kernel support, mu
  double **spacing;                 // per type pair: particle spacing dp of the artificial pressure
  double **wdp_inv;                 // per type pair: 1 / W(dp), kernel shape only

  void allocate();
  double shape(double) const;
};

}    // namespace LAMMPS_NS

#endif
