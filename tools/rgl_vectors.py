#!/usr/bin/env python3
"""Reference vectors for Specula's RGL `.bsdf` reader, from Mitsuba 3's `measured` plugin.

For each isotropic RGB file of the RGL material database in shared/data/measured/rgl_bsdf/,
evaluates Mitsuba 3 (variant scalar_rgb) at 1200 direction pairs and writes

    crates/specula-formats/tests/data/rgl_mitsuba_<material>.csv

with the header theta_i,phi_i,theta_o,phi_o,r,g,b: angles in degrees (printed exactly), and
f_r in 1/sr per channel. Mitsuba's BSDF.eval returns f_r * cos(theta_o) (for this plugin the
stored RGL quantity itself); the script divides by cos(theta_o). Mitsuba does not clamp the
small negative (out-of-gamut) values of the data; they are written as they come.

Direction pairs (seeded, reproducible): 500 uniform over the hemisphere pair (elevations up to
88 deg), 500 near the mirror direction (half vector within about 15 deg of the normal, where
the glossy peaks are), 100 at normal incidence and 100 in (or, forward, 0.05 deg off) the plane of incidence.

Run from the repository root:  python3 tools/rgl_vectors.py
Needs: mitsuba 3.9.1 and numpy (pip install mitsuba==3.9.1 numpy).
"""

import math
import os
import sys

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.environ.get(
    "SPECULA_MEASURED_DIR", os.path.join(ROOT, "..", "shared", "data", "measured")
)
OUT = os.path.join(ROOT, "crates", "specula-formats", "tests", "data")
MATERIALS = [
    "cc_ibiza_sunset_rgb",
    "cc_iris_purple_gem_rgb",
    "colodur_napoli_4f_rgb",
    "paper_white_rgb",
    "satin_rosaline_rgb",
]
MAX_ELEVATION_DEG = 88.0


def direction(theta_deg, phi_deg):
    """The unit vector of spherical angles in degrees (z is the normal), as Specula builds it."""
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def angles(v):
    """Spherical angles in degrees of a unit vector, azimuth in [0, 360)."""
    theta = math.degrees(math.acos(max(-1.0, min(1.0, v[2]))))
    phi = math.degrees(math.atan2(v[1], v[0])) % 360.0
    return theta, phi


def uniform_angle_pair(rng):
    cos_max = math.cos(math.radians(MAX_ELEVATION_DEG))
    pick = lambda: (math.degrees(math.acos(rng.uniform(cos_max, 1.0))), rng.uniform(0.0, 360.0))
    return pick() + pick()


def near_mirror_pair(rng, spread_deg=6.0, cap_deg=15.0, max_elevation_deg=MAX_ELEVATION_DEG):
    """wi uniform up to 80 deg, wo = wi reflected about a half vector close to the normal
    (its elevation |N(0, spread_deg)| modulo cap_deg)."""
    while True:
        ti = math.degrees(math.acos(rng.uniform(math.cos(math.radians(80.0)), 1.0)))
        pi_ = rng.uniform(0.0, 360.0)
        h = direction(abs(rng.normal(0.0, spread_deg)) % cap_deg, rng.uniform(0.0, 360.0))
        wi = direction(ti, pi_)
        wo = 2.0 * wi.dot(h) * h - wi
        to, po = angles(wo / np.linalg.norm(wo))
        if to <= max_elevation_deg:
            return ti, pi_, to, po


def pairs(rng):
    out = [uniform_angle_pair(rng) for _ in range(500)]
    out += [near_mirror_pair(rng) for _ in range(500)]
    out += [(0.0, 0.0) + uniform_angle_pair(rng)[2:] for _ in range(100)]
    for _ in range(100):
        # In the plane of incidence, backward (same azimuth) or forward. Exactly forward, the
        # half vector's azimuth relative to wi is on the +-180 deg seam of the tables, where
        # Mitsuba's float32 rounding picks either side and the data differ by up to ~0.2%
        # across the seam; forward pairs are turned 0.05 deg off it.
        ti, pi_, to, _ = uniform_angle_pair(rng)
        turn = float(rng.choice([0.0, 180.05]))
        out.append((ti, pi_, to, (pi_ + turn) % 360.0))
    return out


def main():
    os.makedirs(OUT, exist_ok=True)
    ctx = mi.BSDFContext()
    for k, name in enumerate(MATERIALS):
        path = os.path.join(DATA, "rgl_bsdf", name + ".bsdf")
        bsdf = mi.load_dict({"type": "measured", "filename": path})
        rng = np.random.default_rng(20180 + k)
        rows = []
        for ti, pi_, to, po in pairs(rng):
            wi, wo = direction(ti, pi_), direction(to, po)
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(*wi)
            value = np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo)), dtype=np.float64) / wo[2]
            rows.append(
                f"{ti!r},{pi_!r},{to!r},{po!r},{value[0]:.9g},{value[1]:.9g},{value[2]:.9g}"
            )
        target = os.path.join(OUT, f"rgl_mitsuba_{name}.csv")
        with open(target, "w") as f:
            f.write("theta_i,phi_i,theta_o,phi_o,r,g,b\n")
            f.write("\n".join(rows) + "\n")
        print(f"{target}: {len(rows)} direction pairs (mitsuba {mi.__version__})", file=sys.stderr)


if __name__ == "__main__":
    main()
