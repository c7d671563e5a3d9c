/* -*- c++ -*- ----------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.
------------------------------------------------------------------------- */

#ifndef LMP_CGMS_PARAMETER_FILE_H
#define LMP_CGMS_PARAMETER_FILE_H

#include <string>
#include <vector>

namespace LAMMPS_NS {

class LAMMPS;

namespace CGMS {

  // One "name value" line of a parameter file (a material file, a drying
  // parameter file); the value stays text so that each reader checks it
  // against its own table and names the parameter in its message.
  struct ParameterLine {
    std::string name;
    std::string value;
    int line;
  };

  // Rank 0 reads the file, found like any potential file (current folder,
  // then LAMMPS_POTENTIALS); every rank gets the same lines, '#' comments and
  // blank lines dropped. error->all() with cannot_open when the file cannot
  // be opened, and with "<where> line N: ..." for a line that is not two
  // words or a name given twice. first_line, when given, receives the file's
  // first line (its "DATE: ... UNITS: ..." tags) on every rank.
  std::vector<ParameterLine> read_parameter_file(LAMMPS *lmp, const std::string &file,
                                                 const std::string &where,
                                                 const std::string &cannot_open,
                                                 std::string *first_line = nullptr);

  // the word after "<tag>:" in a potential file's first line ("" when absent),
  // e.g. potential_file_tag("# DATE: 2026-12-02 UNITS: si MODEL: cgms", "MODEL") = "cgms"
  std::string potential_file_tag(const std::string &first_line, const std::string &tag);

}    // namespace CGMS
}    // namespace LAMMPS_NS

#endif
