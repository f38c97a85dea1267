#!/usr/bin/env python3
"""Reference data for `specula fit`'s Mitsuba 3 export, from Mitsuba 3 itself.

For each test case (a conductor preset, the green paint, and a real RGL file fitted with the
conductor; no rough coat, see docs/book/src/renderers.md, "Fitted materials for renderers": Mitsuba's single-scattering
`roughplastic` darkens the base of rough coats, which Specula's coat does not):

1. `specula fit SOURCE --model MODEL --out <case>.toml --mitsuba <case>.xml` fits the model and
   writes the fitted material (Specula's TOML) and the Mitsuba 3 scene holding it, both into
   crates/specula-formats/tests/data/fit_export_<case>.{toml,xml};
2. Mitsuba 3.9.1 (variant scalar_rgb) loads the scene XML, takes the sphere's BSDF and
   evaluates it at 2100 direction pairs (seeded): 1400 uniform over the hemisphere pair
   (elevations up to 85 deg) and 700 near the mirror direction (wi up to 80 deg, half vector
   |N(0, 1.5 deg)| mod 5 deg from the normal), writing

       crates/specula-formats/tests/data/fit_export_mitsuba_<case>.csv

   with the header theta_i,phi_i,theta_o,phi_o,r,g,b (degrees, printed exactly; f_r in 1/sr,
   Mitsuba's eval divided by cos(theta_o)).

crates/specula-formats/tests/fit_export_mitsuba.rs checks that the export of the committed
TOML is the committed XML and that Specula's evaluation of the fitted material agrees with
Mitsuba's; CI needs no Python.

Usage (from the repository root, after `cargo build -p specula-cli`):
    python3 tools/fit_export_check.py [--specula target/debug/specula]
Needs: mitsuba 3.9.1 and numpy (pip install mitsuba==3.9.1 numpy).
"""

import argparse
import os
import subprocess
import sys

import mitsuba as mi

mi.set_variant("scalar_rgb")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rgl_vectors import DATA as MEASURED  # noqa: E402
from rgl_export_check import write_vectors  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "crates", "specula-formats", "tests", "data")
RGL = os.path.join(MEASURED, "rgl_bsdf")
# case -> (BRDF source, model)
CASES = {
    "silver-925": ("silver-925", "conductor"),
    "green-paint": ("green-paint", "coat"),
    "cc_ibiza_sunset_conductor": (os.path.join(RGL, "cc_ibiza_sunset_rgb.bsdf"), "conductor"),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--specula", default=os.path.join(ROOT, "target", "debug", "specula"))
    args = parser.parse_args()
    for k, (case, (source, model)) in enumerate(CASES.items()):
        toml = os.path.join(OUT, f"fit_export_{case}.toml")
        xml = os.path.join(OUT, f"fit_export_{case}.xml")
        subprocess.run(
            [args.specula, "fit", source, "--model", model, "--out", toml, "--mitsuba", xml],
            check=True,
        )
        bsdf = mi.load_file(xml).shapes()[0].bsdf()
        write_vectors(bsdf, os.path.join(OUT, f"fit_export_mitsuba_{case}.csv"), 280 + k)
    return 0


if __name__ == "__main__":
    sys.exit(main())
