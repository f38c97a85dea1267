#!/usr/bin/env python3
"""Reference values for the probe model's spline (crates/specula-sampling/src/probe_model.rs).

SciPy's CubicSpline with bc_type=((1, 0.0), (2, 0.0)) (slope 0 at the first knot, second
derivative 0 at the last) through ln(f + floor) of GGX-like lobes sampled like the probe
(90 square-root-spaced theta_h), evaluated at 268 points. Writes
crates/specula-sampling/tests/data/log_spline_reference.csv with columns
case,kind,t,z (kind = knot or query; z of a query is SciPy's value).

    python3 tools/log_spline_reference.py
"""
import os

import numpy as np
from scipy.interpolate import CubicSpline

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "../crates/specula-sampling/tests/data/log_spline_reference.csv")


def lobe(theta_deg, alpha_rad, floor):
    th = np.radians(np.minimum(theta_deg, 85.0))
    t2 = np.tan(th) ** 2
    return alpha_rad**2 / (np.pi * np.cos(th) ** 4 * (alpha_rad**2 + t2) ** 2) + floor


def main():
    rows = []
    rng = np.random.default_rng(7)
    for case, (alpha, floor, noise) in enumerate([(0.003, 0.01, 0.0), (0.03, 0.1, 0.0), (0.2, 0.5, 0.02)]):
        t = np.linspace(0.0, 90.0, 90)
        y = lobe(t**2 / 90.0, alpha, floor) * (1.0 + noise * rng.standard_normal(t.size))
        z = np.log(y)
        spline = CubicSpline(t, z, bc_type=((1, 0.0), (2, 0.0)))
        query = np.sort(np.concatenate([np.linspace(0.0, 90.0, 268), rng.uniform(0, 90, 32)]))
        rows += [(case, "knot", a, b) for a, b in zip(t, z)]
        rows += [(case, "query", a, b) for a, b in zip(query, spline(query))]
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    with open(OUT, "w") as f:
        f.write("case,kind,t,z\n")
        for case, kind, a, b in rows:
            f.write(f"{case},{kind},{float(a)!r},{float(b)!r}\n")
    print(f"wrote {len(rows)} rows to {os.path.relpath(OUT)}")


if __name__ == "__main__":
    main()
