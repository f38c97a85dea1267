"""The accuracy study over the built-in database, in parallel with Dask (local cluster).

Each material is one task: `specula.evaluate` plans its measurement, simulates the samples,
reconstructs and compares (a few hundred ms). The script times the same study serially and
on a local Dask cluster and prints the mean figures of both (they must agree).

    pip install dask distributed
    python3 examples/dask_study.py [--workers 2] [--materials 24] [--method lobe]
"""
import argparse
import time

import specula


def figures(name, method):
    """The task: one material's figures (the samples stay on the worker)."""
    result = specula.evaluate(name, method=method)
    return name, result["k"], result["within"]["relative_rmse"], result["all"]["relative_rmse"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--materials", type=int, default=24, help="how many of the database's")
    parser.add_argument("--method", default="lobe")
    args = parser.parse_args()
    names = specula.materials()[: args.materials]

    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    serial = [figures(name, args.method) for name in names]
    serial_s = time.perf_counter() - t0

    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
        t0 = time.perf_counter()
        futures = client.map(figures, names, method=args.method)
        parallel = client.gather(futures)
        dask_s = time.perf_counter() - t0

    # Equal up to the rounding of parallel sums (rayon splits the work as the load allows).
    worst = max(abs(p[i] - s[i]) / abs(s[i]) for p, s in zip(parallel, serial) for i in (2, 3))
    assert [p[:2] for p in parallel] == [s[:2] for s in serial] and worst < 1e-9, worst
    mean = sum(r[2] for r in parallel) / len(parallel)
    print(f"{len(names)} materials, method {args.method}: mean relative RMSE within 75 deg {mean:.4f}")
    print(f"serial {serial_s:.1f} s, Dask {args.workers} workers {dask_s:.1f} s; figures agree to {worst:.1e}")


if __name__ == "__main__":
    main()
