/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_COLUMN_CG_H
#define LMP_CGMS_COLUMN_CG_H

#include <mpi.h>

#include <functional>
#include <vector>

namespace LAMMPS_NS {
namespace CGMS {

  // The matrix of one linearised backward Euler step of fix cgms/transport: every
  // bead's column of `layers` nodes (node = bead * layers + layer), coupled
  // along the column (a tridiagonal block per bead) and, layer by layer, to
  // the same layer of its in-plane neighbours (which may be ghosts). The
  // arrays belong to the caller and must outlive the solve.
  struct ColumnMatrix {
    int nlocal = 0;
    int layers = 1;
    const double *diag = nullptr;       // nlocal * layers
    const double *lower = nullptr;      // the column couplings, nlocal * (layers - 1)
    const int *pair_start = nullptr;    // nlocal + 1 offsets into pair_j
    const int *pair_j = nullptr;        // in-plane neighbours (local or ghost index)
    const double *pair_g = nullptr;     // their couplings, layers per pair; nullptr: none
  };

  // Conjugate gradients on that symmetric positive definite matrix,
  // preconditioned by the exact solve of every column (LDL^T of its
  // tridiagonal block), started from the column solve of the right-hand side.
  // The ghost values a matrix-vector product needs come from `exchange`, which
  // fills the ghost entries of a node array (the owner's forward communication).
  class ColumnCG {
   public:
    ColumnCG(MPI_Comm world, std::function<void(double *)> exchange);

    // factor the column blocks of m, which the next solve uses. Returns the
    // first local bead whose block is singular to rounding (a pivot not above
    // SINGULAR times its diagonal entry, or not finite), or -1.
    int factor(const ColumnMatrix &m);
    // the rounding of a column's elimination grows with its length: a few
    // hundred units of 1e-16 for up to 1000 layers
    static constexpr double SINGULAR = 1e-12;
    // solve A x = b over the local nodes; x needs room for nall * layers
    // entries (local and ghost). Returns the iterations; residual is the last
    // residual norm relative to |b| (or NaN if the iteration broke down).
    int solve(const double *b, double *x, int nall, double tol, int max_iterations,
              double &residual);

   private:
    MPI_Comm world;
    std::function<void(double *)> exchange;
    ColumnMatrix m;
    std::vector<double> piv, mul;      // the column factors
    std::vector<double> r, z, p, q;    // the CG vectors (p with ghost room)

    double dot(const double *, const double *) const;
    void precondition(const double *, double *) const;
    void matvec(double *, double *);
  };

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
