/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_CGMS_SHAPED_H
#define LMP_PAIR_CGMS_SHAPED_H

#include "cgms_material.h"
#include "cgms_shaped_laws.h"
#include "pair.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

// pair_style cgms/shaped: the shaped coarse model with a shape tensor per cell
// (doc/pair_cgms_shaped.rst, doc/model.md "A coarse model with cell shape"). Each bead
// carries its 2x2 deformation F (per-atom custom array shaped_F) and the fixed data of
// the fresh tissue (fresh neighbours and bond vectors, wall vectors, polygon area,
// boundary flag; custom properties of a fix property/atom, written into the data file by
// python/cgms/shaped_data.py). compute() evaluates, per local bead, its cell's fluid and
// wall energy (a function of F alone), its fresh bonds' compatibility (a bond between two
// local beads once for both; a bond to a ghost in full with its energy halved, the
// neighbour's owner evaluating the same bond), and the LJ repulsion
// over the half neighbour list without the fresh neighbours. Only F and the boundary flag
// travel to the ghosts (forward communication); no force goes back. F is a per-atom
// degree of freedom of the line-search minimisers (min_xf_* hooks, as pair eff/cut).
class PairCGMSShaped : public Pair {
 public:
  // two doubles per instruction (GCC and Clang vector extensions; SSE2 on x86-64)
  typedef double v2d __attribute__((vector_size(16)));

  PairCGMSShaped(class LAMMPS *);
  ~PairCGMSShaped() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void *extract(const char *, int &) override;
  double memory_usage() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;

  void min_xf_pointers(int, double **, double **) override;
  void min_xf_get(int) override;
  void min_x_set(int) override;

 protected:
  CGMS::Material mat;
  CGMS::Shaped::Params par;
  double dryness;       // s of every bead
  double reach;         // the cutoff covers reach x the longest fresh bond
  double cut_global;    // neighbour-list cutoff: max(LJ radius, reach x longest bond)
  double eps;           // the fresh wall strain (from the tissue, init_style)
  double bond_max;      // the longest fresh bond (m)
  double dof_scale;     // the minimiser moves dof_scale F (m): a power of 2 near x_ref

  // indices of the per-atom custom properties (Atom::find_custom)
  int iF, inb, ibondx, ibondy, iwallx, iwally, iid, inwall, iarea, iboundary, iforce;
  int nb_max, wall_max;     // columns of the neighbour and wall arrays
  int pair_max;             // wall pairs per bead in walls, (wall_max + 1) / 2
  bool lists_asymmetric;    // init found a bond listed by one bead only

  double *target;    // G(F) of every local and ghost bead, by columns (G11 G21 G12 G22)
  int nmax_target;
  double *min_x, *min_f;    // the minimiser's view of F and its force (4 per bead)
  int nmax_min;
  void grow_min_arrays();
  // fixed per-bead data, in the local order of the current neighbour list (cache_fresh_data,
  // at every new list): per wall its fresh vector's d0 d0^T, the contour's smoothing and the
  // wall law's constants; per bead its rest-length sum and fresh fluid area; per fresh
  // bond that this bead evaluates (bonds[bond_first[i] .. bond_first[i + 1]]) the closest
  // image j of the neighbour, f/2 d0, and whether j is local and evaluates the bond with
  // bead i as its own closest image (paired: evaluated once, by the lower index, for both)
  // a cell's walls 2p and 2p + 1 are one WallPair, two walls per vector; an odd cell's last
  // lane repeats its last wall
  struct WallPair {
    v2d dxx, dxy, dyy;    // d0 d0^T: l^2 = d0^T (F^T F) d0
    v2d delta;            // the contour's smoothing half-width
    CGMS::Shaped::WallLawOf<v2d> law;
  };
  struct Bond {
    int j, paired;
    double hdx, hdy;
  };
  std::vector<WallPair> walls;
  std::vector<double> rest_sum, fluid_area0;
  std::vector<Bond> bonds;
  std::vector<int> bond_first;
  // per local bead, summed over its bonds: m and f/2 m (x) d0 by columns (f/2 m d0x, then
  // f/2 m d0y), for its force and its bonds' dE/dF
  std::vector<double> bond_sums;
  std::vector<CGMS::Shaped::Polar> polar;    // per local bead, F's polar part (bond_target)
  std::vector<int> pair_first, pair_j;       // the LJ pairs: the list without fresh neighbours
  std::vector<v2d> wall_scratch;             // per wall pair of one cell: 1 / l_e, dm/dl_e, dE/dl_e
  int cache_current;            // 0 after init_style: rebuild before the next evaluation
  std::string material_file;    // pair_coeff's arguments, for the restart record

  void allocate();
  void add_force_property();
  void check_fresh_neighbours();
  void refuse_asymmetric_lists();
  void refuse_renamed_ids();
  void refuse_nonfinite(int i);
  void refuse_inverted();
  void find_properties();
  void fresh_strain_and_bond_length();
  void check_topology();
  void cache_fresh_data();
  double cell_terms(int from, int to, int &bad);
  void cache_bonds();
  double bond_terms();
  template <int EATOM, int VIRIAL> double bond_terms_of();
  void bond_virial(int i, int j, int paired, double fx, double fy);
  int bond_forces();
  void lj_terms();
  void exclude_fresh_pairs();
};

}    // namespace LAMMPS_NS

#endif
