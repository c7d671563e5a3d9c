/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_LAWS_H
#define LMP_CGMS_LAWS_H

// The model's laws, one copy each, for every style of the plugin: plain inline
// functions of numbers, so that the per-bead loops inline them and a test can
// compile this header alone (tests/test_laws.py holds it equal to its twin,
// python/cgms/model.py). Each law names its equation in doc/model.md. The
// arithmetic is the one the styles have always used, operation for operation:
// a reordering would change results in the last bits.

#include <cmath>

namespace LAMMPS_NS {
namespace CGMS {

  inline const double SQRT3 = std::sqrt(3.0);
  inline const double HEX_AREA = 1.5 * std::sqrt(3.0);    // hexagon area / side^2

  // ---- Reference cell and initial state ----

  // the regular hexagon of the area of a circle of diameter d:
  // A_ref = pi d^2 / 4, b_ref = sqrt(2 A_ref / (3 sqrt 3)), l_ref = 6 b_ref,
  // x_ref = sqrt(3) b_ref + d_p
  struct ReferenceCell {
    double A_ref, b_ref, l_ref, x_ref;
  };
  inline ReferenceCell reference_cell(double d, double pectin)
  {
    const double pi = 3.14159265358979323846;
    ReferenceCell c;
    c.A_ref = pi * d * d / 4.0;
    c.b_ref = std::sqrt(2.0 * c.A_ref / (3.0 * SQRT3));
    c.l_ref = 6.0 * c.b_ref;
    c.x_ref = SQRT3 * c.b_ref + pectin;
    return c;
  }

  // ---- Virtual-cell geometry, eqns (10)-(11) ----

  // periphery factor beta(s) = beta_a + beta_b ln s (eqn 11)
  inline double beta(double beta_a, double beta_b, double s)
  {
    return beta_a + beta_b * std::log(s);
  }

  // N + beta max(0, 6 - N): the sides of the virtual hexagon in units of b_int (eqn 11)
  inline double sides(double nn, double beta)
  {
    const double free_sides = 6.0 - nn;
    return nn + beta * (0.0 > free_sides ? 0.0 : free_sides);    // LAMMPS's MAX(0, 6 - N)
  }

  // 1 / (sqrt(3) N) of eqn (10), from a table for the neighbour counts that occur
  // (a lookup instead of a division per bead; the table holds the same quotients)
  inline constexpr int MAXCOUNT = 32;
  struct InverseCounts {
    double value[MAXCOUNT];
    InverseCounts()
    {
      value[0] = 0.0;
      for (int n = 1; n < MAXCOUNT; n++) value[n] = 1.0 / (SQRT3 * n);
    }
  };
  inline const InverseCounts INV_SQRT3_N;
  inline double inv_sqrt3_n(double nn)
  {
    const int n = static_cast<int>(nn);
    return n < MAXCOUNT && n == nn ? INV_SQRT3_N.value[n] : 1.0 / (SQRT3 * nn);
  }

  // the side b_i of eqns (10)-(11) of a bead with nn neighbours at a summed centre
  // distance sum_r: b_int = (sum_r - N d_p) / (sqrt(3) N), b = b_int / 6 (N + beta
  // max(0, 6 - N)); b_ref for a bead without neighbours
  inline double cell_side(double nn, double sum_r, double beta, double pectin, double b_ref)
  {
    if (!(nn > 0.0)) return b_ref;
    const double b_int = (sum_r - nn * pectin) * inv_sqrt3_n(nn);
    return b_int * (1.0 / 6.0) * sides(nn, beta);
  }

  // g_i = dl_i/dx_ik = (N + beta max(0, 6 - N)) / (sqrt(3) N) (Potential energy)
  inline double perimeter_gradient(double nn, double beta)
  {
    return sides(nn, beta) / (SQRT3 * nn);
  }

  // ---- Fluid phase, eqns (4), (7), (9) ----

  // q^7, q the density over its reference (eqn 4)
  inline double pow7(double q)
  {
    const double q2 = q * q;
    return q2 * q2 * q2 * q;
  }

  // the Tait law P = P_ref + K (q^7 - 1) (eqn 4; own reference P_ref = s P_f)
  inline double tait_pressure(double q7, double P_ref, double K)
  {
    return P_ref + K * (q7 - 1.0);
  }

  // the density of pressure P in the Tait law (eqn 4 inverted), rho_ref (1 + (P - P_ref)/K)^(1/7),
  // given 1/rho_ref; the steady state's P = -Pi gives the balance density (Steady state)
  inline double tait_density(double P, double P_ref, double K, double inv_rho_ref)
  {
    return std::pow(1.0 + (P - P_ref) / K, 1.0 / 7.0) / inv_rho_ref;
  }

  // l_d / l0' = 1 - (a/b)(1 - s), the contraction law of the perimeter (eqn 9)
  inline double perimeter_contraction(double perim_a, double perim_b, double s)
  {
    return 1.0 - perim_a / perim_b * (1.0 - s);
  }

  // eqn (7), dm_f/dt = -l h L_p rho (P + Pi), with hLp = h L_p
  inline double mass_rate(double perim, double hLp, double rho, double press, double Pi)
  {
    return -perim * hLp * rho * (press + Pi);
  }

