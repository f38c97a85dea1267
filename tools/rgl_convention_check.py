#!/usr/bin/env python3
"""Which direction of a render Mitsuba 3 passes as an RGL `.bsdf` file's incident direction.

For every incident elevation `theta_i` tabulated in a file (the pole excepted) and every node of
its `rgb` grid, the node's directions are rebuilt with Mitsuba's own classes: the node's sample
point warped by the file's `vndf` (MarginalContinuous2D2, as the `measured` plugin) gives the
normal `m`, `wi` lies at `theta_i` in the plane `phi_i = 0` and `wo` is `wi` mirrored about `m`.
There the file's own value is the tensor entry times `ndf(m) / (4 sigma(wi))` (jacobian = 1).
The script evaluates Mitsuba's `measured` BSDF with `si.wi = wi` and `eval(.., wo)`, and in the
other order, and prints the relative difference of each order from the tabulated value over the
significant nodes (luminance of f_r cos(theta_o) at least 1 % of the largest; both directions at least 3 deg above
the horizon), comparing f_r (Mitsuba's value over the cosine of its `wo`). In radiance transport Mitsuba's `si.wi` points towards the camera and `wo` towards
the light, so the order that reproduces the table says where the camera sits in the file; the
other order measures how far the file is from reciprocal.

Usage: python3 tools/rgl_convention_check.py [FILE.bsdf ...]
       (default: every file of shared/data/measured/rgl_bsdf)
Needs: mitsuba 3.9.1 and numpy (pip install mitsuba==3.9.1 numpy).
"""

import glob
import math
import os
import struct
import sys

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rgl_vectors import DATA  # noqa: E402

DTYPES = {1: np.uint8, 2: np.int8, 3: np.uint16, 4: np.int16, 5: np.uint32, 6: np.int32,
          7: np.uint64, 8: np.int64, 9: np.float16, 10: np.float32, 11: np.float64}
MIN_ELEVATION_COS = math.cos(math.radians(87.0))
SIGNIFICANT = 0.01


def read_tensor_file(path):
    """The fields of a Mitsuba `tensor_file` as numpy arrays (layout: rgl/tensor.rs)."""
    data = open(path, "rb").read()
    assert data[:12] == b"tensor_file\0", f"{path}: not a tensor file"
    (count,) = struct.unpack_from("<I", data, 14)
    at, fields = 18, {}
    for _ in range(count):
        (length,) = struct.unpack_from("<H", data, at)
        name = data[at + 2:at + 2 + length].decode()
        at += 2 + length
        rank, code, offset = struct.unpack_from("<HBQ", data, at)
        at += 11
        shape = struct.unpack_from(f"<{rank}Q", data, at)
        at += 8 * rank
        dtype = np.dtype(DTYPES[code]).newbyteorder("<")
        fields[name] = np.frombuffer(data, dtype, int(np.prod(shape)), offset).reshape(shape)
    return fields


def f32(array):
    return np.array(array, dtype=np.float32, order="C", copy=True)


def luminance(rgb):
    return float(rgb @ np.array([0.2126, 0.7152, 0.0722]))


def node_values(path):
    """At every usable node: f_r tabulated, f_r of Mitsuba with si.wi = wi and with si.wi = wo,
    and the luminance of the tabulated f_r cos(theta_o)."""
    t = read_tensor_file(path)
    bsdf = mi.load_dict({"type": "measured", "filename": path})
    ctx = mi.BSDFContext()
    phi_i = [float(v) for v in t["phi_i"]]
    theta_i = [float(v) for v in t["theta_i"]]
    vndf = mi.MarginalContinuous2D2(f32(t["vndf"]), [phi_i, theta_i], True)
    ndf = mi.MarginalContinuous2D0(f32(t["ndf"]), [], False, False)
    sigma = mi.MarginalContinuous2D0(f32(t["sigma"]), [], False, False)
    rgb = t["rgb"]
    size = rgb.shape[-1]

    def mitsuba(wi, wo):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*wi)
        return np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo)), dtype=np.float64)

    rows = []
    for k, theta in enumerate(theta_i):
        wi = np.array([math.sin(theta), 0.0, math.cos(theta)])
        if theta == 0.0 or wi[2] < MIN_ELEVATION_COS:
            continue
        four_sigma = 4.0 * sigma.eval(mi.Point2f(math.sqrt(2.0 * theta / math.pi), 0.5))
        for row in range(size):
            for column in range(size):
                sample = mi.Point2f(column / (size - 1), row / (size - 1))
                u_m, _ = vndf.sample(sample, [phi_i[0], theta])
                theta_m, phi_m = u_m[0] ** 2 * math.pi / 2.0, (2.0 * u_m[1] - 1.0) * math.pi
                m = np.array([math.sin(theta_m) * math.cos(phi_m),
                              math.sin(theta_m) * math.sin(phi_m), math.cos(theta_m)])
                wo = 2.0 * wi.dot(m) * m - wi
                if wo[2] < MIN_ELEVATION_COS:
                    continue
                table = rgb[0, k, :, row, column].astype(np.float64) * ndf.eval(u_m) / four_sigma
                # f_r: Mitsuba returns f_r times the cosine of its `wo`.
                rows.append((table / wo[2], mitsuba(wi, wo) / wo[2], mitsuba(wo, wi) / wi[2],
                             luminance(table)))
    return rows


def main():
    files = sys.argv[1:] or sorted(glob.glob(os.path.join(DATA, "rgl_bsdf", "*.bsdf")))
    for path in files:
        rows = node_values(path)
        peak = max(r[3] for r in rows)
        significant = [r for r in rows if r[3] >= SIGNIFICANT * peak]
        print(f"{os.path.basename(path)}: {len(significant)} significant nodes")
        for label, j in (("si.wi = the file's incident direction", 1),
                         ("si.wi = the file's outgoing direction", 2)):
            rel = np.array([abs(luminance(r[j]) - luminance(r[0])) / luminance(r[0])
                            for r in significant])
            print(f"  {label}: relative difference from the table median {np.median(rel):.2g}, "
                  f"90th percentile {np.percentile(rel, 90):.2g}, max {rel.max():.2g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
