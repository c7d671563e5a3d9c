# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A 3-D fine-scale (MFC) cell: a closed triangulated wall around its fluid (doc/mfc.md,
"3-D cell").

The wall is an icosphere (an icosahedron whose triangles are split in four ``level``
times, the new vertices pushed out onto the sphere): ``10 4^level + 2`` wall particles.
LAMMPS carries it as

* bonds along every edge (``bond harmonic``, one bond type per distinct rest length):
  stretching;
* one angle per triangle (atoms a b c counter-clockwise seen from outside, angle type 1,
  ``angle_style zero``): the triangles ``fix mfc/pressure3d`` reads the enclosed volume
  from. Decision: angles, because LAMMPS stores and migrates them with their atoms on any
  number of ranks, a triangle is exactly three atoms, and their order carries the
  orientation; a molecule template is not per-atom state, and dihedrals hold two triangles
  each;
* one dihedral per edge (the two triangles' far corners, ``dihedral harmonic`` with d = +1,
  n = 1: E = K (1 + cos phi) = K (1 - n1.n2), zero when flat): bending.

Parameters (Decision: the 2-D MFC's wall carried over to a shell): extensional stiffness
E t = 330 N/m as a triangular spring net, whose 2-D Young's modulus is 2k/sqrt(3) and
Poisson ratio 1/3, so k = sqrt(3) E t / 2 per bond; bending K = 2 kappa / sqrt(3) with
kappa = E t^3 / (12 (1 - 1/9)) (Seung and Nelson, Phys. Rev. A 38, 1988, 1005); a fresh
free cell is a sphere of diameter D at turgor P_T, its wall stretched by the isotropic
tension of Laplace's law, gamma = P_T R / 2 = sqrt(3) k (1 - l0/l), so every bond's rest
length is its built length times ``1 - P_T R / (2 sqrt(3) k)``; the fluid's rest volume is
the built wall's volume.
"""

import math

import numpy as np

from .. import folders

#: the wall's fixed values (the rest comes from cgms.mfc.model.parameters)
WALL3D = dict(level=3, angle_type=1)


def icosphere(level):
    """Unit-sphere vertices (n, 3) and triangles (m, 3), counter-clockwise seen from
    outside, of an icosahedron split ``level`` times."""
    if int(level) != level or not 0 <= level <= 6:
        raise ValueError(f"icosphere level must be an integer 0..6, got {level!r}")
    t = (1 + math.sqrt(5)) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(int(level)):
        middle, split = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                middle[key] = len(verts) - 1
            return middle[key]
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = split
    x, tri = np.array(verts), np.array(f, int)
    normal = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
    outward = np.einsum("ij,ij->i", normal, x[tri].mean(axis=1)) > 0
    tri[~outward] = tri[~outward][:, ::-1]
    return x, tri


def edges_and_hinges(tri):
    """The edges (k, 2) of a closed triangle mesh and, per edge, its dihedral (i, j, k, l):
    j-k the edge, i and l the far corners of its two triangles."""
    far = {}
    for a, b, c in tri:
        for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
            far.setdefault((min(p, q), max(p, q)), []).append(r)
    if any(len(v) != 2 for v in far.values()):
        raise ValueError("the triangles do not form a closed surface (an edge is not shared "
                         "by exactly two triangles)")
    edges = np.array(sorted(far), int)
    hinges = np.array([(far[(j, k)][0], j, k, far[(j, k)][1]) for j, k in edges], int)
    return edges, hinges


def volume(x, tri):
    """Enclosed volume of a closed, outward-oriented triangle mesh (divergence theorem),
    with the gradient dV/dx per vertex (NumPy oracle of fix mfc/pressure3d)."""
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    v = np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0
    grad = np.zeros_like(x)
    for k, (p, q) in enumerate(((b, c), (c, a), (a, b))):
        np.add.at(grad, tri[:, k], np.cross(p, q) / 6.0)
    return v, grad


def area(x, tri):
    """Wall area of a triangle mesh."""
    n = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
    return 0.5 * np.linalg.norm(n, axis=1).sum()


def wall(p, level=WALL3D["level"]):
    """The fresh 3-D wall of the MFC parameters ``p`` (:func:`cgms.mfc.model.parameters`):
    stiffnesses, the pre-stress of Laplace's law, rest lengths, and the mesh."""
    x, tri = icosphere(level)
    radius = p["diameter"] / 2
    x = x * radius
    edges, hinges = edges_and_hinges(tri)
    k = math.sqrt(3) * p["wall_Et"] / 2
    stretch = p["P_f"] * radius / (2 * math.sqrt(3) * k)     # 1 - l0 / l
    t = p["wall_thickness"]
    kappa = p["wall_Et"] * t * t / (12 * (1 - 1 / 9))
    length = np.linalg.norm(x[edges[:, 1]] - x[edges[:, 0]], axis=1)
    # one bond type per rest length: the icosphere's edges fall into a few symmetry classes
    classes, kind = np.unique(np.round(length * (1 - stretch) / radius, 9),
                              return_inverse=True)
    return dict(x=x, tri=tri, edges=edges, hinges=hinges, radius=radius, k_bond=k,
                stretch=stretch, rest=classes[kind] * radius, rest_classes=classes * radius,
                bond_type=kind + 1,
                k_dihedral=p["bend_factor"] * 2 * kappa / math.sqrt(3),
                fluid_volume=volume(x, tri)[0], level=level)


def write_data(path, centres, p, level=WALL3D["level"], margin=None, overwrite=False):
    """LAMMPS data file of one 3-D cell per centre (``atom_style molecular``: ``id mol type
    x y z``): bonds (type = rest-length class, coefficients in the file), triangles as
    angles (type 1), hinges as dihedrals (type 1). Returns the :func:`wall` dict."""
    w = wall(p, level)
    centres = np.atleast_2d(np.asarray(centres, float))
    if centres.shape[1] != 3:
        raise ValueError(f"cell centres must be (n, 3) positions, got shape {centres.shape}")
    n = len(w["x"])
    x = np.concatenate([w["x"] + c for c in centres])
    margin = 2 * w["radius"] if margin is None else margin
    lo, hi = x.min(axis=0) - margin, x.max(axis=0) + margin
    mass = p["solid_ratio"] * p["rho0"] * w["fluid_volume"] / n
    lines = ["MFC 3-D cells: icosphere walls", "",
             f"{len(x)} atoms", f"{len(w['edges']) * len(centres)} bonds",
             f"{len(w['tri']) * len(centres)} angles",
             f"{len(w['hinges']) * len(centres)} dihedrals", "",
             "1 atom types", f"{len(w['rest_classes'])} bond types", "1 angle types",
             "1 dihedral types", ""]
    lines += [f"{lo[d]:.10e} {hi[d]:.10e} {a}lo {a}hi" for d, a in enumerate("xyz")]
    lines += ["", "Masses", "", f"1 {mass:.10e}", "", "Bond Coeffs # harmonic", ""]
    lines += [f"{t + 1} {w['k_bond'] / 2:.17e} {r:.17e}"
              for t, r in enumerate(w["rest_classes"])]
    lines += ["", "Dihedral Coeffs # harmonic", "", f"1 {w['k_dihedral']:.12e} 1 1"]
    lines += ["", "Atoms # molecular", ""]
    lines += [f"{i + 1} {i // n + 1} 1 {a:.15e} {b:.15e} {c:.15e}"
              for i, (a, b, c) in enumerate(x)]
    rows = {"Bonds": [], "Angles": [], "Dihedrals": []}
    for cell in range(len(centres)):
        o = cell * n + 1
        rows["Bonds"] += [(t, *(e + o)) for t, e in zip(w["bond_type"], w["edges"])]
        rows["Angles"] += [(WALL3D["angle_type"], *(t + o)) for t in w["tri"]]
        rows["Dihedrals"] += [(1, *(h + o)) for h in w["hinges"]]
    for name, entries in rows.items():
        lines += ["", name, ""]
        lines += [" ".join(str(int(v)) for v in (k + 1, *e)) for k, e in enumerate(entries)]
    folders.write_text(path, "\n".join(lines) + "\n", overwrite=overwrite)
    return w


def commands(data, w, p, fix_id="cell", processors=None, bending=True, newton="on"):
    """LAMMPS commands of the 3-D cells of ``data``: styles, the fluid's fix (fresh turgor
    and fluid volume of ``w``) with its energy, and a communication cutoff that reaches a
    dihedral's far corner on another rank. No pair style: these free cells do not touch
    (the tissue's lamella and self-avoidance: :func:`cgms.mfc.run3d.pair_commands`)."""
    skin = float(np.max(w["rest"]))
    lines = ["units si", "dimension 3", "boundary f f f", f"newton {newton}",
             "atom_style molecular", "atom_modify map array"]
    if processors:
        lines.append(f"processors {processors}")
    lines += ["bond_style harmonic", "angle_style zero", "dihedral_style harmonic",
              f"read_data {data}", "angle_coeff *", f"neighbor {skin:.6e} bin",
              "neigh_modify delay 0 every 1 check yes", f"comm_modify cutoff {3 * skin:.6e}",
              f"fix {fix_id} all mfc/pressure3d modulus {p['K']:.10g} turgor {p['P_f']:.10g} "
              f"volume {w['fluid_volume']:.15e}", f"fix_modify {fix_id} energy yes"]
    if not bending:
        lines.insert(lines.index("angle_coeff *") + 1, "dihedral_coeff 1 0.0 1 1")
    return lines
