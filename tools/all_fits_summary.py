#!/usr/bin/env python3
"""Summarises tools/all_fits_through_device.sh's CSV: per fit set and over all, the median and
the worst of max(relative ratio, log ratio) to the paper's way, how many are above 1.0 in
either figure, and the ten worst truths (Markdown).

    python3 tools/all_fits_summary.py fits.csv
"""
import csv
import statistics
import sys


def rows(path):
    with open(path, newline="") as f:
        for r in csv.reader(f):
            if len(r) < 5 or r[1].startswith("error"):
                print(f"{r[0]}: {','.join(r[1:]) or 'no result'}", file=sys.stderr)
                continue
            rel, log, prel, plog = map(float, r[1:5])
            ratio_rel, ratio_log = ratio(rel, prel), ratio(log, plog)
            yield {
                "truth": r[0],
                "set": r[0].split(":")[0],
                "rel": rel,
                "log": log,
                "prel": prel,
                "plog": plog,
                "ratio_rel": ratio_rel,
                "ratio_log": ratio_log,
                "ratio": max(ratio_rel, ratio_log),
                "hours": float(r[6]) if len(r) > 6 and r[6] else float("nan"),
                "fallback": r[8] if len(r) > 8 else "",
            }


def ratio(ours, paper):
    """ours / paper; infinite where the paper's way has no error at the printed precision."""
    return ours / paper if paper > 0 else float("inf")


def line(name, group):
    ratios = [g["ratio"] for g in group]
    worst = max(group, key=lambda g: g["ratio"])
    above = sum(1 for g in group if g["ratio_rel"] > 1.0 or g["ratio_log"] > 1.0)
    return (
        f"| {name} | {len(group)} | {statistics.median(ratios):.2f} | "
        f"{worst['ratio']:.2f} ({worst['truth']}) | {above} |"
    )


def main():
    data = list(rows(sys.argv[1]))
    print("| set | truths | median ratio | worst ratio | above 1.0 in either figure |")
    print("|---|---|---|---|---|")
    for name in ["nbrdf", "nbrdf-rgl", "sgd", "abc"]:
        group = [d for d in data if d["set"] == name]
        if group:
            print(line(name, group))
    print(line("all", data))
    print()
    print("| truth | default rel / log | paper's way rel / log | ratio | fallback |")
    print("|---|---|---|---|---|")
    for d in sorted(data, key=lambda d: -d["ratio"])[:10]:
        print(
            f"| {d['truth']} | {d['rel']:.4f} / {d['log']:.4f} | "
            f"{d['prel']:.4f} / {d['plog']:.4f} | {d['ratio']:.2f} | {d['fallback']} |"
        )
    hours = [d["hours"] for d in data]
    print()
    print(f"simulated hours: {min(hours):.2f} to {max(hours):.2f}")


if __name__ == "__main__":
    main()
