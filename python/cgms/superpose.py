# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Rigid superposition and eqn (2) of the paper: the root mean square distance between
simulated bead positions and reference centroids, after removing the rigid motion that the
steady state is not defined up to."""

import math

import numpy as np

#: the rigid motions that :func:`align` removes
ALIGN = ("translation", "rigid", "none")


def align(p, q, mode="translation"):
    """``p`` moved rigidly onto ``q`` by the motion that minimises eqn (2): the centroid
    shift (``"translation"``), that and the best rotation (``"rigid"``, 2-D Kabsch), or
    nothing (``"none"``)."""
    if mode not in ALIGN:
        raise ValueError(f"align must be one of {ALIGN}, got {mode!r}")
    p = np.asarray(p, float)
    q = np.asarray(q, float)
    if mode == "none":
        return p
    pc, qc = p - p.mean(axis=0), q.mean(axis=0)
    if mode == "rigid":
        pc = pc @ rotation(p, q).T
    return pc + qc


def rotation(p, q):
    """R (2, 2): the rotation about the centroids that brings ``p`` closest to ``q`` (2-D
    Kabsch), the one :func:`align` applies with ``"rigid"``; e.g. for a shaped state, whose
    cells' F turn with it."""
    p = np.asarray(p, float)
    q = np.asarray(q, float)
    pc, qq = p - p.mean(axis=0), q - q.mean(axis=0)
    angle = math.atan2(np.sum(pc[:, 0] * qq[:, 1] - pc[:, 1] * qq[:, 0]), np.sum(pc * qq))
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def rmsd(p, q, mode="translation"):
    """Eqn (2): root mean square over beads of the distance between the simulated position
    ``p_i`` (after :func:`align`) and the reference centroid ``q_i``."""
    d = align(p, q, mode) - np.asarray(q, float)
    return float(np.sqrt(np.mean(np.sum(d * d, axis=1))))
