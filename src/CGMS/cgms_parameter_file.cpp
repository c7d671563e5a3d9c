/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#include "cgms_parameter_file.h"

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "utils.h"

#include <cstdio>
#include <set>

using namespace LAMMPS_NS;

std::vector<CGMS::ParameterLine> CGMS::read_parameter_file(LAMMPS *lmp, const std::string &file,
                                                           const std::string &where,
                                                           const std::string &cannot_open,
                                                           std::string *first_line)
{
  std::string text;
  int ok = 1;
  if (lmp->comm->me == 0) {
    FILE *fp = utils::open_potential(file, lmp, nullptr);
    if (!fp) {
      ok = 0;
    } else {
      char buf[4096];
      size_t n;
      while ((n = fread(buf, 1, sizeof(buf), fp)) > 0) text.append(buf, n);
      fclose(fp);
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, lmp->world);
  if (!ok) lmp->error->all(FLERR, cannot_open);
  int len = text.size();
  MPI_Bcast(&len, 1, MPI_INT, 0, lmp->world);
  text.resize(len);
  MPI_Bcast(text.data(), len, MPI_CHAR, 0, lmp->world);
  if (first_line) *first_line = text.substr(0, text.find('\n'));

  std::vector<ParameterLine> lines;
  std::set<std::string> seen;
  // split by hand: LAMMPS's Tokenizer (and utils::split_lines) drops empty
  // lines, which would shift the line numbers the messages give
  int lineno = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string rawline = text.substr(start, end - start);
    start = end + 1;
    ++lineno;
    auto words = utils::split_words(utils::trim_comment(rawline));
    if (words.empty()) continue;
    if (words.size() != 2)
      lmp->error->all(FLERR, "{} line {}: expected 'name value', got '{}'", where, lineno,
                      utils::trim(rawline));
    if (!seen.insert(words[0]).second)
      lmp->error->all(FLERR, "{} line {}: parameter {} given twice", where, lineno, words[0]);
    lines.push_back({words[0], words[1], lineno});
  }
  return lines;
}

std::string CGMS::potential_file_tag(const std::string &first_line, const std::string &tag)
{
  const auto words = utils::split_words(first_line);
  for (std::size_t k = 0; k + 1 < words.size(); k++)
    if (words[k] == tag + ":") return words[k + 1];
  return "";
}
