#!/usr/bin/env python3
"""Independent reference for specula-reconstruct, with numpy and scipy.

The paper's task (section 5.3): 30 theta_h positions of the exponential sampling function
(k = 4.78), theta_d 0, 3, ..., 87 deg, phi_d 0, 15, ..., 90 deg, phi_h = 45 deg; a sample is
measured when light and camera are both within 75 deg of the normal. Unreached lattice nodes
take the nearest known node along theta_d, then theta_h, then phi_d (specula's
extrapolation); the lattice is then interpolated linearly in (theta_h, theta_d, phi_d)
degrees at the 1,458,000 MERL bin centres (phi_d folded into [0, 90], coordinates clamped to
the lattice) with scipy.interpolate.RegularGridInterpolator.

    python3 tools/reconstruct_scipy.py vectors   # writes the test vectors of the crate
    python3 tools/reconstruct_scipy.py time      # times scipy on the task (median of 7 runs)
"""
import argparse
import pathlib
import time

import numpy as np
from scipy.interpolate import PchipInterpolator, RegularGridInterpolator

DATA = pathlib.Path(__file__).resolve().parent.parent / "crates/specula-reconstruct/tests/data"


def exponential_positions(k, n):
    t = np.linspace(0.0, 1.0, n)
    return 90.0 * np.expm1(k * t) / np.expm1(k)


def directions(theta_h, theta_d, phi_d, phi_h):
    """cos of the light's and camera's angles from the normal (degrees in)."""
    th, td, pd = (np.radians(a) for a in (theta_h, theta_d, phi_d))
    cos_i = np.cos(th) * np.cos(td) - np.sin(th) * np.sin(td) * np.cos(pd)
    cos_o = 2.0 * np.cos(td) * np.cos(th) - cos_i
    return cos_i, cos_o


def synthetic(theta_h, theta_d, phi_d):
    """A smooth specular-like test function, per channel (1/sr)."""
    peak = 300.0 * np.exp(-((theta_h / 1.5) ** 2)) * (1.0 + 0.3 * theta_d / 90.0)
    r = 0.1 + peak * (1.0 + 0.1 * np.cos(np.radians(2.0 * phi_d)))
    return np.stack([r, 0.8 * r, 0.05 + 0.5 * peak], axis=-1)


def paper_task():
    """Lattice axes, the measured mask and the node values of the paper's task.

    The lattice is the one the measured samples span (a reconstruction from samples knows
    nothing of the plan's unreached theta_h and theta_d), as in specula.
    """
    h = exponential_positions(4.78, 30)
    d = np.arange(0.0, 88.0, 3.0)
    p = np.arange(0.0, 91.0, 15.0)
    H, D, P = np.meshgrid(h, d, p, indexing="ij")
    cos_i, cos_o = directions(H, D, P, 45.0)
    limit = np.cos(np.radians(75.0))
    measured = (cos_i >= limit) & (cos_o >= limit)
    keep = [measured.any(axis=tuple(a for a in range(3) if a != axis)) for axis in range(3)]
    sub = np.ix_(*keep)
    axes = (h[keep[0]], d[keep[1]], p[keep[2]])
    return axes, measured[sub], synthetic(H, D, P)[sub]


def fill_missing(axes, values, measured):
    """Nearest known node along theta_d, then theta_h, then phi_d (ties: the lower node)."""
    values = values.copy()
    known = measured.copy()
    for axis in (1, 0, 2):
        coords = axes[axis]
        v = np.moveaxis(values, axis, -2)  # [..., n, channel]
        k = np.moveaxis(known, axis, -1)  # [..., n]
        before = k.copy()
        for idx in np.ndindex(k.shape[:-1]):
            line = before[idx]
            if not line.any() or line.all():
                continue
            src = np.flatnonzero(line)
            for i in np.flatnonzero(~line):
                j = src[np.argmin(np.abs(coords[src] - coords[i]))]
                v[idx + (i,)] = v[idx + (j,)]
                k[idx + (i,)] = True
    return values


