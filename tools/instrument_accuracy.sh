#!/usr/bin/env bash
# The accuracy of `specula measure` through the instrument (issue 14): for each truth, the
# default measurement (deblurred through the measured response), the same without deblurring
# (--no-deblur), the paper's way on the same device (--method linear --order nested --hdr
# bracket) and the point-light measurement, each on the default simulated device with its
# disk and its noise; scored by `specula compare` (cosine-weighted relative RMSE and log RMSE
# within 75 deg at the MERL bin centres) against the truth, with k-hat from the summaries.
#
#   cargo build -p specula-cli && tools/instrument_accuracy.sh [TRUTH...] > table.md
#
# Default truths: tools/instrument_truths/*.toml (GGX and Beckmann conductors, two-lobe
# materials), green-paint, two NBRDF fits of MERL and an RGL measurement when
# ../shared/data/measured is present. The paper's way is measured on the paper's grid; the
# other runs on the grid preset $GRID_PRESET (default recommended, today's default of
# `measure`; paper for the paper's grid throughout).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SPECULA:-$here/target/debug/specula}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
if [ "$#" -eq 0 ]; then
    set -- "$here"/tools/instrument_truths/*.toml green-paint
    measured="$here/../shared/data/measured"
    if [ -d "$measured" ]; then
        set -- "$@" nbrdf:chrome-steel nbrdf:gold-metallic-paint2 "$measured/rgl_bsdf/cc_ibiza_sunset_rgb.bsdf"
    fi
fi
score() { # table truth -> "relative log"
    "$bin" compare "$1" "$2" | awk -F, '$1 == "within" { printf "%.4f %.4f", $3, $4 }'
}
khat() { sed -n 's/^k_hat=//p' "$1"; }
same_grid() { # summary -> --theta-h-samples N --theta-d-step STEP[:GRAZING@FROM]
    sed -n 's/^grid=\([0-9]*\) theta_h, theta_d step \([0-9.]*\) deg\( (\([0-9.]*\) deg from \([0-9.]*\))\)\{0,1\},.*/--theta-h-samples \1 --theta-d-step \2:\4@\5/p' "$1" | sed 's/:@$//'
}
run() { # truth out grid args...
    local truth="$1" out="$2" grid="$3"; shift 3
    "$bin" measure --truth "$truth" --grid-preset "$grid" --out "$out" "$@" > /dev/null 2>&1
}
grid="${GRID_PRESET:-recommended}"
echo "| truth | deblurred (default) rel / log | k-hat | --no-deblur rel / log | paper's way rel / log | --point-light rel / log | point-light k-hat | ratio to the paper's way rel / log | minus point-light rel |"
echo "|---|---|---|---|---|---|---|---|---|"
for truth in "$@"; do
    name="$(basename "$truth" .toml)"
    d="$work/$name"
    mkdir -p "$d"
    run "$truth" "$d/default.binary" "$grid"
    run "$truth" "$d/blurred.binary" "$grid" --no-deblur
    run "$truth" "$d/paper.binary" paper --method linear --order nested --hdr bracket
    # The point light on the grid the default measured (the same theta_h count, so that
    # k-hat and the error compare): a peak the disk hides takes more theta_h (GridSpec's
    # rule for an unresolved peak), which a point light never needs.
    run "$truth" "$d/point.binary" "$grid" --point-light $(same_grid "$d/default.summary.txt")
    read -r dr dl <<< "$(score "$d/default.binary" "$truth")"
    read -r br bl <<< "$(score "$d/blurred.binary" "$truth")"
    read -r pr pl <<< "$(score "$d/paper.binary" "$truth")"
    read -r lr ll <<< "$(score "$d/point.binary" "$truth")"
    ratio="$(awk -v a="$dr" -v b="$pr" -v c="$dl" -v e="$pl" 'BEGIN { printf "%.3f / %.3f", a / b, c / e }')"
    minus="$(awk -v a="$dr" -v b="$lr" 'BEGIN { printf "%+.4f", a - b }')"
    echo "| $name | $dr / $dl | $(khat "$d/default.summary.txt") | $br / $bl | $pr / $pl | $lr / $ll | $(khat "$d/point.summary.txt") | $ratio | $minus |"
done
