#!/usr/bin/env python3
"""Reference data for Specula's RGL `.bsdf` writer, from Mitsuba 3's own `measured` plugin.

For each test material (a sharp conductor, the green paint, the five real RGL files written
again from the original, the MERL tabulations of the five, three neural fits of MERL materials):

1. `specula convert SOURCE out.bsdf` writes the file at the default resolution (a MERL
   tabulation is first written by `specula tabulate SOURCE --out tabulated.binary`);
2. Mitsuba 3.9.1 (variant scalar_rgb) loads it with `measured` and evaluates it at 2100
   direction pairs (seeded), the fixed set over which the writer's fidelity is measured:
   1400 uniform over the hemisphere pair (cos theta uniform, elevations up to 85 deg,
   azimuths uniform) and 700 near the mirror direction (wi uniform in cos theta up to 80 deg,
   the half vector |N(0, 1.5 deg)| mod 5 deg from the normal), writing

       crates/specula-formats/tests/data/rgl_export_mitsuba_<material>.csv

   with the header theta_i,phi_i,theta_o,phi_o,r,g,b (degrees, printed exactly; f_r in 1/sr,
   Mitsuba's eval divided by cos(theta_o));
3. Mitsuba renders the unit sphere with that file, at the settings of tools/mitsuba_render_check.py
   (standard camera, box filter, `direct` integrator) under the standard point light and a
   constant environment of radiance 1, writing

       crates/specula-visual/tests/data/mitsuba_rgl_<material>_{point,constant}.exr

   which crates/specula-visual/tests/mitsuba_check.rs compares with Specula's render of the
   source itself; for a source that is itself a `.bsdf` file, Mitsuba's renders of the
   original file too (mitsuba_rgl_<material>_original_{point,constant}.exr), which separate
   the writer's fidelity (written against original, both in Mitsuba) from the renderers'
   agreement (Specula's render of the original against Mitsuba's).

The Rust tests read these committed files, so CI needs no Python:
`cargo test -p specula-formats --test rgl_export_mitsuba -- --nocapture` prints, per material,
the fraction of the 2100 pairs at which Mitsuba's value of the written file is within 5 % of
the source (docs/book/src/renderers.md). Only the first three materials are rendered.

Usage (from the repository root, after `cargo build --release`):
    python3 tools/rgl_export_check.py [--specula target/release/specula] [--size 128]
Needs: mitsuba 3.9.1 and numpy (pip install mitsuba==3.9.1 numpy).
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
# The original RGL files hold small negative (out-of-gamut) values, which Mitsuba renders as
# they are and warns about once per sample.
mi.set_log_level(mi.LogLevel.Error)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_render_check import FOV_X_DEG, CAMERA_ORIGIN, POINT_POSITION, POINT_INTENSITY  # noqa: E402
from rgl_vectors import DATA as MEASURED, direction, near_mirror_pair  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VECTORS = os.path.join(ROOT, "crates", "specula-formats", "tests", "data")
RENDERS = os.path.join(ROOT, "crates", "specula-visual", "tests", "data")
RGL_FILES = [
    "cc_ibiza_sunset_rgb",
    "cc_iris_purple_gem_rgb",
    "colodur_napoli_4f_rgb",
    "paper_white_rgb",
    "satin_rosaline_rgb",
]
NBRDF_FITS = ["gold-metallic-paint", "specular-blue-phenolic", "red-fabric"]
# name -> (BRDF source given to `specula convert`, whether it is first tabulated into the MERL
# grid, whether Mitsuba renders it); the order fixes each material's seed.
MATERIALS = {
    "chrome": ("chrome", False, True),
    "green-paint": ("green-paint", False, True),
    "cc_ibiza_sunset_rgb": (os.path.join(MEASURED, "rgl_bsdf", "cc_ibiza_sunset_rgb.bsdf"), False, True),
    **{f"merl_{name}": (os.path.join(MEASURED, "rgl_bsdf", name + ".bsdf"), True, False) for name in RGL_FILES},
    **{f"nbrdf_{name}": (f"nbrdf:{name}", False, False) for name in NBRDF_FITS},
    # The other four real files written directly from the original (appended: the order above
    # keeps its seeds).
    **{name: (os.path.join(MEASURED, "rgl_bsdf", name + ".bsdf"), False, False) for name in RGL_FILES[1:]},
}
MAX_ELEVATION_DEG = 85.0
REFERENCE_SPP = {"point": 256, "constant": 1024}


def uniform_pair(rng):
    cos_max = math.cos(math.radians(MAX_ELEVATION_DEG))
    pick = lambda: (math.degrees(math.acos(rng.uniform(cos_max, 1.0))), rng.uniform(0.0, 360.0))
    return pick() + pick()


def write_vectors(bsdf, target, seed):
    """Evaluates the Mitsuba `bsdf` at the 2100 seeded direction pairs into the CSV `target`."""
    ctx = mi.BSDFContext()
    rng = np.random.default_rng(seed)
    pairs = [uniform_pair(rng) for _ in range(1400)] + [near_mirror_pair(rng, 1.5, 5.0, MAX_ELEVATION_DEG) for _ in range(700)]
    rows = []
    for ti, pi_, to, po in pairs:
        wi, wo = direction(ti, pi_), direction(to, po)
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*wi)
        value = np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo)), dtype=np.float64) / wo[2]
        rows.append(f"{ti!r},{pi_!r},{to!r},{po!r},{value[0]:.9g},{value[1]:.9g},{value[2]:.9g}")
    with open(target, "w") as f:
        f.write("theta_i,phi_i,theta_o,phi_o,r,g,b\n")
        f.write("\n".join(rows) + "\n")
    print(f"wrote {os.path.relpath(target, ROOT)}: {len(rows)} direction pairs", file=sys.stderr)


def render(name, path, lighting, size):
    emitter = (
        {"type": "point", "position": POINT_POSITION,
         "intensity": {"type": "rgb", "value": [POINT_INTENSITY] * 3}}
        if lighting == "point"
        else {"type": "constant", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}}
    )
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct"},
        "sensor": {
            "type": "perspective", "fov": FOV_X_DEG, "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(origin=CAMERA_ORIGIN, target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": size, "height": size,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": REFERENCE_SPP[lighting]},
        },
        "sphere": {"type": "sphere", "radius": 1.0, "bsdf": {"type": "measured", "filename": path}},
        "light": emitter,
    })
    target = os.path.join(RENDERS, f"mitsuba_rgl_{name}_{lighting}.exr")
    mi.Bitmap(mi.render(scene)).write(target)
    print(f"wrote {os.path.relpath(target, ROOT)}", file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--specula", default=os.path.join(ROOT, "target", "release", "specula"))
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--no-render", action="store_true", help="write the vectors only")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, (source, tabulated, rendered)) in enumerate(MATERIALS.items()):
            path = os.path.join(tmp, f"{name}.bsdf")
            if tabulated:
                merl = os.path.join(tmp, f"{name}.binary")
                subprocess.run([args.specula, "tabulate", source, "--out", merl], check=True)
                source = merl
            subprocess.run([args.specula, "convert", source, path], check=True)
            bsdf = mi.load_dict({"type": "measured", "filename": path})
            write_vectors(bsdf, os.path.join(VECTORS, f"rgl_export_mitsuba_{name}.csv"), 180 + k)
            if rendered and not args.no_render:
                for lighting in ("point", "constant"):
                    render(name, path, lighting, args.size)
                    if source.endswith(".bsdf"):
                        render(f"{name}_original", source, lighting, args.size)
    return 0


if __name__ == "__main__":
    sys.exit(main())
