# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Moisture transport (cgms.drying.transport) against Crank's analytic solutions, water balance,
and the apple surface law (doc/drying.md). No LAMMPS: the mechanics is frozen here."""

import math

import numpy as np
import pytest

from scipy.ndimage import gaussian_filter1d

import crank
from cgmstest import MAT
from cgms import morphology, tissue
from cgms.drying import transport

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
                                       lambda v, t_c: np.full_like(v, 1e-6))
    assert abs(tp - 34.2) < 2.5      # 34.2 C: the adiabatic-saturation balance by hand
    assert 0.01 < kc < 0.05 and 15 < h < 40


def pinned_column(layers, b, x_hi=5.94, x_lo=0.594, x0=5.94, d0=1e-9, thick=2e-3):
    """One column, no face and no outline in air, its first and last node held at x_hi and
    x_lo (solids 1e12 times the others: reservoirs), D = d0 exp(b (X/X0 - 1)), stepped
    with backward Euler steps 100 diffusion times long to the steady state (D is taken at
    the start of each step: the steps are Picard iterations). Returns the node centres
    (m), the moisture, the flow out of the wet reservoir in the last step (kg/s) and the
    grid."""
    area = 1e-8
    geo = dict(pairs=np.zeros((0, 2), int), dist=np.zeros(0), face=np.zeros(0),
               area=np.array([area]), edge=np.zeros(1), spacing=np.array([1e-4]))
    grid = transport.column_grid(geo, np.array([thick]), np.array([RHO_S * area * thick]),
                                 layers, faces=0)
    big = 1e12 * grid["solids"][0]
    grid["solids"][[0, -1]] = big
    x = np.linspace(x_hi, x_lo, layers)
    diff = lambda v: transport.diffusivity(v, 70.0, d0, 70.0, 5e4, b, x0)
    law = transport.linear_surface(0.0)
    dt = 100 * thick**2 / d0
    for _ in range(60):
        last = x
        x, *_ = transport.step(grid, x, dt, diff, law, outline=False)
    flow = big * (last[0] - x[0]) / dt
    z = (np.arange(layers) + 0.5) * grid["dz"][0]
    return z, x, flow, grid


@pytest.mark.parametrize("b", [3.0, -2.0])
def test_moisture_dependent_d_matches_kirchhoff(b):
    """Steady flow through a column whose D varies 15-fold (b = 3, X/X0 from 1 to 0.1) or
    falls the other way (b = -2): the profile and the flux match the Kirchhoff-transform
    solution, and converge at second order in the layer thickness (the face D is the
    arithmetic mean of the two nodes' D, a second-order approximation of the Kirchhoff
    mean; the D of either node alone is first order). Measured, 20 / 40 / 80 layers,
    b = 3: profile 2.9e-3 / 7.4e-4 / 1.9e-4 of X0, flux 2.9e-3 / 7.0e-4 / 1.7e-4;
    b = -2: profile 5.0e-4 / 1.2e-4 / 3.0e-5, flux 9.7e-4 / 2.3e-4 / 5.6e-5."""
    x0, d0 = 5.94, 1e-9
    errors = []
    for layers in (20, 40, 80):
        z, x, flow, grid = pinned_column(layers, b, x0=x0, d0=d0)
        span = z[-1] - z[0]
        exact = crank.kirchhoff_profile((z - z[0]) / span, x[0], x[-1], b, x0)
        flux = crank.kirchhoff_flux(x[0], x[-1], b, d0, span, x0) * RHO_S * 1e-8
        errors.append((np.abs(x - exact).max() / x0, abs(flow / flux - 1)))
    errors = np.array(errors)
    assert errors[0, 0] < 4e-3 and errors[0, 1] < 4e-3
    # second order: halving the layer thickness divides both errors by about 4
    assert np.all(errors[:-1] / errors[1:] > 3.5)
