/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "pair_cgms_shaped.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "min.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

using namespace LAMMPS_NS;
using CGMS::Shaped::Params;

// two doubles per instruction where a bead's x and y (or a 2x2 matrix's two rows) follow
// the same formula (GCC and Clang vector extensions; SSE2 on x86-64, two scalar
// instructions elsewhere): each lane does the scalar code's operations in the same order,
// so the results are bit-identical to it
typedef PairCGMSShaped::v2d v2d;
static inline v2d load2(const double *p)
{
  v2d v;
  memcpy(&v, p, sizeof(v));
  return v;
}
static inline void store2(double *p, v2d v)
{
  memcpy(p, &v, sizeof(v));
}
// sqrt of both lanes, correctly rounded as std::sqrt
static inline v2d sqrt2(v2d q)
{
#if defined(__SSE2__)
  return (v2d) _mm_sqrt_pd((__m128d) q);
#else
  return v2d{std::sqrt(q[0]), std::sqrt(q[1])};
#endif
}

// the per-atom properties the data file gives every bead (python/cgms/shaped_data.py)
// the cutoff need not reach beyond a few fresh bonds: a larger reach only fills the ghost
// shell (and at 1e300 overflows LAMMPS's neighbour bins)
static constexpr double REACH_MAX = 10.0;
// values past the last bead's in the minimiser's extra arrays (see min_xf_get)
static constexpr int MIN_PAD = 3;

static const char *const PROPERTY_HINT =
    "write the tissue with cgms.shaped_data.write_data() and define its properties before "
    "read_data with the fix command cgms.shaped_data.fix_command() prints (see "
    "doc/pair_cgms_shaped.rst)";

/* ---------------------------------------------------------------------- */

PairCGMSShaped::PairCGMSShaped(LAMMPS *lmp) :
    Pair(lmp), dryness(-1.0), reach(1.25), cut_global(0.0), eps(0.0), bond_max(0.0), dof_scale(1.0),
    iF(-1), inb(-1), ibondx(-1), ibondy(-1), iwallx(-1), iwally(-1), iid(-1), inwall(-1), iarea(-1),
    iboundary(-1), iforce(-1), nb_max(0), wall_max(0), pair_max(0), lists_asymmetric(false),
    target(nullptr), nmax_target(0), min_x(nullptr), min_f(nullptr), nmax_min(0), cache_current(0)
{
  single_enable = 0;
  restartinfo = 1;
  one_coeff = 1;
  manybody_flag = 1;
  no_virial_fdotr_compute = 1;    // bond forces act on local beads only
  centroidstressflag = CENTROID_NOTAVAIL;
  comm_forward = 5;    // F and the boundary flag
}

PairCGMSShaped::~PairCGMSShaped()
{
  memory->destroy(target);
  memory->destroy(min_x);
  memory->destroy(min_f);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

/* ----------------------------------------------------------------------
   pair_style cgms/shaped dryness s [keyword value ...]
------------------------------------------------------------------------- */

void PairCGMSShaped::settings(int narg, char **arg)
{
  if (strcmp(update->unit_style, "si") != 0)
    error->all(FLERR, "Pair style cgms/shaped requires units si (found units {})",
               update->unit_style);
  const char *known =
      "dryness wall_EA buckle soft beta_a beta_b lamella kg_ratio void void_onset smooth iso "
      "strip reach";
  Params p;
  double s = -1.0, r = 1.25;
  for (int iarg = 0; iarg < narg; iarg += 2) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair style cgms/shaped keyword {} needs a value", key);
    const char *value = arg[iarg + 1];
    auto number = [&](double lo, bool lo_open, double hi) {
      if (!utils::is_double(value))
        error->all(FLERR, "Pair style cgms/shaped keyword {} needs a number, not '{}'", key, value);
      const double v = utils::numeric(FLERR, value, false, lmp);
      if (!(lo_open ? v > lo : v >= lo) || !(v <= hi))
        error->all(FLERR, "Pair style cgms/shaped {} {} is out of range: it must be {} {}{}", key,
                   value, lo_open ? ">" : ">=", lo,
                   std::isinf(hi) ? std::string() : fmt::format(" and <= {}", hi));
      return v;
    };
    const double inf = HUGE_VAL;
    if (key == "dryness")
      s = number(0.0, true, 1.0);
    else if (key == "wall_EA")
      p.wall_EA = number(0.0, true, inf);
    else if (key == "buckle")
      p.buckle = number(0.0, false, inf);
    else if (key == "soft")
      p.soft = number(0.0, false, inf);
    else if (key == "beta_a")
      p.beta_a = number(0.0, true, inf);
    else if (key == "beta_b")
      p.beta_b = number(-inf, true, inf);
    else if (key == "lamella")
      p.lamella = number(0.0, false, inf);
    else if (key == "kg_ratio")
      p.kg_ratio = number(0.0, false, inf);
    else if (key == "void")
      p.void_frac = number(0.0, false, 0.99);
    else if (key == "void_onset")
      p.void_onset = number(0.0, true, inf);
    else if (key == "smooth")
      p.smooth = number(0.0, true, inf);
    else if (key == "iso")
      p.iso = number(0.0, false, 1.0);
    else if (key == "reach")
      r = number(0.0, true, REACH_MAX);
    else if (key == "strip") {
      if (strcmp(value, "contour") == 0)
        p.contour = 1;
      else if (strcmp(value, "chord") == 0)
        p.contour = 0;
      else
        error->all(FLERR, "Pair style cgms/shaped strip must be contour or chord, not '{}'", value);
    } else
      error->all(FLERR, "Unknown pair style cgms/shaped keyword '{}' (known: {})", key, known);
  }
  if (s < 0.0)
    error->all(FLERR,
               "Pair style cgms/shaped needs the dryness of the tissue: 'pair_style cgms/shaped "
               "dryness <s>' with 0 < s <= 1");
  par = p;
  dryness = s;
  reach = r;
}

/* ----------------------------------------------------------------------
   pair_coeff * * material-file [name value ...], as pair cgms
------------------------------------------------------------------------- */

void PairCGMSShaped::coeff(int narg, char **arg)
{
  if (narg < 3 || (narg - 3) % 2 != 0)
    error->all(FLERR, "Pair coeff for cgms/shaped: expected '* * material-file [name value ...]'");
  allocate();
  mat = CGMS::Material();
  mat.read_file(lmp, arg[2]);
  mat.require_model(lmp, "cgms/shaped", arg[2]);
  for (int iarg = 3; iarg < narg; iarg += 2) mat.set(lmp, arg[iarg], arg[iarg + 1], "pair_coeff");
  mat.finish(lmp, fmt::format("CGMS material {}", arg[2]));
  material_file = arg[2];
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = 1; j <= atom->ntypes; j++) setflag[i][j] = 1;
  add_force_property();
}

