#!/usr/bin/env python3
# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Cost per bead-step of CGMS (pair_style cgms + fix cgms/fluid) against pair_style lj/cut.

Timing mode (default): one LAMMPS process runs, for every tissue size, the CGMS case
(bench/in.cgms, "A") and the lj/cut case (bench/in.ljcut, "B") on the same bead positions,
cutoff, skin, integrator fixes and step count, interleaved A/B/A/B... separated by
`clear`, so machine noise hits both. LAMMPS's own timing breakdown (Pair, Neigh, Comm,
Modify, Other) and the loop time of every run are parsed from the log and divided by
beads x steps.

Callgrind mode (--callgrind): one small run of each case under
`valgrind --tool=callgrind`, collecting inside Verlet::run only (the MD loop: no start-up,
no set-up); callgrind_annotate gives the instructions (Ir) of the CGMS pair kernel
(PairCGMS::eval<...>), of fix cgms/fluid (pre_force, update_fluid_state, end_of_step or
transfer_mass, whichever the build has) and of PairLJCut::compute, divided by
beads x steps. Call counts come from the callgrind output file itself.

Outputs go to --out (default /tmp/cgms-bench), never into the repository:
  runs.csv       one row per timed run
  summary.csv    medians per size and case, and median A/B ratios of interleaved pairs
  callgrind.csv  instructions per bead-step per function (with --callgrind)
  meta.json      machine, LAMMPS, plugin checksum, git state, parameters
plus the LAMMPS inputs, logs and callgrind files.

The tissues are hexagonal patches at the equilibrium spacing of the CGMS tissue at the
chosen dryness (found by a short relaxation run first, see equilibrium_spacing), so both
cases run near rest; lj/cut gets sigma = spacing / 2^(1/6) so its minimum sits on the
lattice, and the cutoff 1.35 x_ref of pair cgms.

Usage (after `source build/env.sh`):
  /usr/bin/python3 bench/run_bench.py                      # timing, 1k and 20k beads
  /usr/bin/python3 bench/run_bench.py --callgrind --no-timing
