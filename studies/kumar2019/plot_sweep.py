#!/usr/bin/python3
"""Plots of `grainlift sweep` tables (sweep.csv) against the papers' trends.

  plot_sweep.py ld-omega  OUT.png  CSV[:LABEL] ...   L/D against spin ratio Omega
  plot_sweep.py drag-speed OUT.png CSV[:LABEL] ...   drag against V0, log-log, fitted slope
  plot_sweep.py ld-mu     OUT.png  CSV[:LABEL] ...   L/D against mu (saturated spin), with
                                                     L/D = mu and Kumar eq. (15)
  plot_sweep.py drag-omega OUT.png CSV[:LABEL] ...   drag against spin ratio Omega
A table of `--solver both` gives one series per solver; CSV#dem or CSV#fem keeps one solver's
rows.
Error bars are the block-average standard errors (propagated for ratios) by the one statistics
rule: each DEM row's drag, lift and torque errors are recomputed from its run's dem.h5 (the
row's run_dir, or the folder of that name beside the CSV) by grainlift.io's
Result.block_errors(), the correlation-corrected block error, since a sweep.csv written before
fa2750a holds the uncorrected one; a row whose dem.h5 is missing keeps the CSV's errors, with a
warning. Tables given the same LABEL (independent seeds) are pooled by
grainlift.stats.pooled_mean (ld-omega also prints each bed's L/D and the spread across beds).
Prints the table it plots, so the numbers can go into docs/."""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.plots import plt  # noqa: E402
from grainlift.stats import pooled_mean  # noqa: E402


def first_number(text):
    text = text.strip().strip('"').strip("[]")
    return float(text.split(",")[0])


def dem_h5(csv_path, row):
    """The dem.h5 of a sweep row: in its run_dir (relative to the working folder, as the sweep
    wrote it), else in the folder of that name beside the CSV (a moved or copied sweep)."""
    run_dir = row.get("run_dir") or ""
    for d in (run_dir, os.path.join(os.path.dirname(csv_path), os.path.basename(run_dir))):
        if d and os.path.isfile(os.path.join(d, "dem.h5")):
            return os.path.join(d, "dem.h5")
    return None


def rule_errors(csv_path, rows):
    """Replaces the DEM rows' drag, lift and torque errors by the one statistics rule's
    (Result.block_errors() of the run's dem.h5)."""
    for r in rows:
        if r["solver"] != "dem":
            continue
        h5 = dem_h5(csv_path, r)
        if h5 is None:
            print(f"warning: {csv_path}: no dem.h5 for {r.get('run_dir')}: its errors are the "
                  "CSV's", file=sys.stderr)
            continue
        for key, e in io.read(h5, "dem").block_errors().items():
            r[key] = repr(e)
    return rows


def read(spec):
    path, _, label = spec.partition(":")
    path, _, only = path.partition("#")
    rows = [r for r in io.sweep_rows(path) if r["solver"] in ((only,) if only else ("dem", "fem"))]
    return rule_errors(path, rows), label or path


def pooled(specs):
    """Tables that share a label (independent seeds) are pooled value by value: means of
    drag, lift, torque and their errors by grainlift.stats.pooled_mean (the larger of the
    between-bed error and sqrt(sum se^2) / n)."""
    groups = {}
    for spec in specs:
        rows, label = read(spec)
        groups.setdefault(label, []).append(rows)
    for label, tables in groups.items():
        if len(tables) == 1:
            yield tables[0], label
            continue
        out = []
        for i, r in enumerate(tables[0]):
            same = [s for t in tables for s in t if s["value"] == r["value"]]
            p = dict(r)
            for key in ("drag", "lift", "torque"):
                pm = pooled_mean([num(s, key) for s in same],
                                 [num(s, key + "_stderr") for s in same])
                p[key], p[key + "_stderr"] = str(pm.mean), str(pm.error)
            for key in ("contacts", "wall_seconds"):
                p[key] = str(np.mean([num(s, key) for s in same]))
            p["beds_ld"] = [num(s, "lift") / num(s, "drag") for s in same]
            out.append(p)
        yield out, f"{label} ({len(tables)} seeds)"


def by_solver(series):
    """Splits each table that holds rows of both solvers into one series per solver."""
    for rows, label in series:
        solvers = sorted({r["solver"] for r in rows})
        if len(solvers) == 1:
            yield rows, label
            continue
        for s in solvers:
            yield [r for r in rows if r["solver"] == s], f"{label}: {s}"


def num(r, key):
    v = r.get(key, "")
    return float(v) if v not in ("", None) else float("nan")


def ratio_err(r):
    d, l = num(r, "drag"), num(r, "lift")
    sd, sl = num(r, "drag_stderr"), num(r, "lift_stderr")
    if not (math.isfinite(sd) and math.isfinite(sl)) or d == 0:
        return float("nan")
    return abs(l / d) * math.sqrt((sl / l) ** 2 + (sd / d) ** 2) if l != 0 else abs(sl / d)


