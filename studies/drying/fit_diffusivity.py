# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Fit D_ref and D_energy of potentials/apple-drying.params to measured apple drying
(doc/results/drying.md, "Fitting the diffusivity"), like for like: the model dries a slice under
the measurement's conditions, and its drying curve is reduced by the slope method the
literature uses (Crank's slab series, first term: ln MR = ln(8/pi^2) - pi^2 D t / (4 l^2),
l the half thickness, a straight line fitted to ln MR over 1 >= MR >= 0.1). The model's
D_eff at the slice's temperature is adjusted (secant on its logarithm) until that apparent
D_eff equals the measured one; D_energy follows from the two temperatures and D_ref from
Arrhenius at T_ref = 70 C. Then it prints the model's drying times for the measured
conditions and for a 2 mm slice at 70 C, 1.5 m/s, with the fitted parameters.

Transport only (shape frozen, a window of a large slice: both faces in air, no outline),
on a 16-bead patch (the field is uniform in plane), 20 layers across the half thickness.
A few minutes on one core:

    /usr/bin/python3 studies/drying/fit_diffusivity.py
"""

import argparse
import math

import numpy as np

from cgms import drying, tissue
from cgms.drying import transport

R_GAS = transport.R_GAS
KELVIN = transport.KELVIN

#: measured effective diffusivities of apple slices (slope method), with the conditions
#: the abstracts give. Sacilik and Elicin (2006, J. Food Eng. 73, 281): organic apple
#: slices 5 and 9 mm thick, convective hot-air dryer at 40-60 C, D_eff from 2.27e-10 to
#: 4.97e-10 m^2/s. The abstract does not pair the values with temperatures or thicknesses;
#: here the lowest is taken at 40 C and the highest at 60 C (D_eff grows with temperature),
#: both on 5 mm slices. Air velocity and humidity are not in the abstract: 1.5 m/s and
#: 10 % are guesses (their effect is printed).
DATA = [
    dict(source="Sacilik and Elicin 2006", temperature=40.0, thickness=5e-3, d_eff=2.27e-10),
    dict(source="Sacilik and Elicin 2006", temperature=60.0, thickness=5e-3, d_eff=4.97e-10),
]
AIR = dict(velocity=1.5, humidity=0.1)
#: Sacilik and Elicin (2006): the slices "dry" within 240-460 min (all slices, 40-60 C);
#: the end moisture is not in the abstract, X/X0 = 0.1 is taken
MEASURED_HOURS = (240 / 60, 460 / 60)
LEVERS = dict(layers=20, dx_max=0.02, dt_max=1200.0)


def curve(params, temperature, thickness, velocity, humidity, stop=0.05, hours=60.0):
    """Drying curve (t in h, X/X0) of a slice, shape frozen, both faces in air."""
    xy = tissue.hex_rectangle(4, 4, 1.5e-4)
    cond = dict(temperature=temperature, thickness=thickness, velocity=velocity,
                humidity=humidity, outline=False, faces=2)
    rows = drying.dry(xy, params, cond, LEVERS, hours=hours, stop=stop)["rows"]
    return np.array([r["t_h"] for r in rows]), np.array([r["X/X0"] for r in rows])


def slope_method(t_h, mr, thickness, low=0.1, high=1.0):
    """Apparent D_eff (m^2/s) of a drying curve, as the slope method takes it: ln MR
    against t over high >= MR >= low, a least-squares line, D = -slope 4 l^2 / pi^2."""
    keep = (mr >= low) & (mr <= high)
    slope = np.polyfit(t_h[keep] * 3600.0, np.log(mr[keep]), 1)[0]
    return -slope * 4 * (thickness / 2) ** 2 / math.pi**2


def two_periods(params, velocities, temperature=60.0, thickness=5e-3, humidity=0.1):
    """The model's slope-method D_eff over the wet (1 >= MR >= 0.5) and the dry
    (0.5 >= MR >= 0.1) half of its curve, at each air velocity: what a study that fits
    two falling-rate periods separately (at 60 C, 5 mm, 0.64-2.75 m/s) would read from this model. With D constant the dry half reads larger because the
    wet slice sits near the wet-bulb temperature, where D is smaller (the heat balance);
    with the product at the air temperature it reads smaller (tests/
    test_fit_diffusivity_script.py)."""
    print(f"{temperature:.0f} C, {thickness * 1e3:.0f} mm, D_moisture {params['D_moisture']:g}:")
    print("| air velocity | D_eff, MR 1-0.5 | MR 0.5-0.1 | ratio | MR 1-0.1 |")
    print("|---|---|---|---|---|")
    for velocity in velocities:
        t, mr = curve(params, temperature, thickness, velocity, humidity)
        wet = slope_method(t, mr, thickness, low=0.5)
        whole = slope_method(t, mr, thickness)
        dry = slope_method(t, mr, thickness, high=0.5)
        print(f"| {velocity:g} m/s | {wet:.3g} | {dry:.3g} | {dry / wet:.2f} | "
              f"{whole:.3g} |", flush=True)


def d_at(params, temperature):
    """The model's D at fresh moisture (X/X0 = 1, where the moisture factor is 1)."""
    return float(transport.diffusivity(params["X0"], temperature, params["D_ref"],
                                       params["T_ref"], params["D_energy"]))


