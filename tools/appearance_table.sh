#!/usr/bin/env bash
# The appearance table of docs/book/src/appearance.md, generated from the program's output:
# `specula appearance --csv` of the presets and of the RGL measurements, a selection of its
# columns as a Markdown table with 3 significant figures.
#
#   tools/appearance_table.sh [BRDF...] > table.md
#
# Default BRDFs: the five presets and every .bsdf file of the RGL folder
# ($SPECULA_MEASURED_DIR/rgl_bsdf, else ../shared/data/measured/rgl_bsdf beside the clone).
# The binary: $SPECULA (default: specula on PATH).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SPECULA:-specula}"
rgl="${SPECULA_MEASURED_DIR:-$here/../shared/data/measured}/rgl_bsdf"
if [ "$#" -eq 0 ]; then
    set -- silver-925 silver-925-scratched green-paint chrome steel
    for f in "$rgl"/*.bsdf; do
        [ -e "$f" ] && set -- "$@" "$f"
    done
fi
columns="gloss_20 gloss_60 gloss_85 haze doi haze_20 L_15 L_45 L_110 a_45 b_45 flop_index"
"$bin" appearance "$@" --csv | python3 -c '
import csv, math, os, sys
columns = sys.argv[1].split()
def fig(text):
    if text == "":
        return "n/a"
    v = float(text)
    if v == 0:
        return "0"
    digits = max(0, 2 - int(math.floor(math.log10(abs(v)))))
    return f"{v:.{digits}f}"
rows = list(csv.DictReader(sys.stdin))
print("| BRDF | " + " | ".join(columns) + " |")
print("|---" * (len(columns) + 1) + "|")
for row in rows:
    name = os.path.basename(row["source"])
    print(f"| `{name}` | " + " | ".join(fig(row[c]) for c in columns) + " |")
' "$columns"
