# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The paper's sensitivity study (section 4.4): the 86-bead tissue, fresh and at s = 0.3,
with k_T, k_PA and beta scaled. One steady state per setting, normalised by the fresh
steady state of the same setting."""

from pathlib import Path

from .. import material, study

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
