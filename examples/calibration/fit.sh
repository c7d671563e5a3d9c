#!/bin/sh
# Calibrate CGMS against the fine-scale (MFC) reference of the 86-cell calibration tissue
# (doc/calibration.md, "Against the MFC"). Run from the repository root after
# `source build/env.sh`:
#
#   examples/calibration/fit.sh [MFC_FOLDER [OUT]]
#
# MFC_FOLDER: the calibration tissue's MFC results, centroids.s<s>.txt per level
# (default examples/calibration/mfc-reference/calibration; made by `python3 -m cgms mfc`).
# OUT: results folder (default results/calibration-mfc), one sub-folder per fit:
#   paper - k_T, k_PA, beta_a, beta_b (the paper's parameters, beta(s) = beta_a + beta_b ln s)
#   kS    - the same and the cell-shape stiffness k_S (start 0.1 N/m)
# Rigid motion (translation and rotation) is removed before eqn (2). The bounds are wider
# than the defaults because the MFC drives k_PA and k_T far below apple's values.
set -e
py=${PYTHON:-/usr/bin/python3}
ref=${1:-examples/calibration/mfc-reference/calibration}
out=${2:-results/calibration-mfc}
levels=""
for s in 1 0.8 0.6 0.4 0.3; do
    [ -f "$ref/centroids.s$s.txt" ] && levels="$levels --reference $s=$ref/centroids.s$s.txt"
done
[ -n "$levels" ] || { echo "fit.sh: no centroids.s<s>.txt in $ref" >&2; exit 1; }
wide="--bounds k_T=0.01:100 --bounds k_PA=0.001:20 --align rigid --max-evaluations 80"
"$py" -m cgms calibrate $levels $wide --fit k_T,k_PA,beta_a,beta_b --out "$out/paper"
"$py" -m cgms calibrate $levels $wide --fit k_T,k_PA,beta_a,beta_b,k_S \
    --start k_S=0.1 --bounds k_S=0.001:50 --out "$out/kS"

# Optionally install one fit as potentials/apple-mfc.cgms (never replaces an existing file):
#   examples/calibration/fit.sh REF OUT kS
pick=${3:-}
[ -n "$pick" ] || exit 0
target=potentials/apple-mfc.cgms
[ ! -e "$target" ] || { echo "fit.sh: $target exists; move it away first" >&2; exit 1; }
src="$out/$pick/apple-calibrated.cgms"
{
    head -n 2 "$src"
    echo "# Made by: examples/calibration/fit.sh $ref $out $pick (fit '$pick', commit" \
         "$(git rev-parse --short HEAD))"
    echo "# References: MFC centroids in $ref (examples/calibration/mfc-reference/README.md)"
    tail -n +3 "$src"
} > "$target.tmp"
mv "$target.tmp" "$target"
echo "fit.sh: wrote $target from $src"
