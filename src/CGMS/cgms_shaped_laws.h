/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_SHAPED_LAWS_H
#define LMP_CGMS_SHAPED_LAWS_H

// The laws of the shaped coarse model with a shape tensor per cell (doc/model.md, "A
// coarse model with cell shape", the tensor variant), one copy each: the C++ twin of
// python/cgms/shaped.py and shaped_tensor.py. Plain inline functions of numbers; the
// paper's laws they build on (Tait, eqn 9, the LJ radius, beta) stay in cgms_laws.h.
// A 2x2 deformation F is stored row-major, F = (F11, F12, F21, F22) = (a, b, c, d).

#include "cgms_laws.h"

#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace LAMMPS_NS {
namespace CGMS {
  namespace Shaped {

    // the parameters of the shaped model that the material file does not hold
    // (python/cgms/shaped.py and shaped_tensor.py DEFAULTS), at the best set of
    // doc/results/shaped-results.md as defaults
    struct Params {
      double wall_EA = 330.0 * 6e-6;    // axial wall stiffness E t H (N)
      double buckle = 8.6e-7;           // force at which a wall buckles (N)
      double soft = 0.002;              // buckled stiffness / (EA / r)
      double beta_a = 1.0;              // rim bonds: f = beta_a + beta_b ln s
      double beta_b = 0.04;
      double lamella = 0.391;      // strip width along each wall / d_p
      double kg_ratio = 1.0;       // k_g in units of EA / x_ref
      double void_frac = 0.063;    // intercellular space of a turgid cell / polygon
      double void_onset = 0.5;     // the void opens over mean strain 0 .. onset x eps
      double smooth = 0.25;        // contour joined C1 over +-smooth eps r
      double iso = 1.0;            // bond target (1 - iso) F + iso sqrt(det F) R(F)
      int contour = 1;             // strip along max(chord, rest) (1) or the chord (0)
    };

    // the fluid's energy at fixed mass, E = -H int_{A_f}^{A} P dA' of the Tait law
    // P = P_T + K [(A_f / A)^7 - 1] (shaped.fluid_energy, there written with A_f^7 (A^-6 -
    // A_f^-6) = A_f (q^6 - 1), q = A_f / A: the same number to rounding, without pow);
    // dE/dA = -H P
    inline double fluid_energy(double A, double A_f, double P_T, double K, double H)
    {
      const double q = A_f / A, q2 = q * q;
      return -H * ((P_T - K) * (A - A_f) - K / 6.0 * A_f * (q2 * q2 * q2 - 1.0));
    }
    inline double fluid_pressure(double A, double A_f, double P_T, double K)
    {
      return tait_pressure(pow7(A_f / A), P_T, K);
    }

    // one wall of chord l and rest length r: EA/(2r) (l - r)^2 while stretched or
    // mildly compressed; shorter than r - buckle r / EA it buckles and pushes with buckle
    // plus soft EA/r times the further shortening (shaped.wall_energy); de = dE/dl. The
    // law's constants of one wall (WallLaw, from wall_law) are fixed: pair cgms/shaped
    // keeps them per neighbour list. T is double or a vector of doubles (GCC/Clang vector
    // extensions: the comparisons give masks, ?: selects per lane): where the lanes
    // differ, both sides are computed, each with the scalar code's operations
    template <typename T> struct WallLawOf {
      T r, k, half_k;    // rest length, stiffness EA / r, k / 2
      T lb;              // buckling length r - buckle / k
      T e_b;             // the energy at lb, buckle^2 / (2 k)
      T soft_k, half_soft_k;
    };
    typedef WallLawOf<double> WallLaw;
    inline WallLaw wall_law(double r, double EA, double buckle, double soft)
    {
      const double k = EA / r;
      return {r, k, 0.5 * k, r - buckle / k, 0.5 * buckle * buckle / k, soft * k, 0.5 * soft * k};
    }
    // true when c holds in every lane (all_lanes) or in none (no_lane): a vector's walls all
    // on one side of a law skip the other side's arithmetic and the selects (for a double,
    // the scalar law's branch). The mask of a two-lane vector in one instruction on x86-64
    inline bool all_lanes(bool c)
    {
      return c;
    }
    inline bool no_lane(bool c)
    {
      return !c;
    }
    template <typename M> inline int lane_bits(M c)
    {
#if defined(__SSE2__)
      return _mm_movemask_pd((__m128d) c);
#else
      return (c[0] ? 1 : 0) | (c[1] ? 2 : 0);
#endif
    }
    template <typename M> inline bool all_lanes(M c)
    {
      return lane_bits(c) == 3;
    }
    template <typename M> inline bool no_lane(M c)
    {
      return lane_bits(c) == 0;
    }

    template <typename T> inline T wall_energy(T l, const WallLawOf<T> &w, double buckle, T &de)
    {
      const auto stretched = l >= w.lb;
      const T stretch = l - w.r, shortening = w.lb - l;
      if (all_lanes(stretched)) {
        de = w.k * stretch;
        return w.half_k * stretch * stretch;
      }
      const T de_b = -buckle - w.soft_k * shortening;
      const T e_b = w.e_b + buckle * shortening + w.half_soft_k * shortening * shortening;
      if (no_lane(stretched)) {
        de = de_b;
        return e_b;
      }
      de = stretched ? w.k * stretch : de_b;
      return stretched ? w.half_k * stretch * stretch : e_b;
    }