void PairCGMSShaped::allocate()
{
  if (allocated) return;
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  memory->create(cutsq, n, n, "pair:cutsq");
  for (int i = 1; i < n; i++)
    for (int j = 1; j < n; j++) setflag[i][j] = 0;
}

/* ----------------------------------------------------------------------
   the generalised force -dE/dF of every bead (J), for dump, compute and the minimiser:
   added with pair_coeff, so that a dump defined before the run finds it
------------------------------------------------------------------------- */

void PairCGMSShaped::add_force_property()
{
  int flag = -1, cols = -1;
  iforce = atom->find_custom("shaped_fF", flag, cols);
  if (iforce < 0)
    iforce = atom->add_custom("shaped_fF", 1, 4);
  else if (flag != 1 || cols != 4)
    error->all(FLERR,
               "Pair style cgms/shaped: the per-atom property shaped_fF is its own output "
               "(d2_shaped_fF, 4 columns); do not define it otherwise");
}

/* ----------------------------------------------------------------------
   the per-atom properties of the fresh tissue and the state F
------------------------------------------------------------------------- */

void PairCGMSShaped::find_properties()
{
  struct Wanted {
    const char *name;
    int is_double, array, *index, *cols;
  };
  int ncols_F = 0, ncols_bondy = 0, ncols_wally = 0, dummy = 0;
  const Wanted wanted[] = {{"shaped_F", 1, 1, &iF, &ncols_F},
                           {"shaped_nb", 0, 1, &inb, &nb_max},
                           {"shaped_bondx", 1, 1, &ibondx, &ncols_bondy},
                           {"shaped_bondy", 1, 1, &ibondy, &ncols_bondy},
                           {"shaped_wallx", 1, 1, &iwallx, &ncols_wally},
                           {"shaped_wally", 1, 1, &iwally, &wall_max},
                           {"shaped_id", 0, 0, &iid, &dummy},
                           {"shaped_nwall", 0, 0, &inwall, &dummy},
                           {"shaped_area0", 1, 0, &iarea, &dummy},
                           {"shaped_boundary", 0, 0, &iboundary, &dummy}};
  for (const auto &w : wanted) {
    int flag = -1, cols = -1;
    *w.index = atom->find_custom(w.name, flag, cols);
    const std::string full =
        fmt::format("{}{}_{}", w.is_double ? "d" : "i", w.array ? "2" : "", w.name);
    if (*w.index < 0)
      error->all(FLERR,
                 "Pair style cgms/shaped needs the per-atom property {}, which is not "
                 "defined: {}",
                 full, PROPERTY_HINT);
    if (flag != w.is_double || (cols > 0) != (w.array != 0))
      error->all(FLERR,
                 "Pair style cgms/shaped: the per-atom property {} has the wrong kind "
                 "(it must be {}); {}",
                 w.name, full, PROPERTY_HINT);
    if (w.cols == &ncols_bondy && *w.cols && cols != *w.cols)
      error->all(FLERR,
                 "Pair style cgms/shaped: d2_shaped_bondx and d2_shaped_bondy must have "
                 "the same number of columns; {}",
                 PROPERTY_HINT);
    if (w.cols == &wall_max && cols != ncols_wally)
      error->all(FLERR,
                 "Pair style cgms/shaped: d2_shaped_wallx and d2_shaped_wally must have "
                 "the same number of columns; {}",
                 PROPERTY_HINT);
    *w.cols = cols;
  }
  if (ncols_F != 4)
    error->all(FLERR,
               "Pair style cgms/shaped: d2_shaped_F must have 4 columns (F11 F12 F21 F22), "
               "not {}",
               ncols_F);
  if (ncols_bondy != nb_max)
    error->all(FLERR,
               "Pair style cgms/shaped: d2_shaped_bondx and d2_shaped_bondy must have as "
               "many columns as i2_shaped_nb ({}), not {}",
               nb_max, ncols_bondy);

  add_force_property();
}

/* ----------------------------------------------------------------------
   the fresh wall strain eps of the built tissue, from its first interior cell (the one
   of the lowest ID, as the prototype's first non-boundary index), and the longest fresh
   bond, for the cutoff
------------------------------------------------------------------------- */

