#!/usr/bin/env python3
"""What a user would otherwise do to read a MERL .binary: numpy.fromfile plus the reshape.

Writes a 35 MB file of the MERL layout to a temporary folder, then reports the best and the
median of 20 reads. Compare with `cargo bench -p specula-core --bench merl_read`.
"""
import os
import statistics
import tempfile
import time

import numpy as np


def read_merl(path):
    with open(path, "rb") as f:
        dims = np.fromfile(f, dtype="<i4", count=3)
        data = np.fromfile(f, dtype="<f8")
    return data.reshape(3, *dims)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "bench.binary")
        with open(path, "wb") as f:
            np.array([90, 90, 180], dtype="<i4").tofile(f)
            np.random.default_rng(1).random(3 * 1458000).astype("<f8").tofile(f)
        read_merl(path)
        times = []
        for _ in range(20):
            t0 = time.perf_counter()
            read_merl(path)
            times.append(time.perf_counter() - t0)
        print(f"numpy fromfile+reshape: best {min(times)*1e3:.1f} ms, median {statistics.median(times)*1e3:.1f} ms")


if __name__ == "__main__":
    main()
