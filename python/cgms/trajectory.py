# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Tissue morphology over a whole run, frame by frame, read with MDAnalysis.

A LAMMPS run writes its trajectory with ``dump custom`` (text, columns ``id type x y z``
and any others). MDAnalysis reads it frame by frame without loading the file into memory,
which matters for a 20 000-bead tissue dumped thousands of times, and reads the binary
trajectories of ``dump dcd`` and ``dump xtc`` the same way (those need a LAMMPS with the
EXTRA-DUMP package, which ``./cgms setup`` does not build: untested here). Each frame's bead
positions go to :func:`cgms.morphology.measures`: the tissue area, perimeter and elongation of the paper
(doc/model.md, "Tissue morphology").

- :func:`universe`: an MDAnalysis Universe over a dump (or a data file and a DCD/XTC);
- :func:`shapes`: area, perimeter, elongation and their normalised values for every frame.

MDAnalysis's dump reader keeps positions in float32 (7 digits: 1e-10 m, 1e-6 x_ref, on a
tissue of a few mm) and moves the box's lower corner to the origin; the shape measures do not depend
on either. Per-bead fields (``pressure``, ``mf``, ...) are not read by it (MDAnalysis
2.4 reads only id, type, positions, velocities and forces): read those with
:func:`cgms.morphology.read_dump`.
"""

import warnings

import numpy as np

from . import morphology

#: the per-frame results of :func:`shapes`
SHAPE_KEYS = ("area", "perimeter", "elongation", "A/A0", "P/P0", "EL/EL0")


def universe(trajectory, topology=None, **kwargs):
    """An MDAnalysis Universe over a LAMMPS trajectory.

    ``trajectory``: a LAMMPS text dump with the columns ``id``, ``type`` and ``x y z`` (or
    ``xu yu zu``, ``xs ys zs``), read with MDAnalysis's LAMMPSDUMP reader; or, with
    ``topology`` (a LAMMPS data file of the tissue, ``Atoms # cgms``: ``id type x y z``),
    such a dump or any trajectory MDAnalysis reads (``dump dcd``). Raises ValueError naming
    what a dump lacks."""
    text_dump = _is_text_dump(trajectory)
    if text_dump:
        _check_dump_columns(trajectory)
    # record: MDAnalysis adds its own warning filters on import (xdrlib deprecation, ...)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("ignore")
        import MDAnalysis as mda

        if text_dump:
            kwargs.setdefault("format", "LAMMPSDUMP")
        if topology is None:
            return mda.Universe(str(trajectory), **kwargs)
        kwargs.setdefault("atom_style", "id type x y z")
        return mda.Universe(str(topology), str(trajectory), topology_format="DATA", **kwargs)


def _is_text_dump(path):
    """A LAMMPS text dump begins with 'ITEM: TIMESTEP' (binary DCD/XTC files do not)."""
    with open(path, "rb") as fh:
        return fh.read(5) == b"ITEM:"


def _check_dump_columns(path):
    """The columns MDAnalysis needs, checked on the first frame for a clear message (it
    would otherwise stop with an IndexError or 'No coordinate information detected')."""
    with open(path) as fh:
        for line in fh:
            if line.startswith("ITEM: ATOMS"):
                columns = line.split()[2:]
                break
        else:
            raise ValueError(f"{path}: not a LAMMPS dump (no 'ITEM: ATOMS' line)")
    missing = [c for c in ("id", "type") if c not in columns]
    coords = [("x", "y", "z"), ("xu", "yu", "zu"), ("xs", "ys", "zs"), ("xsu", "ysu", "zsu")]
    if not any(all(c in columns for c in xyz) for xyz in coords):
        missing.append("x y z")
    if missing:
        raise ValueError(f"{path}: MDAnalysis reads LAMMPS dumps with the columns id, type and "
                         f"x y z (z too in 2-D); this one lacks {', '.join(missing)} "
                         f"(ITEM: ATOMS {' '.join(columns)})")


def shapes(u, fresh=None, start=None, stop=None, step=None, max_edge=None):
    """Tissue shape in every frame of Universe ``u`` (from :func:`universe`), or of the
    frames ``start:stop:step``.

    Returns a dict of arrays, one value per frame: ``frame`` (index), ``step`` (LAMMPS time
    step, from the dump; the frame index for trajectories without it), ``area`` (m^2),
    ``perimeter`` (m), ``elongation`` (:func:`cgms.morphology.measures`), and ``A/A0``,
    ``P/P0``, ``EL/EL0`` normalised by ``fresh`` (measures of the fresh tissue, e.g.
    ``morphology.measures(fresh_xy)``) or, without it, by the first frame read."""
    out = {key: [] for key in ("frame", "step") + SHAPE_KEYS}
    for ts in u.trajectory[start:stop:step]:
        xy = np.asarray(u.atoms.positions[:, :2], dtype=float)
        m = morphology.measures(xy, max_edge)
        if fresh is None:
            fresh = m
        out["frame"].append(ts.frame)
        out["step"].append(ts.data.get("step", ts.frame))
        for key in ("area", "perimeter", "elongation"):
            out[key].append(m[key])
        for key, value in morphology.normalise(m, fresh).items():
            if key in out:
                out[key].append(value)
    return {key: np.asarray(values) for key, values in out.items()}