void PairCGMSShaped::fresh_strain_and_bond_length()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int *boundary = atom->ivector[iboundary];
  const int *nwall = atom->ivector[inwall];
  double **wallx = atom->darray[iwallx], **wally = atom->darray[iwally];
  double **bondx = atom->darray[ibondx], **bondy = atom->darray[ibondy];
  int **nb = atom->iarray[inb];

  tagint first = MAXTAGINT, first_all, bad = MAXTAGINT, bad_all;
  double longest = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (!boundary[i] && tag[i] < first) first = tag[i];
    if (nwall[i] < 3 || nwall[i] > wall_max || !(atom->dvector[iarea][i] > 0.0))
      bad = std::min(bad, tag[i]);
    for (int b = 0; b < nb_max; b++)
      if (nb[i][b] > 0) longest = std::max(longest, std::hypot(bondx[i][b], bondy[i][b]));
  }
  MPI_Allreduce(&bad, &bad_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (bad_all != MAXTAGINT)
    error->all(FLERR,
               "Pair style cgms/shaped: bead {} has fewer than 3 walls, more walls than "
               "d2_shaped_wallx holds ({}), or a fresh polygon area that is not positive (a bead "
               "added by create_atoms has no fresh data: add beads before writing the tissue); {}",
               bad_all, wall_max, PROPERTY_HINT);
  MPI_Allreduce(&first, &first_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  MPI_Allreduce(&longest, &bond_max, 1, MPI_DOUBLE, MPI_MAX, world);
  if (first_all == MAXTAGINT)
    error->all(FLERR,
               "Pair style cgms/shaped: the tissue has no interior cell (every bead is on "
               "the boundary), so the fresh wall strain that balances turgor is undefined");
  if (!(bond_max > 0.0))
    error->all(FLERR, "Pair style cgms/shaped: no bead has a fresh neighbour; {}", PROPERTY_HINT);

  double mine = 0.0;
  const int i = atom->map(first_all);
  if (i >= 0 && i < nlocal) {
    double L = 0.0;
    for (int e = 0; e < nwall[i]; e++)
      L += std::sqrt(wallx[i][e] * wallx[i][e] + wally[i][e] * wally[i][e]);
    mine = CGMS::Shaped::fresh_strain(mat.height, mat.P_f, atom->dvector[iarea][i], L,
                                      par.void_frac, par.lamella * mat.pectin, par.wall_EA);
  }
  MPI_Allreduce(&mine, &eps, 1, MPI_DOUBLE, MPI_SUM, world);
  if (!(eps > -1.0))
    error->all(FLERR,
               "Pair style cgms/shaped: the fresh wall strain {} is not above -1 (lamella "
               "or void too large for these cells)",
               eps);
}

/* ----------------------------------------------------------------------
   the fresh neighbour lists are those of a tissue: every ID a bead that exists, not the
   bead itself nor twice in a row, each bond listed by both its beads (each evaluates it
   halved; a bond listed once would count half) with opposite vectors. The pairing is
   checked with a signed sum of a hash of each bond (zero when every i->k has its k->i)
   and the vector sum of the bonds (zero when every pair's vectors cancel)
------------------------------------------------------------------------- */

static uint64_t bond_hash(uint64_t a, uint64_t b)
{
  uint64_t z = a * 0x9e3779b97f4a7c15ULL + b + 0x632be59bd9b4e019ULL;    // splitmix64
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

void PairCGMSShaped::refuse_renamed_ids()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int *fresh_id = atom->ivector[iid];
  tagint created = MAXTAGINT, created_all, renamed = MAXTAGINT, renamed_all;
  for (int i = 0; i < nlocal; i++) {
    if (fresh_id[i] == 0) created = std::min(created, tag[i]);
    if (fresh_id[i] != tag[i] && tag[i] < renamed) renamed = tag[i];
  }
  MPI_Allreduce(&created, &created_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (created_all != MAXTAGINT)
    error->all(FLERR,
               "Pair style cgms/shaped: bead {} has no fresh data (no walls, no neighbours: it "
               "was added after read_data, e.g. by create_atoms); add beads to the tissue before "
               "writing it with cgms.shaped_data.write_data()",
               created_all);
  MPI_Allreduce(&renamed, &renamed_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (renamed_all != MAXTAGINT)
    error->all(FLERR,
               "Pair style cgms/shaped: the atom IDs changed since the tissue was written "
               "(bead {} was written with another ID), so the fresh neighbours' IDs name other "
               "beads; use 'delete_atoms ... compress no' and no reset_atoms id",
               renamed_all);
}

void PairCGMSShaped::check_fresh_neighbours()
{
  refuse_renamed_ids();
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  int **nb = atom->iarray[inb];
  double **bondx = atom->darray[ibondx], **bondy = atom->darray[ibondy];
  tagint bad[2] = {0, 0};    // the lowest bead with a bad row and the ID it names
  uint64_t pairing = 0;
  double sum[2] = {0.0, 0.0}, scale = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int b = 0; b < nb_max; b++) {
      const tagint t = nb[i][b];
      if (t == 0) continue;
      bool wrong = t < 0 || t == tag[i] || t > atom->map_tag_max ||
          !(std::hypot(bondx[i][b], bondy[i][b]) > 0.0);
      for (int c = 0; c < b; c++) wrong = wrong || nb[i][c] == t;
      if (wrong && (!bad[0] || tag[i] < bad[0])) bad[0] = tag[i], bad[1] = t;
      const uint64_t lo = std::min(tag[i], t), hi = std::max(tag[i], t);
      pairing += (tag[i] < t ? 1 : -1) * bond_hash(lo, hi);
      sum[0] += bondx[i][b];
      sum[1] += bondy[i][b];
      scale += std::fabs(bondx[i][b]) + std::fabs(bondy[i][b]);
    }
  tagint first = bad[0] ? bad[0] : MAXTAGINT, first_all;
  MPI_Allreduce(&first, &first_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (first_all != MAXTAGINT) {
    tagint named = bad[0] == first_all ? bad[1] : 0, named_all;
    MPI_Allreduce(&named, &named_all, 1, MPI_LMP_TAGINT, MPI_MAX, world);
    error->all(
        FLERR,
        "Pair style cgms/shaped: bead {} lists fresh neighbour {}, which is not a bead of "
        "this tissue (an ID above the largest, the bead itself, listed twice, or a bond of zero "
        "length): the data file's shaped properties are damaged or were edited; write "
        "the tissue again with cgms.shaped_data.write_data()",
        first_all, named_all);
  }
  uint64_t pairing_all;
  double sum_all[2], scale_all;
  MPI_Allreduce(&pairing, &pairing_all, 1, MPI_UINT64_T, MPI_SUM, world);
  MPI_Allreduce(sum, sum_all, 2, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&scale, &scale_all, 1, MPI_DOUBLE, MPI_SUM, world);
  // the bond vectors cancel in pairs to rounding: 64 ulp of their magnitude is far above it
  // reported by check_topology after its search for deleted neighbours (a deleted bead
  // leaves its neighbours' lists unanswered too, and that cause is the one to name)
  lists_asymmetric = pairing_all != 0 ||
      std::hypot(sum_all[0], sum_all[1]) > 64.0 * DBL_EPSILON * scale_all;
}

void PairCGMSShaped::refuse_asymmetric_lists()
{
  if (lists_asymmetric)
    error->all(FLERR,
               "Pair style cgms/shaped: the fresh neighbour lists are not symmetric (a bead "
               "lists a neighbour that does not list it back, or their bond vectors are not "
               "opposite): the data file's shaped properties are damaged or were edited; write "
               "the tissue again with cgms.shaped_data.write_data()");
}

/* ---------------------------------------------------------------------- */

void PairCGMSShaped::init_style()
{
  if (domain->dimension != 2)
    error->all(FLERR, "Pair style cgms/shaped is two-dimensional: use 'dimension 2'");
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR,
               "Pair style cgms/shaped finds the fresh neighbours by ID: add 'atom_modify "
               "map array' before read_data");
  if (update->whichflag == 1 && update->nsteps > 0)
    error->all(FLERR,
               "Pair style cgms/shaped has no integrator for the shape tensors F: 'run' "
               "only with 0 steps (forces and energy); find steady states with 'minimize' and "
               "min_style cg or sd");
  if (update->whichflag == 2 &&
      !(strcmp(update->minimize_style, "cg") == 0 || strcmp(update->minimize_style, "sd") == 0))
    error->all(FLERR,
               "Pair style cgms/shaped: min_style {} does not move the shape tensors F "
               "(per-atom degrees of freedom); use min_style cg or sd",
               update->minimize_style);
  find_properties();
  check_fresh_neighbours();
  fresh_strain_and_bond_length();
  cache_current = 0;
  // a power of two near x_ref: the minimiser's dof_scale F and F convert exactly
  dof_scale = std::ldexp(1.0, (int) std::lround(std::log2(mat.x_ref)));
  if (update->whichflag == 2) update->minimize->request(this, 4, 0.1 * dof_scale);
  neighbor->add_request(this);
}

/* ----------------------------------------------------------------------
   the cutoff holds the LJ radius at this dryness and reach x the longest fresh bond,
   so that every fresh neighbour is a ghost (check_topology holds the bonds to it)
------------------------------------------------------------------------- */

double PairCGMSShaped::init_one(int, int)
{
  cut_global = std::max(mat.lj_radius(dryness), reach * bond_max);
  return cut_global;
}

/* ----------------------------------------------------------------------
   every fresh neighbour of every local bead is here (local or ghost) and closer than the
   cutoff; collective, at every new neighbour list
------------------------------------------------------------------------- */

void PairCGMSShaped::check_topology()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  double **x = atom->x;
  int **nb = atom->iarray[inb];
  refuse_renamed_ids();

  tagint missing[2] = {0, 0}, far_pair[2] = {0, 0};
  double longest = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int b = 0; b < nb_max; b++) {
      const tagint t = nb[i][b];
      if (t <= 0) continue;
      int j = t > atom->map_tag_max ? -1 : atom->map(t);
      if (j < 0) {
        if (!missing[0]) missing[0] = tag[i], missing[1] = t;
        continue;
      }
      j = domain->closest_image(i, j);
      const double r = std::hypot(x[j][0] - x[i][0], x[j][1] - x[i][1]);
      if (r > longest) longest = r, far_pair[0] = tag[i], far_pair[1] = t;
    }

  // the lowest-tagged missing neighbour: does it exist on any rank?
  tagint k = missing[1] ? missing[1] : MAXTAGINT, k_all;
  MPI_Allreduce(&k, &k_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (k_all != MAXTAGINT) {
    tagint who = missing[1] == k_all ? missing[0] : 0, who_all;
    MPI_Allreduce(&who, &who_all, 1, MPI_LMP_TAGINT, MPI_MAX, world);
    const int j = k_all > atom->map_tag_max ? -1 : atom->map(k_all);
    int owned = j >= 0 && j < nlocal, exists;
    MPI_Allreduce(&owned, &exists, 1, MPI_INT, MPI_MAX, world);
    if (!exists)
      error->all(FLERR,
                 "Pair style cgms/shaped: bead {}'s fresh neighbour {} no longer exists "
                 "(deleted?): the shaped model's bonds are fixed at the fresh tissue; delete "
                 "beads before writing its data file (cgms.shaped_data.write_data), not after",
                 who_all, k_all);
    error->all(FLERR,
               "Pair style cgms/shaped: bead {}'s fresh neighbour {} is not within this "
               "rank's ghost atoms: the ghost cutoff {:.6g} m is shorter than their bond; raise "
               "the pair's reach (now {}) or 'comm_modify cutoff'",
               who_all, k_all, comm->get_comm_cutoff(), reach);
  }
  refuse_asymmetric_lists();
  double longest_all;
  MPI_Allreduce(&longest, &longest_all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (longest_all > cut_global) {
    tagint pair[2] = {0, 0}, pair_all[2];
    if (longest == longest_all) pair[0] = far_pair[0], pair[1] = far_pair[1];
    MPI_Allreduce(pair, pair_all, 2, MPI_LMP_TAGINT, MPI_MAX, world);
    error->all(FLERR,
               "Pair style cgms/shaped: the fresh bond {}-{} is {:.6g} m long, beyond the "
               "pair's cutoff {:.6g} m (reach {} x the longest fresh bond {:.6g} m), so the ghost "
               "atoms may not hold it; raise reach",
               pair_all[0], pair_all[1], longest_all, cut_global, reach, bond_max);
  }
}

/* ----------------------------------------------------------------------
   the fixed per-bead data the kernels would otherwise derive again at every force
   evaluation, in the local order of the new neighbour list: the walls' rest lengths
   r_e = c(s) |d0_e| / (1 + eps), their sum and the fresh fluid area s A_f of every cell,
   and per fresh bond the closest image of the neighbour and f/2, f = beta(s) on rim bonds
------------------------------------------------------------------------- */

void PairCGMSShaped::cache_fresh_data()
{
  const int nlocal = atom->nlocal;
  const double w = par.lamella * mat.pectin;
  const double contraction = mat.perimeter_contraction(dryness);
  const int *nwall = atom->ivector[inwall];
  const double *area0 = atom->dvector[iarea];
  double **wallx = atom->darray[iwallx], **wally = atom->darray[iwally];

  pair_max = (wall_max + 1) / 2;
  walls.resize((size_t) nlocal * pair_max);
  wall_scratch.resize(3 * (size_t) pair_max);
  rest_sum.resize(nlocal);
  fluid_area0.resize(nlocal);
  for (int i = 0; i < nlocal; i++) {
    WallPair *pairs = &walls[(size_t) i * pair_max];
    double L0 = 0.0, R = 0.0;
    for (int e = 0; e < nwall[i]; e++) {
      const double dx = wallx[i][e], dy = wally[i][e];
      const double chord0 = std::sqrt(dx * dx + dy * dy);
      L0 += chord0;
      const double rest = chord0 / (1.0 + eps) * contraction;
      const CGMS::Shaped::WallLaw law =
          CGMS::Shaped::wall_law(rest, par.wall_EA, par.buckle, par.soft);
      // lane e % 2 of pair e / 2; the last wall of an odd cell fills both lanes
      for (int lane = e % 2; lane < (e + 1 == nwall[i] ? 2 : e % 2 + 1); lane++) {
        WallPair &p = pairs[e / 2];
        p.dxx[lane] = dx * dx;
        p.dxy[lane] = dx * dy;
        p.dyy[lane] = dy * dy;
        p.delta[lane] = par.smooth * eps * rest;
        p.law.r[lane] = law.r;
        p.law.k[lane] = law.k;
        p.law.half_k[lane] = law.half_k;
        p.law.lb[lane] = law.lb;
        p.law.e_b[lane] = law.e_b;
        p.law.soft_k[lane] = law.soft_k;
        p.law.half_soft_k[lane] = law.half_soft_k;
      }
      R += rest;
    }
    rest_sum[i] = R;
    fluid_area0[i] = dryness * CGMS::Shaped::fresh_fluid_area(area0[i], L0, par.void_frac, w);
  }
  cache_bonds();
}

/* ----------------------------------------------------------------------
   the fresh bonds each local bead evaluates: a bond between two local beads that are each
   other's closest image once (by the lower local index, its share applied to both), any
   other bond (to a ghost: its owner evaluates its own half) by each of its local beads
------------------------------------------------------------------------- */

void PairCGMSShaped::cache_bonds()
{
  const int nlocal = atom->nlocal;
  const double beta = CGMS::beta(par.beta_a, par.beta_b, dryness);
  const int *boundary = atom->ivector[iboundary];
  const tagint *tag = atom->tag;
  double **bondx = atom->darray[ibondx], **bondy = atom->darray[ibondy];
  int **nb = atom->iarray[inb];

  bonds.clear();
  bond_first.resize(nlocal + 1);
  bond_sums.resize(6 * (size_t) nlocal);
  for (int i = 0; i < nlocal; i++) {
    bond_first[i] = (int) bonds.size();
    for (int b = 0; b < nb_max; b++) {
      if (nb[i][b] <= 0) continue;
      // check_topology has made sure that every fresh neighbour is here
      const int j = domain->closest_image(i, atom->map(nb[i][b]));
      const int paired = j < nlocal && domain->closest_image(j, atom->map(tag[i])) == i;
      if (paired && j < i) continue;    // bead j evaluates it
      const double hf = 0.5 * (boundary[i] && boundary[j] ? beta : 1.0);
      bonds.push_back({j, paired, hf * bondx[i][b], hf * bondy[i][b]});
    }
  }
  bond_first[nlocal] = (int) bonds.size();
}

/* ----------------------------------------------------------------------
   the fluid and wall energy of the cells of local beads from <= i < to (summed, and per atom)
   and each cell's derivative dE/dF, written to the force property (shaped_tensor.energy):
   walls e with fresh vectors d0_e, chords l_e = |F d0_e|, rest lengths r_e (cached);
   fluid area A = det(F) A_poly0 (1 - void psi) - w sum m(l_e, r_e); bad = 1 when
   A <= 0 (infinite energy, no gradient). dl_e/dF = F d0_e d0_e^T / l_e, so
   dE/dF = -H P dD/dF (1 - void psi) + F sum_e c_e d0_e d0_e^T / l_e with one scalar c_e
   per wall (the chord sum's, the strip's and the wall's share): the first pass over the
   walls finds l_e, the second, once P is known, sums the symmetric 2x2 matrices.
------------------------------------------------------------------------- */

double PairCGMSShaped::cell_terms(int from, int to, int &bad)
{
  // the settings and arrays read once for all cells
  double **Fs = atom->darray[iF];
  double **fF = atom->darray[iforce];
  const int *nwall = atom->ivector[inwall];
  const double *area0s = atom->dvector[iarea];
  v2d *inv_len = wall_scratch.data(), *m1 = inv_len + pair_max, *de = m1 + pair_max;
  const double w = par.lamella * mat.pectin;
  const double buckle = par.buckle;
  const int contour = par.contour;
  const double P_T = dryness * mat.P_f;
  const double K = mat.K, H = mat.height;
  const double void_frac = par.void_frac, void_e1 = par.void_onset * eps;
  double energy = 0.0;
  for (int i = from; i < to; i++) {
    // F in registers: the scratch stores below could alias it
    const double F[4] = {Fs[i][0], Fs[i][1], Fs[i][2], Fs[i][3]};
    double *dEdF = fF[i];
    const WallPair *pairs = &walls[(size_t) i * pair_max];
    const int nw = nwall[i];
    const int np = (nw + 1) / 2;
    const double area0 = area0s[i];

    // l_e^2 = |F d0_e|^2 = d0_e^T C d0_e with C = F^T F (C12 doubled: d0x d0y appears twice);
    // two walls per vector, then the sums over the walls in the walls' order
    const double C11 = F[0] * F[0] + F[2] * F[2], C22 = F[1] * F[1] + F[3] * F[3];
    const double C12x2 = 2.0 * (F[0] * F[1] + F[2] * F[3]);
    v2d S_m = {0.0, 0.0};
    double wall = 0.0;
    for (int p = 0; p < np; p++) {
      const WallPair &wp = pairs[p];
      const v2d len = sqrt2(C11 * wp.dxx + C12x2 * wp.dxy + C22 * wp.dyy);
      inv_len[p] = 1.0 / len;
      v2d m;
      if (contour)
        m = CGMS::Shaped::contour_length(len, wp.law.r, wp.delta, m1[p]);
      else
        m = len, m1[p] = v2d{1.0, 1.0};
      const v2d e = CGMS::Shaped::wall_energy(len, wp.law, buckle, de[p]);
      // (S, sum_m) as the two lanes of one sum, wall by wall
      S_m += v2d{len[0], m[0]};
      wall += e[0];
      if (2 * p + 1 < nw) {
        S_m += v2d{len[1], m[1]};
        wall += e[1];
      }
    }
    const double S = S_m[0], sum_m = S_m[1];
    const double A_f = fluid_area0[i];
    double psi = 0.0, p1 = 0.0;
    if (void_frac != 0.0) psi = CGMS::Shaped::void_open(S, rest_sum[i], void_e1, p1);
    const double det = F[0] * F[3] - F[1] * F[2];
    const double D = det * area0;
    const double A = D * (1.0 - void_frac * psi) - w * sum_m;
    if (!(A > 0.0)) {
      bad = 1;
      for (int k = 0; k < 4; k++) dEdF[k] = 0.0;
      continue;
    }

    const double e = CGMS::Shaped::fluid_energy(A, A_f, P_T, K, H) + wall;
    if (eflag_atom) eatom[i] += e;
    energy += e;
    const double f1 = -H * CGMS::Shaped::fluid_pressure(A, A_f, P_T, K);

    // c_e = f1 dA/dl_e + dE_wall/dl_e, dA/dl_e = -void D p1 - w m1_e
    const double c_S = -f1 * void_frac * D * p1, c_m = -f1 * w;
    v2d Mxx_xy = {0.0, 0.0};    // (Mxx, Mxy) as the two lanes of one sum, wall by wall
    double Myy = 0.0;
    for (int p = 0; p < np; p++) {
      const v2d c = (c_S + c_m * m1[p] + de[p]) * inv_len[p];
      const v2d xx = c * pairs[p].dxx, xy = c * pairs[p].dxy, yy = c * pairs[p].dyy;
      Mxx_xy += v2d{xx[0], xy[0]};
      Myy += yy[0];
      if (2 * p + 1 < nw) {
        Mxx_xy += v2d{xx[1], xy[1]};
        Myy += yy[1];
      }
    }
    const double Mxx = Mxx_xy[0], Mxy = Mxx_xy[1];
    // f1 dD/dF (1 - void psi) + F M, dD/dF = A_poly0 cof(F)
    const double fD = f1 * area0 * (1.0 - void_frac * psi);
    dEdF[0] = fD * F[3] + F[0] * Mxx + F[1] * Mxy;
    dEdF[1] = -fD * F[2] + F[0] * Mxy + F[1] * Myy;
    dEdF[2] = -fD * F[1] + F[2] * Mxx + F[3] * Mxy;
    dEdF[3] = fD * F[0] + F[2] * Mxy + F[3] * Myy;
  }
  return energy;
}

/* ----------------------------------------------------------------------
   the fresh bonds bead i evaluates: k_g/2 |m|^2 with m = x_k - x_i - f (G(F_i) + G(F_k))
   d0_ik / 2, f = beta(s) on rim bonds (both beads on the boundary). A paired bond (both
   beads local) counts in full, its sums go to both beads (bead k's m and d0 are bead i's
   negated, so its m (x) d0 is the same); a bond to a ghost counts half (the ghost's owner
   evaluates the other half) and its sums go to bead i alone. Per bead, bond_sums gathers
   sum m (the force is k_g times it) and sum f/2 m (x) d0 (contracted with dG once per bead
   in bond_forces: dm_c/dF_i = -f/2 sum_n dG[2c + n] d0_n). Returns the bonds' energy.
------------------------------------------------------------------------- */

double PairCGMSShaped::bond_terms()
{
  if (eflag_atom) return vflag_either ? bond_terms_of<1, 1>() : bond_terms_of<1, 0>();
  return vflag_either ? bond_terms_of<0, 1>() : bond_terms_of<0, 0>();
}

// the per-atom energy (EATOM) and the virial (VIRIAL) as template arguments: no test of
// either flag per bond
template <int EATOM, int VIRIAL> double PairCGMSShaped::bond_terms_of()
{
  const double *x = atom->x[0];    // 3 per bead, contiguous
  const int nlocal = atom->nlocal;
  const double k_g = par.kg_ratio * par.wall_EA / mat.x_ref;
  const Bond *bond_list = bonds.data();
  const int *first = bond_first.data();
  double *sums = bond_sums.data();
  std::fill(bond_sums.begin(), bond_sums.end(), 0.0);
  double energy = 0.0;
  for (int i = 0; i < nlocal; i++) {
    // G(F_i) by columns, (G0, G2) and (G1, G3)
    const v2d Gi0 = load2(target + 4 * i), Gi1 = load2(target + 4 * i + 2);
    const v2d xi = load2(x + 3 * i);
    // bead i's sums in registers: |m|^2 (paired bonds twice), m, f/2 m d0x, f/2 m d0y
    double msq = 0.0;
    v2d m_sum = {0.0, 0.0}, md0x = {0.0, 0.0}, md0y = {0.0, 0.0};
    for (int b = first[i]; b < first[i + 1]; b++) {
      const Bond &bond = bond_list[b];
      const int j = bond.j;
      const double hdx = bond.hdx, hdy = bond.hdy;
      const double *Gj = target + 4 * j;
      const v2d m =
          (load2(x + 3 * j) - xi) - ((Gi0 + load2(Gj)) * hdx + (Gi1 + load2(Gj + 2)) * hdy);
      const v2d m2 = m * m;
      const double sq = m2[0] + m2[1];
      const v2d ax = m * hdx, ay = m * hdy;
      msq += sq;
      m_sum += m;
      md0x += ax;
      md0y += ay;
      if (bond.paired) {
        double *sj = sums + 6 * j;
        store2(sj, load2(sj) - m);
        store2(sj + 2, load2(sj + 2) + ax);
        store2(sj + 4, load2(sj + 4) + ay);
        msq += sq;
        if (EATOM) eatom[j] += 0.25 * k_g * sq;
      }
      if (VIRIAL) bond_virial(i, j, bond.paired, k_g * m[0], k_g * m[1]);
    }
    double *si = sums + 6 * i;
    store2(si, load2(si) + m_sum);
    store2(si + 2, load2(si + 2) + md0x);
    store2(si + 4, load2(si + 4) + md0y);
    const double e = 0.25 * k_g * msq;
    if (EATOM) eatom[i] += e;
    energy += e;
  }
  return energy;
}

/* ----------------------------------------------------------------------
   the virial r_ik (x) f_i of a bond with force (fx, fy) on bead i: a paired bond's in full,
   half of it to each bead; a ghost bond's half, the other half from bead k's owner
------------------------------------------------------------------------- */

void PairCGMSShaped::bond_virial(int i, int j, int paired, double fx, double fy)
{
  double **x = atom->x;
  const double delx = x[i][0] - x[j][0], dely = x[i][1] - x[j][1];
  const double v[6] = {0.5 * delx * fx, 0.5 * dely * fy, 0.0, 0.5 * delx * fy, 0.0, 0.0};
  for (int n = 0; n < 6; n++) {
    if (vflag_global) virial[n] += paired ? 2.0 * v[n] : v[n];
    if (vflag_atom) {
      vatom[i][n] += (paired ? 0.5 : 1.0) * v[n];
      if (paired) vatom[j][n] += 0.5 * v[n];
    }
  }
}

/* ----------------------------------------------------------------------
   every local bead's bond force k_g sum m and its bonds' dE/dF, -k_g (sum f/2 m (x) d0)
   : dG(F_i), added to its cell's dE/dF in fF; fF then holds -dE/dF. Returns the first
   local bead whose force or -dE/dF is not finite or too large for the minimiser (-1: none;
   the LJ forces are in f already)
------------------------------------------------------------------------- */

int PairCGMSShaped::bond_forces()
{
  double **f = atom->f;
  double **F = atom->darray[iF];
  double **fF = atom->darray[iforce];
  const double k_g = par.kg_ratio * par.wall_EA / mat.x_ref;
  const double *sums = bond_sums.data();
  // the largest force the minimiser's norm holds (a sum of 6 squares per bead); dof_scale
  // is a power of two: |fF / dof_scale| < limit is |fF| < limit dof_scale exactly
  const double limit = std::sqrt(DBL_MAX / (6.0 * std::max(atom->natoms, (bigint) 1)));
  const double limit_F = limit * dof_scale;
  int first_bad = -1;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *si = sums + 6 * i;
    double *fi = f[i], *fFi = fF[i];
    fi[0] += k_g * si[0];
    fi[1] += k_g * si[1];
    // f/2 m (x) d0 row-major from its columns (m d0x, m d0y)
    const double v[4] = {si[2], si[4], si[3], si[5]};
    double dm[4];
    CGMS::Shaped::bond_target_pullback(F[i], par.iso, v, polar[i], dm);
    for (int k = 0; k < 4; k++) fFi[k] = -(fFi[k] - k_g * dm[k]);
    // & (not &&): six comparisons without a branch each
    const bool finite = (std::fabs(fi[0]) < limit) & (std::fabs(fi[1]) < limit) &
        (std::fabs(fFi[0]) < limit_F) & (std::fabs(fFi[1]) < limit_F) &
        (std::fabs(fFi[2]) < limit_F) & (std::fabs(fFi[3]) < limit_F);
    if (!finite && first_bad < 0) first_bad = i;
  }
  return first_bad;
}

/* ----------------------------------------------------------------------
   the pairs of the neighbour list that were not fresh neighbours (the LJ repulsion's),
   gathered once per neighbour list: (i, j) as pair_j[pair_first[ii] ..]. Only pairs
   closer than the LJ radius plus twice the skin: until the next list each bead moves
   less than half the skin from where the list was built, and less than the skin from
   where it is now (the cache is also rebuilt after init_style, between two lists), so a
   pair beyond that cannot come inside the radius before the next list
------------------------------------------------------------------------- */

void PairCGMSShaped::exclude_fresh_pairs()
{
  const tagint *tag = atom->tag;
  double **x = atom->x;
  int **nbs = atom->iarray[inb];
  const double reach_lj = mat.lj_radius(dryness) + 2.0 * neighbor->skin;
  const double reach_lj_sq = reach_lj * reach_lj;
  pair_first.resize(list->inum + 1);
  pair_j.clear();
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *nb = nbs[i];
    const int *jlist = list->firstneigh[i];
    pair_first[ii] = (int) pair_j.size();
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1];
      if (dx * dx + dy * dy >= reach_lj_sq) continue;
      bool fresh = false;
      for (int b = 0; b < nb_max; b++)
        if (nb[b] == tag[j]) fresh = true;
      if (!fresh) pair_j.push_back(j);
    }
  }
  pair_first[list->inum] = (int) pair_j.size();
}

