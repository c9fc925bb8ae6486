#!/usr/bin/env python3
"""Figures and table of the depth sweep (scripts/study_depth.sh, docs/results-guillard2014.md).

    python3 scripts/plot_depth_study.py OUT_DIR [IMG_DIR]

Reads OUT_DIR/{dem,dem_rigid,fem_full,fem_linearised}/<run>/<solver>.h5 (dem_rigid: the same
runs with a rigid lid, domain.lid = "rigid") (the grainlift schema, nothing
from logs) and writes into IMG_DIR (default OUT_DIR):
  depth_lift.png        L / B against h / D, both solvers, with and without the gradient
  depth_drag.png        C_d = drag / (rho g h D) against h / D
  depth_antisym.png     (sigma_n - sigma_n(no gradient, same h)) / (rho g D) against theta
  depth_sym.png         symmetric part of sigma_n over P0 against theta
  depth_hydrostatic.png DEM bed pressure away from the intruder against height, and rho g (h - y)
and OUT_DIR/depth_study.csv, one row per run, and prints the same table as Markdown.
"""
import csv
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

SERIES = ("dem", "dem_rigid", "fem_full", "fem_linearised")


def read_run(path):
    """The scalars and distributions of one result file."""
    with h5py.File(path, "r") as f:
        g = f["geometry"].attrs
        m = f["means"].attrs
        der = f["derived"].attrs
        r = {
            "D": float(g["intruder_diameter"]),
            "rho": float(g["bulk_density"]),
            "g_grains": math.hypot(float(g["gravity_x"]), float(g["gravity_y"])),
            "g_ref": float(g.get("reference_gravity", 0.0)),
            "h": float(g.get("equivalent_depth", 0.0)),
            "P0": float(g["pressure_scale"]),
            "width": float(g["domain_xmax"]) - float(g["domain_xmin"]),
            "below": float(g["intruder_y"]) - float(g["domain_ymin"]),
            "drag": float(m["drag"]),
            "lift": float(m["lift"]),
            "drag_err": float(m.get("drag_stderr", 0.0)),
            "lift_err": float(m.get("lift_stderr", 0.0)),
            "B": float(der.get("buoyancy", float("nan"))),
            "Cd": float(der.get("drag_coefficient", float("nan"))),
            "wall_s": float(f["metadata"].attrs["wall_seconds"]),
            "lid_mean": float(f["lid"].attrs["mean"]) if "lid" in f else float("nan"),
            "lid_target": float(f["lid"].attrs["target"]) if "lid" in f else float("nan"),
            "far_field": float(f["far_field"].attrs["mean"]) if "far_field" in f else float("nan"),
        }
        if r["g_ref"] == 0:
            r["g_ref"] = r["g_grains"]
        r["gradient"] = r["g_grains"] > 0
        r["theta"] = f["surface/theta"][:]
        r["sn"] = f["surface/sigma_n"][:]
        r["sn_err"] = f["surface/sigma_n_stderr"][:] if "sigma_n_stderr" in f["surface"] else None
        r["sym"] = f["derived/sigma_n_symmetric"][:]
        r["anti"] = f["derived/sigma_n_antisymmetric"][:]
        if "fields" in f and "pressure" in f["fields"]:
            r["fx"] = f["fields/x"][:]
            r["fy"] = f["fields/y"][:]
            r["fp"] = f["fields/pressure"][:]
            r["fsyy"] = -f["fields/stress_yy"][:]  # compressive positive
    r["hD"] = r["h"] / r["D"]
    r["rgD"] = r["rho"] * r["g_ref"] * r["D"]
    return r


def hydrostatic(r, field="fp"):
    """Bed pressure (field "fp"; "fsyy": the vertical stress) away from the intruder (|x| >= 4 D) in bands of D/2 over |y| <= 1.5 D (the
    DEM's fine grid shows the grain layering row by row) against the expected P0 - rho g y
    (gradient) or P0 (lid only): fitted slope over -rho g (1 for hydrostatic), and the largest
    relative deviation of a band mean from the expected line."""
    if "fp" not in r:
        return None
    D = r["D"]
    cols = np.abs(r["fx"]) >= 4 * D
    edges = np.arange(-1.5, 1.5001, 0.5) * D
    y, p = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        rows = (r["fy"] >= lo) & (r["fy"] < hi)
        if rows.sum() == 0 or cols.sum() == 0:
            return None
        y.append(0.5 * (lo + hi))
        p.append(r[field][np.ix_(rows, cols)].mean())
    y, p = np.array(y), np.array(p)
    rho_g = r["rho"] * r["g_grains"]
    expected = r["P0"] - rho_g * y
    slope = np.polyfit(y, p, 1)[0]
    return {
        "y": y,
        "p": p,
        "expected": expected,
        "slope_ratio": (-slope / rho_g) if rho_g > 0 else float("nan"),
        "max_dev": float(np.max(np.abs(p / expected - 1))),
    }


