/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_MATERIAL_H
#define LMP_CGMS_MATERIAL_H

#include "cgms_laws.h"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

class LAMMPS;

namespace CGMS {

  // Material parameters of one plant tissue (doc/model.md, Parameters), SI units,
  // plus the reference-cell quantities derived from them (section 3).
  struct Material {
    double k_T = 0.0;       // turgor coefficient (N/Pa)
    double k_PA = 0.0;      // perimeter adjustment coefficient (N/m)
    double k_d = 0.0;       // damping coefficient (N s/m)
    double f0_a = 0.0;      // LJ attraction strength (N m)
    double f0_r = 0.0;      // LJ repulsion strength (N m)
    double beta_a = 0.0;    // beta(s) = beta_a + beta_b ln s
    double beta_b = 0.0;
    double lj_slope = 0.0;        // r = r0 (1 + lj_slope ln s_ik)
    double r0 = 0.0;              // fresh LJ radius (m); 0 selects x_ref
    double diameter = 0.0;        // cell diameter D (m)
    double height = 0.0;          // virtual-cell height h (m)
    double pectin = 0.0;          // pectin layer d_p (m)
    double perim_a = 0.0;         // a of eqn (9)
    double perim_b = 0.0;         // b of eqn (9)
    double P_f = 0.0;             // fresh turgor (Pa)
    double Pi_f = 0.0;            // fresh osmotic potential (Pa), negative
    double K = 0.0;               // compression modulus (Pa)
    double turgid_ratio = 0.0;    // l0' / l_ref
    double rho0 = 0.0;            // fresh fluid density (kg/m^3)
    double L_p = 0.0;             // membrane conductivity (m/(Pa s))
    double solid_ratio = 0.0;     // m_s / m_f at any dryness (paper: 10 %)
    double k_S = 0.0;             // cell-shape stiffness (N/m); not in the paper, 0 = off
    double k_S_exponent = 0.0;    // n of k_S(s) = k_S s^n; 0 = the same k_S at every dryness
    double k_S_floor = 0.0;       // k_S(s) never falls below it (N/m); 0 = no floor

    unsigned long given = 0;    // bit k set: parameter k was given
    // the pair style a file's values were calibrated for, from the "MODEL:" tag of its
    // first line (cgms.material.write marks a fit so); empty: measured values, which every
    // style may read
    std::string model;

    // derived by finish()
    double A_ref = 0.0, b_ref = 0.0, l_ref = 0.0, x_ref = 0.0;

    // read "name value" lines; error->all() names any problem
    void read_file(LAMMPS *lmp, const std::string &file);
    // error->all() unless the file read is for pair style 'style' (its MODEL tag empty or
    // style): a model's fitted values mean nothing to another model
    void require_model(LAMMPS *lmp, const std::string &style, const std::string &file) const;
    // set one parameter by name (material file line or pair_coeff override)
    void set(LAMMPS *lmp, const std::string &name, const std::string &value,
             const std::string &where);
    // check ranges and completeness, derive the reference cell
    void finish(LAMMPS *lmp, const std::string &where);

    // the material record of a restart file (pair cgms, pair cgms/shaped): a tag, a format
    // version and the size of a text of "name value" lines, one per parameter, then one
    // "<key> <value>" line of the style's own (its pair_coeff arguments) and "end".
    // read_record fills this material and value and returns false for a record of
    // another format (the caller names the cure); every rank calls it
    void write_record(FILE *fp, const std::string &key, const std::string &value) const;
    bool read_record(LAMMPS *lmp, FILE *fp, const std::string &key, std::string &value);

    // every parameter of the table with its value, in table order (r0 resolved)
    std::vector<std::pair<std::string, double>> parameters() const;

    // the laws of cgms_laws.h with this material's parameters
    double beta(double s) const { return CGMS::beta(beta_a, beta_b, s); }
    double lj_radius(double s) const { return CGMS::lj_radius(r0, lj_slope, s); }
    // cell-shape stiffness of a bead of dryness s, max(k_S s^n, k_S_floor) (exactly k_S
    // when n = 0, since finish() keeps k_S_floor <= k_S; exactly k_S s^n when the floor is 0)
    double shape_stiffness(double s) const
    {
      return CGMS::shape_stiffness(k_S, k_S_exponent, k_S_floor, s);
    }
    // l_d / l0' at dryness s (eqn 9)
    double perimeter_contraction(double s) const
    {
      return CGMS::perimeter_contraction(perim_a, perim_b, s);
    }
  };

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