/* ----------------------------------------------------------------------
   LJ repulsion between beads that were not fresh neighbours (shaped.lj_energy):
   f0_r [(r/x)^8/8 - (r/x)^4/4 + 1/8] inside the LJ radius r(s)
------------------------------------------------------------------------- */

void PairCGMSShaped::lj_terms()
{
  double **x = atom->x;
  double **f = atom->f;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  const double rad = mat.lj_radius(dryness);
  const double radsq = rad * rad;
  const double f0 = mat.f0_r;
  const int *jlist = pair_j.data();
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const double xi = x[i][0], yi = x[i][1];
    for (int jj = pair_first[ii]; jj < pair_first[ii + 1]; jj++) {
      const int j = jlist[jj];
      const double delx = xi - x[j][0], dely = yi - x[j][1];
      const double rsq = delx * delx + dely * dely;
      if (rsq >= radsq) continue;
      const double r2inv = 1.0 / rsq;
      const double q2 = radsq * r2inv, q4 = q2 * q2, q8 = q4 * q4;
      const double fpair = f0 * (q8 - q4) * r2inv;
      f[i][0] += fpair * delx;
      f[i][1] += fpair * dely;
      if (newton_pair || j < nlocal) {
        f[j][0] -= fpair * delx;
        f[j][1] -= fpair * dely;
      }
      const double evdwl = eflag_either ? f0 * (0.125 * q8 - 0.25 * q4 + 0.125) : 0.0;
      if (evflag) ev_tally(i, j, nlocal, newton_pair, evdwl, 0.0, fpair, delx, dely, 0.0);
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairCGMSShaped::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  comm->forward_comm(this);
  // the local order changes only with a new neighbour list; init_style (new settings,
  // data changed by 'set', 'run 0 pre no') also asks for a new cache
  if (neighbor->ago == 0 || !cache_current) {
    check_topology();
    cache_fresh_data();
    exclude_fresh_pairs();
    cache_current = 1;
  }

  // G(F) of every local and ghost bead, for the bonds
  const int nall = atom->nlocal + atom->nghost;
  if (atom->nmax > nmax_target) {
    memory->destroy(target);
    nmax_target = atom->nmax;
    memory->create(target, 4 * nmax_target, "pair:target");
  }
  double **F = atom->darray[iF];
  const int nlocal = atom->nlocal;
  polar.resize(nlocal);
  int bad = 0;
  for (int i = 0; i < nall; i++) {
    double G[4];
    CGMS::Shaped::Polar ghost;    // a local bead's polar part is kept for bond_forces
    if (!CGMS::Shaped::bond_target(F[i], par.iso, G, i < nlocal ? polar[i] : ghost)) bad = 1;
    // by columns, (G11, G21) and (G12, G22), as bond_terms reads them
    double *t = target + 4 * i;
    t[0] = G[0];
    t[1] = G[2];
    t[2] = G[1];
    t[3] = G[3];
  }
  const int targets_valid = !bad;

  // fF holds the cells' dE/dF until bond_forces makes it -dE/dF
  double **fF = atom->darray[iforce];
  double energy = cell_terms(0, nlocal, bad);
  lj_terms();
  int nonfinite = -1;
  if (targets_valid) {
    energy += bond_terms();
    nonfinite = bond_forces();
  } else
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < 4; k++) fF[i][k] = -fF[i][k];
  if (bad && update->setupflag) refuse_inverted();
  if (!bad && (nonfinite >= 0 || !std::isfinite(energy))) refuse_nonfinite(nonfinite);
  // a cell turned inside out (fluid area or det F not positive) has infinite energy: a
  // line search steps back from it
  if (eflag_global) eng_vdwl += bad ? HUGE_VAL : energy;
}

