#!/usr/bin/env python3
"""Markdown tables for docs/BENCHMARKS.md from levelset_benchmarks' JSON output.

Usage: benchmarks/summarize.py out/levelset_benchmarks.json

Reads the median aggregates and prints, per sphere radius R: the cost of each
method per iteration and per unit of simulated time (the fair comparison: the
methods advance different times per iteration), the ratios against the peers
from the same run, thread scaling, growth with R, memory, and the paper's
Table 1 ratio (sparse over dense time per iteration).
"""
import json
import math
import re
import sys


def load(path):
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name = re.sub(r"/iterations:\d+|/repeats:\d+|/real_time|/manual_time|_median", "", b["run_name"])
        rows[name] = b
    return data.get("context", {}), rows


def ms(b):
    unit = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
    return b["real_time"] * unit


def main():
    context, rows = load(sys.argv[1])
    radii = sorted({int(m.group(1)) for k in rows for m in [re.search(r"MeanCurvature/(\d+)$", k)] if m})
    methods = [("levelfuse sparse field", "BM_SparseFieldMeanCurvature"),
               ("ITK parallel sparse field", "BM_ITKSparseFieldMeanCurvature"),
               ("OpenVDB LevelSetFilter", "BM_OpenVDBLevelSetFilterMeanCurvature"),
               ("levelfuse dense field", "BM_DenseFieldMeanCurvature")]
    print(f"Machine: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs at "
          f"{context.get('mhz_per_cpu', '?')} MHz; run {context.get('date', '?')}\n")

    print("| R | method | ms / iteration | sim_time / iteration | s / unit sim_time | active | bytes / voxel |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in radii:
        for label, prefix in methods:
            b = rows.get(f"{prefix}/{r}")
            if not b:
                continue
            print(f"| {r} | {label} | {ms(b):.3g} | {b['sim_time']:.4f} | {b['sec_per_sim_time']:.4g} | "
                  f"{b['active']:.0f} | {b['bytes_per_voxel']:.1f} |")
    print()

    print("Cost per unit of simulated time, peers over levelfuse (same run; above 1: levelfuse is faster):\n")
    print("| R | ITK / levelfuse | OpenVDB / levelfuse | sparse / dense time per iteration (Table 1) |")
    print("| --- | --- | --- | --- |")
    for r in radii:
        ours = rows.get(f"BM_SparseFieldMeanCurvature/{r}")
        if not ours:
            continue
        cells = []
        for prefix in ("BM_ITKSparseFieldMeanCurvature", "BM_OpenVDBLevelSetFilterMeanCurvature"):
            b = rows.get(f"{prefix}/{r}")
            cells.append(f"{b['sec_per_sim_time'] / ours['sec_per_sim_time']:.1f}x" if b else "-")
        dense = rows.get(f"BM_DenseFieldMeanCurvature/{r}")
        cells.append(f"{ms(ours) / ms(dense):.3f}" if dense else "-")
        print(f"| {r} | " + " | ".join(cells) + " |")
    print()

    print("Thread scaling (time per iteration, 1 thread over 2 threads):\n")
    print("| R | levelfuse | ITK |")
    print("| --- | --- | --- |")
    for r in radii:
        one = rows.get(f"BM_SparseFieldMeanCurvatureThreads/{r}/1")
        two = rows.get(f"BM_SparseFieldMeanCurvatureThreads/{r}/2")
        itk1 = rows.get(f"BM_ITKSparseFieldMeanCurvatureThreads/{r}/1")
        itk2 = rows.get(f"BM_ITKSparseFieldMeanCurvature/{r}")
        ours = f"{ms(one) / ms(two):.2f}" if one and two else "-"
        itk = f"{ms(itk1) / ms(itk2):.2f}" if itk1 and itk2 else "-"
        print(f"| {r} | {ours} | {itk} |")
    print()

    print("Growth of the time per iteration with R (exponent between successive radii):\n")
    print("| R | levelfuse | ITK |")
    print("| --- | --- | --- |")
    for a, b in zip(radii, radii[1:]):
        cells = []
        for prefix in ("BM_SparseFieldMeanCurvature", "BM_ITKSparseFieldMeanCurvature"):
            x, y = rows.get(f"{prefix}/{a}"), rows.get(f"{prefix}/{b}")
            cells.append(f"{math.log(ms(y) / ms(x)) / math.log(b / a):.2f}" if x and y else "-")
        print(f"| {a} to {b} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
