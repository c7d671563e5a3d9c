# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""CGMS: coarse-grained multiscale model of plant-tissue drying, on LAMMPS.

Plain functions on NumPy arrays. The names a script needs (doc/python.md)::

    import cgms
    mat = cgms.read_material("apple")                    # parameters of potentials/apple.cgms
    xy = cgms.rectangle(1.25e-3, 1.5e-3, mat["x_ref"])   # bead positions, m
    cgms.write_data("tissue.data", xy, 3 * mat["x_ref"])
    state = cgms.relax("tissue.data", cgms.find_material("apple"), 0.3, "out",
                       method="quasistatic")             # the steady state at s = 0.3

The rest is in the modules: :mod:`cgms.tissue` (tissues), :mod:`cgms.material`,
:mod:`cgms.run` (LAMMPS), :mod:`cgms.study` (steady states, sweeps), :mod:`cgms.morphology`
(A, P, EL), :mod:`cgms.pictures`, :mod:`cgms.drying` (drying in air over time),
:mod:`cgms.mfc` (the fine-scale model), :mod:`cgms.calibration`; :mod:`cgms.cli` is the
command line (``python3 -m cgms --help``), which no other module imports.

Each name is imported on first use, so ``import cgms`` starts neither LAMMPS nor
matplotlib (nor loads SciPy).
"""

import importlib

__version__ = "0.1.0"

#: the public face: name -> (module, name in it)
_FACE = {
    "find_material": ("material", "find"),           # the file of a material name
    "read_material": ("material", "read"),           # a material file's parameters
    "rectangle": ("tissue", "rectangle"),            # bead positions of a W x H tissue
    "write_data": ("positions", "write_data"),       # a LAMMPS data file of positions
    "open_lammps": ("run", "open_lammps"),           # LAMMPS with the plugin loaded
    "tissue_script": ("run", "tissue_script"),       # the input lines of one level
    "steady_state": ("run", "steady_state"),         # positions, X/X0, residual after a run
    "bead_state": ("fields", "bead_state"),          # every bead's fields by name
    "relax": ("study", "relax"),                     # one level to steady state, in a folder
    "sweep": ("study", "sweep"),                     # every level, resumable
    "measures": ("morphology", "measures"),          # area, perimeter, elongation
    "read_drying_params": ("drying", "read_params"),  # transport parameters of a slice
    "dry": ("drying", "dry"),                        # a slice dried in air over time
}

__all__ = list(_FACE)


def __getattr__(name):
    """The public names, imported from their modules on first use (PEP 562)."""
    if name not in _FACE:
        raise AttributeError(f"module 'cgms' has no attribute {name!r}")
    module, attribute = _FACE[name]
    value = getattr(importlib.import_module(f"{__name__}.{module}"), attribute)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
