# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""cgms.solve's factorisation orderings (newton's ``ordering``): the geometric nested
dissection that cgms dry's warm solves use, against SuperLU's minimum degree, on matrices
with the pattern of a Newton Jacobian (every pair of beads within ``reach``)."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.spatial import cKDTree

from cgms import solve, tissue

REACH = 2.04 * 1.35     # two cutoffs of 1.35 spacings, as newton's reach


def pattern_matrix(xy, reach=REACH, seed=0):
    """A symmetric, diagonally dominant 2n x 2n matrix (coordinates interleaved) with an
    entry for every coordinate pair of beads within ``reach``."""
    pairs = cKDTree(xy).query_pairs(reach, output_type="ndarray")
    rng = np.random.default_rng(seed)
    rows, cols, vals = [], [], []
    for d in range(2):
        for e in range(2):
            w = rng.uniform(-1, 1, len(pairs))
            rows += [2 * pairs[:, 0] + d, 2 * pairs[:, 1] + e]
            cols += [2 * pairs[:, 1] + e, 2 * pairs[:, 0] + d]
            vals += [w, w]
    off = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(2 * len(xy), 2 * len(xy)))
    diag = np.asarray(abs(off).sum(axis=1)).ravel() + 1.0
    return (off + sp.diags(diag)).tocsc()


def fill(lu):
    lu = getattr(lu, "lu", lu)
    return lu.L.nnz + lu.U.nnz


def test_nested_dissection_is_an_order_of_all_beads():
    xy = tissue.hex_rectangle(37, 31, 1.0)
    order = solve.nested_dissection(xy, 0.5 * REACH)
    assert np.array_equal(np.sort(order), np.arange(len(xy)))


def test_geometric_ordering_solves_the_same_system_with_less_fill():
    """Same solution to rounding (the matrix is well conditioned: 1e-12 of the solution
    asserted, 9e-16 measured), and no more fill than minimum degree (this 1 147-bead patch:
    673 922 entries in L + U against 680 126; 17.8 M against 20.2 M on the 20 273-bead
    tissue's Hessian). A band half as wide as the coupling separates nothing, and the
    fill grows to 1 000 128: the ordering depends on its band covering the coupling."""
    xy = tissue.hex_rectangle(37, 31, 1.0)
    a = pattern_matrix(xy)
    rhs = np.random.default_rng(1).normal(size=a.shape[0])
    reference = solve._factorise(a, xy, REACH, "minimum-degree")
    geometric = solve._factorise(a, xy, REACH, "geometric")
    x0, x1 = reference.solve(rhs), geometric.solve(rhs)
    assert np.abs(a @ x1 - rhs).max() < 1e-12 * np.abs(rhs).max()
    assert np.abs(x1 - x0).max() < 1e-12 * np.abs(x0).max()
    assert fill(geometric) <= fill(reference)
    # a band of half the coupling's half-width does not cut the coupling
    beads = solve.nested_dissection(xy, 0.25 * REACH)
    perm = np.column_stack([2 * beads, 2 * beads + 1]).ravel()
    narrow = solve.spla.splu(a[perm][:, perm].tocsc(), permc_spec="NATURAL",
                             diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
    assert fill(narrow) > 1.3 * fill(geometric)


def test_unknown_ordering_is_refused():
    xy = tissue.hex_rectangle(5, 5, 1.0)
    with pytest.raises(ValueError, match="ordering must be"):
        solve._factorise(pattern_matrix(xy), xy, REACH, "metis")


@pytest.mark.parametrize("ordering", ["minimum-degree", "geometric"])
def test_newton_converges_with_either_ordering(ordering):
    """Newton on a field of springs between beads within 1.35 spacings (a convex
    potential) reaches 1e-12 with either ordering (tests/plugin/test_quasistatic.py's
    field, without LAMMPS)."""
    xy = tissue.hex_rectangle(12, 11, 1.0)
    rest = {tuple(p): np.linalg.norm(xy[p[0]] - xy[p[1]])
            for p in cKDTree(xy).query_pairs(1.35, output_type="ndarray")}
    pairs = np.array(list(rest))
    length = np.array(list(rest.values()))

    def field(x):
        d = x[pairs[:, 0]] - x[pairs[:, 1]]
        r = np.linalg.norm(d, axis=1)
        stretch = r - length
        f = np.zeros_like(x)
        g = (stretch / r)[:, None] * d
        np.add.at(f, pairs[:, 0], -g)
        np.add.at(f, pairs[:, 1], g)
        return 0.5 * float(stretch @ stretch), f

    class Counted:
        evaluations = 0

        def __call__(self, x):
            Counted.evaluations += 1
            return field(x)

    start = xy + np.random.default_rng(2).uniform(-0.05, 0.05, xy.shape)
    x, info = solve.newton(Counted(), start, 1.35, ftol=1e-12, ordering=ordering)
    assert info["converged"], info["fmax"]
    assert np.abs(field(x)[1]).max() < 1e-12
