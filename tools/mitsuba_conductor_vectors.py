#!/usr/bin/env python3
"""Reference vectors of Mitsuba 3's `roughconductor` for specula-core's rough conductor.

Evaluates `bsdf.eval(ctx, si, wo)` (variant scalar_rgb) at random direction pairs in the local
frame for GGX and Beckmann, several roughness values and two metals, divides out the
cos(theta_o) that Mitsuba's eval includes, and writes the BRDF in 1/sr to
crates/specula-core/tests/data/mitsuba_roughconductor.csv. The Rust test
`materials_mitsuba.rs` reads it; CI needs no Python.

Half of the pairs are uniform over the two hemispheres (tails, grazing angles); the other
half place the half vector within a few alpha of the normal (the highlight). Directions are
rounded to float32, Mitsuba's precision, and written with 9 significant digits, which
identify a float32 exactly, so both sides evaluate the same vectors.

Run from the repository root:  python3 tools/mitsuba_conductor_vectors.py
"""

import csv
import pathlib

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

PAIRS_PER_CONFIGURATION = 1000
SEED = 20240611
OUT = pathlib.Path("crates/specula-core/tests/data/mitsuba_roughconductor.csv")

# Optical constants at 650/550/450 nm (see crates/specula-core/src/materials/database.rs).
METALS = {
    "chromium": ([3.535, 2.901, 2.145], [4.348, 4.231, 3.862]),  # Rakic et al. 1998
    "gold": ([0.156, 0.424, 1.383], [3.602, 2.472, 1.915]),  # Johnson & Christy 1972
}
DISTRIBUTIONS = ["ggx", "beckmann"]
ALPHAS = [0.01, 0.05, 0.3]


def uniform_hemisphere(rng, n):
    """Uniform directions with cos(theta) in [0.02, 1)."""
    cos_t = rng.uniform(0.02, 1.0, n)
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    sin_t = np.sqrt(1.0 - cos_t**2)
    return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=1)


def near_highlight_pairs(rng, n, alpha):
    """wi uniform; wo the mirror of wi about a half vector within ~3 alpha of the normal."""
    wi = uniform_hemisphere(rng, 4 * n)
    theta_h = np.arctan(3.0 * alpha * np.sqrt(rng.uniform(0.0, 1.0, 4 * n)))
    phi_h = rng.uniform(0.0, 2.0 * np.pi, 4 * n)
    h = np.stack(
        [np.sin(theta_h) * np.cos(phi_h), np.sin(theta_h) * np.sin(phi_h), np.cos(theta_h)],
        axis=1,
    )
    wo = 2.0 * np.sum(wi * h, axis=1, keepdims=True) * h - wi
    keep = wo[:, 2] > 0.02
    return wi[keep][:n], wo[keep][:n]


def to_float32_unit(v):
    """Normalise in float64, then round to float32: the vectors both sides evaluate."""
    v = v / np.linalg.norm(v, axis=1, keepdims=True)
    return v.astype(np.float32)


def main():
    rng = np.random.default_rng(SEED)
    ctx = mi.BSDFContext()
    rows = []
    for distribution in DISTRIBUTIONS:
        for alpha in ALPHAS:
            for eta, k in METALS.values():
                bsdf = mi.load_dict(
                    {
                        "type": "roughconductor",
                        "distribution": distribution,
                        "alpha": alpha,
                        "eta": {"type": "rgb", "value": eta},
                        "k": {"type": "rgb", "value": k},
                    }
                )
                half = PAIRS_PER_CONFIGURATION // 2
                wi_u = uniform_hemisphere(rng, half)
                wo_u = uniform_hemisphere(rng, half)
                wi_h, wo_h = near_highlight_pairs(rng, PAIRS_PER_CONFIGURATION - half, alpha)
                wi_all = to_float32_unit(np.concatenate([wi_u, wi_h]))
                wo_all = to_float32_unit(np.concatenate([wo_u, wo_h]))
                for wi, wo in zip(wi_all, wo_all):
                    si = mi.SurfaceInteraction3f()
                    si.wi = mi.Vector3f(*(float(x) for x in wi))
                    value = bsdf.eval(ctx, si, mi.Vector3f(*(float(x) for x in wo)))
                    cos_o = float(wo[2])
                    f = [float(value[c]) / cos_o for c in range(3)]
                    rows.append(
                        [distribution, alpha, *eta, *k]
                        + [float(x) for x in wi]
                        + [float(x) for x in wo]
                        + f
                    )
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w", newline="") as out:
        writer = csv.writer(out)
        writer.writerow(
            "distribution,alpha,eta_r,eta_g,eta_b,k_r,k_g,k_b,"
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,f_r,f_g,f_b".split(",")
        )
        for row in rows:
            # 9 significant digits identify a float32 uniquely: the Rust test rounds the
            # directions back to f32 and gets Mitsuba's exact inputs.
            writer.writerow([row[0]] + [repr(x) for x in row[1:8]] + [f"{x:.9g}" for x in row[8:]])
    print(f"wrote {len(rows)} rows to {OUT}")


if __name__ == "__main__":
    main()
