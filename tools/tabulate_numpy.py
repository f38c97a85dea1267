#!/usr/bin/env python3
"""The numpy baseline of issue 2 item 5: tabulate the `silver-925` preset (GGX alpha 0.04
rough conductor, Johnson & Christy 1972 silver) into the MERL grid, vectorised.

Same bin centres as specula (theta_h = (i + 0.5)^2 / 90 deg, theta_d = j + 0.5 deg,
phi_d = k + 0.5 deg), same model (exact conductor Fresnel, GGX D, separable Smith G) and the
same shortcut from half-difference angles to the cosines the isotropic model needs. Reports
the best and median of 5 runs. Compare with `cargo bench -p specula-core --bench tabulate`.

    python3 tools/tabulate_numpy.py
    python3 tools/tabulate_numpy.py --check silver.binary   # from `specula tabulate silver-925`
"""
import argparse
import statistics
import time

import numpy as np

ALPHA = 0.04
ETA = np.array([0.052, 0.060, 0.040])
K = np.array([4.409, 3.597, 2.648])
SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])


def bin_centres():
    """Half-difference angles (radians) of every MERL cell, in file order."""
    theta_h = np.radians((np.arange(90) + 0.5) ** 2 / 90.0)
    theta_d = np.radians(np.arange(90) + 0.5)
    phi_d = np.radians(np.arange(180) + 0.5)
    return np.meshgrid(theta_h, theta_d, phi_d, indexing="ij")


def g1(cos_v):
    tan2 = ALPHA**2 * (1.0 - cos_v**2) / cos_v**2
    return 2.0 / (1.0 + np.sqrt(1.0 + tan2))


def fresnel_conductor(cos_i):
    """Exact unpolarised reflectance, shape (3, ...) for the three channels."""
    n = (ETA + 1j * K)[:, None]
    n2 = n * n
    c = cos_i.reshape(1, -1)
    n_cos_t = np.sqrt(n2 - (1.0 - c * c))
    r_s = (c - n_cos_t) / (c + n_cos_t)
    r_p = (n2 * c - n_cos_t) / (n2 * c + n_cos_t)
    return 0.5 * (np.abs(r_s) ** 2 + np.abs(r_p) ** 2)


def tabulate(theta_h, theta_d, phi_d):
    cos_h, sin_h = np.cos(theta_h), np.sin(theta_h)
    cos_d, sin_d = np.cos(theta_d), np.sin(theta_d)
    cos_i = cos_h * cos_d - sin_h * sin_d * np.cos(phi_d)
    cos_o = 2.0 * cos_h * cos_d - cos_i
    above = (cos_i > 0) & (cos_o > 0)
    ci, co = np.where(above, cos_i, 1.0), np.where(above, cos_o, 1.0)
    cos2_h = cos_h**2
    t = (1.0 - cos2_h) / (cos2_h * ALPHA**2)
    d = 1.0 / (np.pi * ALPHA**2 * cos2_h**2 * (1.0 + t) ** 2)
    microfacet = d * g1(ci) * g1(co) / (4.0 * ci * co)
    f = fresnel_conductor(cos_d.ravel()) * np.where(above, microfacet, 0.0).ravel()
    return f / SCALE[:, None]  # stored MERL values, (3, 1458000)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", help="a MERL .binary of silver-925 to compare with")
    args = parser.parse_args()
    angles = bin_centres()
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        table = tabulate(*angles)
        times.append(time.perf_counter() - t0)
    print(f"numpy tabulation of silver-925: best {min(times):.3f} s, median {statistics.median(times):.3f} s")
    if args.check:
        with open(args.check, "rb") as f:
            dims = np.fromfile(f, dtype="<i4", count=3)
            theirs = np.fromfile(f, dtype="<f8").reshape(3, -1)
        assert list(dims) == [90, 90, 180], dims
        relative = np.abs(table - theirs) / np.maximum(np.abs(theirs), 1e-9)
        print(f"max relative difference from {args.check}: {relative.max():.2e}")


if __name__ == "__main__":
    main()