def main(argv):
    if len(argv) < 4:
        print(__doc__)
        return 2
    mode, out, specs = argv[1], argv[2], argv[3:]
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for rows, label in by_solver(pooled(specs)):
        if mode == "drag-omega":
            x = np.array([num(r, "spin_ratio") for r in rows])
            y = np.array([num(r, "drag") for r in rows])
            e = np.array([num(r, "drag_stderr") for r in rows])
            ax.errorbar(x, y, yerr=e, marker="o", capsize=3, label=label)
            print(f"# {label}\n# Omega  drag  stderr  torque  stderr")
            for r, xi, yi, ei in zip(rows, x, y, e):
                print(f"{xi:8.3f} {yi:10.4g} {ei:10.3g} {num(r,'torque'):10.4g} "
                      f"{num(r,'torque_stderr'):10.3g}")
        elif mode == "ld-omega":
            x = np.array([num(r, "spin_ratio") for r in rows])
            y = np.array([num(r, "lift") / num(r, "drag") for r in rows])
            e = np.array([ratio_err(r) for r in rows])
            ax.errorbar(x, y, yerr=e, marker="o", capsize=3, label=label)
            print(f"# {label}\n# Omega  L/D  stderr  drag  lift  wall_s  contacts"
                  + ("  [beds: L/D of each bed; sd across beds; sd/sqrt(n)]"
                     if "beds_ld" in rows[0] else ""))
            for r, xi, yi, ei in zip(rows, x, y, e):
                line = (f"{xi:8.3f} {yi:8.4f} {ei:8.4f} {num(r,'drag'):10.4g} {num(r,'lift'):10.4g}"
                        f" {num(r,'wall_seconds'):8.1f} {num(r,'contacts'):7.3f}")
                if "beds_ld" in r:
                    b = r["beds_ld"]
                    sem = pooled_mean(b).between
                    line += ("  [" + " ".join(f"{v:+.3f}" for v in b)
                             + f"; sd {sem * math.sqrt(len(b)):.3f}; sem {sem:.3f}]")
                print(line)
        elif mode == "drag-speed":
            x = np.array([first_number(r["value"]) for r in rows])
            y = np.array([num(r, "drag") for r in rows])
            e = np.array([num(r, "drag_stderr") for r in rows])
            ax.errorbar(x, y, yerr=e, marker="o", ls="none", capsize=3, label=label)
            ok = (x > 0) & (y > 0)
            slope, icpt = np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)
            xx = np.linspace(x[ok].min(), x[ok].max(), 50)
            ax.plot(xx, np.exp(icpt) * xx ** slope, "--", label=f"fit: slope {slope:.2f}")
            ax.set_xscale("log")
            ax.set_yscale("log")
            print(f"# {label}: log-log slope {slope:.3f} (paper: about 2)\n# V0  drag  stderr")
            for xi, yi, ei in zip(x, y, e):
                print(f"{xi:8.3f} {yi:10.4g} {ei:10.3g}")
        elif mode == "ld-mu":
            x = np.array([first_number(r["value"]) for r in rows])
            y = np.array([-num(r, "lift") / num(r, "drag") for r in rows])
            e = np.array([ratio_err(r) for r in rows])
            ax.errorbar(x, y, yerr=e, marker="o", capsize=3, label=label + " (-L/D)")
            print(f"# {label}\n# mu  -L/D  stderr")
            for xi, yi, ei in zip(x, y, e):
                print(f"{xi:6.3f} {yi:8.4f} {ei:8.4f}")
        else:
            print(f"unknown mode {mode}", file=sys.stderr)
            return 2
    if mode == "ld-omega":
        ax.axhline(0, color="k", lw=0.5)
        # Kumar eq. (15) at mu = 0.5: kappa 0.9 (Phi 0.818) and 0.95 (Phi 0.352), as -L/D
        for kappa, phi, c in ((0.9, 0.818, "C0"), (0.95, 0.352, "C1")):
            ax.axhline(-(kappa * 0.5 - (1 - kappa) / 0.5), color=c, ls=":", lw=1,
                       label=f"Kumar eq. 15, Phi {phi}: "
                             f"L/D = -{kappa * 0.5 - (1 - kappa) / 0.5:.3f}")
        ax.set_xlabel("spin ratio Omega = omega R / V0")
        ax.set_ylabel("L / D  (negative: along -omega x V)")
    elif mode == "drag-omega":
        ax.set_xlabel("spin ratio Omega = omega R / V0")
        ax.set_ylabel("mean drag D (N/m)")
        ax.set_ylim(bottom=0)
    elif mode == "drag-speed":
        ax.set_xlabel("V0 (m/s)")
        ax.set_ylabel("mean drag D (N/m)")
    elif mode == "ld-mu":
        mu = np.linspace(0, max(1.0, ax.get_xlim()[1]), 50)
        ax.plot(mu, mu, "k:", label="L/D = mu (Kumar eq. 9)")
        for kappa in (0.9, 0.95):
            m = mu[mu > 0.05]
            ax.plot(m, kappa * m - (1 - kappa) / m, "--", lw=0.8,
                    label=f"Kumar eq. 15, kappa {kappa}")
        ax.set_ylim(bottom=0)
        ax.set_xlabel("friction coefficient mu")
        ax.set_ylabel("|L / D| at saturated spin")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
