/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "cgms_material.h"

#include "cgms_parameter_file.h"

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "math_const.h"
#include "utils.h"

#include <mpi.h>

#include <cmath>

using namespace LAMMPS_NS;
using MathConst::MY_PI;

namespace {

enum Range { POSITIVE, NONNEGATIVE, NEGATIVE, ANY };

struct Entry {
  const char *name;
  double CGMS::Material::*member;
  Range range;
  bool required;
};

// the one list of parameters: file keys, pair_coeff keys and checks
const Entry entries[] = {
    {"k_T", &CGMS::Material::k_T, POSITIVE, true},
    {"k_PA", &CGMS::Material::k_PA, POSITIVE, true},
    {"k_d", &CGMS::Material::k_d, POSITIVE, true},
    {"f0_a", &CGMS::Material::f0_a, POSITIVE, true},
    {"f0_r", &CGMS::Material::f0_r, POSITIVE, true},
    // beta(1) = beta_a: the periphery factor of a fresh tissue is positive
    {"beta_a", &CGMS::Material::beta_a, POSITIVE, true},
    {"beta_b", &CGMS::Material::beta_b, ANY, true},
    // lj_slope >= 0 keeps r(s) <= r0, which the neighbour-list cutoff relies on
    {"lj_slope", &CGMS::Material::lj_slope, NONNEGATIVE, true},
    {"r0", &CGMS::Material::r0, NONNEGATIVE, false},
    {"diameter", &CGMS::Material::diameter, POSITIVE, true},
    {"height", &CGMS::Material::height, POSITIVE, true},
    {"pectin", &CGMS::Material::pectin, NONNEGATIVE, true},
    {"perim_a", &CGMS::Material::perim_a, NONNEGATIVE, true},
    {"perim_b", &CGMS::Material::perim_b, POSITIVE, true},
    {"P_f", &CGMS::Material::P_f, POSITIVE, true},
    {"Pi_f", &CGMS::Material::Pi_f, NEGATIVE, true},
    {"K", &CGMS::Material::K, POSITIVE, true},
    {"turgid_ratio", &CGMS::Material::turgid_ratio, POSITIVE, true},
    {"rho0", &CGMS::Material::rho0, POSITIVE, true},
    {"L_p", &CGMS::Material::L_p, POSITIVE, true},
    {"solid_ratio", &CGMS::Material::solid_ratio, NONNEGATIVE, true},
    // an extension, off unless given: stiffness against the spread of a bead's
    // neighbour distances, which gives the lattice the shear stiffness the paper's
    // forces lack (doc/pair_cgms.rst)
    {"k_S", &CGMS::Material::k_S, NONNEGATIVE, false},
    // k_S(s) = k_S s^n: the fine model's shear stiffness is borne by turgor and falls
    // with the dryness (to 0.28 at s = 0.8, 0.05 at 0.6: n of about 6, doc/calibration.md);
    // n >= 0 keeps k_S(s) <= k_S below s = 1, which the time-step check relies on
    {"k_S_exponent", &CGMS::Material::k_S_exponent, NONNEGATIVE, false},
    // k_S(s) = max(k_S s^n, k_S_floor): below s = 0.6 the fine model's shear modulus
    // rises again as the dried cells stiffen (doc/calibration.md)
    {"k_S_floor", &CGMS::Material::k_S_floor, NONNEGATIVE, false},
};
constexpr int NENTRIES = sizeof(entries) / sizeof(entries[0]);

const char *range_text(Range r)
{
  switch (r) {
    case POSITIVE:
      return "> 0";
    case NONNEGATIVE:
      return ">= 0";
    case NEGATIVE:
      return "< 0";
    default:
      return "finite";
  }
}

}    // namespace

/* ----------------------------------------------------------------------
   rank 0 reads the file (found through LAMMPS_POTENTIALS like any
   potential file, its UNITS: tag checked), all ranks parse the same text
------------------------------------------------------------------------- */

void CGMS::Material::read_file(LAMMPS *lmp, const std::string &file)
{
  const auto where = fmt::format("CGMS material file {}", file);
  std::string first_line;
  for (const auto &p : read_parameter_file(
           lmp, file, where,
           fmt::format("Cannot open CGMS material file {}: give a path, or put it in a folder "
                       "listed in LAMMPS_POTENTIALS",
                       file),
           &first_line))
    set(lmp, p.name, p.value, fmt::format("{} line {}", where, p.line));
  model = potential_file_tag(first_line, "MODEL");
}

/* ----------------------------------------------------------------------
   a calibrated file holds the values one model needs to match the fine model (fitted
   k_T, k_PA, beta, lj_slope ... of pair cgms): read by another model they would give it
   other physics without a word
------------------------------------------------------------------------- */

void CGMS::Material::require_model(LAMMPS *lmp, const std::string &style,
                                   const std::string &file) const
{
  if (model.empty() || model == style) return;
  lmp->error->all(FLERR,
                  "Pair style {}: CGMS material file {} was calibrated for pair_style {} (its "
                  "first line says 'MODEL: {}'), and its fitted values hold for that model only; "
                  "give a file of measured values (apple.cgms, potato.cgms) or one calibrated for "
                  "{}",
                  style, file, model, model, style);
}

