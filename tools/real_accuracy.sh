#!/usr/bin/env bash
# Accuracy on real measured truths: each file of a folder of measurements (default
# the five RGL files, ../shared/data/measured/rgl_bsdf) is measured without noise on the
# paper's plan (k-hat fitted to the probe, 30 theta_h, theta_d step 3, phi_d step 15, phi_h 45,
# the UTIA device model), reconstructed by each method and scored against the file at the
# MERL bin centres (cosine-weighted relative RMSE and log RMSE, light and camera within
# 75 deg). Prints a markdown table of the paper pipeline's (`linear`) figures and every
# method's ratio to them, and the median ratio.
#
#   CARGO_INCREMENTAL=0 cargo build --release -p specula-cli
#   tools/real_accuracy.sh [FOLDER] [-- EXTRA evaluate OPTIONS] > table.md
#
# Methods: $METHODS (default "lobe log linear"); the binary: $SPECULA (default
# target/release/specula); the grid: $GRID_PRESET (default paper, the paper's plan above;
# recommended for the default of `evaluate`, whose halves of phi_d every method then
# reconstructs apart, the `linear` baseline included).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SPECULA:-$here/target/release/specula}"
folder="${1:-$here/../shared/data/measured/rgl_bsdf}"
shift $(( $# > 0 ? 1 : 0 ))
[ "${1:-}" = "--" ] && shift
methods="${METHODS:-lobe log linear}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# material,rel_within,log_within for one method (the per-material rows of `evaluate`).
figures() {
    "$bin" evaluate --truth "$folder" --grid-preset "${GRID_PRESET:-paper}" --method "$1" "${@:2}" 2>/dev/null |
        awk -F, '!/^#/ && $1 != "material" && $1 !~ /^mean of/ { print $1 "," $4 "," $5 }'
}
figures linear "$@" > "$work/linear"
header="| file | paper rel RMSE | paper log RMSE |"
rule="|---|---|---|"
for m in $methods; do
    figures "$m" "$@" > "$work/$m"
    header="$header \`$m\` rel / log |"
    rule="$rule---|"
done
echo "$header"
echo "$rule"
while IFS=, read -r name rel log; do
    row="| $name | $(printf %.4f "$rel") | $(printf %.4f "$log") |"
    for m in $methods; do
        row="$row $(awk -F, -v n="$name" -v r="$rel" -v l="$log" '$1 == n { printf "%.2f / %.2f", $2 / r, $3 / l }' "$work/$m") |"
    done
    echo "$row"
done < "$work/linear"
row="| median ratio | | |"
for m in $methods; do
    row="$row $(join -t, "$work/linear" "$work/$m" | awk -F, '{ print $4 / $2 "," $5 / $3 }' |
        sort -t, -k1,1g | awk -F, '{ r[NR] = $1 } END { printf "%.2f", (r[int((NR + 1) / 2)] + r[int(NR / 2) + 1]) / 2 }') / $(
        join -t, "$work/linear" "$work/$m" | awk -F, '{ print $5 / $3 }' | sort -g |
        awk '{ r[NR] = $1 } END { printf "%.2f", (r[int((NR + 1) / 2)] + r[int(NR / 2) + 1]) / 2 }') |"
done
echo "$row"