    // a wall's length along its folds (the strip's length): max(chord, rest) joined C1 over
    // chord - rest in +-delta (shaped_tensor.contour_length; with contour 0 the strip is the
    // chord itself, m = l); m1 = dm/dl. T double or a vector, as in wall_energy
    template <typename T> inline T contour_length(T l, T r, T delta, T &m1)
    {
      const T t = l - r, zero = T{};
      const auto above = t >= delta, below = t <= -delta;
      if (all_lanes(below)) {
        m1 = zero;
        return r;
      }
      if (all_lanes(above)) {
        m1 = zero + 1.0;
        return l;
      }
      const T from_low = t + delta;
      m1 = above ? zero + 1.0 : (below ? zero : from_low / (2.0 * delta));
      return above ? l : (below ? r : r + from_low * from_low / (4.0 * delta));
    }

    // the open fraction psi of a cell's intercellular space from its chord sum S, the
    // cubic step over the mean wall strain S / R - 1 from 0 to e1 (shaped_tensor.void_open);
    // p1 = dpsi/dS
    inline double void_open(double S, double R, double e1, double &p1)
    {
      double t = (S / R - 1.0) / e1;
      t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
      p1 = (t > 0.0 && t < 1.0) ? 6.0 * t * (1.0 - t) / (e1 * R) : 0.0;
      return t * t * (3.0 - 2.0 * t);
    }

    // the fresh wall strain eps of the built tissue from one interior cell of polygon
    // area D and perimeter L: H P_f (2 D (1 - void) - w L) = EA eps L (virtual work of a
    // uniform dilation; shaped_tensor._fresh_with_void, shaped.fresh_balance_strain)
    inline double fresh_strain(double H, double P_f, double D, double L, double void_frac, double w,
                               double EA)
    {
      return H * P_f * (2.0 * D * (1.0 - void_frac) - w * L) / L / EA;
    }
    // the fresh fluid area of a cell, D (1 - void) - w L
    inline double fresh_fluid_area(double D, double L, double void_frac, double w)
    {
      return D * (1.0 - void_frac) - w * L;
    }

    // the polar part of F that the bond target and its derivative share: J = det F,
    // p = a + d, q = c - b, r2 = p^2 + q^2 and phi = sqrt(J) / sqrt(r2), so that the polar
    // rotation is R(F) = [[p, -q], [q, p]] / sqrt(r2). False when det F <= 0 (no polar
    // rotation of an inverted cell).
    struct Polar {
      double J, p, q, r2, phi;
    };
    inline bool polar_part(const double *F, Polar &t)
    {
      const double a = F[0], b = F[1], c = F[2], d = F[3];
      t.J = a * d - b * c;
      if (!(t.J > 0.0)) return false;
      t.p = a + d;
      t.q = c - b;
      t.r2 = t.p * t.p + t.q * t.q;
      t.phi = std::sqrt(t.J) / std::sqrt(t.r2);
      return true;
    }

    // the bond target G(F) = (1 - iso) F + iso sqrt(det F) R(F), R the rotation of F's polar
    // decomposition (shaped_tensor._bond_target); t its polar part (set when iso > 0).
    // False when iso > 0 and det F <= 0.
    inline bool bond_target(const double *F, double iso, double *G, Polar &t)
    {
      for (int m = 0; m < 4; m++) G[m] = (1.0 - iso) * F[m];
      if (iso == 0.0) return true;
      if (!polar_part(F, t)) return false;
      const double M[4] = {t.p, -t.q, t.q, t.p};
      for (int m = 0; m < 4; m++) G[m] += iso * t.phi * M[m];
      return true;
    }

    // the pull-back of a vector v through the bond target's derivative, out_k = sum_m v_m
    // dG_m/dF_k, without forming the 4x4 dG: with G = (1 - iso) F + iso phi M, phi =
    // sqrt(J) / r, r = |(p, q)|, M = (p, -q, q, p), dG_m/dF_k = (1 - iso) delta_mk +
    // iso (M_m dphi/dF_k + phi dM_m/dF_k), dp/dF = (1, 0, 0, 1), dq/dF = (0, -1, 1, 0),
    // dphi/dF = phi (cof(F) / (2 J) - (p dp/dF + q dq/dF) / r^2). t is F's polar part (from
    // bond_target, needed when iso > 0).
    inline void bond_target_pullback(const double *F, double iso, const double *v, const Polar &t,
                                     double *out)
    {
      const double keep = 1.0 - iso;
      if (iso == 0.0) {
        for (int k = 0; k < 4; k++) out[k] = keep * v[k];
        return;
      }
      const double a = F[0], b = F[1], c = F[2], d = F[3];
      const double J = t.J, p = t.p, q = t.q, r2 = t.r2;
      const double vM = v[0] * p - v[1] * q + v[2] * q + v[3] * p;
      const double vp = v[0] + v[3], vq = v[2] - v[1];    // v . dM/dp and v . dM/dq
      // iso (vM dphi/dF + phi (vp dp/dF + vq dq/dF)), dphi/dF = phi (cof(F) / (2 J) - (p
      // dp/dF + q dq/dF) / r^2), cof(F) = (d, -c, -b, a), written out per component
      const double isophi = iso * t.phi;
      const double gJ = isophi * vM / (2.0 * J), gr = isophi * vM / r2;
      const double P = isophi * vp - gr * p, Q = isophi * vq - gr * q;
      out[0] = keep * v[0] + gJ * d + P;
      out[1] = keep * v[1] - gJ * c - Q;
      out[2] = keep * v[2] - gJ * b + Q;
      out[3] = keep * v[3] + gJ * a + P;
    }

  }    // namespace Shaped
}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