/* ----------------------------------------------------------------------
   a finite state with a non-finite energy or force: a keyword or material value so far
   out of range that the energy overflows, or a force whose square overflows the
   minimiser's force norm (a sum of 6 squares per bead); stop before it moves on NaN; i is the
   first local bead bond_forces found (-1: the energy sum)
------------------------------------------------------------------------- */

void PairCGMSShaped::refuse_nonfinite(int i)
{
  const tagint who = i >= 0 ? atom->tag[i] : 0;
  error->one(FLERR,
             "Pair style cgms/shaped: the energy or the force {} is not finite (or so large "
             "that the minimiser's force norm overflows) in a state of finite F: a keyword "
             "(wall_EA, soft, beta_a, beta_b, kg_ratio, "
             "smooth) or material value is far outside its physical range; give values of "
             "the order of the defaults (doc/pair_cgms_shaped.rst)",
             who ? fmt::format("on bead {}", who) : std::string("sum"));
}

/* ----------------------------------------------------------------------
   the state a run or minimize starts from has a cell turned inside out (infinite energy):
   a line search steps back from such a trial state, but it cannot start from one
------------------------------------------------------------------------- */

void PairCGMSShaped::refuse_inverted()
{
  tagint who = 0;
  for (int i = 0; i < atom->nlocal && !who; i++) {
    int bad = 0;
    cell_terms(i, i + 1, bad);    // overwrites cell i's dE/dF: the run stops here
    if (bad) who = atom->tag[i];
  }
  error->one(FLERR,
             "Pair style cgms/shaped: the starting state has cell {} turned inside out (its fluid "
             "area or det F is not positive), so its energy is infinite: start from the fresh "
             "tissue's F (cgms.shaped_tensor.fresh_state) or a state a minimisation reached; or "
             "a keyword (lamella, smooth, void) is far outside its physical range",
             who);
}

