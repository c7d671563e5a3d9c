# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Per-bead CGMS state by name, from a running LAMMPS instance.

:func:`bead_state` is the call a Python user needs instead of column numbers::

    from cgms import fields
    state = fields.bead_state(lmp)        # after a run (or 'run 0')
    state["pressure"], state["mf"]        # numpy arrays ordered by atom id

The names are those of ``compute cgms/atom`` (doc/compute_cgms_atom.rst), in the
order of fix cgms/fluid's per-atom array (``f_ID[1]`` ... ``f_ID[14]``). The stored
ones (``dryness mf ms mf0 l0p rho area dmdt``) are also LAMMPS custom per-atom
vectors: ``lmp.numpy.extract_atom("d_mf")`` gives this rank's beads without a
gather, and ``set atom * d_mf ...`` changes them (doc/atom_style_cgms.rst).
"""

import numpy as np

# the per-bead fields of atom_style cgms in the column order of fix cgms/fluid's
# per-atom array (src/CGMS/cgms_store.cpp, column_names)
FIELDS = ("cgmscoef", "dryness", "nneigh", "side", "mf", "ms", "mf0", "l0p", "rho",
          "pressure", "area", "perim", "ldeq", "dmdt")

_COMPUTE = "cgms_fields_"


def bead_state(lmp, names=FIELDS):
    """The per-bead fields ``names`` of the beads in ``lmp`` (a ``lammps`` instance with
    atom_style cgms), as a dict name -> numpy array ordered by atom id, plus ``"id"``,
    ``"x"`` and ``"y"`` (m). Values are those of the last force evaluation: call it after
    a run or ``run 0``. Under MPI it is collective: call it on every rank; every rank
    gets the whole arrays (rank 0 may simply ignore them on the others)."""
    names = tuple(names)
    unknown = [n for n in names if n not in FIELDS]
    if unknown:
        raise ValueError(f"unknown CGMS field(s) {', '.join(unknown)}; known: "
                         f"{', '.join(FIELDS)}")
    natoms = int(lmp.get_natoms())
    ids = np.array(lmp.gather_concat("id", 0, 1), dtype=np.int64)
    order = np.argsort(ids)
    x = np.array(lmp.gather_concat("x", 1, 3)).reshape(natoms, 3)[order]
    state = {"id": ids[order], "x": x[:, 0].copy(), "y": x[:, 1].copy()}
    if names:
        lmp.command(f"compute {_COMPUTE} all cgms/atom {' '.join(names)}")
        try:
            values = np.array(lmp.gather_concat(f"c_{_COMPUTE}", 1, len(names)))
        finally:
            lmp.command(f"uncompute {_COMPUTE}")
        values = values.reshape(natoms, len(names))[order]
        for k, name in enumerate(names):
            state[name] = values[:, k].copy()
    return state
