/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "cgms_column_cg.h"

#include <cmath>
#include <utility>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::CGMS;

ColumnCG::ColumnCG(MPI_Comm world_in, std::function<void(double *)> exchange_in) :
    world(world_in), exchange(std::move(exchange_in))
{
}

/* ---------------------------------------------------------------------- */

int ColumnCG::factor(const ColumnMatrix &matrix)
{
  int singular = -1;
  m = matrix;
  const int layers = m.layers;
  piv.resize((size_t) m.nlocal * layers);
  mul.resize((size_t) m.nlocal * (layers > 1 ? layers - 1 : 1));
  for (int i = 0; i < m.nlocal; i++) {
    const double *d = &m.diag[(size_t) i * layers];
    const double *g = &m.lower[(size_t) i * (layers - 1)];
    double *pv = &piv[(size_t) i * layers];
    double *mu = &mul[(size_t) i * (layers - 1)];
    pv[0] = d[0];
    for (int l = 1; l < layers; l++) {
      mu[l - 1] = -g[l - 1] / pv[l - 1];
      pv[l] = d[l] + mu[l - 1] * g[l - 1];
    }
    for (int l = 0; l < layers && singular < 0; l++)
      if (!(pv[l] > SINGULAR * d[l]) || !std::isfinite(pv[l])) singular = i;
  }
  return singular;
}

/* ---------------------------------------------------------------------- */

double ColumnCG::dot(const double *a, const double *b) const
{
  const size_t nn = (size_t) m.nlocal * m.layers;
  double local = 0.0, all;
  for (size_t n = 0; n < nn; n++) local += a[n] * b[n];
  MPI_Allreduce(&local, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

// z = column blocks^-1 r: forward and back substitution with the LDL^T factors
void ColumnCG::precondition(const double *rv, double *zv) const
{
  const int layers = m.layers;
  for (int i = 0; i < m.nlocal; i++) {
    double *y = &zv[(size_t) i * layers];
    const double *mu = &mul[(size_t) i * (layers - 1)];
    const double *pv = &piv[(size_t) i * layers];
    for (int l = 0; l < layers; l++) y[l] = rv[(size_t) i * layers + l];
    for (int l = 1; l < layers; l++) y[l] -= mu[l - 1] * y[l - 1];
    for (int l = 0; l < layers; l++) y[l] /= pv[l];
    for (int l = layers - 2; l >= 0; l--) y[l] -= mu[l] * y[l + 1];
  }
}

// y = A v over the local nodes; v needs room for the ghosts, which are refreshed here
void ColumnCG::matvec(double *v, double *y)
{
  exchange(v);
  const int layers = m.layers;
  for (int i = 0; i < m.nlocal; i++) {
    const double *vi = &v[(size_t) i * layers];
    double *yi = &y[(size_t) i * layers];
    for (int l = 0; l < layers; l++) yi[l] = m.diag[(size_t) i * layers + l] * vi[l];
    for (int l = 0; l + 1 < layers; l++) {
      const double g = m.lower[(size_t) i * (layers - 1) + l];
      yi[l] -= g * vi[l + 1];
      yi[l + 1] -= g * vi[l];
    }
    if (m.pair_g)
      for (int k = m.pair_start[i]; k < m.pair_start[i + 1]; k++) {
        const double *vj = &v[(size_t) m.pair_j[k] * layers];
        const double *g = &m.pair_g[(size_t) k * layers];
        for (int l = 0; l < layers; l++) yi[l] -= g[l] * vj[l];
      }
  }
}

/* ---------------------------------------------------------------------- */

int ColumnCG::solve(const double *b, double *x, int nall, double tol, int max_iterations,
                    double &residual)
{
  const size_t nn = (size_t) m.nlocal * m.layers;
  r.resize(nn);
  z.resize(nn);
  q.resize(nn);
  p.resize((size_t) nall * m.layers);

  const double bnorm = sqrt(dot(b, b));
  precondition(b, x);
  matvec(x, q.data());
  for (size_t n = 0; n < nn; n++) r[n] = b[n] - q[n];
  double rnorm = sqrt(dot(r.data(), r.data()));
  residual = bnorm > 0.0 ? rnorm / bnorm : 0.0;
  if (rnorm <= tol * bnorm) return 0;
  precondition(r.data(), z.data());
  for (size_t n = 0; n < nn; n++) p[n] = z[n];
  double rz = dot(r.data(), z.data());
  int it = 0;
  while (it < max_iterations) {
    it++;
    matvec(p.data(), q.data());
    const double a = rz / dot(p.data(), q.data());
    for (size_t n = 0; n < nn; n++) {
      x[n] += a * p[n];
      r[n] -= a * q[n];
    }
    rnorm = sqrt(dot(r.data(), r.data()));
    residual = rnorm / bnorm;
    if (rnorm <= tol * bnorm) return it;
    precondition(r.data(), z.data());
    const double rz_new = dot(r.data(), z.data());
    const double beta = rz_new / rz;
    rz = rz_new;
    for (size_t n = 0; n < nn; n++) p[n] = z[n] + beta * p[n];
  }
  return it;
}
