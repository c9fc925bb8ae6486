#!/usr/bin/env python3
"""FEM error against time: a Pareto table of drag and lift against wall time, per level.

    studies/fem_pareto/fem_pareto.py NESTED_RUN... [-- FLAT_RUN...]

Each argument is an output folder of `grainlift run CASE --solver fem` (fem.h5, summary.json)
at one continuum.refinement, coarsest first. The reference is the Richardson extrapolation of
the three finest runs of the first group (refinements r-2, r-1, r, a ratio 2 of mesh sizes) by
grainlift.stats.richardson: order p = log2((f_{r-1} - f_{r-2}) / (f_r - f_{r-1})), limit
f_r + (f_r - f_{r-1}) / (2^p - 1), uncertainty the size of its last correction |f_inf - f_r|.
Where the changes are not monotone or the order is outside [0.5, 3] (not yet asymptotic) the
reference is f_r and its uncertainty the last change |f_r - f_{r-1}|. The time exponent is
the least-squares slope of log(wall time) against log(unknowns) over the levels with dofs >= 3,000.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402
from grainlift.stats import richardson as richardson_rule  # noqa: E402


def read(folder):
    s = io.summary(folder, "fem")
    a = io.read(folder, "fem").diagnostics
    dofs = int(a["dofs"])
    newton = int(a["newton_steps"]) + int(a["picard_steps"])
    solves = int(a["linear_solves"])
    return {"drag": s["drag"], "lift": s["lift"], "seconds": s["wall_seconds"], "dofs": dofs,
            "steps": newton, "solves": solves, "folder": folder}


def richardson(f1, f2, f3):
    """(reference, order, uncertainty) of three levels halving the mesh size."""
    r = richardson_rule((4.0, 2.0, 1.0), (f1, f2, f3))
    return r.limit, r.order, r.error


def slope(runs):
    pts = [(math.log(r["dofs"]), math.log(r["seconds"])) for r in runs if r["dofs"] >= 3000]
    if len(pts) < 2:
        return float("nan")
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        sys.exit(0 if argv else 2)
    if "--" in argv:
        k = argv.index("--")
        groups = [argv[:k], argv[k + 1:]]
    else:
        groups = [argv]
    nested = [read(f) for f in groups[0]]
    if len(nested) < 3:
        sys.exit("fem_pareto.py: needs at least three refinements (coarsest first)")
    ref = {q: richardson(*[r[q] for r in nested[-3:]]) for q in ("drag", "lift")}
    for q in ("drag", "lift"):
        lim, p, err = ref[q]
        print(f"reference {q}: {lim:.2f} N/m (Richardson from the three finest levels, order "
              f"{p:.2f}; uncertainty {err:.2f} N/m = {100 * err / abs(lim):.2f}%)")
    names = ["nested iteration", "whole continuation on each mesh"]
    for name, folders in zip(names, groups):
        runs = [read(f) for f in folders]
        steps = ", ".join(
            f"{math.log(b['seconds'] / a['seconds']) / math.log(b['dofs'] / a['dofs']):.2f}"
            for a, b in zip(runs, runs[1:]) if a["dofs"] >= 3000)
        print(f"\n{name}: time against unknowns exponent {slope(runs):.2f} (least squares; "
              f"level to level from 3,000 unknowns: {steps}; target <= 1.15)")
        print("| unknowns | drag (N/m) | error | lift (N/m) | error | nonlinear steps | "
              "linear solves | wall (s) |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        for r in runs:
            ed = abs(r["drag"] - ref["drag"][0]) / abs(ref["drag"][0])
            el = abs(r["lift"] - ref["lift"][0]) / abs(ref["lift"][0])
            print(f"| {r['dofs']} | {r['drag']:.2f} | {100 * ed:.2f}% | {r['lift']:.2f} | "
                  f"{100 * el:.2f}% | {r['steps']} | {r['solves']} | {r['seconds']:.1f} |")


if __name__ == "__main__":
    main(sys.argv[1:])