  // lambda = -d(dm_f/dt)/dm_f = L_p (l/A) (P + Pi + 7 K q^7) of the linearised backward
  // Euler step (Fluid phase): d rho/d m_f = rho/m_f at fixed geometry, dP/d rho = 7 K q^6 /
  // rho_ref; the implicit step stores dm_f/dt / (1 + dt lambda) when lambda > 0
  inline double transfer_rate(double L_p, double perim, double inv_area, double press, double Pi,
                              double K, double q7)
  {
    return L_p * perim * inv_area * (press + Pi + 7.0 * K * q7);
  }

  // ---- Forces, eqns (3), (8), (13)-(15) ----

  // the pair coefficient c_i = (k_T (P - P_f) - k_PA (l - l_d)) / 2 (eqns 3, 8)
  inline double pair_coefficient(double kT, double kPA, double P_f, double press, double perim,
                                 double ldeq)
  {
    return 0.5 * (kT * (press - P_f) - kPA * (perim - ldeq));
  }

  // the LJ radius r(s) = r0 (1 + lj_slope ln s) (Forces)
  inline double lj_radius(double r0, double lj_slope, double s)
  {
    return r0 * (1.0 + lj_slope * std::log(s));
  }

  // the cell-shape stiffness k_S(s) = max(k_S s^n, k_S_floor) (Shear and the cell-shape
  // stiffness); exactly k_S when n = 0
  inline double shape_stiffness(double kS, double n, double floor, double s)
  {
    if (n == 0.0) return kS;
    const double k = kS * std::pow(s, n);
    return k < floor ? floor : k;    // std::max(k, floor)
  }

  // ---- Potential energy ----

  // a bead's quasi-static potential with its pressure held: -k_T/2 (P - P_f) sum_k x_ik
  // + k_PA (l - l_d)^2 / (4 g_i)
  inline double quasi_static_energy(double kT, double kPA, double P_f, double press, double sum_r,
                                    double perim, double ldeq, double g)
  {
    const double excess = perim - ldeq;
    return -0.5 * kT * (press - P_f) * sum_r + 0.25 * kPA * excess * excess / g;
  }

  // ---- Time integration: explicit stability limits ----

  // relative-velocity damping: dt < 2 m / (1.5 N k_d)
  inline double damping_dt_limit(double m, double nn, double kd)
  {
    return 2.0 * m / (1.5 * nn * kd);
  }
  // cell-shape springs: dt < sqrt(m / (2 k_S N))
  inline double shape_dt_limit(double m, double nn, double kS)
  {
    return std::sqrt(m / (2.0 * kS * nn));
  }
  // turgor: omega^2 = 56 k_T K q^7 / (m sum_k (x_ik - d_p)), dt < 2 / omega
  inline double turgor_omega2(double kT, double K, double q7, double m, double sum_gap)
  {
    return 56.0 * kT * K * q7 / (m * sum_gap);
  }

  // the smaller of a and b as LAMMPS's MIN has it (b when a is NaN)
  inline double lower_of(double a, double b)
  {
    return a < b ? a : b;
  }

  // the explicit time-step limits of a bead of inertial mass m with nn neighbours, for
  // the forces that are switched on (a coefficient 0 is off), at the time step dt; k_S
  // the fresh one, the largest k_S(s) (an upper bound when k_S falls with the dryness).
  // The per-step checks use the *_exceeded forms, which compare without a division;
  // f_ID[5] and the errors the limits.
  struct StepLimits {
    double kd, kT, K, kS;
    double kd_dt, turgor_dt2, shape_dt2;    // at the time step dt

    StepLimits(double kd_, double kT_, double K_, double kS_, double dt) :
        kd(kd_), kT(kT_), K(K_), kS(kS_), kd_dt(1.5 * kd * dt), turgor_dt2(56.0 * kT * K * dt * dt),
        shape_dt2(2.0 * kS * dt * dt)
    {
    }

    bool damping_exceeded(double m, double nn) const { return kd_dt * nn > 2.0 * m; }
    // (omega dt)^2 > bound
    bool turgor_suspect(double q7, double m, double sum_gap, double bound) const
    {
      return turgor_dt2 * q7 > bound * m * sum_gap;
    }
    bool shape_exceeded(double m, double nn) const { return shape_dt2 * nn > m; }

    double damping(double m, double nn) const { return damping_dt_limit(m, nn, kd); }
    double turgor_omega2(double q7, double m, double sum_gap) const
    {
      return CGMS::turgor_omega2(kT, K, q7, m, sum_gap);
    }
    double shape(double m, double nn) const { return shape_dt_limit(m, nn, kS); }

    // the smallest of the limits that apply (HUGE_VAL: none)
    double smallest(double m, double nn, double q7, double sum_gap) const
    {
      double limit = HUGE_VAL;
      if (kd > 0.0) limit = lower_of(limit, damping(m, nn));
      if (kT > 0.0) limit = lower_of(limit, 2.0 / std::sqrt(turgor_omega2(q7, m, sum_gap)));
      if (kS > 0.0) limit = lower_of(limit, shape(m, nn));
      return limit;
    }
  };

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
