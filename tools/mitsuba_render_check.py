#!/usr/bin/env python3
"""Checks `specula render` against Mitsuba 3 (scalar_rgb) at equal settings.

Both render the unit sphere of an analytic rough conductor (GGX, gold; the material file
crates/specula-visual/tests/data/mitsuba_conductor.toml) with the standard camera of
crates/specula-visual/src/camera.rs (at (0, 0, 4), looking at the origin, 34 deg horizontal
field of view, box pixel filter), under

  point     the standard point light: (-2.5, 3, 4), intensity 60 W/sr, black background;
  constant  a constant environment of radiance 1.

Mitsuba's `direct` integrator computes the same quantity as Specula's renderer (direct light
only, MIS of light and BSDF sampling). The script writes Mitsuba's linear images as
tests/data/mitsuba_{point,constant}.exr, which the Rust test tests/mitsuba_check.rs holds the
renderer against (so CI needs no Python), and, when a `specula` binary is given or built, the
figures tests/data/mitsuba_check_{point,constant}.png (Specula | Mitsuba | 10 x |difference|)
and the mean relative difference over the pixels fully covered by the sphere whose reference
luminance exceeds 0.1 percent of the brightest.

Usage:
    python3 tools/mitsuba_render_check.py [--specula target/release/specula] [--size 128]
"""

import argparse
import os
import subprocess
import sys
import tomllib

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "crates", "specula-visual", "tests", "data")
MATERIAL = os.path.join(DATA, "mitsuba_conductor.toml")

CAMERA_ORIGIN = [0.0, 0.0, 4.0]
FOV_X_DEG = 34.0
POINT_POSITION = [-2.5, 3.0, 4.0]
POINT_INTENSITY = 60.0
# Samples per pixel of the references: enough that their own noise is far below 1 percent.
REFERENCE_SPP = {"point": 256, "constant": 4096}
# Samples per pixel of Specula's renders in the figures (the Rust test uses the same).
SPECULA_SPP = {"point": 64, "constant": 256}


def conductor_bsdf():
    with open(MATERIAL, "rb") as f:
        base = tomllib.load(f)["base"]
    return {
        "type": "roughconductor",
        "distribution": base["distribution"],
        "alpha": base["alpha"],
        "sample_visible": True,
        "eta": {"type": "rgb", "value": base["eta"]},
        "k": {"type": "rgb", "value": base["k"]},
    }


def scene(lighting, size, spp):
    emitter = (
        {
            "type": "point",
            "position": POINT_POSITION,
            "intensity": {"type": "rgb", "value": [POINT_INTENSITY] * 3},
        }
        if lighting == "point"
        else {"type": "constant", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}}
    )
    return mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "direct"},
            "sensor": {
                "type": "perspective",
                "fov": FOV_X_DEG,
                "fov_axis": "x",
                "to_world": mi.ScalarTransform4f().look_at(
                    origin=CAMERA_ORIGIN, target=[0, 0, 0], up=[0, 1, 0]
                ),
                "film": {
                    "type": "hdrfilm",
                    "width": size,
                    "height": size,
                    "rfilter": {"type": "box"},
                    "pixel_format": "rgb",
                },
                "sampler": {"type": "independent", "sample_count": spp},
            },
            "sphere": {"type": "sphere", "radius": 1.0, "bsdf": conductor_bsdf()},
            "light": emitter,
        }
    )


def covered_mask(size):
    """Pixels whose four corners all see the unit sphere (the camera of camera.rs)."""
    half_width = np.tan(np.radians(FOV_X_DEG / 2))
    edges = np.arange(size + 1)
    sx = (2 * edges / size - 1) * half_width
    sy = (1 - 2 * edges / size) * half_width
    x, y = np.meshgrid(sx, sy)
    d = np.stack([x, y, -np.ones_like(x)], axis=-1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.array(CAMERA_ORIGIN)
    b = d @ o
    hit = b * b - (o @ o - 1.0) >= 0
    return hit[:-1, :-1] & hit[1:, :-1] & hit[:-1, 1:] & hit[1:, 1:]


def luminance(img):
    return img @ np.array([0.2126, 0.7152, 0.0722])


def mean_relative_difference(ours, reference):
    mask = covered_mask(reference.shape[0])
    lum = luminance(reference)
    mask &= lum > 1e-3 * lum[mask].max()
    rel = np.abs(ours[mask] - reference[mask]) / np.maximum(reference[mask], 1e-12)
    return float(rel.mean()), int(mask.sum())


def read_exr(path):
    return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]


def write_figure(path, ours, reference):
    diff = 10.0 * np.abs(ours - reference)
    strip = np.concatenate([ours, reference, diff], axis=1).astype(np.float32)
    bitmap = mi.Bitmap(np.clip(strip, 0.0, 1.0), pixel_format=mi.Bitmap.PixelFormat.RGB)
    bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--specula", default=os.path.join(ROOT, "target", "release", "specula"))
    parser.add_argument("--size", type=int, default=128)
    args = parser.parse_args()

    for lighting in ("point", "constant"):
        reference_path = os.path.join(DATA, f"mitsuba_{lighting}.exr")
        image = mi.render(scene(lighting, args.size, REFERENCE_SPP[lighting]))
        mi.Bitmap(image).write(reference_path)
        print(f"wrote {os.path.relpath(reference_path, ROOT)}")

        if not os.path.exists(args.specula):
            print(f"{args.specula} not found: build it (cargo build --release) for the figures")
            continue
        ours_path = os.path.join(DATA, f"specula_{lighting}.exr")
        light_args = ["--light", "point"] if lighting == "point" else ["--env", "constant:1"]
        subprocess.run(
            [args.specula, "render", MATERIAL, "--out", ours_path, "--size", str(args.size),
             "--spp", str(SPECULA_SPP[lighting])] + light_args,
            check=True,
        )
        ours, reference = read_exr(ours_path), read_exr(reference_path)
        os.remove(ours_path)
        figure = os.path.join(DATA, f"mitsuba_check_{lighting}.png")
        write_figure(figure, ours, reference)
        rel, pixels = mean_relative_difference(ours, reference)
        print(f"{lighting}: mean relative difference {100 * rel:.2f} % over {pixels} pixels; "
              f"wrote {os.path.relpath(figure, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
