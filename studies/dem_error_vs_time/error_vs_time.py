#!/usr/bin/env python3
"""Error against wall time of DEM runs: how the relative standard errors of the mean drag and
lift fall as a run goes on, and what a stated error would cost.

    error_vs_time.py RUN_DIR_OR_DEM_H5 [...] [--targets 0.05,0.1] [--blocks 20]

For each dem.h5, at every 10% of the averaged samples, the relative errors of the mean drag
and lift over the samples so far: block averages (--blocks, default the file's), corrected for
correlated blocks exactly as `dem.target_error` does (shared/src/statistics/force_statistics.cc: the
lag-1 autocorrelation r of the block means, clipped to [0, 0.9], multiplies the error by
sqrt((1 + r) / (1 - r))). Wall time is the file's wall_seconds pro rata of the steps (the
packing, when it was prepared rather than reused, counts in wall_seconds: see the notes).
Then, from the last row and error ~ 1 / sqrt(time), the travel and wall time that each target
of --targets would take."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402
from grainlift.stats import block_mean  # noqa: E402


def table(path, blocks, targets):
    f = io.read(path, "dem")
    t = f["forces/time"]
    drag, lift = f.drag_lift()
    g = f.geometry
    v = math.hypot(*f.velocity())
    diag = f.diagnostics
    first = int(diag["steady_start_sample"])
    wall = f.wall_seconds
    notes = io.text(f.metadata["notes"])
    d = g["grain_diameter"]
    nb = blocks or int(f.means["blocks"])
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
        bd, bl = block_mean(drag[first:end], nb), block_mean(lift[first:end], nb)
        md, sd, ml, sl = bd.mean, bd.stderr_corrected, bl.mean, bl.stderr_corrected
        travel = t[end - 1] * v / d
        travel0 = t[first] * v / d
        w = wall * end / len(t)
        rows.append((travel, w, travel - travel0, md, sd / abs(md), ml, sl / abs(ml)))
        print(f"| {travel:.1f} | {w:.1f} | {travel - travel0:.1f} | {md:.4g} | "
              f"{100 * sd / abs(md):.1f}% "
              f"| {ml:.4g} | {100 * sl / abs(ml):.1f}% |")
    if rows and targets:
        travel, w, avg, _, ed, _, el = rows[-1]
        lead = travel - avg  # the transient before averaging
        print()
        print("| target | averaging needed (d) | run travel (d) | "
              "wall time (s), from this run's rate |")
        print("| --- | --- | --- | --- |")
        for tg in targets:
            need = avg * max(ed, el) ** 2 / tg ** 2
            print(f"| {100 * tg:.0f}% | {need:.0f} | {lead + need:.0f} | "
                  f"{w * (lead + need) / travel:.0f} |")
    print()


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--targets", default="0.05,0.1,0.2")
    ap.add_argument("--blocks", type=int, default=0)
    a = ap.parse_args()
    targets = [float(x) for x in a.targets.split(",") if x]
    for r in a.runs:
        table(r, a.blocks, targets)


if __name__ == "__main__":
    sys.exit(main())
