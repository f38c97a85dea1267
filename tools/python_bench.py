#!/usr/bin/env python3
"""Benchmarks of the Python package (issue 19's targets), against numpy doing the same work.

1. Reading a 35 MB MERL .binary into a (90, 90, 180, 3) array of f_r in 1/sr:
   `specula.read_merl` (header, length and every value checked, NaN where not measured)
   against `numpy.fromfile` + reshape + the channel scale (no checks, no mask).
2. Evaluating 10^6 direction pairs of `silver-925` (GGX alpha 0.04 rough conductor, exact
   Fresnel, separable Smith G): `Brdf.eval` against the same model vectorised in numpy
   (the model of tools/tabulate_numpy.py, from directions); the two are checked equal.
3. `Brdf.eval` of other sources, which evaluate pair by pair (`Brdf::eval_pairs`' default):
   a MERL table, an RGL `.bsdf` file (when the shared data set is there) and an NBRDF fit,
   10^5 pairs each (crates/specula-py/tests check them against `specula eval`).

Best and median of the runs, page cache warm. Needs the package (`pip install
./crates/specula-py`):

    python3 tools/python_bench.py
"""
import os
import statistics
import sys
import tempfile
import time

import numpy as np

import specula

sys.path.insert(0, os.path.dirname(__file__))
from tabulate_numpy import ALPHA, SCALE, fresnel_conductor, g1  # noqa: E402


def numpy_read(path):
    """numpy.fromfile, the reshape to (90, 90, 180, 3) (a view) and the scale."""
    planes = np.fromfile(path, dtype="<f8", offset=12).reshape(3, 90, 90, 180)
    return np.moveaxis(planes, 0, -1) * SCALE


def numpy_eval(wi, wo):
    """silver-925 at direction pairs, (N, 3), in numpy."""
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    cos_i, cos_o, cos_h = wi[:, 2], wo[:, 2], h[:, 2]
    cos_d = np.sum(wi * h, axis=1)
    above = (cos_i > 0) & (cos_o > 0)
    ci, co = np.where(above, cos_i, 1.0), np.where(above, cos_o, 1.0)
    cos2_h = cos_h**2
    t = (1.0 - cos2_h) / (cos2_h * ALPHA**2)
    d = 1.0 / (np.pi * ALPHA**2 * cos2_h**2 * (1.0 + t) ** 2)
    microfacet = np.where(above, d * g1(ci) * g1(co) / (4.0 * ci * co), 0.0)
    return (fresnel_conductor(cos_d) * microfacet).T


RGL_FILE = "/work/shared/data/measured/rgl_bsdf/satin_rosaline_rgb.bsdf"


def timed(function, runs):
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        function()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times)


def random_directions(rng, n):
    theta = np.radians(rng.uniform(0.0, 89.0, n))
    phi = np.radians(rng.uniform(0.0, 360.0, n))
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], 1)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "silver.binary")
        specula.write_merl(path, specula.load("silver-925").tabulate())
        np.testing.assert_allclose(specula.read_merl(path), numpy_read(path), rtol=1e-15)
        for label, read in [("specula.read_merl", specula.read_merl), ("numpy fromfile+reshape+scale", numpy_read)]:
            best, median = timed(lambda: read(path), 20)
            print(f"{label}: best {best * 1e3:.1f} ms, median {median * 1e3:.1f} ms")

    rng = np.random.default_rng(1)
    n = 1_000_000
    wi, wo = random_directions(rng, n), random_directions(rng, n)
    brdf = specula.load("silver-925")
    np.testing.assert_allclose(brdf.eval(wi, wo), numpy_eval(wi, wo), rtol=1e-9, atol=1e-300)
    ours = timed(lambda: brdf.eval(wi, wo), 10)
    theirs = timed(lambda: numpy_eval(wi, wo), 5)
    print(f"Brdf.eval, 10^6 pairs: best {ours[0] * 1e3:.1f} ms, median {ours[1] * 1e3:.1f} ms")
    print(f"numpy eval, 10^6 pairs: best {theirs[0] * 1e3:.1f} ms, median {theirs[1] * 1e3:.1f} ms")
    print(f"speed-up: {theirs[0] / ours[0]:.1f}x (best), {theirs[1] / ours[1]:.1f}x (medians)")

    with tempfile.TemporaryDirectory() as tmp:
        table = os.path.join(tmp, "silver-925.binary")
        specula.write_merl(table, brdf.tabulate())
        n = 100_000
        wi, wo = wi[:n].copy(), wo[:n].copy()
        for source in [table, RGL_FILE, "nbrdf:alum-bronze"]:
            if not os.path.exists(source) and source != "nbrdf:alum-bronze":
                print(f"{source}: not found, skipped")
                continue
            other = specula.load(source)
            best, median = timed(lambda: other.eval(wi, wo), 3)
            print(f"Brdf.eval of {other.name}, 10^5 pairs: best {best * 1e3:.1f} ms, median {median * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