def weight_balance(r):
    """The bed's vertical stress over the whole width in bands of D/2 clear of the intruder
    (0.5 D <= |y| <= 1.5 D) against P0 - rho g y: largest relative deviation. Across a whole
    horizontal line that misses the intruder, force balance makes sigma_yy the lid's pressure
    plus the weight above."""
    if "fsyy" not in r:
        return float("nan")
    D = r["D"]
    dev = 0.0
    for lo in (-1.5, -1.0, 0.5, 1.0):
        rows = (r["fy"] >= lo * D) & (r["fy"] < (lo + 0.5) * D)
        y = (lo + 0.25) * D
        expected = r["P0"] - r["rho"] * r["g_grains"] * y
        dev = max(dev, abs(float(np.nanmean(r["fsyy"][rows, :])) / expected - 1))
    return dev


def hydrostatic_weighting(r):
    """Guillard 2014's estimate (Sec. V): the no-gradient sigma_n0(theta) weighted by the local
    hydrostatic pressure, sigma_n = sigma_n0 (1 - rho g R sin(theta) / P0), gives
    L / B = (1 / (pi P0)) * integral of sigma_n0 sin^2(theta) dtheta."""
    dtheta = 2 * math.pi / len(r["theta"])
    return float(np.sum(r["sn"] * np.sin(r["theta"]) ** 2) * dtheta / (math.pi * r["P0"]))


def load(out):
    runs = {}
    for s in SERIES:
        base = os.path.join(out, s)
        if not os.path.isdir(base):
            continue
        solver = "dem" if s.startswith("dem") else "fem"
        for name in sorted(os.listdir(base)):
            path = os.path.join(base, name, solver + ".h5")
            if os.path.isfile(path):
                runs[(s, name)] = read_run(path)
    return runs


def series(runs, s, gradient, bigbox=False, free_surface=False):
    """Runs of series s with or without the gradient, on the standard box, sorted by depth: the
    lid runs, or (free_surface) the free-surface ones."""
    sel = [(k[1], r) for k, r in runs.items()
           if k[0] == s and r["gradient"] == gradient and k[1].endswith("bigbox") == bigbox
           and k[1].startswith("free_surface") == free_surface]
    return sorted(sel, key=lambda t: t[1]["hD"])


STYLE = {
    ("dem", True): dict(color="C0", marker="o", label="DEM, gradient"),
    ("dem", False): dict(color="C0", marker="o", mfc="none", ls="--", label="DEM, no gradient (lid only)"),
    ("dem_rigid", True): dict(color="C7", marker="v", ms=5, label="DEM, gradient, rigid lid"),
    ("dem_rigid", False): dict(color="C7", marker="v", ms=5, mfc="none", ls="--", label="DEM, no gradient, rigid lid"),
    ("fem_full", True): dict(color="C3", marker="s", label="FEM full, gradient"),
    ("fem_full", False): dict(color="C3", marker="s", mfc="none", ls="--", label="FEM, no gradient"),
    ("fem_linearised", True): dict(color="C2", marker="^", ls=":", label="FEM O(eps), gradient"),
}


def plot_scalar(runs, key, err_key, ylabel, path, norm):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for (s, grad), st in STYLE.items():
        sel = series(runs, s, grad)
        if not sel:
            continue
        x = [r["hD"] for _, r in sel]
        y = [norm(r, r[key]) for _, r in sel]
        e = [norm(r, r[err_key]) if err_key else 0 for _, r in sel]
        ax.errorbar(x, y, yerr=e if s.startswith("dem") else None, capsize=3, **st)
        for name, r in series(runs, s, grad, free_surface=True):
            ax.errorbar(r["hD"], norm(r, r[key]), yerr=norm(r, r[err_key]) if s.startswith("dem") else None,
                        color=st["color"], marker="*", ms=12, ls="none", capsize=3)
    for s in ("dem", "fem_full"):
        for name, r in series(runs, s, True, bigbox=True):
            ax.errorbar(r["hD"], norm(r, r[key]), yerr=norm(r, r[err_key]) if s == "dem" else None,
                        color=STYLE[(s, True)]["color"], marker="D", ms=8, mfc="none", ls="none",
                        capsize=3, label=f"{s.split('_')[0].upper()}, box 1.5x wider, 6 D below")
    ax.plot([], [], "k*", ms=11, ls="none", label="free surface (method i), same colours")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_xlabel("h / D")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def wrapped_degrees(theta):
    """theta in degrees, in (-180, 180]."""
    return np.degrees(np.angle(np.exp(1j * np.asarray(theta))))


