#!/usr/bin/env bash
# Coverage of the measurement uncertainty (OUT.uncertainty.binary) on the simulator: for each
# truth and seed, `specula measure` on the default simulated device (disk and noise), as a lab
# runs it (the sequential default; GRID_PRESET=recommended measures the whole recommended grid
# instead), then
# `specula coverage` (the share of measured and interpolated cells within 75 deg whose truth
# lies within 2u) and the figures' coverage (gloss 20/60/85, haze, DOI within their U).
#
#   cargo build --release -p specula-cli && SPECULA=target/release/specula \
#       tools/uncertainty_coverage.sh [TRUTH...] > table.md
#
# SEEDS (default "1 2") chooses the seeds; WORK=DIR keeps the tables there. Default truths: the training truths the scales
# were calibrated on and the held-out ones (docs/book/src/uncertainty.md); the RGL files
# when ../shared/data/measured is present.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SPECULA:-$here/target/debug/specula}"
if [ -n "${WORK:-}" ]; then
    work="$WORK"; mkdir -p "$work"
else
    work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fi
grid=()
[ -n "${GRID_PRESET:-}" ] && grid=(--grid-preset "$GRID_PRESET")
if [ "$#" -eq 0 ]; then
    set -- chrome green-paint sgd:red-metallic-paint nbrdf:alum-bronze \
        "$here"/tools/instrument_truths/chrome-ggx-0.011.toml \
        "$here"/tools/instrument_truths/two-lobe-silver-haze.toml abc:polyethylene \
        paint-red-high-gloss nbrdf:aluminium nbrdf:nickel nbrdf:chrome nbrdf:tungsten-carbide \
        nbrdf:steel nbrdf:chrome-steel
    rgl="$here/../shared/data/measured/rgl_bsdf"
    if [ -d "$rgl" ]; then
        set -- "$@" "$rgl"/cc_ibiza_sunset_rgb.bsdf "$rgl"/paper_white_rgb.bsdf \
            "$rgl"/colodur_napoli_4f_rgb.bsdf "$rgl"/satin_rosaline_rgb.bsdf \
            "$rgl"/cc_iris_purple_gem_rgb.bsdf
    fi
fi
figures="gloss_20 gloss_60 gloss_85 haze doi"
all_covered=0; all_figures=0; all_without=0
echo "| truth | seed | cells within 2u | figures within U | figures without U |"
echo "|---|---|---|---|---|"
for truth in "$@"; do
    name="$(basename "$truth")"; name="${name%.*}"; name="${name//:/_}"
    for seed in ${SEEDS:-1 2}; do
        out="$work/$name-$seed.binary"
        "$bin" measure --truth "$truth" --seed "$seed" "${grid[@]}" --out "$out" > /dev/null 2>&1
        cells="$("$bin" coverage "$out" "$truth" | awk -F, '$1 == "both" { print $4 }')"
        "$bin" appearance --csv "$truth" "$out" > "$work/figures.csv" 2> /dev/null
        within="$(awk -F, -v want="$figures" '
            NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
            NR == 2 { for (i = 1; i <= NF; i++) truth[i] = $i; next }
            NR == 3 { n = split(want, f, " "); covered = 0; total = 0; none = ""
                      for (k = 1; k <= n; k++) {
                          v = col[f[k]]; u = col["U_" f[k]]
                          if (u == "" || $u == "") { none = none " " f[k]; continue }
                          total++; d = $v - truth[v]; if (d < 0) d = -d
                          if (d <= $u) covered++ }
                      printf "%d/%d %d%s", covered, total, n - total, none }' "$work/figures.csv")"
        read -r within without none <<< "${within:-0/0 0}"
        echo "| $name | $seed | $cells | $within | ${none:-} |"
        all_covered=$((all_covered + ${within%/*})); all_figures=$((all_figures + ${within#*/}))
        all_without=$((all_without + without))
    done
done
echo
echo "figures within U: $all_covered of $all_figures with a U (target: at least 90 %); $all_without without one"
echo "(a figure has none where it rests on cells beyond the samples' reach, gloss 85 on a device whose camera stops at 75 deg)"
