/* ----------------------------------------------------------------------
   CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)

   This software is distributed under the GNU General Public License
   version 2; see the LICENSE file in the top-level directory.

   Registers every CGMS style. `plugin load cgmsplugin.so` (or a folder in
   LAMMPS_PLUGIN_PATH) makes atom_style cgms, pair_style cgms and
   fix cgms/fluid, fix cgms/transport and compute cgms/atom available.
------------------------------------------------------------------------- */

#include "lammpsplugin.h"

#include "atom.h"
#include "atom_vec_cgms.h"
#include "comm.h"
#include "compute_cgms_atom.h"
#include "error.h"
#include "fix_cgms_fluid.h"
#include "fix_cgms_transport.h"
#include "fix_mfc_pressure.h"
#include "fix_mfc_pressure3d.h"
#include "lammps.h"
#include "pair_cgms.h"
#include "pair_cgms_shaped.h"
#include "pair_sph_taitwater_ap.h"
#include "version.h"

#include <cstring>

using namespace LAMMPS_NS;

static Pair *pair_cgms_creator(LAMMPS *lmp)
{
  return new PairCGMS(lmp);
}

static Pair *pair_cgms_shaped_creator(LAMMPS *lmp)
{
  return new PairCGMSShaped(lmp);
}

static Pair *pair_sph_taitwater_ap_creator(LAMMPS *lmp)
{
  return new PairSPHTaitwaterAP(lmp);
}

static Fix *fix_cgms_fluid_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixCGMSFluid(lmp, argc, argv);
}

static Fix *fix_cgms_transport_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixCGMSTransport(lmp, argc, argv);
}

static Fix *fix_mfc_pressure_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixMFCPressure(lmp, argc, argv);
}

static Fix *fix_mfc_pressure3d_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixMFCPressure3d(lmp, argc, argv);
}

static Compute *compute_cgms_atom_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new ComputeCGMSAtom(lmp, argc, argv);
}

static AtomVec *atom_vec_cgms_creator(LAMMPS *lmp)
{
  return new AtomVecCGMS(lmp);
}

extern "C" void lammpsplugin_init(void *lmp_ptr, void *handle, void *regfunc)
{
  auto lmp = static_cast<LAMMPS *>(lmp_ptr);
  auto register_plugin = (lammpsplugin_regfunc) regfunc;
  lammpsplugin_t plugin;

  // the atom style reaches into LAMMPS's classes: another version may lay them out
  // differently, so refuse rather than crash later
  if (strcmp(lmp->version, LAMMPS_VERSION) != 0)
    lmp->error->all(FLERR,
                    "The CGMS plugin was built for LAMMPS {} but was loaded into LAMMPS {}: "
                    "rebuild it against this LAMMPS ('./cgms setup' with LAMMPS_SOURCE_DIR and "
                    "LAMMPS_BUILD_DIR, see README.md)",
                    LAMMPS_VERSION, lmp->version);

  plugin.version = LAMMPS_VERSION;
  plugin.author = "CGMS developers";
  plugin.handle = handle;

  plugin.style = "pair";
  plugin.name = "cgms";
  plugin.info =
      "CGMS pair style: turgor, perimeter, damping and LJ forces between plant-cell beads";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_cgms_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "cgms/shaped";
  plugin.info = "CGMS pair style: the shaped coarse model, a bead and a shape tensor per cell";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_cgms_shaped_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "sph/taitwater/ap";
  plugin.info = "MFC pair style: SPH Tait water with Monaghan's artificial pressure";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_sph_taitwater_ap_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "cgms/fluid";
  plugin.info = "CGMS fix: virtual-cell geometry, turgor pressure and mass transfer";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_cgms_fluid_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "cgms/transport";
  plugin.info = "CGMS fix: moisture transport through the slice and into air (drying over time)";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_cgms_transport_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "mfc/pressure";
  plugin.info = "MFC fix: one equation-of-state pressure per cell from the area its wall encloses";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_mfc_pressure_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "mfc/pressure3d";
  plugin.info = "MFC fix: one equation-of-state pressure per cell from the volume its "
                "triangulated wall encloses";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_mfc_pressure3d_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "compute";
  plugin.name = "cgms/atom";
  plugin.info = "CGMS compute: per-bead state and derived outputs (pressure, side, ...) by name";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &compute_cgms_atom_creator;
  (*register_plugin)(&plugin, lmp);

  // LAMMPS's plugin loader has no atom styles; the creator map is public,
  // so the style is added to this instance's map directly
  (*lmp->atom->avec_map)["cgms"] = &atom_vec_cgms_creator;
  if (lmp->comm->me == 0) utils::logmesg(lmp, "Loading plugin: CGMS atom style cgms\n");
}