"""

import argparse
import csv
import hashlib
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(REPO / "python"))

from cgms import material, tissue  # noqa: E402

SECTIONS = ("Pair", "Neigh", "Comm", "Output", "Modify", "Other")
MIB = 1024 * 1024  # LAMMPS's "Mbytes"
CUTOFF_XREF = 1.35  # CGMS default cutoff in units of x_ref (src/CGMS/pair_cgms.cpp)


# ----------------------------------------------------------------------------- set-up


def parse_size(text):
    m = re.fullmatch(r"(\d+)x(\d+)", text)
    if not m:
        raise argparse.ArgumentTypeError(f"size {text!r} is not NCOLSxNROWS, e.g. 33x30")
    return int(m.group(1)), int(m.group(2))


def case_vars(args, mat, plugin, spacing):
    """LAMMPS variables shared by both cases (the data file and steps are added per run).
    ``spacing`` is the lattice spacing (m): the lj/cut minimum 2^(1/6) sigma sits on it."""
    x_ref = mat["x_ref"]
    return {
        "plugin": str(plugin),
        "material": str(material.find(args.material)),
        "dryness": repr(args.dryness),
        "skin": repr(args.skin),
        "dt": repr(args.dt),
        "cut": repr(CUTOFF_XREF * x_ref),
        "eps": repr(args.lj_epsilon),
        "sigma": repr(spacing / 2 ** (1 / 6)),
        "mass": repr((1 + mat["solid_ratio"]) * mat["rho0"] * mat["height"] * mat["A_ref"]),
    }


def write_tissue(out, ncols, nrows, spacing, x_ref, prefix="tissue"):
    """Same positions in two data files: atom_style cgms (A) and atomic (B); hexagonal
    lattice with the given spacing, box margin 3 x_ref."""
    xy = tissue.hex_rectangle(ncols, nrows, spacing)
    a = out / f"{prefix}_{ncols}x{nrows}.cgms.data"
    n = tissue.write_data(a, xy, 3 * x_ref, title=f"CGMS bench {ncols}x{nrows}", overwrite=True)
    b = out / f"{prefix}_{ncols}x{nrows}.atomic.data"
    b.write_text(a.read_text().replace("Atoms # cgms", "Atoms # atomic"))
    return n, a, b


def lmp_command(args, nproc):
    if nproc > 1:
        return [args.mpirun, "-np", str(nproc), args.lmp]
    return [args.lmp]


def child_env():
    env = dict(os.environ)
    # the plugin is loaded explicitly (a snapshot, see main); no autoload on top
    env.pop("LAMMPS_PLUGIN_PATH", None)
    env.setdefault("OMP_NUM_THREADS", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    return env


# ----------------------------------------------------------------------------- spacing


def equilibrium_spacing(args, mat, plugin, out, meta):
    """Lattice spacing of a CGMS tissue at rest at the benchmark dryness: relax a small
    patch built at x_ref, then take the median nearest-neighbour distance of its inner
    half (the edges carry the periphery correction). Starting every benchmark tissue at
    this spacing avoids the contraction (s = 0.3) or inflation (s = 1) transient of a tissue
    built at x_ref, which for 20 000 beads ends in an unstable mass transfer (s = 0.3) or
    lost atoms (s = 1) within 2 500 steps of dt = 1e-7 s."""
    import numpy as np

    x_ref = mat["x_ref"]
    ncols, nrows = args.relax_size
    _, data, _ = write_tissue(out, ncols, nrows, x_ref, x_ref, prefix="relax")
    dump = out / "relax.dump"
    script = out / "relax.in"
    var = dict(case_vars(args, mat, plugin, x_ref), data=str(data), steps=str(args.relax_steps))
    lines = [f'variable {k} string "{v}"' for k, v in var.items()]
    lines += [f"include {HERE / 'in.cgms'}",
              f"write_dump all custom {dump} id x y modify sort id"]
    script.write_text("\n".join(lines) + "\n")
    cmd = lmp_command(args, 1) + ["-in", str(script), "-log", str(out / "relax.log"),
                                  "-screen", "none"]
    print("relaxing:", " ".join(cmd), flush=True)
    res = subprocess.run(cmd, env=child_env(), cwd=out)
    if res.returncode != 0:
        sys.exit(f"relaxation run failed (exit {res.returncode}); see {out / 'relax.log'}")
    xy = np.loadtxt(dump, skiprows=9)[:, 1:3]
    centre = 0.5 * (xy.max(axis=0) + xy.min(axis=0))
    half = 0.5 * (xy.max(axis=0) - xy.min(axis=0))
    inner = xy[np.all(np.abs(xy - centre) < 0.5 * half, axis=1)]
    d = np.sqrt(((inner[:, None, :] - xy[None, :, :]) ** 2).sum(axis=-1))
    nn = d[(d > 0) & (d < 1.25 * x_ref)]
    spacing = float(np.median(nn))
    meta["relax"] = dict(size=f"{ncols}x{nrows}", steps=args.relax_steps, inner_beads=len(inner),
                         nn_per_inner_bead=len(nn) / len(inner),
                         nn_min_xref=float(nn.min() / x_ref), nn_max_xref=float(nn.max() / x_ref),
                         spacing_xref=spacing / x_ref)
    print(f"equilibrium spacing at dryness {args.dryness}: {spacing / x_ref:.4f} x_ref "
          f"({nn.min() / x_ref:.4f}-{nn.max() / x_ref:.4f} over {len(inner)} inner beads)")
    return spacing


# ----------------------------------------------------------------------------- timing


def driver_script(runs, common):
    """One LAMMPS input: every run re-defines its variables, prints a marker and includes
    the case input; `clear` between runs (variables survive clear, the plugin does not,
    so each case input loads it again)."""
    lines = ["# generated by bench/run_bench.py: interleaved CGMS (A) / lj/cut (B) runs", ""]
    for name, value in common.items():
        lines.append(f'variable {name} string "{value}"')
    for k, run in enumerate(runs):
        lines += [
            "",
            "clear" if k else "# first run",
            f'variable data string "{run["data"]}"',
            f"variable steps string {run['steps']}",
            f'print "BENCH-RUN {run["label"]}"',
            f"include {HERE / ('in.cgms' if run['case'] == 'A' else 'in.ljcut')}",
        ]
    return "\n".join(lines) + "\n"


def parse_log(text):
    """Split the log at the BENCH-RUN markers; per run: loop time, steps, atoms, the avg
    column of the timing breakdown, neighbour-list builds."""
    out = {}
    chunks = re.split(r"^BENCH-RUN (\S+)\s*$", text, flags=re.M)
    for label, body in zip(chunks[1::2], chunks[2::2]):
        m = re.search(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", body)
        if not m:
            raise RuntimeError(f"run {label}: no 'Loop time' line in the log")
        rec = {
            "loop": float(m.group(1)),
            "procs": int(m.group(2)),
            "steps": int(m.group(3)),
            "atoms": int(m.group(4)),
        }
        for sec in SECTIONS:
            sm = re.search(rf"^{sec}\s*\|([^|\n]*)\|([^|\n]*)\|", body, flags=re.M)
            if not sm:
                raise RuntimeError(f"run {label}: no '{sec}' line in the timing breakdown")
            rec[sec.lower()] = float(sm.group(2))  # avg column
        # the share of the loop rank 0 was on a core: on a shared machine the loop's
        # CPU time (loop x share) is the steadier measure
        cm = re.search(r"^([\d.]+)% CPU use with", body, flags=re.M)
        rec["cpu_share"] = float(cm.group(1)) / 100 if cm else float("nan")
        bm = re.search(r"Neighbor list builds = (\d+)", body)
        rec["neigh_builds"] = int(bm.group(1)) if bm else -1
        # memory: LAMMPS's own count (avg per rank, from the styles' memory_usage) and
        # the heap in use on rank 0 after the run (info memory: every array, counted or not)
        mm = re.search(r"Per MPI rank memory allocation \(min/avg/max\) = \S+ \| (\S+) \|", body)
        rec["mem_lammps_mb"] = float(mm.group(1)) if mm else float("nan")
        hm = re.search(r"Current reserved memory pool size: (\S+) Mbyte", body)
        rec["heap_mb"] = float(hm.group(1)) if hm else float("nan")
        out[label] = rec
    return out


def timing(args, mat, common, out, meta):
    runs = []
    sizes = []
    for (ncols, nrows), steps in zip(args.sizes, args.steps):
        n, data_a, data_b = write_tissue(out, ncols, nrows, args.spacing_m, mat["x_ref"])
        sizes.append((f"{ncols}x{nrows}", n, steps))
        tag = f"{ncols}x{nrows}"
        for w in range(args.warmup):
            for case, data in (("A", data_a), ("B", data_b)):
                runs.append(dict(label=f"{tag}:{case}:warm{w}", case=case, data=data,
                                 steps=args.warmup_steps, size=tag, rep=-1 - w))
        for rep in range(args.repeats):
            for case, data in (("A", data_a), ("B", data_b)):
                runs.append(dict(label=f"{tag}:{case}:{rep}", case=case, data=data,
                                 steps=steps, size=tag, rep=rep))

    script = out / "bench.in"
    script.write_text(driver_script(runs, common))
    log = out / "bench.log"
    cmd = lmp_command(args, args.np) + ["-in", str(script), "-log", str(log), "-screen", "none"]
    meta["timing_command"] = " ".join(cmd)
    print("running:", " ".join(cmd), flush=True)
    meta["load_before"] = os.getloadavg()
    t0 = time.time()
    res = subprocess.run(cmd, env=child_env(), cwd=out)
    meta["timing_wall_s"] = time.time() - t0
    meta["load_after"] = os.getloadavg()
    if res.returncode != 0:
        tail = log.read_text().splitlines()[-20:] if log.exists() else []
        sys.exit("LAMMPS failed (exit %d); log tail:\n%s" % (res.returncode, "\n".join(tail)))
    parsed = parse_log(log.read_text())

    rows = []
    for run in runs:
        if run["rep"] < 0:
            continue
        rec = parsed[run["label"]]
        if rec["steps"] != run["steps"]:
            sys.exit(f"run {run['label']}: log says {rec['steps']} steps, asked {run['steps']}")
        bs = rec["atoms"] * rec["steps"]
        row = dict(size=run["size"], case=run["case"],
                   style="cgms" if run["case"] == "A" else "lj/cut", rep=run["rep"],
                   atoms=rec["atoms"], steps=rec["steps"], procs=rec["procs"],
                   neigh_builds=rec["neigh_builds"], loop_s=rec["loop"],
                   # bytes per bead (LAMMPS's "Mbytes" are MiB): LAMMPS's count over all
                   # ranks; the heap of rank 0 over the beads of rank 0 (about atoms / procs)
                   mem_lammps_b=MIB * rec["mem_lammps_mb"] * rec["procs"] / rec["atoms"],
                   heap_b=MIB * rec["heap_mb"] * rec["procs"] / rec["atoms"])
        for sec in SECTIONS:
            row[f"{sec.lower()}_s"] = rec[sec.lower()]
        row["loop_ns"] = 1e9 * rec["loop"] / bs
        row["cpu_share"] = rec["cpu_share"]
        row["loop_cpu_ns"] = row["loop_ns"] * rec["cpu_share"]
        for sec in SECTIONS:
            row[f"{sec.lower()}_ns"] = 1e9 * rec[sec.lower()] / bs
        row["pair_modify_ns"] = row["pair_ns"] + row["modify_ns"]
        rows.append(row)
    write_csv(out / "runs.csv", rows)

    # medians per size and case; ratios of the interleaved A/B pairs, then their median
    metrics = ["loop_ns", "loop_cpu_ns", "cpu_share", "pair_ns", "modify_ns", "pair_modify_ns",
               "neigh_ns", "comm_ns", "other_ns"]
    summary = []
    for tag, n, steps in sizes:
        by = {(r["case"], r["rep"]): r for r in rows if r["size"] == tag}
        reps = sorted({rep for (_, rep) in by})
        entry = dict(size=tag, atoms=n, steps=steps, repeats=len(reps))
        for case in "AB":
            for met in metrics + ["neigh_builds", "mem_lammps_b", "heap_b"]:
                vals = [by[(case, rep)][met] for rep in reps]
                entry[f"{case}_{met}"] = statistics.median(vals)
            entry[f"{case}_loop_ns_min"] = min(by[(case, rep)]["loop_ns"] for rep in reps)
            entry[f"{case}_loop_ns_max"] = max(by[(case, rep)]["loop_ns"] for rep in reps)
        for met in ["loop_ns", "loop_cpu_ns", "pair_ns", "modify_ns", "pair_modify_ns"]:
            ratios = [by[("A", rep)][met] / by[("B", rep)][met] for rep in reps]
            entry[f"ratio_{met}"] = statistics.median(ratios)
            entry[f"ratio_{met}_min"] = min(ratios)
            entry[f"ratio_{met}_max"] = max(ratios)
        # CGMS pair + fix against the lj/cut pair alone: the fix is Modify(A) - Modify(B)
        # (both carry the same nve and enforce2d)
        strict = [(by[("A", rep)]["pair_ns"] + by[("A", rep)]["modify_ns"]
                   - by[("B", rep)]["modify_ns"]) / by[("B", rep)]["pair_ns"] for rep in reps]
        entry["ratio_pairfix_vs_ljpair"] = statistics.median(strict)
        summary.append(entry)
    write_csv(out / "summary.csv", summary)

    print()
    print("ns per bead-step, medians of %d interleaved repeats (A = cgms, B = lj/cut)"
          % args.repeats)
    hdr = ("size", "beads", "steps", "case", "loop", "loop CPU", "CPU share", "Pair", "Modify",
           "Pair+Mod", "Neigh", "Comm", "Other", "builds", "B/bead LAMMPS", "B/bead heap")
    print("| " + " | ".join(hdr) + " |")
    print("|" + "---|" * len(hdr))
    for e in summary:
        for case, name in (("A", "cgms"), ("B", "lj/cut")):
            cells = [e["size"], e["atoms"], e["steps"], name]
            cells += ["%.2f" % e[f"{case}_{met}"] for met in
                      ("loop_ns", "loop_cpu_ns", "cpu_share", "pair_ns", "modify_ns",
                       "pair_modify_ns", "neigh_ns", "comm_ns", "other_ns")]
            cells += ["%d" % e[f"{case}_neigh_builds"], "%.0f" % e[f"{case}_mem_lammps_b"],
                      "%.0f" % e[f"{case}_heap_b"]]
            print("| " + " | ".join(str(c) for c in cells) + " |")
    print("load average (1, 5, 15 min) before %s, after %s" % (
        " ".join("%.2f" % v for v in meta["load_before"]),
        " ".join("%.2f" % v for v in meta["load_after"])))
    print()
    print("median A/B ratio of interleaved pairs [min-max]")
    print("| size | loop | loop CPU | Pair | Modify | Pair+Modify | (Pair+fix)/lj Pair |")
    print("|---|---|---|---|---|---|---|")
    for e in summary:
        cells = ["%.2f [%.2f-%.2f]" % (e[f"ratio_{m}"], e[f"ratio_{m}_min"], e[f"ratio_{m}_max"])
                 for m in ("loop_ns", "loop_cpu_ns", "pair_ns", "modify_ns", "pair_modify_ns")]
        print("| %s | %s | %.2f |" % (e["size"], " | ".join(cells), e["ratio_pairfix_vs_ljpair"]))
    return summary


# ----------------------------------------------------------------------------- callgrind


def callgrind_calls(path):
    """Total calls into each function, from the calls= lines of a callgrind output file
    (name compression: '(id) name' defines, '(id)' refers)."""
    names = {}
    calls = {}
    cfn = None

    def resolve(spec):
        m = re.match(r"\((\d+)\)(?:\s+(.*))?$", spec.strip())
        if not m:
            return spec.strip()
        if m.group(2):
            names[m.group(1)] = m.group(2)
        return names.get(m.group(1), spec)

    with open(path, errors="replace") as fh:
        for line in fh:
            if line.startswith("fn="):
                resolve(line[3:])
            elif line.startswith("cfn="):
                cfn = resolve(line[4:])
            elif line.startswith("calls=") and cfn is not None:
                calls[cfn] = calls.get(cfn, 0) + int(line[6:].split()[0])
    return calls


CACHE_EVENTS = ("Ir", "DLmr", "DLmw")  # instructions, last-level data read / write misses
COUNT = r"([\d,]+|\.)\s+(?:\(\s*[\d.]+%\)\s+)?"


def annotate(path, inclusive, events=("Ir",)):
    """{function: Ir} from callgrind_annotate (inclusive or self); with several events,
    {function: (count per event)}."""
    cmd = ["callgrind_annotate", f"--inclusive={'yes' if inclusive else 'no'}",
           f"--show={','.join(events)}", f"--sort={events[0]}", "--threshold=100", str(path)]
    text = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    res = {}
    pattern = r"\s*" + COUNT * len(events) + r"(.*?)\s*(?:\[[^\]]*\])?\s*$"
    for line in text.splitlines():
        m = re.match(pattern, line)
        if not m:
            continue
        counts = [int(m.group(k + 1).replace(",", "").replace(".", "") or 0) for k in range(len(events))]
        # "file:function": the first single colon (C++ names carry "::")
        fm = re.match(r"^(.*?[^:]):(?!:)(.*)$", m.group(len(events) + 1))
        fn = fm.group(2) if fm else m.group(len(events) + 1)
        if fn == "PROGRAM TOTALS" or not fn:
            continue
        old = res.get(fn, [0] * len(events))
        res[fn] = [a + b for a, b in zip(old, counts)]
    if len(events) == 1:
        res = {f: c[0] for f, c in res.items()}
    return res, text


def run_callgrind(args, out, name, data, inp, common, options, meta, key):
    """Run one bench input under callgrind (with ``options``), collecting only inside
    Verlet::run, the timed MD loop (no start-up, no set-up); the command goes into
    ``meta[key]``. Returns the output file ``out/<name>.out``."""
    cgout = out / f"{name}.out"
    var = dict(common, data=str(data), steps=str(args.cg_steps))
    if args.cg_plugin:
        var["plugin"] = str(Path(args.cg_plugin).resolve())
    cmd = ["valgrind", "--tool=callgrind", "--toggle-collect=*Verlet::run*", *options,
           f"--callgrind-out-file={cgout}"]
    cmd += lmp_command(args, 1) + ["-in", str(HERE / inp), "-log", "none", "-screen", "none"]
    for k, v in var.items():
        cmd += ["-var", k, v]
    meta[key] = " ".join(cmd)
    print("running:", " ".join(cmd), flush=True)
    res = subprocess.run(cmd, env=child_env(), cwd=out, capture_output=True, text=True)
    (out / f"{name}.stderr").write_text(res.stderr)
    if res.returncode != 0:
        sys.exit(f"valgrind run {name} failed:\n{res.stderr[-3000:]}")
    return cgout


def callgrind(args, mat, common, out, meta):
    ncols, nrows = args.cg_size
    n, data_a, data_b = write_tissue(out, ncols, nrows, args.spacing_m, mat["x_ref"])
    rows = []
    report = []
    for case, data, inp in (("A", data_a, "in.cgms"), ("B", data_b, "in.ljcut")):
        cgout = run_callgrind(args, out, f"callgrind.{case}", data, inp, common, [], meta,
                              f"callgrind_command_{case}")
        incl, text_i = annotate(cgout, True)
        excl, text_e = annotate(cgout, False)
        (out / f"callgrind.{case}.inclusive.txt").write_text(text_i)
        (out / f"callgrind.{case}.self.txt").write_text(text_e)
        calls = callgrind_calls(cgout)
        total = sum(excl.values())

        if case == "A":
            pat = (r"PairCGMS::(eval<|compute\()|FixCGMSFluid::|CGMS::Material::(lj_radius|beta)"
                   r"|CGMS::store\(")
        else:
            pat = r"PairLJCut::compute\("
        pat += (r"|Verlet::run\(|FixNVE::(initial|final)_integrate\(|FixEnforce2D::post_force\("
                r"|Neighbor::decide\(|Comm\w*::forward_comm\(int\)")
        for f in sorted((f for f in incl if re.search(pat, f)), key=lambda f: -incl[f]):
            c = calls.get(f, 0)
            # Ir inside the MD loop / (beads x steps)
            per = args.cg_steps
            if "Verlet::run(" not in f and c < args.cg_steps // 10:
                continue
            rows.append(dict(case=case, style="cgms" if case == "A" else "lj/cut", function=f,
                             calls=c, atoms=n, ir_inclusive=incl[f], ir_self=excl.get(f, 0),
                             ir_incl_per_bead_step=incl[f] / (per * n),
                             ir_self_per_bead_step=excl.get(f, 0) / (per * n)))
        top = sorted(excl.items(), key=lambda kv: -kv[1])[: args.cg_top]
        report.append((case, n, total, top))
    write_csv(out / "callgrind.csv", rows)

    print()
    print(f"callgrind, {n} beads x {args.cg_steps} steps: instructions (Ir) per bead-step")
    print("| case | function | calls | Ir incl / bead-step | Ir self / bead-step |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| %s | `%s` | %d | %.1f | %.1f |" % (r["style"], r["function"], r["calls"],
                                                    r["ir_incl_per_bead_step"],
                                                    r["ir_self_per_bead_step"]))
    for case, n, total, top in report:
        print()
        print(f"top self cost, case {case} (total Ir {total:,}):")
        for f, ir in top:
            print("  %5.1f%%  %12.1f Ir/bead-step  %s" % (100 * ir / total,
                                                       ir / (n * args.cg_steps), f))
    return rows


# groups of functions (self cost) for the cache profile, first match wins
CACHE_GROUPS = (
    ("pair", r"PairCGMS::|PairLJCut::"),
    ("fix geometry pass", r"FixCGMSFluid::geometry_pass|FixCGMSFluid::(un)?pack_reverse"),
    ("fix fluid pass", r"FixCGMSFluid::"),
    ("neighbor", r"NPair|NBin|NStencil|Neighbor::|NeighList::|MyPage"),
    ("comm, exchange, sort", r"Comm|AtomVec|Atom::sort|Domain::|Irregular|FixNVE::(un)?pack"),
    ("nve, enforce2d", r"FixNVE::|FixEnforce2D::"),
    ("memset, memcpy", r"mem(set|cpy|move)"),
)


def cache_profile(args, mat, common, out, meta):
    """Callgrind's cache simulation of the MD loop of both cases (--cg-cache): instructions
    and last-level data misses (read + write) per bead-step, by group of functions (self
    cost). --LL sets the simulated last level: a small one (4 MiB) makes 10^5 beads miss
    as 10^6 beads do on the real machine, where nothing stays cached between passes."""
    ncols, nrows = args.cg_size
    n, data_a, data_b = write_tissue(out, ncols, nrows, args.spacing_m, mat["x_ref"])
    rows = []
    for case, data, inp in (("A", data_a, "in.cgms"), ("B", data_b, "in.ljcut")):
        cache = ["--cache-sim=yes", "--D1=32768,8,64", f"--LL={args.cg_ll},16,64"]
        cgout = run_callgrind(args, out, f"cachegrind.{case}", data, inp, common, cache, meta,
                              f"cache_command_{case}")
        excl, text = annotate(cgout, False, CACHE_EVENTS)
        (out / f"cachegrind.{case}.self.txt").write_text(text)
        groups = {name: [0, 0, 0] for name, _ in CACHE_GROUPS}
        groups["rest"] = [0, 0, 0]
        total = [0, 0, 0]
        for fn, counts in excl.items():
            name = next((g for g, pat in CACHE_GROUPS if re.search(pat, fn)), "rest")
            groups[name] = [a + b for a, b in zip(groups[name], counts)]
            total = [a + b for a, b in zip(total, counts)]
        groups["whole loop"] = total
        per = n * args.cg_steps
        for name, (ir, lr, lw) in groups.items():
            rows.append(dict(case=case, style="cgms" if case == "A" else "lj/cut", group=name,
                             atoms=n, steps=args.cg_steps, ir_per_bead_step=ir / per,
                             ll_read_misses_per_bead_step=lr / per,
                             ll_write_misses_per_bead_step=lw / per,
                             ll_misses_per_bead_step=(lr + lw) / per))
    write_csv(out / "cache.csv", rows)
    print()
    print(f"callgrind cache simulation, {n} beads x {args.cg_steps} steps, LL {args.cg_ll} B: "
          "per bead-step (self cost by group)")
    print("| case | group | Ir | LL read misses | LL write misses | LL misses |")
    print("|---|---|---:|---:|---:|---:|")
    for r in rows:
        print("| %s | %s | %.1f | %.2f | %.2f | %.2f |" % (
            r["style"], r["group"], r["ir_per_bead_step"], r["ll_read_misses_per_bead_step"],
            r["ll_write_misses_per_bead_step"], r["ll_misses_per_bead_step"]))
    return rows


# ----------------------------------------------------------------------------- misc


def write_csv(path, rows):
    if not rows:
        return
    keys = list(rows[0].keys())
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def machine_info():
    info = {"nproc": os.cpu_count()}
    try:
        cpu = Path("/proc/cpuinfo").read_text()
        m = re.search(r"^model name\s*:\s*(.*)$", cpu, flags=re.M)
        info["cpu"] = m.group(1) if m else "?"
        m = re.search(r"^cpu MHz\s*:\s*(.*)$", cpu, flags=re.M)
        info["cpu_mhz"] = m.group(1) if m else "?"
    except OSError:
        pass
    return info


def git_state():
    try:
        head = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "src"],
                               capture_output=True, text=True).stdout.strip()
        if not dirty:
            return head
        diff = subprocess.run(["git", "-C", str(REPO), "diff", "HEAD", "--", "src"],
                              capture_output=True).stdout
        return f"{head}+dirty-src(diff sha256 {hashlib.sha256(diff).hexdigest()[:12]})"
    except OSError:
        return "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("/tmp/cgms-bench"),
                    help="folder for inputs, logs and CSV results (default /tmp/cgms-bench)")
    ap.add_argument("--lmp", default=os.environ.get("CGMS_LMP"), help="lmp binary ($CGMS_LMP)")
    ap.add_argument("--plugin", default=os.environ.get("CGMS_PLUGIN"),
                    help="cgmsplugin.so ($CGMS_PLUGIN); a copy in --out is what gets loaded")
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--np", type=int, default=1, help="MPI ranks for the timing runs (1: serial)")
    ap.add_argument("--sizes", type=parse_size, nargs="+", default=[(33, 30), (150, 135)],
                    help="tissues as NCOLSxNROWS hexagonal patches (default 33x30 150x135)")
    ap.add_argument("--steps", type=int, nargs="+", default=[10000],
                    help="steps per run: one value, or one per size (default 10000)")
    ap.add_argument("--repeats", type=int, default=5, help="A/B pairs per size (default 5)")
    ap.add_argument("--warmup", type=int, default=1, help="untimed A/B pairs per size first")
    ap.add_argument("--warmup-steps", type=int, default=1000)
    ap.add_argument("--material", default="apple")
    ap.add_argument("--dryness", type=float, default=0.3)
    ap.add_argument("--skin", type=float, default=1.5e-5)
    ap.add_argument("--dt", type=float, default=1e-7)
    ap.add_argument("--spacing", default="auto",
                    help="lattice spacing in units of x_ref, or 'auto' (default): the "
                    "equilibrium spacing at --dryness from a relaxation run")
    ap.add_argument("--relax-size", type=parse_size, default=(33, 30))
    ap.add_argument("--relax-steps", type=int, default=20000)
    ap.add_argument("--lj-epsilon", type=float, default=1e-9,
                    help="lj/cut epsilon in J (default 1e-9: stable at dt 1e-7)")
    ap.add_argument("--no-timing", action="store_true", help="skip the timing runs")
    ap.add_argument("--callgrind", action="store_true", help="also run the callgrind profiles")
    ap.add_argument("--cg-size", type=parse_size, default=(33, 30))
    ap.add_argument("--cg-steps", type=int, default=2000)
    ap.add_argument("--cg-plugin", default=None,
                    help="plugin for the callgrind runs only, e.g. a build with -g for "
                    "line-level annotation (default: the same snapshot as the timing)")
    ap.add_argument("--cg-top", type=int, default=12, help="functions in the top-self lists")
    ap.add_argument("--cg-cache", action="store_true",
                    help="also run callgrind's cache simulation (LL misses per bead-step)")
    ap.add_argument("--cg-ll", type=int, default=4194304,
                    help="simulated last-level cache size in bytes for --cg-cache (4 MiB)")
    args = ap.parse_args()

    if not args.lmp or not Path(args.lmp).exists():
        ap.error("no lmp binary: source build/env.sh or pass --lmp")
    if not args.plugin or not Path(args.plugin).exists():
        ap.error("no cgmsplugin.so: source build/env.sh or pass --plugin")
    if len(args.steps) == 1:
        args.steps = args.steps * len(args.sizes)
    if len(args.steps) != len(args.sizes):
        ap.error("--steps takes one value or one per --sizes entry")
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")

    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    # load a snapshot of the plugin: a rebuild during the benchmark cannot change it
    plugin = out / "cgmsplugin.snapshot.so"
    shutil.copyfile(args.plugin, plugin)
    mat = material.read(args.material)

    meta = dict(machine_info(), lmp=args.lmp, plugin=args.plugin,
                plugin_sha256=hashlib.sha256(plugin.read_bytes()).hexdigest(),
                git=git_state(), x_ref=mat["x_ref"],
                argv=sys.argv, started=time.strftime("%Y-%m-%d %H:%M:%S"))
    print(f"machine: {meta['nproc']} cpus, {meta.get('cpu', '?')}; git {meta['git']}; "
          f"x_ref {mat['x_ref']:.6g} m, cutoff {CUTOFF_XREF * mat['x_ref']:.6g} m")
    try:
        if args.spacing == "auto":
            args.spacing_m = equilibrium_spacing(args, mat, plugin, out, meta)
        else:
            args.spacing_m = float(args.spacing) * mat["x_ref"]
        meta["spacing_xref"] = args.spacing_m / mat["x_ref"]
        common = case_vars(args, mat, plugin, args.spacing_m)
        meta["variables"] = common
        if not args.no_timing:
            meta["summary"] = timing(args, mat, common, out, meta)
        if args.callgrind:
            meta["callgrind"] = callgrind(args, mat, common, out, meta)
        if args.cg_cache:
            meta["cache"] = cache_profile(args, mat, common, out, meta)
    finally:
        (out / "meta.json").write_text(json.dumps(meta, indent=1, default=str) + "\n")
    print(f"\nresults in {out}")


if __name__ == "__main__":
    main()