def merl_centres():
    i = np.arange(90)
    theta_h = (i + 0.5) ** 2 / 90.0
    theta_d = np.arange(90) + 0.5
    phi = np.arange(180) + 0.5
    phi_d = np.minimum(phi, 180.0 - phi)
    return theta_h, theta_d, phi_d


def reconstruct_linear(axes, values, measured):
    """The MERL grid (90, 90, 180, 3) from the lattice."""
    return interpolate_linear(axes, fill_missing(axes, values, measured))


def interpolate_linear(axes, filled):
    """RegularGridInterpolator at the MERL bin centres of a complete lattice."""
    interp = RegularGridInterpolator(axes, filled, method="linear")
    th, td, pd = merl_centres()
    H, D, P = np.meshgrid(
        np.clip(th, axes[0][0], axes[0][-1]),
        np.clip(td, axes[1][0], axes[1][-1]),
        np.clip(pd, axes[2][0], axes[2][-1]),
        indexing="ij",
    )
    points = np.stack([H.ravel(), D.ravel(), P.ravel()], axis=-1)
    return interp(points).reshape(90, 90, 180, 3)


def write_samples(path, axes, values, measured):
    h, d, p = axes
    with open(path, "w") as f:
        f.write("theta_h,phi_h,theta_d,phi_d,r,g,b\n")
        for a, b, c in zip(*np.nonzero(measured)):
            row = [h[a], 45.0, d[b], p[c], *values[a, b, c]]
            f.write(",".join(repr(float(v)) for v in row) + "\n")


def vectors():
    DATA.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(6)
    with open(DATA / "pchip_scipy.csv", "w") as f:
        f.write("# scipy.interpolate.PchipInterpolator: per case, lines x / y / targets / values\n")
        cases = [
            (np.array([0.0, 0.2, 0.5, 1.0, 3.0, 10.0]), np.array([1000.0, 800.0, 100.0, 5.0, 1.0, 0.9])),
            (np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 0.0])),
            (np.array([0.0, 3.0, 6.0, 9.0]), np.array([1.0, 2.0, 2.0, 5.0])),
        ]
        for _ in range(4):
            x = np.sort(rng.uniform(0.0, 90.0, rng.integers(4, 12)))
            cases.append((x, rng.normal(0.0, 3.0, x.size)))
        for x, y in cases:
            t = np.linspace(x[0], x[-1], 23)
            for row in (x, y, t, PchipInterpolator(x, y)(t)):
                f.write(",".join(repr(float(v)) for v in row) + "\n")
    axes, measured, values = paper_task()
    write_samples(DATA / "paper_task_samples.csv", axes, values, measured)
    grid = reconstruct_linear(axes, values, measured).reshape(-1, 3)
    with open(DATA / "paper_task_linear_scipy.csv", "w") as f:
        f.write("cell,r,g,b\n")
        for cell in range(0, grid.shape[0], 997):
            f.write(f"{cell}," + ",".join(repr(float(v)) for v in grid[cell]) + "\n")
    print(f"measured samples: {measured.sum()} of {measured.size}; wrote {DATA}")


def timing(repeat):
    """Times the interpolation alone (the fill is a Python loop, left out to be fair)."""
    axes, measured, values = paper_task()
    filled = fill_missing(axes, values, measured)
    runs = []
    for _ in range(repeat):
        start = time.perf_counter()
        interpolate_linear(axes, filled)
        runs.append(time.perf_counter() - start)
    runs.sort()
    print(
        f"scipy RegularGridInterpolator (interpolation only), {measured.sum()} samples -> "
        f"1458000 cells: median {1000 * runs[len(runs) // 2]:.1f} ms, best {1000 * runs[0]:.1f} ms "
        f"({repeat} runs)"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["vectors", "time"])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    if args.mode == "vectors":
        vectors()
    else:
        timing(args.repeat)


if __name__ == "__main__":
    main()
