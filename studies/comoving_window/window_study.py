#!/usr/bin/python3
"""The co-moving window against a long box (issue 14, docs/performance.md, Skips).

Runs a reduced Kumar case (default: the dense one, Phi 0.8, at V0 0.25 m/s and omega 5 rad/s;
one thread each) three ways per seed: the 60 d box (the intruder meets its own wake after 60 d \
of travel), the same box
with dem.window_width, and a box LONG times as long (no wake comes round in the travel) as
the reference. Prints a Markdown table: drag and lift over the laps of travel (block means,
10 blocks each, block errors: grainlift.stats.block_mean), the wall time, and the window's
diagnostics; then the pooled means over the seeds (grainlift.stats.pooled_mean: the larger of
the between-seed error and the block errors combined).

    studies/comoving_window/window_study.py build/bin/grainlift WORK [--case FILE] [--v0 0.25] \
[--omega 5]
        [--seeds 1 2] [--travel 150] [--width 10] [--long 3] [--runs short window long]
        [--set KEY=VALUE ...]
"""
import argparse
import os
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "python"))
from grainlift import io  # noqa: E402
from grainlift.stats import block_mean as block_rule, pooled_mean  # noqa: E402

D_GRAIN, HALF_BOX = 0.02, 0.6  # the reduced Kumar cases' grain diameter and half box length


def block_mean(x, blocks=10):
    """(mean, correlation-corrected block standard error) of x over `blocks` blocks."""
    b = block_rule(x, blocks)
    return b.mean, b.stderr_corrected


def run(a, name, seed, extra):
    gl, travel = a.grainlift, a.travel
    out = os.path.join(a.work, name)
    if not os.path.exists(os.path.join(out, "summary.json")):
        cmd = [gl, "run", os.path.join(ROOT, a.case), "--solver", "dem", "--threads", "1",
               "--quiet", "--out", out, "--set", f"intruder.velocity=[{a.v0},0.0]",
               "--set", f"intruder.omega={a.omega}", "--set", f"dem.travel={travel}",
               "--set", "dem.steady_travel=30", "--set", "output.fields=false",
               "--set", f"dem.seed={seed}"]
        for s in extra + a.sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    f = io.read(out, "dem")
    t = f["forces/time"] * a.v0 / D_GRAIN
    drag, lift = -f["forces/fx"], f["forces/fy"]
    diag = {k: float(v) for k, v in f.diagnostics.items() if k.startswith("window")}
    wall = io.summary(out, "dem")["wall_seconds"]
    return t, drag, lift, diag, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("grainlift")
    ap.add_argument("work")
    ap.add_argument("--case", default="cases/kumar2019/reduced_phi080.toml")
    ap.add_argument("--v0", type=float, default=0.25)
    ap.add_argument("--omega", type=float, default=5.0)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--travel", type=float, default=150)
    ap.add_argument("--width", type=float, default=10)
    ap.add_argument("--long", type=float, default=3)
    ap.add_argument("--runs", nargs="+", default=["short", "window", "long"])
    ap.add_argument("--set", action="append", default=[], dest="sets")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    kinds = {"short": [], "window": [f"dem.window_width={a.width}"],
             "long": [f"domain.x_range=[{-HALF_BOX * a.long},{HALF_BOX * a.long}]"]}
    laps = [(30, 60)] + [(lo, lo + 30) for lo in range(60, int(a.travel), 30)]
    laps = [(lo, min(hi, a.travel)) for lo, hi in laps] + [(60, a.travel), (30, a.travel)]
    head = " | ".join(f"{lo:g}-{hi:g} d drag / lift" for lo, hi in laps)
    print(f"| run | seed | {head} | wall (s) | window: band grains, with a site, core rms (d), "
          "bed slide (d), band contacts |")
    print("| --- | --- | " + " | ".join("---" for _ in laps) + " | --- | --- |")
    pooled = {}
    for kind in a.runs:
        for seed in a.seeds:
            t, drag, lift, diag, wall = run(a, f"{kind}{seed}", seed, kinds[kind])
            cells = []
            for lo, hi in laps:
                m = (t >= lo) & (t < hi)
                (dm, de), (lm, le) = block_mean(drag[m]), block_mean(lift[m])
                cells.append(f"{dm:.3f} +- {de:.3f} / {lm:.3f} +- {le:.3f}")
                pooled.setdefault((kind, lo, hi), []).append((dm, de, lm, le))
            w = (f"{diag['window_band_grains']:.0f}, {diag['window_matched_fraction']:.3f}, "
                 f"{diag['window_core_rms']:.3f}, {diag['window_bed_slide']:.1f}, "
                 f"{diag.get('window_band_contacts', float('nan')):.2f}" if diag else "-")
            print(f"| {kind} | {seed} | " + " | ".join(cells) + f" | {wall:.0f} | {w} |")
    print()
    print("Pooled over the seeds (mean of the beds; error: the larger of between-seed and "
          "block errors combined):")
    print()
    print("| run | " + " | ".join(f"{lo:g}-{hi:g} d drag / lift" for lo, hi in laps) + " |")
    print("| --- | " + " | ".join("---" for _ in laps) + " |")
    for kind in a.runs:
        cells = []
        for lo, hi in laps:
            v = pooled[(kind, lo, hi)]
            d = pooled_mean([x[0] for x in v], [x[1] for x in v])
            li = pooled_mean([x[2] for x in v], [x[3] for x in v])
            cells.append(f"{d.mean:.3f} +- {d.error:.3f} / {li.mean:.3f} +- {li.error:.3f}")
        print(f"| {kind} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
