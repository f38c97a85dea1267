#!/usr/bin/env python3
"""Reference linear-sRGB values of the 24 ColorChecker patches, computed with colour-science.

Independent check of `crates/specula-acquisition/src/calibration/colorchecker.rs`, which
converts X-Rite's published L*a*b* (D50) values of the ColorChecker Classic (editions from
November 2014 on) to linear sRGB (D65) by the CIE formulas and a Bradford adaptation.

Usage (needs `pip install colour-science numpy`):

    python3 tools/colorchecker_reference.py > crates/specula-acquisition/tests/data/colorchecker_linear_srgb.csv
"""
import sys
import warnings

import colour
import numpy as np

warnings.filterwarnings("ignore")

checker = colour.CCS_COLOURCHECKERS["ColorChecker24 - After November 2014"]
srgb = colour.RGB_COLOURSPACES["sRGB"]
print("name,r,g,b")
for name, xyY in checker.data.items():
    xyz = colour.xyY_to_XYZ(xyY)
    rgb = colour.XYZ_to_RGB(
        xyz,
        srgb,
        illuminant=checker.illuminant,
        chromatic_adaptation_transform="Bradford",
        apply_cctf_encoding=False,
    )
    print(f"{name},{rgb[0]:.6f},{rgb[1]:.6f},{rgb[2]:.6f}")
sys.stdout.flush()
