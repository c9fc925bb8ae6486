#!/usr/bin/env python3
"""Error against wall time of DEM runs: how the relative standard errors of the mean drag and
lift fall as a run goes on, and what a stated error would cost.

    error_vs_time.py RUN_DIR_OR_DEM_H5 [...] [--targets 0.05,0.1] [--blocks 20]

For each dem.h5, at every 10% of the averaged samples, the relative errors of the mean drag
and lift over the samples so far: block averages (--blocks, default the file's), corrected for
correlated blocks exactly as `dem.target_error` does (shared/src/force_statistics.cc: the
lag-1 autocorrelation r of the block means, clipped to [0, 0.9], multiplies the error by
sqrt((1 + r) / (1 - r))). Wall time is the file's wall_seconds pro rata of the steps (the
packing, when it was prepared rather than reused, counts in wall_seconds: see the notes).
Then, from the last row and error ~ 1 / sqrt(time), the travel and wall time that each target
of --targets would take."""
import argparse
import math
import os
import sys

import h5py
import numpy as np


def corrected_stderr(x, blocks):
    """Mean, block error and correlation-corrected block error of x (the C++ block_mean)."""
    n = len(x)
    b = max(1, min(blocks, n))
    length = n // b
    start = n - length * b
    m = x[start:].reshape(b, length).mean(axis=1)
    mean = m.mean()
    var = float(((m - mean) ** 2).sum())
    if b < 2:
        return mean, float("nan"), float("nan")
    se = math.sqrt(var / (b - 1) / b)
    r = float(((m[:-1] - mean) * (m[1:] - mean)).sum() / var) if b >= 3 and var > 0 else 0.0
    rho = min(0.9, max(0.0, r))
    return mean, se, se * math.sqrt((1 + rho) / (1 - rho))


def table(path, blocks, targets):
    f = h5py.File(os.path.join(path, "dem.h5") if os.path.isdir(path) else path, "r")
    t = f["forces/time"][()]
    fx, fy = f["forces/fx"][()], f["forces/fy"][()]
    g = f["geometry"].attrs
    vx, vy = g["velocity_x"], g["velocity_y"]
    v = math.hypot(vx, vy)
    ex, ey = vx / v, vy / v
    drag, lift = -(fx * ex + fy * ey), -fx * ey + fy * ex
    diag = f["diagnostics"].attrs
    first = int(diag["steady_start_sample"])
    steps = int(diag["steps"])
    wall = float(f["metadata"].attrs["wall_seconds"])
    notes = f["metadata"].attrs["notes"]
    notes = notes.decode() if isinstance(notes, bytes) else str(notes)
    d = g["grain_diameter"]
    nb = blocks or int(f["means"].attrs["blocks"])
    print(f"## {path}")
    print(f"{notes.split(', pressure_scale')[0]}; wall {wall:.1f} s; {nb} blocks")
    print()
    print("| travel (d) | wall (s) | averaged (d) | drag | rel. error | lift | rel. error |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    n_avg = len(t) - first
    rows = []
    for k in range(1, 11):
        end = first + (n_avg * k) // 10
        if end - first < 5 * nb:
            continue
        md, _, sd = corrected_stderr(drag[first:end], nb)
        ml, _, sl = corrected_stderr(lift[first:end], nb)
        travel = t[end - 1] * v / d
        travel0 = t[first] * v / d
        w = wall * end / len(t)
        rows.append((travel, w, travel - travel0, md, sd / abs(md), ml, sl / abs(ml)))
        print(f"| {travel:.1f} | {w:.1f} | {travel - travel0:.1f} | {md:.4g} | {100 * sd / abs(md):.1f}% "
              f"| {ml:.4g} | {100 * sl / abs(ml):.1f}% |")
    if rows and targets:
        travel, w, avg, _, ed, _, el = rows[-1]
        lead = travel - avg  # the transient before averaging
        print()
        print("| target | averaging needed (d) | run travel (d) | wall time (s), from this run's rate |")
        print("| --- | --- | --- | --- |")
        for tg in targets:
            need = avg * max(ed, el) ** 2 / tg ** 2
            print(f"| {100 * tg:.0f}% | {need:.0f} | {lead + need:.0f} | {w * (lead + need) / travel:.0f} |")
    print()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--targets", default="0.05,0.1,0.2")
    ap.add_argument("--blocks", type=int, default=0)
    a = ap.parse_args()
    targets = [float(x) for x in a.targets.split(",") if x]
    for r in a.runs:
        table(r, a.blocks, targets)


if __name__ == "__main__":
    sys.exit(main())
