# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Hold ``python3 -m cgms dry`` against measured drying of apple (doc/drying-measured.md).

Runs ``cgms dry`` once per measured condition of reference/drying/ (one run at a time,
each into its own folder, reused when its drying.csv exists), then compares curve against
curve and shrinkage against shrinkage, and writes a table (CSV and Markdown) and a figure.

    source build/env.sh
    /usr/bin/python3 studies/measured_drying/compare.py            # run what is missing, compare
    /usr/bin/python3 studies/measured_drying/compare.py --no-run   # compare existing runs only

Runs, table and figure go to --out (default: <temp dir>/cgms-measured-drying, outside the
repository). What was FITTED (the diffusivity's source, Sacilik and Elicin 2006) is run and
tabled apart from what is only PREDICTED.
"""

import argparse
import csv
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REF = ROOT / "reference" / "drying"

# Royen et al. 2020: 50 C, 40-45 % RH (0.425 taken), 6 mm slices. A slice of a few cm
# whose interior the 2.0 x 2.5 mm tissue stands for: --no-outline (doc/drying.md).
ROYEN = "--temperature 50 --humidity 0.425 --thickness 6 --no-outline --hours 10 --stop 0.035"
RUNS = {
    "royen-v0.85": dict(kind="predicted", data="royen2020_T50_v0.85_RH40-45_6mm.csv",
                        args=f"{ROYEN} --velocity 0.85",
                        what="Royen et al. 2020, 50 C, 0.85 m/s, RH 40-45 %, 6 mm"),
    "royen-v1.1": dict(kind="predicted", data="royen2020_T50_v1.1_RH40-45_6mm.csv",
                       args=f"{ROYEN} --velocity 1.1",
                       what="Royen et al. 2020, 50 C, 1.1 m/s, RH 40-45 %, 6 mm"),
    # the CGMS paper's own experiment: 2 mm pieces of 1.5 x 1.5 mm, outline in air, at
    # 70 C and 1.5 m/s; humidity not stated (0.1, the CLI's default)
    "paper-piece": dict(kind="predicted", data=None,
                        args="--temperature 70 --humidity 0.1 --velocity 1.5 --thickness 2 "
                             "--width 1.5 --height 1.5 --hours 2 --stop 0.05",
                        what="Wijerathne et al. 2019 experiment: 1.5 x 1.5 x 2 mm piece, 70 C, "
                             "1.5 m/s"),
    "paper-window": dict(kind="predicted", data=None,
                         args="--temperature 70 --humidity 0.1 --velocity 1.5 --thickness 2 "
                              "--no-outline --hours 3 --stop 0.05",
                         what="the same air, interior of a 2 mm slice (--no-outline)"),
    # the fitted source: 5 mm slices at 40 and 60 C under the fit's assumed air
    "sacilik-40": dict(kind="fitted", data=None,
                       args="--temperature 40 --humidity 0.1 --velocity 1.5 --thickness 5 "
                            "--no-outline --hours 14 --stop 0.05",
                       what="Sacilik and Elicin 2006 (fitted), 40 C, 5 mm, assumed 1.5 m/s"),
    "sacilik-60": dict(kind="fitted", data=None,
                       args="--temperature 60 --humidity 0.1 --velocity 1.5 --thickness 5 "
                            "--no-outline --hours 8 --stop 0.05",
                       what="Sacilik and Elicin 2006 (fitted), 60 C, 5 mm, assumed 1.5 m/s"),
}
# Sacilik and Elicin 2006: every slice "dry" within 240-460 min (what "dry" means is not
# stated; the table gives the model's time to X/X0 = 0.1 and 0.05 beside it)
SACILIK_WINDOW_H = (240 / 60, 460 / 60)
# Khama et al. 2018, oven 50-70 C, end of drying (X/X0 not stated): stated V/V0, L/L0 and
# the face-area ratio derived from the stated diameter ratio
KHAMA = dict(V=0.20, L=0.30, A=0.80 ** 2)
# Wijerathne et al. 2019, section 4.3: A/A0 at X/X0 = 0.3 deviates from the experiment by
# 15-24 % (CGMS); the moisture-domain CGMS A/A0 at s = 0.3 of these tissues is 0.705-0.711
# (doc/validation.md); with the model above the experiment the measured A/A0 was
# A_model / (1 + e): an inference, not a reading
PAPER_ERROR = (0.15, 0.24)
PAPER_MODEL_A03 = (0.705, 0.711)


def read_table(path):
    """Columns of a CSV with '#' comment lines, as float arrays keyed by header name."""
    lines = [line for line in Path(path).read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    rows = list(csv.reader(lines))
    cols = {}
    for j, name in enumerate(rows[0]):
        try:
            cols[name] = np.array([float(r[j]) for r in rows[1:]])
        except ValueError:
            cols[name] = [r[j] for r in rows[1:]]
    return cols


def read_measured(name):
    """(t in h, X in kg/kg) of a measured curve, in time order (stable for ties)."""
    d = read_table(REF / name)
    t, x = d["time_min"] / 60, d["X_kg_per_kg_db"]
    order = np.argsort(t, kind="stable")
    return t[order], x[order]


def x0_extrapolated(t, x, window_h=35 / 60):
    """X at t = 0 from a straight line through the points of the first ``window_h``."""
    m = t <= window_h
    return float(np.polyval(np.polyfit(t[m], x[m], 1), 0.0))


def crossing(t, y, level):
    """First time at which ``y`` falls to ``level`` (linear between points), or None."""
    below = np.nonzero(y <= level)[0]
    if len(below) == 0 or below[0] == 0:
        return None
    i = below[0]
    return float(t[i - 1] + (y[i - 1] - level) / (y[i - 1] - y[i]) * (t[i] - t[i - 1]))


def initial_rate(t, y, span_h=1.0):
    """-dy/dt (1/h) of a straight line through the points of the first ``span_h``."""
    m = t <= t[0] + span_h
    return float(-np.polyfit(t[m], y[m], 1)[0])


def compare_curve(t_data, mr_data, t_model, mr_model):
    """RMS and largest |model - data| of MR at the data times the model covers, the
    number of those points, the times to MR 0.5 and 0.1 of each, and the initial drying
    rate of each over the first hour after the first measured time."""
    covered = t_data <= t_model[-1]
    diff = np.interp(t_data[covered], t_model, mr_model) - mr_data[covered]
    t_m = np.concatenate([[t_data[0]], t_model[t_model > t_data[0]]])
    rate_model = initial_rate(t_m, np.interp(t_m, t_model, mr_model))
    return dict(rms=float(np.sqrt(np.mean(diff ** 2))), largest=float(np.max(np.abs(diff))),
                rate_data=initial_rate(t_data, mr_data), rate_model=rate_model,
                signed_at_largest=float(diff[np.argmax(np.abs(diff))]),
                n=int(covered.sum()), n_all=len(t_data),
                t05_data=crossing(t_data, mr_data, 0.5), t05_model=crossing(t_model, mr_model, 0.5),
                t01_data=crossing(t_data, mr_data, 0.1), t01_model=crossing(t_model, mr_model, 0.1))


def run_dry(name, spec, out, extra=()):
    """``python3 -m cgms dry`` for one condition into out/name (skipped when done)."""
    folder = out / name
    if (folder / "drying.csv").exists():
        return folder
    if folder.exists() and any(folder.iterdir()):
        sys.exit(f"compare.py: {folder} holds an unfinished run; remove it and run again")
    cmd = [sys.executable, "-m", "cgms", "dry", *shlex.split(spec["args"]), *extra, "--maps", "0.3",
           "--out", str(folder)]
    print("$", " ".join(cmd[1:]), flush=True)
    done = subprocess.run(cmd)
    if done.returncode != 0:
        sys.exit(f"compare.py: cgms dry failed for {name} (exit {done.returncode}); "
                 f"command: {' '.join(cmd[1:])}")
    return folder


def model_rows(folder):
    """The columns of a ``cgms dry`` run's drying.csv."""
    return read_table(folder / "drying.csv")


def at_level(d, level, key):
    """``key`` of a run where its X/X0 first falls to ``level`` (linear), or None."""
    x, y = d["X/X0"], d[key]
    t = crossing(np.arange(len(x), dtype=float), x, level)
    if t is None:
        return None
    i = int(np.floor(t))
    return float(y[i] + (t - i) * (y[min(i + 1, len(y) - 1)] - y[i]))


def curve_table(out):
    """One row per measured curve: both normalisations of the measured X/X0."""
    rows = []
    for name, spec in RUNS.items():
        if spec["data"] is None:
            continue
        d = model_rows(out / name)
        t_m, mr_m = d["t_h"], d["X/X0"]
        t, x = read_measured(spec["data"])
        # (a) both curves relative to their value at the first measured time: no X0 needed
        ref_m = float(np.interp(t[0], t_m, mr_m))
        a = compare_curve(t, x / x[0], t_m, mr_m / ref_m)
        # (b) the measured X0 extrapolated to t = 0; the model as it is
        x0 = x0_extrapolated(t, x)
        b = compare_curve(t, x / x0, t_m, mr_m)
        rows.append(dict(name=name, kind=spec["kind"], what=spec["what"], x0_first=float(x[0]),
                         t_first_min=float(t[0] * 60), x0_extrapolated=x0, first=a,
                         extrapolated=b))
    return rows


def fitted_table(out):
    rows = []
    for name, spec in RUNS.items():
        if spec["kind"] != "fitted":
            continue
        d = model_rows(out / name)
        rows.append(dict(name=name, what=spec["what"], t05=crossing(d["t_h"], d["X/X0"], 0.5),
                         t01=crossing(d["t_h"], d["X/X0"], 0.1),
                         t005=crossing(d["t_h"], d["X/X0"], 0.05)))
    return rows


LEVELS = (0.8, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1)

# Velic et al. 2004 (secondary, reference/drying/velic2004_secondary_heat_transfer.csv):
# 60 C, 20 x 20 x 5 mm samples; the model's heat-transfer coefficient at the CLI's default
# plate length and at the samples' own length
VELIC_T, VELIC_PLATES = 60.0, (0.040, 0.020)


def air_side_table():
    """The model's h (cgms.transport.air_coefficients) beside Velic et al.'s at 0.64 and
    2.75 m/s."""
    sys.path.insert(0, str(ROOT / "python"))
    from cgms import transport

    d = read_table(REF / "velic2004_secondary_heat_transfer.csv")
    measured = dict(zip(d["quantity"], zip(d["at_0.64_m_per_s"], d["at_2.75_m_per_s"])))["h"]
    rows = []
    for v, h_measured in zip((0.64, 2.75), measured):
        h_model = [transport.air_coefficients(VELIC_T, v, plate)[1] for plate in VELIC_PLATES]
        rows.append(dict(v=v, measured=h_measured, model=h_model))
    return rows


def shrinkage_table(out):
    rows = []
    for name in ("paper-piece", "paper-window", "royen-v1.1"):
        d = model_rows(out / name)
        for level in LEVELS:
            a = at_level(d, level, "A/A0")
            if a is None:
                continue
            rows.append(dict(name=name, level=level, A=a, P=at_level(d, level, "P/P0"),
                             EL=at_level(d, level, "EL/EL0"), L=np.sqrt(a), V=a ** 1.5))
    return rows


def fmt(v, digits=2):
    return "-" if v is None else f"{v:.{digits}f}"


def write_tables(out, curves, fitted, shrink, air):
    lines = ["## Drying curves: predicted (measured X/X0 and model X/X0 both taken relative "
             "to the first measured time)", "",
             "| condition | kind | first-hour rate measured / model (1/h) "
             "| t(0.5) measured / model (h) | t(0.1) measured / model (h) "
             "| RMS | largest (model - measured) | points compared |",
             "|---|---|---|---|---|---|---|---|"]
    for r in curves:
        a = r["first"]
        lines.append(f"| {r['what']} | {r['kind']} | {a['rate_data']:.3f} / {a['rate_model']:.3f} "
                     f"| {fmt(a['t05_data'])} / {fmt(a['t05_model'])} "
                     f"| {fmt(a['t01_data'])} / {fmt(a['t01_model'])} | {a['rms']:.3f} "
                     f"| {a['signed_at_largest']:+.3f} | {a['n']} of {a['n_all']} |")
    lines += ["", "Sensitivity: measured X0 extrapolated to t = 0 (straight line over the first "
              "35 min), model X/X0 as run:", "",
              "| condition | X first (t) | X0 extrapolated | t(0.5) measured / model | "
              "t(0.1) measured / model | RMS | largest |", "|---|---|---|---|---|---|---|"]
    for r in curves:
        b = r["extrapolated"]
        lines.append(f"| {r['name']} | {r['x0_first']:.3f} ({r['t_first_min']:.1f} min) "
                     f"| {r['x0_extrapolated']:.3f} | {fmt(b['t05_data'])} / {fmt(b['t05_model'])} "
                     f"| {fmt(b['t01_data'])} / {fmt(b['t01_model'])} | {b['rms']:.3f} "
                     f"| {b['signed_at_largest']:+.3f} |")
    lines += ["", "## Fitted source (Sacilik and Elicin 2006): all slices 'dry' within "
              f"{SACILIK_WINDOW_H[0]:.2f}-{SACILIK_WINDOW_H[1]:.2f} h", "",
              "| run | t(0.5) h | t(0.1) h | t(0.05) h |", "|---|---|---|---|"]
    for r in fitted:
        lines.append(f"| {r['what']} | {fmt(r['t05'])} | {fmt(r['t01'])} | {fmt(r['t005'])} |")
    lo = PAPER_MODEL_A03[0] / (1 + PAPER_ERROR[1])
    hi = PAPER_MODEL_A03[1] / (1 + PAPER_ERROR[0])
    lines += ["", "## Shrinkage (model; L/L0 = sqrt(A/A0) and V/V0 = (A/A0)^1.5 are the "
              "model's isotropic-thickness assumption)", "",
              "| run | X/X0 | A/A0 | P/P0 | EL/EL0 | L/L0 | V/V0 |",
              "|---|---|---|---|---|---|---|"]
    for r in shrink:
        lines.append(f"| {r['name']} | {r['level']:.1f} | {r['A']:.3f} | {r['P']:.3f} "
                     f"| {r['EL']:.3f} | {r['L']:.3f} | {r['V']:.3f} |")
    lines += ["", "Measured: Khama et al. 2018, oven 50-70 C, end of drying (X/X0 not stated): "
              f"A/A0 {KHAMA['A']:.2f} (from D/D0 0.80), L/L0 {KHAMA['L']:.2f}, "
              f"V/V0 {KHAMA['V']:.2f}.",
              f"Inferred from Wijerathne et al. 2019 (15-24 % above experiment at X/X0 = 0.3): "
              f"measured A/A0 at 0.3 about {lo:.2f}-{hi:.2f}."]
    lines += ["", "## Air side: h against Velic et al. 2004 (secondary; 60 C, 20 mm samples)", "",
              "| air velocity (m/s) | h measured (W/m^2 K) | model, 40 mm plate | "
              "model, 20 mm plate |", "|---|---|---|---|"]
    for r in air:
        lines.append(f"| {r['v']:.2f} | {r['measured']:.1f} | {r['model'][0]:.1f} "
                     f"| {r['model'][1]:.1f} |")
    text = "\n".join(lines) + "\n"
    (out / "comparison.md").write_text(text)
    with open(out / "comparison.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["condition", "kind", "normalisation", "rate_measured_per_h",
                    "rate_model_per_h", "t05_measured_h", "t05_model_h",
                    "t01_measured_h", "t01_model_h", "rms", "largest_signed", "points"])
        for r in curves:
            for key in ("first", "extrapolated"):
                c = r[key]
                w.writerow([r["name"], r["kind"], key, f"{c['rate_data']:.4f}",
                            f"{c['rate_model']:.4f}", *(fmt(c[k], 3) for k in (
                                "t05_data", "t05_model", "t01_data", "t01_model")),
                            f"{c['rms']:.4f}",
                            f"{c['signed_at_largest']:.4f}", c["n"]])
    return text


