# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The paper's sensitivity study (section 4.4): the 86-bead tissue, fresh and at s = 0.3,
with k_T, k_PA and beta scaled. One steady state per setting, normalised by the fresh
steady state of the same setting."""

from pathlib import Path

from .. import material, morphology, study

# factor sets of the paper's Figs 10-15; None for beta means "without periphery treatment"
FACTORS = {
    "k_T": (0.1, 0.5, 1.0, 5.0, 10.0),
    "k_PA": (0.1, 0.5, 1.0, 10.0, 100.0),
    "beta": (None, 0.98, 1.0, 1.1, 1.2),
}


def setting_args(mat, parameter, factor):
    """pair_style keywords and pair_coeff overrides for one setting."""
    if parameter == "beta":
        if factor is None:
            return "periphery no", ""
        return "", f"beta_a {mat['beta_a'] * factor!r} beta_b {mat['beta_b'] * factor!r}"
    return "", f"{parameter} {mat[parameter] * factor!r}"


def run(data, material_file, out, levels=(1.0, 0.3), method="quasistatic", progress=True):
    """Every setting at every level; rows of the normalised morphology. A setting whose
    quasi-static solve stops is followed with the dynamics instead
    (:func:`cgms.study.relax_or_fallback`; the row says which)."""
    mat = material.read(material_file)
    rows = []
    for parameter, factors in FACTORS.items():
        for factor in factors:
            label = "off" if factor is None else f"{factor:g}"
            pair_args, overrides = setting_args(mat, parameter, factor)
            folder = Path(out) / f"{parameter}-{label}"
            results, failure = [], ""
            for s in levels:
                try:
                    r, _ = study.relax_or_fallback(data, material_file, s, folder,
                                                   fallback_unconverged=False,
                                                   pair_args=pair_args, overrides=overrides,
                                                   method=method)
                except study.LammpsError as err:
                    failure = err.reason
                    break
                results.append(r)
            if failure:
                rows.append({"parameter": parameter, "factor": label, "failed": failure})
                if progress:
                    print(f"  {parameter:5s} x {label:4s}: no steady state: {failure}", flush=True)
                continue
            for row in study.table(results):
                rows.append({"parameter": parameter, "factor": label, **row})
            if progress:
                last = rows[-1]
                print(f"  {parameter:5s} x {label:4s}: s = {last['s']:g}: A/A0 {last['A/A0']:.4f} "
                      f"P/P0 {last['P/P0']:.4f} EL/EL0 {last['EL/EL0']:.4f} "
                      f"({last['method']})", flush=True)
    return rows


def snapshots(out, rows, level=0.3):
    """Snapshots like the paper's Figs 10, 12 and 14, ``out/snapshots-<parameter>.png``:
    the tissue of every setting at ``level``, its cells coloured by the local shrinkage
    from the fresh state of the same setting (dashed: that fresh outline). ``rows``: the
    finished rows of :func:`run`, whose steady states are in ``out``."""
    from .. import pictures    # matplotlib only when pictures are drawn

    for parameter in FACTORS:
        states = []
        setting = [r for r in rows if r["parameter"] == parameter]
        for r in (r for r in setting if r["s"] == level):
            def final(s):
                row = next(q for q in setting if q["factor"] == r["factor"] and q["s"] == s)
                folder = Path(out) / f"{parameter}-{r['factor']}"
                folder = folder / "dynamics" if row["method"] == "dynamics" else folder
                return morphology.read_dump(folder / f"tissue.{study.level_name(s)}.dump")[-1]
            dried, fresh = final(level), final(1.0)
            states.append(dict(title=f"{parameter} x {r['factor']}", xy=dried["xy"],
                               values=morphology.shrinkage(dried["xy"], fresh["xy"]),
                               fresh_xy=fresh["xy"]))
        if states:
            pictures.snapshots(states, Path(out) / f"snapshots-{parameter}.png", "shrinkage",
                               title=f"s = {level:g}")
