#!/usr/bin/env python3
"""Reference values of the SGD (Bagher 2012) and ABC (Low 2012) fits of the MERL materials.

An independent numpy evaluation of the formulas in
shared/data/measured/merl_fits_djbrdf/PROVENANCE.md, written from that text (not from the Rust
code), for every material of both tables at 6 random half-difference configurations each.
Writes crates/specula-formats/tests/data/merl_fits_reference.csv, which the Rust tests in
crates/specula-formats/src/fits/ compare against.

    python3 tools/merl_fits_reference.py [MEASURED_DIR]
"""
import csv
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
MEASURED = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "../../shared/data/measured")
TABLES = os.path.join(MEASURED, "merl_fits_djbrdf")
OUT = os.path.join(HERE, "../crates/specula-formats/tests/data/merl_fits_reference.csv")
POINTS_PER_MATERIAL = 6


def directions(theta_h, phi_h, theta_d, phi_d):
    """Rusinkiewicz half/difference angles (radians) to (wi, wo)."""
    d = np.array([math.sin(theta_d) * math.cos(phi_d), math.sin(theta_d) * math.sin(phi_d), math.cos(theta_d)])
    c, s = math.cos(theta_h), math.sin(theta_h)
    wi = np.array([c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]])
    c, s = math.cos(phi_h), math.sin(phi_h)
    wi = np.array([c * wi[0] - s * wi[1], s * wi[0] + c * wi[1], wi[2]])
    h = np.array([math.sin(theta_h) * math.cos(phi_h), math.sin(theta_h) * math.sin(phi_h), math.cos(theta_h)])
    wo = 2.0 * wi.dot(h) * h - wi
    return wi, wo


def sgd(row, wi, wo):
    h = (wi + wo) / np.linalg.norm(wi + wo)
    cd = wi.dot(h)
    theta_h = math.acos(min(1.0, h[2]))
    out = []
    for ch in "rgb":
        p = {k: float(row[f"{k}_{ch}"]) for k in
             ["rhoD", "rhoS", "alpha", "p", "f0", "f1", "kap", "lambda", "c", "k", "theta0"]}
        fresnel = p["f0"] - cd * p["f1"] + (1 - cd) ** 5 * (1 - p["f0"])
        ax = p["alpha"] + math.tan(theta_h) ** 2 / p["alpha"]
        dist = p["kap"] * math.exp(-ax) / math.pi / (ax ** p["p"] * math.cos(theta_h) ** 4)

        def g1(w):
            x = max(0.0, math.acos(w[2]) - p["theta0"])
            return min(1.0, max(0.0, 1 + p["lambda"] * (1 - math.exp(p["c"] * x ** p["k"]))))

        f = (p["rhoD"] + p["rhoS"] * fresnel * dist * g1(wi) * g1(wo) / (wi[2] * wo[2])) / math.pi
        out.append(max(0.0, f))
    return out


def fresnel_dielectric(cos_i, n):
    sin_t2 = (1 - cos_i * cos_i) / (n * n)
    if sin_t2 >= 1:
        return 1.0
    cos_t = math.sqrt(1 - sin_t2)
    rs = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    rp = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    return 0.5 * (rs * rs + rp * rp)


def abc(row, wi, wo):
    h = (wi + wo) / np.linalg.norm(wi + wo)
    geometry = min(1.0, 2 * h[2] * wi[2] / wi.dot(h), 2 * h[2] * wo[2] / wo.dot(h))
    fresnel = fresnel_dielectric(wi.dot(h), float(row["ior"]))
    out = []
    for ch in "rgb":
        dist = float(row[f"A_{ch}"]) / (1 + float(row["B"]) * (1 - h[2])) ** float(row["C"])
        f = float(row[f"kD_{ch}"]) / math.pi + fresnel * dist * geometry / (math.pi * wi[2] * wo[2])
        out.append(max(0.0, f))
    return out


def main():
    rng = np.random.default_rng(20120601)
    rows = []
    for model, file, evaluate in [("sgd", "merl_sgd_bagher2012.csv", sgd), ("abc", "merl_abc_low2012.csv", abc)]:
        with open(os.path.join(TABLES, file)) as f:
            for row in csv.DictReader(f):
                made = 0
                while made < POINTS_PER_MATERIAL:
                    # The first point sits on the specular peak; the others anywhere well
                    # above the horizon.
                    th = 0.0 if made == 0 else rng.uniform(0, 80)
                    ph, td, pd = rng.uniform(0, 360), rng.uniform(0, 80), rng.uniform(0, 360)
                    wi, wo = directions(*map(math.radians, (th, ph, td, pd)))
                    if min(wi[2], wo[2]) < 0.05:
                        continue
                    rows.append([model, row["material"], th, ph, td, pd, *evaluate(row, wi, wo)])
                    made += 1
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    with open(OUT, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["model", "material", "theta_h_deg", "phi_h_deg", "theta_d_deg", "phi_d_deg", "r", "g", "b"])
        for r in rows:
            w.writerow(r[:2] + [repr(float(v)) for v in r[2:]])
    print(f"wrote {len(rows)} rows to {os.path.relpath(OUT)}")


if __name__ == "__main__":
    main()