def nograd_partner(runs, s, r):
    """The no-gradient run of the same solver at the same P0 (FEM: the full solves)."""
    src = "fem_full" if s.startswith("fem") else s
    for (s2, name), r2 in runs.items():
        if s2 == src and not r2["gradient"] and abs(r2["P0"] / r["P0"] - 1) < 1e-6 and not name.endswith("bigbox"):
            return r2
    return None


def plot_collapse(runs, path_anti, path_sym):
    cmap = plt.get_cmap("viridis")
    for what, path in (("anti", path_anti), ("sym", path_sym)):
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
        for ax, s in zip(axes, ("dem", "fem_full")):
            sel = series(runs, s, True) + [t for t in series(runs, s, True, free_surface=True) if t[0] == "free_surface_h2"]
            sel.sort(key=lambda t: t[1]["hD"])
            hmax = max([r["hD"] for _, r in sel] + [1])
            for name, r in sel:
                c = cmap(r["hD"] / hmax)
                deg = wrapped_degrees(r["theta"])
                order = np.argsort(deg)
                if what == "anti":
                    p = nograd_partner(runs, s, r)
                    if p is None:
                        continue
                    y = (r["sn"] - p["sn"]) / r["rgD"]
                else:
                    y = r["sym"] / r["P0"]
                ax.plot(deg[order], y[order], color=c, label=f"{name}: h = {r['hD']:.0f} D")
            if what == "sym":
                for name, r in series(runs, s, False):
                    deg = wrapped_degrees(r["theta"])
                    order = np.argsort(deg)
                    ax.plot(deg[order], (r["sym"] / r["P0"])[order], color=cmap(r["hD"] / hmax),
                            ls="--", lw=0.8)
            ax.set_title({"dem": "DEM", "fem_full": "FEM (full solves)"}[s])
            ax.set_xlabel("theta (deg; 0 = front, 90 = top, -90 = bottom)")
            ax.axhline(0, color="0.6", lw=0.8)
            ax.legend(fontsize=7)
        axes[0].set_ylabel("(sigma_n - sigma_n(no gradient)) / (rho g D)" if what == "anti"
                           else "symmetric part of sigma_n / P0 (dashed: no gradient)")
        fig.tight_layout()
        fig.savefig(path, dpi=130)
        plt.close(fig)


