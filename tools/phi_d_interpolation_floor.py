#!/usr/bin/env python3
"""The error a design's phi_d planes leave however well everything else is measured.

A table exact on every theta_h and theta_d, but known in phi_d only at the planes a design
measures, interpolated between them as the reconstruction does: ln f by the monotone cubic
(Fritsch-Carlson, the kernel's `MonotoneCubic`) with slope zero at phi_d 0 and 90 deg, each
half of phi_d (0 to 90 and 90 to 180 deg, the second mapped to 180 - phi_d) from its own
planes, as `specula measure` reconstructs the halves apart. Scored as `specula compare`
scores (cosine-weighted relative RMSE and log RMSE within 75 deg) against the truth.

    cargo build --release -p specula-cli
    SPECULA=target/release/specula python3 tools/phi_d_interpolation_floor.py \\
        --phi-d-deg 0,60,90 nbrdf:beige-fabric

`--phi-d-deg` lists each half's planes in degrees from 0 to 90 (a first design's phi_d 0, 60,
90, 120 and 180 deg give 0, 60, 90 in each half); each node takes the MERL bin it falls in.
`--folded` scores the table the halves would make together instead: each half's planes
taken as the mean of the two halves' (reciprocity and the mirror symmetry of an isotropic
surface make them equal; a real material's need not be).
Prints one CSV row per truth: truth,rel,log.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

from merl_read_numpy import read_merl
from resolution_floor import bin_geometry, figures
from tabulate_numpy import SCALE

PHI_D_BINS = 180
HALF_BINS = PHI_D_BINS // 2


def monotone_cubic(x, y, xq):
    """The monotone cubic through (x, y) along y's last axis at `xq`: scipy's PCHIP (the
    kernel's `MonotoneCubic`, Fritsch-Carlson) with the slopes at both ends set to zero, as
    the kernel sets them on phi_d 0 and 90 deg, the symmetry points of a half."""
    slopes = PchipInterpolator(x, y, axis=-1).derivative()(x)
    slopes[..., [0, -1]] = 0.0
    return CubicHermiteSpline(x, y, slopes, axis=-1)(xq)


def interpolated_half(half, nodes_deg):
    """ln of one half (channels x theta_h x theta_d x 90 phi_d bins, phi_d ascending from 0)
    known at the bins of `nodes_deg` only, interpolated back to every bin."""
    centres = np.arange(HALF_BINS) + 0.5
    bins = np.clip(np.floor(nodes_deg).astype(int), 0, HALF_BINS - 1)
    x = centres[bins]
    y = np.log(np.maximum(half[..., bins], 1e-12))
    return np.exp(monotone_cubic(x, y, centres))


def floor_table(truth, nodes_deg, folded):
    """The truth known in phi_d at `nodes_deg` of each half only, or of their mean when
    `folded` (see the module text)."""
    halves = truth[..., :HALF_BINS], truth[..., HALF_BINS:][..., ::-1]
    if folded:
        halves = ((halves[0] + halves[1]) / 2,) * 2
    first = interpolated_half(halves[0], nodes_deg)
    second = interpolated_half(halves[1], nodes_deg)[..., ::-1]
    return np.concatenate([first, second], axis=-1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("truths", nargs="+", help="what `specula tabulate` takes")
    parser.add_argument("--phi-d-deg", default="0,60,90",
                        help="each half's planes, degrees from 0 to 90, ascending")
    parser.add_argument("--folded", action="store_true", help="the halves' mean, not each half's own")
    args = parser.parse_args()
    try:
        nodes = np.array([float(v) for v in args.phi_d_deg.split(",")])
    except ValueError:
        sys.exit(f"error: --phi-d-deg {args.phi_d_deg}: expected degrees separated by commas")
    if len(nodes) < 2 or np.any(np.diff(nodes) <= 0) or nodes[0] < 0 or nodes[-1] > 90:
        sys.exit(f"error: --phi-d-deg {args.phi_d_deg}: expected two or more ascending degrees from 0 to 90")
    specula = os.environ.get("SPECULA", "target/release/specula")
    _, _, light_z, camera_z = bin_geometry()
    print("truth,rel,log")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.truths:
            path = os.path.join(tmp, "truth.binary")
            done = subprocess.run([specula, "tabulate", name, "--out", path], capture_output=True, text=True)
            if done.returncode != 0:
                sys.exit(done.stderr.strip() or f"error: {name}: specula tabulate failed")
            truth = read_merl(path) * SCALE[:, None, None, None]
            rel, log = figures(floor_table(truth, nodes, args.folded), truth, light_z, camera_z)
            print(f"{name},{rel:.6f},{log:.6f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
