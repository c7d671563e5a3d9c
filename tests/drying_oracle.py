# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The test oracle of ``cgms dry``: the moisture loop in Python (:mod:`cgms.transport`, the
equations of ``fix cgms/transport`` written as plain functions on arrays), stepped as
``fix cgms/transport`` steps, coupled to the same :class:`cgms.drying.Mechanics`.

It was the production loop of ``cgms dry`` until the fix became its engine (issue 28);
the tests hold the fix-driven :func:`cgms.drying.dry` to it. Besides the engine it
has one switch of its own: ``transport_geometry`` False keeps the transport on the fresh
geometry while the mechanics moves (the moisture-domain check)."""

import time

import numpy as np

from cgms import drying, morphology
from cgms.drying import transport


def dry(xy, params, conditions=None, levers=None, hours=4.0, stop=0.0, mechanics=None,
        snapshots=(), on_snapshot=None, transport_geometry=True, rows=None):
    """Dry the tissue whose fresh bead positions (id order) are ``xy`` for ``hours`` or
    until its X/X0 falls to ``stop``. ``mechanics``: a :class:`Mechanics` (None: the shape
    is frozen). ``snapshots``: X/X0 levels; when the tissue first reaches one,
    ``on_snapshot(level, row, state)`` is called (``state``: positions and each bead's mean,
    surface and core X/X0).
    ``transport_geometry`` False keeps the transport geometry of the fresh tissue while the
    mechanics moves (an ingredient switch, and the moisture-domain check).
    The run also ends when the tissue's X/X0 comes within :data:`drying.EQUILIBRIUM_GAP` of the
    air's equilibrium moisture (:func:`equilibrium_ratio`), which a lower ``stop`` never
    reaches. ``rows``: a list the records are appended to as they are made, so that a
    caller keeps the records so far when the run stops with an error.
    Returns dict(rows=[...], x=node moisture, grid=..., xy=positions, balance=...,
    ended="stop", "equilibrium" or "hours", equilibrium=the air's X/X0, halved=how many
    moisture steps were halved to keep the moisture non-negative)."""
    cond = dict(drying.CONDITIONS, **(conditions or {}))
    lev = dict(drying.LEVERS, **(levers or {}))
    x0 = params["X0"]
    gab = (params["GAB_Xm"], params["GAB_C"], params["GAB_K"])
    kc, h = transport.air_coefficients(cond["temperature"], cond["velocity"],
                                       cond["plate_length"])
    n = len(xy)
    if mechanics is not None:
        xy = mechanics.solve(np.ones(n))          # the fresh steady state: the reference
    fresh = morphology.measures(xy)
    geo = drying.bead_geometry(xy)
    area0 = geo["area"].copy()
    thick0 = np.full(n, cond["thickness"])
    solids = params["solids_density"] * area0 * thick0
    grid = transport.column_grid(geo, thick0, solids, lev["layers"], cond["faces"])
    x = np.full(n * lev["layers"], x0)
    water0 = transport.water(grid, x)
    s_solved = np.ones(n)
    t, dt, out_face, out_edge = 0.0, lev["dt_first"], 0.0, 0.0
    rows = [] if rows is None else rows
    pending = sorted(snapshots, reverse=True)
    start = time.perf_counter()

    def record(rate):
        mean, surf, core = transport.bead_moisture(grid, x)
        shape = morphology.normalise(morphology.measures(xy), fresh)
        w = transport.water(grid, x)
        row = {"t_h": t / 3600, "X/X0": w / water0, "rate_per_h": rate,
               "surface_X/X0": float(np.average(surf, weights=solids)) / x0,
               "core_X/X0": float(np.average(core, weights=solids)) / x0,
               "T_product": t_product, **shape,
               "out_faces_kg": out_face, "out_outline_kg": out_edge,
               "balance": (water0 - w - out_face - out_edge) / water0,
               "solves": mechanics.solves if mechanics else 0,
               "seconds": time.perf_counter() - start}
        row["case_hardening"] = row["core_X/X0"] - row["surface_X/X0"]
        rows.append(row)
        return row, dict(xy=xy, s=mean / x0, surface=surf / x0, core=core / x0)

    def diffusivity(v, t_c):
        return transport.diffusivity(v, t_c, params["D_ref"], params["T_ref"],
                                     params["D_energy"], params["D_moisture"], x0)

    def temperature(v):
        if not cond["heat"]:
            return cond["temperature"]
        return transport.product_temperature(kc, h, cond["temperature"], cond["humidity"],
                                             gab, grid, v, diffusivity, cond["outline"])

    def coefficients(v):
        """D and the surface law at node moisture ``v``, at its product temperature."""
        tp = temperature(v)
        return (lambda u: diffusivity(u, tp),
                transport.vapour_surface(kc, tp, cond["temperature"], cond["humidity"], gab))

    t_product = temperature(x)
    record(0.0)
    t_end = hours * 3600
    x_eq = drying.equilibrium_ratio(params, cond["humidity"])
    halved = 0
    while t < t_end - 1e-9 and rows[-1]["X/X0"] > max(stop, x_eq + drying.EQUILIBRIUM_GAP):
        dt = min(dt, t_end - t)
        t_product = temperature(x)        # the output: at the start of the step
        before = transport.water(grid, x)
        x_new, face, edge, dt, cut = positive_step(grid, x, dt, coefficients, cond["outline"])
        halved += cut
        change = np.abs(x_new - x).max() / x0
        x = x_new
        t += dt
        out_face += face
        out_edge += edge
        rate = (before - transport.water(grid, x)) / water0 / (dt / 3600)
        dt = min(lev["dt_max"], dt * min(2.0, lev["dx_max"] / max(change, 1e-12)))
        s = np.clip(transport.bead_moisture(grid, x)[0] / x0, lev["s_min"], 1.0)
        if mechanics is not None and drying.resolve_due(s, s_solved, lev["resolve"],
                                                        lev["trigger"]):
            _, surf, core = transport.bead_moisture(grid, x)
            xy = mechanics.solve(s, surf / x0, core / x0)
            s_solved = s
            if transport_geometry:
                geo = drying.bead_geometry(xy)
                thick = thick0 * np.sqrt(geo["area"] / area0) if cond["shrink_thickness"] \
                    else thick0
                grid = transport.column_grid(geo, thick, solids, lev["layers"], cond["faces"])
        row, state = record(rate)
        while pending and row["X/X0"] <= pending[0]:
            level = pending.pop(0)
            if on_snapshot:
                on_snapshot(level, row, state)
    ended = "stop" if rows[-1]["X/X0"] <= stop else \
        "equilibrium" if rows[-1]["X/X0"] <= x_eq + drying.EQUILIBRIUM_GAP else "hours"
    return dict(rows=rows, x=x, grid=grid, xy=xy, water0=water0, kc=kc, h=h,
                seconds=time.perf_counter() - start, ended=ended, equilibrium=x_eq,
                halved=halved)


def positive_step(grid, x, dt, coefficients, outline):
    """:func:`cgms.drying.transport.extrapolated_step` of at most ``dt``, halved until
    every node's moisture stays finite and non-negative at its midpoint and its end: the
    surface law is linearised at the start of each Euler step, and while the surface
    holds free water (aw = 1) it is a constant flux, which a long step draws past the
    water the surface nodes hold (measured with dx_max 1 and no heat: the faces' mean
    X/X0 at -0.15). Returns (x, out through faces, out through the outline, the step
    taken, how often it was halved); RuntimeError after :data:`drying.MAX_HALVINGS`."""
    for cut in range(drying.MAX_HALVINGS + 1):
        x_new, face, edge, mid = transport.extrapolated_step(grid, x, dt, coefficients,
                                                             outline=outline)
        if all(np.all(np.isfinite(v)) and v.min() >= 0 for v in (mid, x_new)):
            return x_new, face, edge, dt, cut
        dt *= 0.5
    raise RuntimeError(f"no moisture step keeps every node's moisture finite and "
                       f"non-negative, down to {2 * dt:.3g} s")