/* ---------------------------------------------------------------------- */

int PairCGMSShaped::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  double **F = atom->darray[iF];
  const int *boundary = atom->ivector[iboundary];
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    for (int k = 0; k < 4; k++) buf[m++] = F[j][k];
    buf[m++] = boundary[j];
  }
  return m;
}

void PairCGMSShaped::unpack_forward_comm(int n, int first, double *buf)
{
  double **F = atom->darray[iF];
  int *boundary = atom->ivector[iboundary];
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int k = 0; k < 4; k++) F[i][k] = buf[m++];
    boundary[i] = static_cast<int>(buf[m++]);
  }
}

/* ----------------------------------------------------------------------
   restart files: the settings (dryness, reach, every Params field) as binary numbers, then
   the material as a tagged "name value" text (as pair cgms's record: values printed so that
   they read back to the same double; a file of another record version is refused)
------------------------------------------------------------------------- */

static constexpr int SHAPED_RECORD_TAG = 0x43475348;    // "CGSH"
// raise this whenever the layout of the record changes
static constexpr int SHAPED_RECORD_VERSION = 1;
static constexpr int SHAPED_NUMBERS = 13;

void PairCGMSShaped::write_restart_settings(FILE *fp)
{
  const int header[2] = {SHAPED_RECORD_TAG, SHAPED_RECORD_VERSION};
  const double v[SHAPED_NUMBERS] = {
      dryness,     reach,        par.wall_EA,   par.buckle,     par.soft,   par.beta_a, par.beta_b,
      par.lamella, par.kg_ratio, par.void_frac, par.void_onset, par.smooth, par.iso};
  fwrite(header, sizeof(int), 2, fp);
  fwrite(v, sizeof(double), SHAPED_NUMBERS, fp);
  fwrite(&par.contour, sizeof(int), 1, fp);
}

