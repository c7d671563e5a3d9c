# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Moisture transport (cgms.transport) against Crank's analytic solutions, water balance,
and the apple surface law (doc/drying.md). No LAMMPS: the mechanics is frozen here."""

import math

import numpy as np
import pytest

from scipy.ndimage import gaussian_filter1d

import crank
from cgmstest import MAT
from cgms import morphology, tissue, transport

RHO_S = 120.0   # dry solid per tissue volume, kg/m^3 (any value: it cancels)
D = 1e-9


def run(grid, x, t_end, steps, law, outline=True):
    dt = t_end / steps
    out = 0.0
    for _ in range(steps):
        x, face, edge, _ = transport.step(grid, x, dt, lambda v: np.full_like(v, D), law,
                                          outline=outline)
        out += face + edge
    return x, out


def slab(layers, biot, fourier, steps=400):
    """A hexagonal patch whose columns exchange only through both slice faces."""
    a = 1.5e-4
    xy = tissue.hex_rectangle(4, 4, a)
    geo = transport.bead_geometry(xy, 1.35 * a)
    thick = 2e-3
    grid = transport.column_grid(geo, np.full(len(xy), thick), RHO_S * geo["area"] * thick,
                                 layers, faces=2)
    half = thick / 2
    law = transport.linear_surface(biot * D / half * RHO_S)
    x0 = np.ones(len(xy) * layers)
    x, out = run(grid, x0, fourier * half**2 / D, steps, law, outline=False)
    return grid, x, out, transport.water(grid, x0)


@pytest.mark.parametrize("biot", [0.5, 2.0, 20.0])
def test_slab_matches_crank(biot):
    fourier = 0.3
    errors = []
    for layers in (5, 10, 20):
        grid, x, _, w0 = slab(layers, biot, fourier)
        errors.append(abs(transport.water(grid, x) / w0 / crank.slab_mean(fourier, biot)[0] - 1))
    assert errors[-1] < 0.01
    assert errors[0] > errors[1] > errors[2]       # converges as the layers get thinner
    # the field across the thickness: layer centres, z/l from the mid-plane
    layers = 20
    z = 1 - (np.arange(layers) + 0.5) / layers
    exact = crank.slab_field(z, fourier, biot)
    column = x.reshape(-1, layers)
    assert np.allclose(column, column[0], rtol=0, atol=1e-12)   # every bead alike
    assert np.abs(column[0] - exact).max() < 0.01


def disc(spacing, biot, fourier, steps=300):
    radius = 1.5e-3
    xy = tissue.disc(radius, spacing)
    geo = transport.bead_geometry(xy, 1.35 * spacing)
    thick = 1e-3
    grid = transport.column_grid(geo, np.full(len(xy), thick), RHO_S * geo["area"] * thick,
                                 1, faces=0)
    r_eff = math.sqrt(geo["area"].sum() / math.pi)   # the disc the beads tile
    law = transport.linear_surface(biot * D / r_eff * RHO_S)
    x0 = np.ones(len(xy))
    x, out = run(grid, x0, fourier * r_eff**2 / D, steps, law)
    r = np.hypot(*(xy - xy.mean(axis=0)).T) / r_eff
    return grid, x, out, transport.water(grid, x0), r


def test_disc_matches_crank():
    biot, fourier = 2.0, 0.2
    errors, field = [], []
    for spacing in (1.5e-4, 1e-4, 0.5e-4):
        grid, x, _, w0, r = disc(spacing, biot, fourier)
        errors.append(abs(transport.water(grid, x) / w0 / crank.disc_mean(fourier, biot)[0] - 1))
        field.append(np.sqrt(np.mean((x - crank.disc_field(r, fourier, biot)) ** 2)))
    assert errors[-1] < 0.01 and field[-1] < 0.01
    assert errors[0] > errors[1] > errors[2] and field[0] > field[1] > field[2]


OUTLINE_TISSUES = {
    "86-bead calibration tissue": (lambda: tissue.rectangle(1.25e-3, 1.5e-3, MAT["x_ref"]),
                                   MAT["x_ref"]),
    "20 273-bead macroscale tissue": (lambda: tissue.rectangle(20e-3, 20e-3, MAT["x_ref"]),
                                      MAT["x_ref"]),
    "disc of 823 beads": (lambda: tissue.disc(1.5e-3, 1e-4), 1e-4),
}


@pytest.mark.parametrize("name", list(OUTLINE_TISSUES))
def test_outline_from_neighbours_is_the_polygon(name):
    """The outline each bead finds from its own neighbours (the construction fix
    cgms/transport makes) is the outline polygon of the whole tissue (Delaunay,
    cgms.morphology.outline): unsmoothed, every bead's share is half its two polygon edges,
    to rounding. Smoothed and offset, it is the polygon smoothed by a Gaussian of 2 beads
    along the ring and offset by pi a spread over the ring (the route before the local
    construction): measured 5e-4 of the total at most, 0.2 spacing per bead (at corners,
    where the local offset is concentrated)."""
    make, spacing = OUTLINE_TISSUES[name]
    xy = make()
    geo = transport.bead_geometry(xy, 1.35 * spacing)
    ring = morphology.outline(xy)

    def shares(poly):
        edges = np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1)
        out = np.zeros(len(xy))
        np.add.at(out, ring, 0.5 * (edges + np.roll(edges, 1)))
        return out, edges.sum()

    plain, _ = shares(xy[ring])
    local = transport.outline_edge(xy, geo["pairs"], geo["spacing"], passes=0, offset=False)
    assert np.abs(local - plain).max() < 1e-12 * spacing
    smooth, perimeter = shares(gaussian_filter1d(xy[ring], 2.0, axis=0, mode="wrap"))
    ref = smooth * (perimeter + math.pi * geo["spacing"][ring].mean()) / perimeter
    assert abs(geo["edge"].sum() / ref.sum() - 1) < 1e-3
    assert np.abs(geo["edge"] - ref).max() < 0.25 * spacing
    assert np.count_nonzero(geo["edge"]) == len(np.unique(ring))


def test_water_balance_closes():
    """What the tissue loses equals what crossed its faces and outline, with D varying with
    moisture and the nonlinear apple surface law."""
    a = 1.5e-4
    xy = tissue.rectangle(1.5e-3, 1.5e-3, a)
    geo = transport.bead_geometry(xy, 1.35 * a)
    grid = transport.column_grid(geo, np.full(len(xy), 2e-3), RHO_S * geo["area"] * 2e-3, 6)
    gab = (0.12, 5.0, 0.9)
    kc, _ = transport.air_coefficients(70.0, 1.5, 0.03)
    law = transport.vapour_surface(kc, 40.0, 70.0, 0.1, gab)
    rng = np.random.default_rng(1)
    x = 6.0 * rng.uniform(0.5, 1.0, len(xy) * 6)
    w0 = transport.water(grid, x)
    out = 0.0
    for _ in range(300):
        x, face, edge, _ = transport.step(grid, x, 20.0,
                                          lambda v: transport.diffusivity(v, 70, 3e-10, 70, 3e4, 2.0, 6.0),
                                          law)
        out += face + edge
    w = transport.water(grid, x)
    assert w < 0.7 * w0                       # it dried
    assert abs(w0 - w - out) / w0 < 1e-10


def test_gab_inverse():
    gab = (0.12, 5.0, 0.9)
    aw = np.linspace(0.05, 0.99, 30)
    x = transport.gab_moisture(aw, *gab)
    back, slope = transport.gab_activity(x, *gab)
    assert np.allclose(back, aw, rtol=1e-10)
    h = 1e-7
    numeric = (transport.gab_moisture(aw + h, *gab) - transport.gab_moisture(aw - h, *gab)) / (2 * h)
    assert np.allclose(slope, 1 / numeric, rtol=1e-6)
    # free water above the moisture of aw = 1
    aw_free, slope_free = transport.gab_activity(10 * transport.gab_moisture(1.0, *gab), *gab)
    assert aw_free == 1.0 and slope_free == 0.0


def test_air_side():
    """Wet-bulb temperature of air at 70 C and 10 % relative humidity: the product
    temperature of a wet surface. The adiabatic-saturation balance c_p (70 - T) =
    (W_sat(T) - W) h_fg, solved by hand with Buck's p_sat, gives 34.2 C; the model's
    Chilton-Colburn coefficients (h / (k_c rho c_p) = Le^2/3 = 0.9, not the Lewis
    relation's 1) put the wet surface 2 K lower."""
    kc, h = transport.air_coefficients(70.0, 1.5, 0.03)
    xy = tissue.hex_rectangle(3, 3, 1.5e-4)
    geo = transport.bead_geometry(xy, 1.35 * 1.5e-4)
    grid = transport.column_grid(geo, np.full(len(xy), 2e-3), RHO_S * geo["area"] * 2e-3, 2)
    wet = np.full(len(xy) * 2, 6.0)          # free water at the surface: aw = 1
    tp = transport.product_temperature(kc, h, 70.0, 0.1, (0.12, 5.0, 0.9), grid, wet,
                                       np.full_like(wet, 1e-6))
    assert abs(tp - 34.2) < 2.5      # 34.2 C: the adiabatic-saturation balance by hand
    assert 0.01 < kc < 0.05 and 15 < h < 40