def with_d(params, temperature, d):
    """params with D_ref scaled so that D_eff(temperature) = d (D_energy kept)."""
    return dict(params, D_ref=params["D_ref"] * d / d_at(params, temperature))


def fit_one(params, datum, air):
    """The model D_eff at the datum's temperature whose apparent D_eff is the measured."""
    target = datum["d_eff"]
    d = [target, 2 * target]
    app = []
    for k in range(8):
        if k >= len(d):
            # secant in log-log: apparent ~ d^p near the answer
            p = math.log(app[-1] / app[-2]) / math.log(d[-1] / d[-2])
            d.append(d[-1] * (target / app[-1]) ** (1 / p))
        t, mr = curve(with_d(params, datum["temperature"], d[k]), datum["temperature"],
                      datum["thickness"], **air)
        app.append(slope_method(t, mr, datum["thickness"]))
        if abs(app[-1] / target - 1) < 2e-3:
            break
    return d[len(app) - 1], app[-1]


def fit(params, air, verbose=True):
    """D_energy and D_ref (at T_ref) whose model curves, read by the slope method, give
    the measured D_eff of DATA; D_moisture as in ``params``."""
    # the slice is below the air temperature while it is wet, so the fit at one
    # temperature depends on the activation energy: iterate to a fixed point
    energy = params["D_energy"]
    for _ in range(8):
        trial = dict(params, D_energy=energy)
        fitted = []
        for datum in DATA:
            d, app = fit_one(trial, datum, air)
            fitted.append(d)
            if verbose:
                print(f"  D_energy {energy / 1e3:.1f} kJ/mol: {datum['source']}, "
                      f"{datum['temperature']:.0f} C, {datum['thickness'] * 1e3:.0f} mm: model "
                      f"D_eff {d:.3g} m^2/s gives apparent {app:.3g} (measured "
                      f"{datum['d_eff']:.3g})")
        (ta, da), (tb, db) = [(x["temperature"] + KELVIN, d) for x, d in zip(DATA, fitted)]
        new_energy = R_GAS * math.log(db / da) / (1 / ta - 1 / tb)
        converged = abs(new_energy - energy) < 100.0
        energy = new_energy
        if converged:
            break
    d_ref = db * math.exp(-energy / R_GAS * (1 / (params["T_ref"] + KELVIN) - 1 / tb))
    return energy, d_ref


def times(params, temperature, thickness, air, levels=(0.5, 0.2, 0.1, 0.05)):
    """Model hours to each X/X0 level (nan where the run stops short)."""
    t, mr = curve(params, temperature, thickness, **air)
    return [float(np.interp(-lev, -mr, t)) if mr[-1] <= lev else float("nan")
            for lev in levels]


def outside(hours, low=MEASURED_HOURS[0], high=MEASURED_HOURS[1]):
    """ln of how far ``hours`` lies outside [low, high] (0 inside)."""
    return max(0.0, math.log(low / hours), math.log(hours / high))