void PairCGMSShaped::read_restart_settings(FILE *fp)
{
  int header[2] = {0, 0};
  double v[SHAPED_NUMBERS];
  if (comm->me == 0) utils::sfread(FLERR, header, sizeof(int), 2, fp, nullptr, error);
  MPI_Bcast(header, 2, MPI_INT, 0, world);
  if (header[0] != SHAPED_RECORD_TAG || header[1] != SHAPED_RECORD_VERSION)
    error->all(FLERR,
               "Pair cgms/shaped: this restart file was written by another version of the CGMS "
               "plugin (its record does not match this version's format {}); start from a data "
               "file written with write_data, or read it with the plugin that wrote it",
               SHAPED_RECORD_VERSION);
  if (comm->me == 0) {
    utils::sfread(FLERR, v, sizeof(double), SHAPED_NUMBERS, fp, nullptr, error);
    utils::sfread(FLERR, &par.contour, sizeof(int), 1, fp, nullptr, error);
  }
  MPI_Bcast(v, SHAPED_NUMBERS, MPI_DOUBLE, 0, world);
  MPI_Bcast(&par.contour, 1, MPI_INT, 0, world);
  dryness = v[0];
  reach = v[1];
  par.wall_EA = v[2];
  par.buckle = v[3];
  par.soft = v[4];
  par.beta_a = v[5];
  par.beta_b = v[6];
  par.lamella = v[7];
  par.kg_ratio = v[8];
  par.void_frac = v[9];
  par.void_onset = v[10];
  par.smooth = v[11];
  par.iso = v[12];
}