/* ---------------------------------------------------------------------- */

void CGMS::Material::set(LAMMPS *lmp, const std::string &name, const std::string &value,
                         const std::string &where)
{
  for (int k = 0; k < NENTRIES; k++) {
    const auto &e = entries[k];
    if (name != e.name) continue;
    if (!utils::is_double(value))
      lmp->error->all(FLERR, "{}: value '{}' of parameter {} is not a number", where, value, name);
    this->*e.member = std::stod(value);
    given |= 1UL << k;
    return;
  }
  std::string known;
  for (const auto &e : entries) known += std::string(" ") + e.name;
  lmp->error->all(FLERR, "{}: unknown CGMS parameter '{}' (known:{})", where, name, known);
}

/* ---------------------------------------------------------------------- */

void CGMS::Material::finish(LAMMPS *lmp, const std::string &where)
{
  for (int k = 0; k < NENTRIES; k++) {
    const auto &e = entries[k];
    if (e.required && !(given & (1UL << k)))
      lmp->error->all(FLERR, "{}: CGMS parameter {} is missing", where, e.name);
    const double v = this->*e.member;
    bool good = std::isfinite(v);
    if (e.range == POSITIVE) good = good && v > 0.0;
    if (e.range == NONNEGATIVE) good = good && v >= 0.0;
    if (e.range == NEGATIVE) good = good && v < 0.0;
    if (!good)
      lmp->error->all(FLERR, "{}: CGMS parameter {} = {} must be {}", where, e.name, v,
                      range_text(e.range));
  }
  if (perim_a >= perim_b)
    lmp->error->all(FLERR, "{}: perim_a ({}) must be below perim_b ({}) so that l_d > 0", where,
                    perim_a, perim_b);
  // the time-step check bounds k_S(s) by the fresh k_S
  if (k_S_floor > k_S)
    lmp->error->all(FLERR,
                    "{}: k_S_floor ({}) must not exceed k_S ({}): the floor is the lowest "
                    "cell-shape stiffness, k_S the fresh (largest) one",
                    where, k_S_floor, k_S);

  const ReferenceCell cell = reference_cell(diameter, pectin);
  A_ref = cell.A_ref;
  b_ref = cell.b_ref;
  l_ref = cell.l_ref;
  x_ref = cell.x_ref;
  if (r0 == 0.0) r0 = x_ref;
}

/* ---------------------------------------------------------------------- */

std::vector<std::pair<std::string, double>> CGMS::Material::parameters() const
{
  std::vector<std::pair<std::string, double>> values;
  for (const auto &e : entries) values.emplace_back(e.name, this->*e.member);
  return values;
}

/* ----------------------------------------------------------------------
   the material record of a restart file. A restart file of another plugin
   version (other parameters, or the raw struct bytes of format 1) is refused
   by the caller instead of being read wrongly; values are printed so that
   they read back to the same double.
------------------------------------------------------------------------- */

static constexpr int MATERIAL_RECORD_TAG = 0x43474d53;    // "CGMS"
// raise this whenever the layout of the record changes (2: name/value text)
static constexpr int MATERIAL_RECORD_VERSION = 2;

void CGMS::Material::write_record(FILE *fp, const std::string &key, const std::string &value) const
{
  std::string text;
  for (const auto &p : parameters()) text += fmt::format("{} {}\n", p.first, p.second);
  text += key + " " + value + "\nend\n";
  const int header[3] = {MATERIAL_RECORD_TAG, MATERIAL_RECORD_VERSION,
                         static_cast<int>(text.size())};
  fwrite(header, sizeof(int), 3, fp);
  fwrite(text.data(), 1, text.size(), fp);
}

bool CGMS::Material::read_record(LAMMPS *lmp, FILE *fp, const std::string &key, std::string &value)
{
  int header[3] = {0, 0, 0};
  if (lmp->comm->me == 0) utils::sfread(FLERR, header, sizeof(int), 3, fp, nullptr, lmp->error);
  MPI_Bcast(header, 3, MPI_INT, 0, lmp->world);
  if (header[0] != MATERIAL_RECORD_TAG || header[1] != MATERIAL_RECORD_VERSION || header[2] <= 0 ||
      header[2] > (1 << 20))
    return false;
  std::string text(header[2], '\0');
  if (lmp->comm->me == 0)
    utils::sfread(FLERR, text.data(), 1, text.size(), fp, nullptr, lmp->error);
  MPI_Bcast(text.data(), text.size(), MPI_CHAR, 0, lmp->world);

  *this = Material();
  value.clear();
  const std::string prefix = key + " ";
  for (const auto &line : utils::split_lines(text)) {
    if (line == "end") {
      finish(lmp, "restart file");
      return true;
    }
    if (utils::strmatch(line, "^" + prefix)) {
      value = line.substr(prefix.size());
      continue;
    }
    const auto words = utils::split_words(line);
    if (words.size() != 2) return false;
    set(lmp, words[0], words[1], "restart file");
  }
  return false;
}
