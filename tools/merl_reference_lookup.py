#!/usr/bin/env python3
"""Independent check of Specula's MERL bins: a line-by-line port of MERL's reference reader
(BRDFRead.cpp, Matusik et al. 2003) evaluated at random direction pairs.

It writes crates/specula-core/tests/data/merl_reference_lookup.csv with, per direction pair
(degrees), the flat cell index the reference reader looks up. The Rust test
`merl_reference.rs` performs the same lookups with Specula's reader and requires the same
cells. Run from the repository root: python3 tools/merl_reference_lookup.py
"""
import csv
import math
import random

RES_THETA_H = 90
RES_THETA_D = 90
RES_PHI_D = 360  # the reference stores half of it (reciprocity)


def rotate_vector(vector, axis, angle):
    """Rodrigues' rotation, as the reference reader's rotate_vector."""
    cos_ang, sin_ang = math.cos(angle), math.sin(angle)
    out = [vector[i] * cos_ang for i in range(3)]
    temp = sum(axis[i] * vector[i] for i in range(3)) * (1.0 - cos_ang)
    out = [out[i] + axis[i] * temp for i in range(3)]
    cross = [
        axis[1] * vector[2] - axis[2] * vector[1],
        axis[2] * vector[0] - axis[0] * vector[2],
        axis[0] * vector[1] - axis[1] * vector[0],
    ]
    return [out[i] + cross[i] * sin_ang for i in range(3)]


def normalize(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def std_coords_to_half_diff_coords(theta_in, fi_in, theta_out, fi_out):
    inv = normalize([math.sin(theta_in) * math.cos(fi_in), math.sin(theta_in) * math.sin(fi_in), math.cos(theta_in)])
    outv = normalize([math.sin(theta_out) * math.cos(fi_out), math.sin(theta_out) * math.sin(fi_out), math.cos(theta_out)])
    half = normalize([(inv[i] + outv[i]) / 2.0 for i in range(3)])
    theta_half = math.acos(half[2])
    fi_half = math.atan2(half[1], half[0])
    temp = rotate_vector(inv, [0.0, 0.0, 1.0], -fi_half)
    diff = rotate_vector(temp, [0.0, 1.0, 0.0], -theta_half)
    theta_diff = math.acos(diff[2])
    fi_diff = math.atan2(diff[1], diff[0])
    return theta_half, fi_half, theta_diff, fi_diff


def theta_half_index(theta_half):
    if theta_half <= 0.0:
        return 0
    theta_half_deg = (theta_half / (math.pi / 2.0)) * RES_THETA_H
    ret = int(math.sqrt(theta_half_deg * RES_THETA_H))
    return min(max(ret, 0), RES_THETA_H - 1)


def theta_diff_index(theta_diff):
    tmp = int(theta_diff / (math.pi * 0.5) * RES_THETA_D)
    return min(max(tmp, 0), RES_THETA_D - 1)


def phi_diff_index(phi_diff):
    if phi_diff < 0.0:
        phi_diff += math.pi
    tmp = int(phi_diff / math.pi * RES_PHI_D / 2)
    return min(max(tmp, 0), RES_PHI_D // 2 - 1)


def lookup_index(theta_in, fi_in, theta_out, fi_out):
    th, _, td, pd = std_coords_to_half_diff_coords(theta_in, fi_in, theta_out, fi_out)
    return phi_diff_index(pd) + theta_diff_index(td) * (RES_PHI_D // 2) + theta_half_index(th) * (RES_PHI_D // 2) * RES_THETA_D


def main():
    rng = random.Random(20261122)
    rows = []
    for n in range(3000):
        theta_i = rng.uniform(0.0, 89.5)
        phi_i = rng.uniform(0.0, 360.0)
        if n % 3 == 0:
            # near the mirror direction, where the theta_h bins are finest
            # reflected at 0 rather than clamped: theta_o = 0 puts phi_d exactly on the 0/180 seam
            theta_o = min(89.5, abs(theta_i + rng.uniform(-2.0, 2.0)))
            phi_o = (phi_i + 180.0 + rng.uniform(-2.0, 2.0)) % 360.0
        else:
            theta_o = rng.uniform(0.0, 89.5)
            phi_o = rng.uniform(0.0, 360.0)
        index = lookup_index(*(math.radians(a) for a in (theta_i, phi_i, theta_o, phi_o)))
        rows.append((repr(theta_i), repr(phi_i), repr(theta_o), repr(phi_o), index))
    with open("crates/specula-core/tests/data/merl_reference_lookup.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["theta_i", "phi_i", "theta_o", "phi_o", "cell"])
        w.writerows(rows)


if __name__ == "__main__":
    main()