void PairCGMSShaped::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  mat.write_record(fp, "file", material_file);
}

void PairCGMSShaped::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  if (!mat.read_record(lmp, fp, "file", material_file))
    error->all(FLERR,
               "Pair cgms/shaped: the material record of this restart file is damaged or of "
               "another CGMS version; start from a data file written with write_data and give "
               "pair_style and pair_coeff");
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = 1; j <= atom->ntypes; j++) setflag[i][j] = 1;
  add_force_property();
}

/* ----------------------------------------------------------------------
   the minimiser moves y = dof_scale F (metres, as the positions) under the force
   -dE/dy = -dE/dF / dof_scale (newtons); dof_scale is a power of two, so F = y / dof_scale
   exactly
------------------------------------------------------------------------- */

void PairCGMSShaped::min_xf_pointers(int, double **xextra, double **fextra)
{
  grow_min_arrays();
  *xextra = min_x;
  *fextra = min_f;
}

// LAMMPS reads the values again through min_xf_pointers after atoms migrated
void PairCGMSShaped::grow_min_arrays()
{
  if (atom->nmax <= nmax_min) return;
  memory->destroy(min_x);
  memory->destroy(min_f);
  nmax_min = atom->nmax;
  memory->create(min_x, 4 * nmax_min + MIN_PAD, "pair:min_x");
  memory->create(min_f, 4 * nmax_min + MIN_PAD, "pair:min_f");
}

/* ----------------------------------------------------------------------
   LAMMPS's max norm (min_modify norm max) reads the extra per-atom values in
   triples, up to index 4 nlocal + 2: past the last bead's 4 values lie MIN_PAD
   more, zeroed on every call. Left unwritten, the minimiser read whatever the
   heap held there (zero in a fresh process, garbage after many LAMMPS instances:
   the force test then never passed)
------------------------------------------------------------------------- */

void PairCGMSShaped::min_xf_get(int)
{
  double **F = atom->darray[iF];
  double **fF = atom->darray[iforce];
  const int nlocal = atom->nlocal;
  grow_min_arrays();    // called before min_xf_pointers when atoms migrated in
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 4; k++) {
      min_x[4 * i + k] = dof_scale * F[i][k];
      min_f[4 * i + k] = fF[i][k] / dof_scale;
    }
  for (int k = 4 * nlocal; k < 4 * nlocal + MIN_PAD; k++) min_x[k] = min_f[k] = 0.0;
}

void PairCGMSShaped::min_x_set(int)
{
  double **F = atom->darray[iF];
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < 4; k++) F[i][k] = min_x[4 * i + k] / dof_scale;
}

/* ---------------------------------------------------------------------- */

void *PairCGMSShaped::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "dryness") == 0) return (void *) &dryness;
  if (strcmp(name, "eps") == 0) return (void *) &eps;
  if (strcmp(name, "cut_global") == 0) return (void *) &cut_global;
  return nullptr;
}

double PairCGMSShaped::memory_usage()
{
  const double caches =
      (double) (sizeof(WallPair) / sizeof(double) * walls.capacity() + 2 * wall_scratch.capacity() +
                rest_sum.capacity() + fluid_area0.capacity() + bond_sums.capacity()) *
          sizeof(double) +
      (double) bonds.capacity() * sizeof(Bond) +
      (double) polar.capacity() * sizeof(CGMS::Shaped::Polar) +
      (double) (bond_first.capacity() + pair_first.capacity() + pair_j.capacity()) * sizeof(int);
  return Pair::memory_usage() + 4.0 * (nmax_target + 2.0 * nmax_min) * sizeof(double) + caches;
}