def scan_moisture(params, air, values):
    """D_ref and D_energy refitted at every D_moisture in ``values``; the model's times to
    X/X0 = 0.1 against the measured window (MEASURED_HOURS) of 5 and 9 mm slices at 40
    and 60 C, and of the 2 mm slice at 70 C, 1.5 m/s, 10 % RH."""
    print("| D_moisture | D_wet/D_dry | D_ref (70 C) | D_energy | t(0.1) 5 mm 40 / 60 C | "
          "9 mm 40 / 60 C | misfit | 2 mm, 70 C: t(0.5) / t(0.1) |")
    print("|---|---|---|---|---|---|---|---|")
    for b in values:
        trial = dict(params, D_moisture=b)
        energy, d_ref = fit(trial, air, verbose=False)
        new = dict(trial, D_ref=d_ref, D_energy=energy)
        corner = [times(new, T, L, air, (0.1,))[0] for L in (5e-3, 9e-3) for T in (40.0, 60.0)]
        misfit = math.sqrt(sum(outside(h) ** 2 for h in corner) / len(corner))
        two = times(new, 70.0, 2e-3, dict(velocity=1.5, humidity=0.1), (0.5, 0.1))
        # D at X/X0 = 1 over D at X/X0 = 0.1 (the end of the measured curves)
        ratio = math.exp(0.9 * b)
        print(f"| {b:g} | {ratio:.3g} | {d_ref:.3g} | {energy / 1e3:.1f} kJ/mol | "
              f"{corner[0]:.2f} / {corner[1]:.2f} h | {corner[2]:.2f} / {corner[3]:.2f} h | "
              f"{misfit:.3f} | {two[0]:.3f} / {two[1]:.3f} h |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--velocity", type=float, default=AIR["velocity"])
    ap.add_argument("--humidity", type=float, default=AIR["humidity"])
    ap.add_argument("--thickness", type=float, help="slice thickness of the data (mm; "
                    "default: as in DATA)")
    ap.add_argument("--no-times", action="store_true", help="fit only, no drying times")
    ap.add_argument("--moisture", type=float, nargs="+", metavar="B",
                    help="refit at each D_moisture B and compare the drying times with the "
                         "measured window (the moisture scan of doc/drying.md)")
    ap.add_argument("--periods", type=float, nargs="+", metavar="V",
                    help="the model's slope-method D_eff over the wet and the dry half of "
                         "its 5 mm, 60 C curve at each air velocity V (m/s), with the file's "
                         "parameters: no fit")
    args = ap.parse_args()
    air = dict(velocity=args.velocity, humidity=args.humidity)
    if args.thickness:
        for datum in DATA:
            datum["thickness"] = args.thickness * 1e-3
    params = drying.read_params()
    print(f"air {air}; file: D_ref {params['D_ref']:.3g} at {params['T_ref']} C, "
          f"D_energy {params['D_energy'] / 1e3:.1f} kJ/mol, D_moisture {params['D_moisture']:g}")
    if args.periods:
        two_periods(params, args.periods, humidity=air["humidity"])
        return
    if args.moisture:
        scan_moisture(params, air, args.moisture)
        return
    for datum in DATA:
        t, mr = curve(params, datum["temperature"], datum["thickness"], **air)
        print(f"  file parameters, {datum['temperature']:.0f} C: apparent D_eff "
              f"{slope_method(t, mr, datum['thickness']):.3g} (measured {datum['d_eff']:.3g})")
    energy, d_ref = fit(params, air)
    print(f"fit: D_energy {energy / 1e3:.1f} kJ/mol, D_ref {d_ref:.3g} m^2/s at "
          f"{params['T_ref']} C")
    new = dict(params, D_ref=d_ref, D_energy=energy)
    if args.no_times:
        return
    print("| conditions | X/X0 = 0.5 | 0.2 | 0.1 | 0.05 |")
    print("|---|---|---|---|---|")
    runs = [(f"{T:.0f} C, {L * 1e3:.0f} mm, {air['velocity']} m/s", T, L, air)
            for L in (5e-3, 9e-3) for T in (40.0, 50.0, 60.0)]
    runs.append(("70 C, 2 mm, 1.5 m/s", 70.0, 2e-3, dict(velocity=1.5, humidity=0.1)))
    for name, T, L, a in runs:
        print(f"| {name} | " + " | ".join(f"{x:.2f} h" for x in times(new, T, L, a)) + " |")


if __name__ == "__main__":
    main()