def plot_hydrostatic(runs, path):
    fig, ax = plt.subplots(figsize=(5.6, 4.4))
    for i, (name, r) in enumerate(series(runs, "dem", True)):
        hs = hydrostatic(r)
        if hs is None:
            continue
        hv = hydrostatic(r, "fsyy")
        ax.plot(hs["p"] / r["rgD"], hs["y"] / r["D"], "o", color=f"C{i}", ms=4, mfc="none",
                label=f"{name}: p, max dev {100 * hs['max_dev']:.0f}%")
        ax.plot(hv["p"] / r["rgD"], hv["y"] / r["D"], "s", color=f"C{i}", ms=4,
                label=f"{name}: sigma_yy, max dev {100 * hv['max_dev']:.0f}%")
        ax.plot(hs["expected"] / r["rgD"], hs["y"] / r["D"], "-", color=f"C{i}", lw=0.8)
    ax.set_xlabel("stress / (rho g D), |x| >= 4 D, bands of D/2")
    ax.set_ylabel("y / D (intruder centre at 0)")
    ax.set_title("DEM bed away from the intruder: p (open), sigma_yy (filled); P0 - rho g y (lines)", fontsize=8)
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def table(runs, out):
    rows = []
    for (s, name), r in sorted(runs.items(), key=lambda t: (t[0][0], not t[1]["gradient"], t[1]["hD"], t[0][1])):
        hs = hydrostatic(r) if s.startswith("dem") else None
        hv = hydrostatic(r, "fsyy") if s.startswith("dem") else None
        rows.append({
            "series": s, "run": name, "h_over_D": round(r["hD"], 3), "gradient": int(r["gradient"]),
            "P0_Pa": r["P0"], "drag_N_per_m": r["drag"], "drag_err": r["drag_err"],
            "lift_N_per_m": r["lift"], "lift_err": r["lift_err"],
            "L_over_B": r["lift"] / r["B"], "L_over_B_err": r["lift_err"] / r["B"],
            "C_d": r["Cd"], "C_d_err": r["drag_err"] / (r["rgD"] * r["h"]) if r["h"] > 0 else float("nan"),
            "lid_mean_over_target": r["lid_mean"] / r["lid_target"] if r["lid_target"] > 0 else float("nan"),
            "far_field_over_P0": r["far_field"] / r["P0"],
            "hydro_slope_ratio": hs["slope_ratio"] if hs else float("nan"),
            "hydro_max_dev": hs["max_dev"] if hs else float("nan"),
            "syy_slope_ratio": hv["slope_ratio"] if hv else float("nan"),
            "syy_max_dev": hv["max_dev"] if hv else float("nan"),
            "syy_full_width_max_dev": weight_balance(r) if s.startswith("dem") else float("nan"),
            "hydrostatic_weighting_L_over_B": hydrostatic_weighting(r) if not r["gradient"] else float("nan"),
            "wall_s": r["wall_s"],
        })
    with open(os.path.join(out, "depth_study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("| series | run | h/D | P0 (Pa) | drag (N/m) | lift (N/m) | L/B | C_d | lid p/target | far-field p/P0 | bed p: slope / rho g, max dev | bed sigma_yy: slope / rho g, max dev | sigma_yy whole width: max dev | hydrostatic weighting L/B | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for x in rows:
        pm = lambda v, e: f"{v:.4g} +- {e:.2g}" if e > 0 else f"{v:.4g}"
        nan = lambda v, f="{:.3f}": "-" if v != v else f.format(v)
        print(f"| {x['series']} | {x['run']} | {x['h_over_D']:g} | {x['P0_Pa']:.4g} | "
              f"{pm(x['drag_N_per_m'], x['drag_err'])} | {pm(x['lift_N_per_m'], x['lift_err'])} | "
              f"{pm(x['L_over_B'], x['L_over_B_err'])} | {pm(x['C_d'], x['C_d_err'])} | "
              f"{nan(x['lid_mean_over_target'])} | {nan(x['far_field_over_P0'])} | {nan(x['hydro_slope_ratio'], '{:.2f}')}, "
              f"{nan(x['hydro_max_dev'], '{:.1%}')} | {nan(x['syy_slope_ratio'], '{:.2f}')}, "
              f"{nan(x['syy_max_dev'], '{:.1%}')} | {nan(x['syy_full_width_max_dev'], '{:.1%}')} | "
              f"{nan(x['hydrostatic_weighting_L_over_B'], '{:.2f}')} | "
              f"{x['wall_s']:.0f} |")


def collapse_table(runs):
    """How well the split holds: per gradient run, the symmetric part of sigma_n over P0 against
    its no-gradient partner's (rms difference over the partner's rms), and the antisymmetric
    part over rho g D against the h = 8 D run of the same series (rms difference over the 8 D
    curve's rms), with the DEM's noise on that scale (rms of sigma_n_stderr / (rho g D))."""
    print("\n| series | run | h/D | sym/P0 vs no gradient: rms diff / rms | anti/(rho g D) vs 8 D: rms diff / rms | noise: rms stderr / (rho g D) / rms(anti 8 D) |")
    print("|---|---|---|---|---|---|")
    rms = lambda v: float(np.sqrt(np.mean(np.square(v))))
    for s in ("dem", "fem_full"):
        ref = dict(series(runs, s, True)).get("heavy_lid_h8")
        if ref is None:
            continue
        a_ref = ref["anti"] / ref["rgD"]
        for name, r in series(runs, s, True):
            p = nograd_partner(runs, s, r)
            sym = (f"{rms(r['sym'] / r['P0'] - p['sym'] / p['P0']) / rms(p['sym'] / p['P0']):.3f}"
                   if p is not None else "-")
            anti = rms(r["anti"] / r["rgD"] - a_ref) / rms(a_ref)
            noise = (f"{rms(r['sn_err'] / r['rgD']) / rms(a_ref):.3f}" if r["sn_err"] is not None else "-")
            print(f"| {s} | {name} | {r['hD']:g} | {sym} | {anti:.3f} | {noise} |")


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    out = sys.argv[1]
    img = sys.argv[2] if len(sys.argv) > 2 else out
    os.makedirs(img, exist_ok=True)
    runs = load(out)
    if not runs:
        print(f"no results under {out}/{{dem,fem_full,fem_linearised}}/*/", file=sys.stderr)
        return 1
    plot_scalar(runs, "lift", "lift_err", "L / B,  B = rho g pi D^2 / 4",
                os.path.join(img, "depth_lift.png"), lambda r, v: v / r["B"])
    plot_scalar(runs, "drag", "drag_err", "C_d = drag / (rho g h D)",
                os.path.join(img, "depth_drag.png"), lambda r, v: v / (r["rgD"] * r["h"]))
    plot_collapse(runs, os.path.join(img, "depth_antisym.png"), os.path.join(img, "depth_sym.png"))
    plot_hydrostatic(runs, os.path.join(img, "depth_hydrostatic.png"))
    table(runs, out)
    collapse_table(runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
