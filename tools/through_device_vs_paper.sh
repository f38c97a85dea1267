#!/usr/bin/env bash
# `specula measure` on the whole recommended grid against the paper's way on the same simulated device (its
# light disk and its noise, seed 1), truth by truth: each measured both ways, scored by
# `specula compare` against the truth tabulated (cosine-weighted relative RMSE and log RMSE
# within 75 deg), with the ratio max(rel ratio, log ratio) and what the safeguard of the
# deblurred table said (its reproduction error in the peak region against the one the
# uncertainties explain, and whether it fell back).
#
#   cargo build --release -p specula-cli
#   SPECULA=target/release/specula tools/through_device_vs_paper.sh TRUTH... > table.md
#
# With no TRUTH: the five RGL files of ../shared/data/measured/rgl_bsdf (skipped with a
# message when absent).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SPECULA:-$here/target/release/specula}"
work="${WORK:-$(mktemp -d)}"
if [ "$#" -eq 0 ]; then
    rgl="$here/../shared/data/measured/rgl_bsdf"
    [ -d "$rgl" ] || { echo "no truths given and $rgl is absent" >&2; exit 1; }
    set -- "$rgl"/*.bsdf
fi
score() { "$bin" compare "$1" "$2" 2>/dev/null | awk -F, '$1 == "within" { print $3, $4 }'; }
echo "| truth | recommended grid rel / log | paper's way rel / log | ratio | wall s | peak reproduction (expected) | check |"
echo "|---|---|---|---|---|---|---|"
for truth in "$@"; do
    n=$(basename "$truth" .toml); n=${n%.bsdf}; n=${n//:/_}
    "$bin" tabulate "$truth" --out "$work/$n.truth.binary" > /dev/null
    start=$(date +%s.%N)
    "$bin" measure --truth "$truth" --seed 1 --grid-preset recommended --out "$work/$n.d.binary" --session "$work/$n.d.sqlite" > /dev/null 2>&1
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    "$bin" measure --truth "$truth" --seed 1 --grid-preset paper --method linear --order nested \
        --hdr bracket --out "$work/$n.p.binary" --session "$work/$n.p.sqlite" > /dev/null 2>&1
    read -r dr dl <<< "$(score "$work/$n.d.binary" "$work/$n.truth.binary")"
    read -r pr pl <<< "$(score "$work/$n.p.binary" "$work/$n.truth.binary")"
    summary="$work/$n.d.summary.txt"
    peak=$(sed -n 's/^consistency_peak=.*reproduction error \([0-9.]* %\) (\([0-9.]* %\) expected).*/\1 (\2)/p' "$summary")
    fallback=$(sed -n 's/^deblur_fallback=\([^:(]*\).*/\1/p' "$summary")
    awk -v n="$n" -v a="$dr" -v b="$dl" -v c="$pr" -v d="$pl" -v w="$wall" -v p="$peak" -v f="$fallback" \
        'BEGIN { r = a / c; l = b / d; m = (r > l) ? r : l;
                 printf "| %s | %.4f / %.4f | %.4f / %.4f | %.2f | %.0f | %s | %s |\n", n, a, b, c, d, m, w, p, f }'
done
