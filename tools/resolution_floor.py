#!/usr/bin/env python3
"""The error of a table that is perfect except where the instrument cannot see.

A peak narrower than the instrument resolves changes what it records hardly at all: the
captures fix the light the peak reflects, not how it is spread within the resolution. A
reconstruction that reports such a peak at the resolution (the measurement's rule: a bound,
never an invented spike) cannot do better than this floor table: the truth everywhere,
except where the half vector lies within WIDTH of the mirror direction (theta_h below WIDTH,
every phi_d), where each theta_d holds the truth's mean over those cells, weighted by the
half vector's solid angle (sin theta_h d theta_h d phi_d), so that it reflects the same
light. Scored as `specula compare` scores (cosine-weighted relative RMSE
and log RMSE within 75 deg), against the paper's way on the same device.

    cargo build --release -p specula-cli
    SPECULA=target/release/specula python3 tools/resolution_floor.py fits.csv > floor.csv

fits.csv holds tools/all_fits_through_device.sh's rows (truth, rel, log, paper_rel,
paper_log, ...). WIDTH defaults to 0.26 deg, the narrowest half width the default device's
captures tell from zero (`width_detection_limit_deg` of its 1.09 deg resolution and 0.03 deg
positioning); `--width-deg` sets another. Prints one CSV row per truth:

    truth,floor_rel,floor_log,floor_ratio,measured_ratio

where a ratio is the worse of relative and log RMSE against the paper's way, the floor's
and the measurement's.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np

from merl_read_numpy import read_merl
from tabulate_numpy import SCALE, bin_centres

THETA_H_BINS = 90
MAX_ELEVATION_DEG = 75.0


def bin_geometry():
    """theta_h of each bin's centre and the bins' edges (MERL's squared spacing), radians,
    and the light's and camera's cosines of every cell's centre."""
    th, td, pd = bin_centres()
    edges = (np.arange(THETA_H_BINS + 1) / THETA_H_BINS) ** 2 * np.pi / 2
    dx, dz = np.sin(td) * np.cos(pd), np.cos(td)
    # The light: the difference vector rotated by theta_h about y (Bin::to_directions).
    light_z = -np.sin(th) * dx + np.cos(th) * dz
    camera_z = np.sin(th) * dx + np.cos(th) * dz
    return th[:, 0, 0], edges, light_z, camera_z


def floor_table(truth, theta_h, edges, width_rad):
    """The truth with the cells below `width_rad` of every theta_d replaced by their mean:
    the half vectors within `width_rad` of the mirror direction, at every phi_d (which
    turns them about it)."""
    below = theta_h < width_rad
    weight = np.sin(theta_h[below]) * np.diff(edges)[below]
    weight = weight / (weight.sum() * truth.shape[3])
    # Channels x theta_d: the mean over theta_h below the width and every phi_d.
    mean = np.einsum("chdp,h->cd", truth[:, below], weight)
    floor = truth.copy()
    floor[:, below] = mean[:, None, :, None]
    return floor


def figures(a, b, light_z, camera_z):
    """`specula compare`'s relative RMSE and log RMSE of `a` against `b` within 75 deg."""
    min_cos = np.cos(np.radians(MAX_ELEVATION_DEG))
    within = (light_z >= min_cos) & (camera_z >= min_cos)
    w2 = ((light_z * camera_z) ** 2)[within]
    rel = np.sqrt((w2 * ((a - b)[:, within] ** 2).sum(0)).sum() / (w2 * (b[:, within] ** 2).sum(0)).sum())
    lz = light_z[within]
    log = np.sqrt(np.mean((np.log1p(a[:, within] * lz) - np.log1p(b[:, within] * lz)) ** 2))
    return rel, log


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("fits", help="tools/all_fits_through_device.sh's CSV")
    parser.add_argument("--width-deg", type=float, default=0.26)
    args = parser.parse_args()
    specula = os.environ.get("SPECULA", "target/release/specula")
    theta_h, edges, light_z, camera_z = bin_geometry()
    width_rad = np.radians(args.width_deg)
    try:
        fits = open(args.fits)
    except OSError as e:
        sys.exit(f"error: {args.fits}: {e.strerror}")
    print("truth,floor_rel,floor_log,floor_ratio,measured_ratio")
    with tempfile.TemporaryDirectory() as tmp, fits as f:
        for row in csv.reader(f):
            if not row or row[0] == "truth":
                continue
            name = row[0]
            rel, log, paper_rel, paper_log = map(float, row[1:5])
            path = os.path.join(tmp, "truth.binary")
            done = subprocess.run([specula, "tabulate", name, "--out", path], capture_output=True, text=True)
            if done.returncode != 0:
                cause = done.stderr.strip().removeprefix("error: ") or "specula tabulate failed"
                sys.exit(f"error: {args.fits}: {cause}")
            truth = read_merl(path) * SCALE[:, None, None, None]
            floor_rel, floor_log = figures(floor_table(truth, theta_h, edges, width_rad), truth, light_z, camera_z)
            floor_ratio = max(floor_rel / paper_rel, floor_log / paper_log)
            measured_ratio = max(rel / paper_rel, log / paper_log)
            print(f"{name},{floor_rel:.6f},{floor_log:.6f},{floor_ratio:.3f},{measured_ratio:.3f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
