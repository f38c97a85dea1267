#!/usr/bin/env bash
# Every published fit of real data as the truth of the default simulated device (its light
# disk and its noise, seed 1): the 100 MERL and 51 RGL neural fits, the 100 SGD and the 100
# ABC fits, each measured by `specula measure` as a lab would (the sequential default) and
# scored by `specula compare` against the truth tabulated (cosine-weighted relative RMSE and
# log RMSE within 75 deg), beside the paper's way through the same instrument response scored
# the same way (`specula evaluate --through-instrument --grid-preset paper --method linear`:
# its grid, k-hat and linear reconstruction, without the camera noise: its figures differ from
# the paper's way measured with `--order nested --hdr bracket` by 0.01 % on glossy fits and
# 1.2 % on nbrdf-rgl:paper_yellow_rgb, while simulating its 15 hours of HDR brackets takes
# minutes per truth). Where that evaluation's relative RMSE is below 0.03 (near-diffuse
# materials, whose figures are at the level of the camera noise), the paper's way is measured
# with its noise instead (`specula measure --grid-preset paper --method linear --order nested
# --hdr bracket`), so that both sides carry it. One CSV row per truth, in the order they
# finish:
#
#   truth,rel,log,paper_rel,paper_log,samples,simulated_hours,wall_s,fallback,energy,normal
#
# `normal` is the table's spread over phi_d at theta_h 0 (`consistency_normal`), followed by
# `fallback` where one half of phi_d took the un-deblurred values to restore it.
#
#   cargo build --release -p specula-cli
#   SPECULA=target/release/specula JOBS=2 tools/all_fits_through_device.sh > fits.csv
#   python3 tools/all_fits_summary.py fits.csv
#
# TRUTH arguments replace the full list. Each truth's files are removed once it is scored.
# PAPER=fits.csv reuses the paper's-way figures of an earlier run for the truths it has (they
# do not depend on `specula measure`'s defaults, and they are the slow half): re-measuring the
# default after a change then takes under a minute per truth.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SPECULA:-$here/target/release/specula}"
work="${WORK:-$(mktemp -d)}"
data="$here/crates/specula-formats/data"
if [ "$#" -eq 0 ]; then
    set -- $(
        sed 's/^/nbrdf:/' "$data/merl_nbrdf/merl100_names.txt"
        sed 's/^/nbrdf-rgl:/' "$data/merl_nbrdf/rgl_isotropic_names.txt"
        tail -n +2 "$data/merl_fits_djbrdf/merl_sgd_bagher2012.csv" | cut -d, -f1 | sed 's/^/sgd:/'
        tail -n +2 "$data/merl_fits_djbrdf/merl_abc_low2012.csv" | cut -d, -f1 | sed 's/^/abc:/'
    )
fi
one() { # truth -> one CSV row
    local truth="$1" dir
    dir="$work/${truth//[:\/]/_}"
    mkdir -p "$dir"
    local start end
    start=$(date +%s.%N)
    if ! "$bin" measure --truth "$truth" --seed 1 --out "$dir/m.binary" > "$dir/m.log" 2>&1; then
        echo "$truth,error: measure failed"; return
    fi
    end=$(date +%s.%N)
    "$bin" tabulate "$truth" --out "$dir/t.binary" > /dev/null 2>&1
    local ours paper
    ours=$("$bin" compare "$dir/m.binary" "$dir/t.binary" 2>/dev/null | awk -F, '$1 == "within" { print $3 "," $4 }')
    paper=""
    if [ -n "${PAPER:-}" ]; then
        paper=$(awk -F, -v t="$truth" '$1 == t && $4 != "" { print $4 "," $5; exit }' "$PAPER")
    fi
    if [ -z "$paper" ]; then
        paper=$("$bin" evaluate --truth "$truth" --through-instrument --grid-preset paper \
            --method linear 2>/dev/null | tail -n 1 | cut -d, -f4,5)
        if awk -F, '{ exit !($1 < 0.03) }' <<< "$paper"; then
            "$bin" measure --truth "$truth" --seed 1 --grid-preset paper --method linear \
                --order nested --hdr bracket --out "$dir/p.binary" > /dev/null 2>&1
            paper=$("$bin" compare "$dir/p.binary" "$dir/t.binary" 2>/dev/null | awk -F, '$1 == "within" { print $3 "," $4 }')
        fi
    fi
    local samples hours fallback energy
    samples=$(sed -n 's/^measured_samples=//p' "$dir/m.log")
    hours=$(sed -n 's/^simulated_hours=//p' "$dir/m.log")
    fallback=$(sed -n 's/^deblur_fallback=\([a-z ]*\).*/\1/p' "$dir/m.log" | sed 's/ *$//')
    energy=$(grep -q '^energy_conserved=' "$dir/m.log" && echo scaled || echo kept)
    normal=$(sed -n 's/^consistency_normal=the table varies \([0-9.]*\)x.*/\1/p' "$dir/m.log")
    grep -q '^deblur_fallback_normal=' "$dir/m.log" && normal="$normal fallback"
    echo "$truth,$ours,$paper,$samples,$hours,$(echo "$end - $start" | bc),${fallback:-none},$energy,${normal:-}"
    rm -rf "$dir"
}
export -f one
export bin work PAPER
printf '%s\n' "$@" | xargs -P "${JOBS:-1}" -I{} bash -c 'one "$1"' _ {}