def figure(out, curves, path):
    sys.path.insert(0, str(ROOT / "python"))
    from cgms import plots  # noqa: F401  (selects the non-interactive backend)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(14, 4.3), constrained_layout=True)
    colours = dict(zip(("royen-v0.85", "royen-v1.1"), ("C0", "C1")))
    for r in curves:
        spec = RUNS[r["name"]]
        t, x = read_measured(spec["data"])
        d = model_rows(out / r["name"])
        ref_m = float(np.interp(t[0], d["t_h"], d["X/X0"]))
        c = colours.get(r["name"], "C2")
        v = r["what"].split(", ")[2]
        ax[0].plot(t, x / x[0], ".", ms=3, color=c, label=f"measured, {v}")
        ax[0].plot(d["t_h"], d["X/X0"] / ref_m, "-", color=c, label=f"cgms dry, {v}")
        covered = t <= d["t_h"][-1]
        ax[1].plot(t[covered], np.interp(t[covered], d["t_h"], d["X/X0"] / ref_m)
                   - x[covered] / x[0], "-", color=c, label=v)
    ax[0].set(xlabel="t (h)", ylabel="X/X0 (relative to the first measured time)",
              title="Royen et al. 2020: 50 C, RH 40-45 %, 6 mm (predicted)")
    ax[0].legend(fontsize=7)
    ax[1].axhline(0, color="k", lw=0.5)
    ax[1].set(xlabel="t (h)", ylabel="model - measured X/X0", title="difference")
    ax[1].legend(fontsize=7)
    names = dict([("paper-piece", "1.5 x 1.5 mm piece, 70 C (paper's experiment)"),
                  ("paper-window", "2 mm slice interior, 70 C"),
                  ("royen-v1.1", "6 mm slice interior, 50 C, 1.1 m/s")])
    for name, label in names.items():
        d = model_rows(out / name)
        ax[2].plot(d["X/X0"], d["A/A0"], label=f"cgms dry A/A0: {label}")
    d = model_rows(out / "paper-window")
    ax[2].plot(d["X/X0"], d["A/A0"] ** 1.5, ":", color="C1",
               label="model V/V0 = (A/A0)^1.5, 2 mm slice interior")
    ax[2].plot(d["X/X0"], d["A/A0"] ** 0.5, "--", color="C1",
               label="model L/L0 = (A/A0)^0.5, 2 mm slice interior")
    lo = PAPER_MODEL_A03[0] / (1 + PAPER_ERROR[1])
    hi = PAPER_MODEL_A03[1] / (1 + PAPER_ERROR[0])
    ax[2].errorbar([0.3], [(lo + hi) / 2], yerr=[[(hi - lo) / 2]], fmt="s", color="k",
                   capsize=3, label="A/A0 inferred from the paper's 15-24 % (X/X0 0.3)")
    ax[2].hlines([KHAMA["A"], KHAMA["V"]], 0.0, 0.15, colors=["C3", "C4"], lw=3,
                 label=None)
    # the axis is inverted: ha="right" puts the text on the wet side of the bar
    ax[2].text(0.17, KHAMA["A"], "Khama 2018, end of drying: face area (D/D0)^2", fontsize=7,
               va="center", ha="right", color="C3")
    ax[2].text(0.17, KHAMA["V"], "Khama 2018, end: V/V0 (X/X0 not stated)", fontsize=7,
               va="center", ha="right", color="C4")
    ax[2].hlines([KHAMA["L"]], 0.0, 0.15, colors=["C5"], lw=3)
    ax[2].text(0.17, KHAMA["L"], "Khama 2018, end: thickness L/L0", fontsize=7, va="center",
               ha="right", color="C5")
    ax[2].axvline(0.6, color="grey", ls="--", lw=0.8)
    ax[2].text(0.61, 0.97, "paper: models part\nfrom experiment below", fontsize=7, va="top")
    ax[2].set(xlabel="X/X0", ylabel="ratio to fresh", xlim=(1.02, 0), ylim=(0, 1.05),
              title="shrinkage against moisture")
    ax[2].legend(fontsize=6, loc="lower left", bbox_to_anchor=(0.0, 0.3))
    for a in ax:
        a.grid(alpha=0.3)
    fig.savefig(path, dpi=85)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()) / "cgms-measured-drying",
                   help="folder of the runs, table and figure (default %(default)s)")
    p.add_argument("--no-run", action="store_true", help="compare existing runs only")
    p.add_argument("--only", nargs="*", choices=sorted(RUNS), help="run only these conditions")
    p.add_argument("--figure", type=Path, help="figure path (default OUT/measured-drying.png)")
    p.add_argument("--frozen", action="store_true",
                   help="run every condition with the shape frozen (cgms dry --frozen: transport "
                        "only); use another --out")
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if not args.no_run:
        for name in args.only or RUNS:
            run_dry(name, RUNS[name], args.out, ("--frozen",) if args.frozen else ())
    missing = [n for n in RUNS if not (args.out / n / "drying.csv").exists()]
    if missing:
        how = "run without --only" if args.only else "run without --no-run"
        sys.exit(f"compare.py: no drying.csv for {', '.join(missing)} in {args.out}; the "
                 f"comparison needs every run ({how})")
    curves, fitted = curve_table(args.out), fitted_table(args.out)
    shrink = shrinkage_table(args.out)
    print(write_tables(args.out, curves, fitted, shrink, air_side_table()))
    path = args.figure or args.out / "measured-drying.png"
    figure(args.out, curves, path)
    print(f"compare.py: table {args.out / 'comparison.md'}, {args.out / 'comparison.csv'}; "
          f"figure {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
