#!/usr/bin/env python3
"""Benchmarks of the Python package (issue 19's targets), against numpy doing the same work.

1. Reading a 35 MB MERL .binary into a (90, 90, 180, 3) array of f_r in 1/sr:
   `specula.read_merl` (header, length and every value checked, NaN where not measured)
   against `numpy.fromfile` + reshape + the channel scale (no checks, no mask).
2. Evaluating 10^6 direction pairs of `silver-925` (GGX alpha 0.04 rough conductor, exact
   Fresnel, separable Smith G): `Brdf.eval` against the same model vectorised in numpy
   (the model of tools/tabulate_numpy.py, from directions); the two are checked equal.
   numpy runs on one thread, `Brdf.eval` on all cores (`RAYON_NUM_THREADS=1` for one).
   numpy's Fresnel is the complex-amplitude form; the same numpy with the Fresnel in real
   arithmetic (the form specula-core evaluates, Moeller 1988) is timed too, as the faster
   numpy baseline.
3. `Brdf.eval` of other sources, which evaluate pair by pair (`Brdf::eval_pairs`' default):
   a MERL table, an RGL `.bsdf` file (when the shared data set is there) and an NBRDF fit,
   10^5 pairs each (crates/specula-py/tests check them against `specula eval`).

Best and median of the runs, page cache warm; the three evaluations of 2. run in turn, round
by round, so that a change in the machine's load falls on all of them. Needs the package
(`pip install ./crates/specula-py`):

    python3 tools/python_bench.py
    RAYON_NUM_THREADS=1 python3 tools/python_bench.py   # Brdf.eval on one thread, as numpy
"""
import os
import statistics
import sys
import tempfile
import time

import numpy as np

import specula

sys.path.insert(0, os.path.dirname(__file__))
from tabulate_numpy import ALPHA, ETA, K, SCALE, fresnel_conductor, g1  # noqa: E402


def numpy_read(path):
    """numpy.fromfile, the reshape to (90, 90, 180, 3) (a view) and the scale."""
    planes = np.fromfile(path, dtype="<f8", offset=12).reshape(3, 90, 90, 180)
    return np.moveaxis(planes, 0, -1) * SCALE


def fresnel_conductor_real(cos_i):
    """fresnel_conductor in real arithmetic (Moeller 1988; specula-core's fresnel::conductor)."""
    c = np.clip(cos_i, 0.0, 1.0)[None, :]
    eta, k = ETA[:, None], K[:, None]
    cos2 = c * c
    sin2 = 1.0 - cos2
    temp = eta * eta - k * k - sin2
    a2_plus_b2 = np.sqrt(temp * temp + 4.0 * eta * eta * k * k)
    a = np.sqrt(np.maximum(0.5 * (a2_plus_b2 + temp), 0.0))
    term_1, term_2 = a2_plus_b2 + cos2, 2.0 * c * a
    term_3, term_4 = a2_plus_b2 * cos2 + sin2 * sin2, term_2 * sin2
    return (term_1 - term_2) * term_3 / ((term_1 + term_2) * (term_3 + term_4))


def numpy_eval(wi, wo, fresnel=fresnel_conductor):
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
    return (fresnel(cos_d) * microfacet).T


RGL_FILE = "/work/shared/data/measured/rgl_bsdf/satin_rosaline_rgb.bsdf"


def timed(function, runs):
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        function()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times)


def timed_interleaved(functions, rounds):
    """Best and median time of each function, the functions run in turn in each round, so
    that a change in the machine's load falls on all of them."""
    times = [[] for _ in functions]
    for _ in range(rounds):
        for function, kept in zip(functions, times):
            t0 = time.perf_counter()
            function()
            kept.append(time.perf_counter() - t0)
    return [(min(kept), statistics.median(kept)) for kept in times]


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
    expected = numpy_eval(wi, wo)
    np.testing.assert_allclose(brdf.eval(wi, wo), expected, rtol=1e-9, atol=1e-300)
    np.testing.assert_allclose(numpy_eval(wi, wo, fresnel_conductor_real), expected, rtol=1e-12, atol=1e-300)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    threads = os.environ.get("RAYON_NUM_THREADS") or cores
    ours, theirs, theirs_real = timed_interleaved(
        [lambda: brdf.eval(wi, wo), lambda: numpy_eval(wi, wo),
         lambda: numpy_eval(wi, wo, fresnel_conductor_real)],
        6,
    )
    print(f"Brdf.eval, 10^6 pairs, {threads} thread(s): best {ours[0] * 1e3:.1f} ms, median {ours[1] * 1e3:.1f} ms")
    for label, (best, median) in [("numpy eval", theirs), ("numpy eval, real Fresnel", theirs_real)]:
        print(f"{label}, 10^6 pairs, 1 thread: best {best * 1e3:.1f} ms, median {median * 1e3:.1f} ms")
        print(f"  speed-up: {best / ours[0]:.1f}x (best), {median / ours[1]:.1f}x (medians)")

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
