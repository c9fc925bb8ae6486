#!/usr/bin/env python3
"""Figures and table of the depth sweep (studies/depth/study_depth.sh, \
docs/results-guillard2014.md).

    python3 studies/depth/plot_depth_study.py OUT_DIR [IMG_DIR] [--window LO HI]

--window LO HI: the DEM's drag and lift over that travel window (grain diameters) from the force
samples, instead of the files' averages (surface stresses and fields stay the files').

Reads OUT_DIR/<series>/<run>/<solver>.h5 for the series of study_depth.sh (dem: the
first box, 4 D of bed below the centre; dem_rigid: the same with a rigid lid; dem_d6: 6 D of
bed below; dem_d6_s2, dem_d6_s3: its beds 2 and 3, pooled with it into dem_d6_pooled;
fem_full, fem_linearised) (the grainlift schema, nothing from logs) and writes into IMG_DIR
(default OUT_DIR); the collapse and hydrostatic figures show dem_d6_pooled where it exists:
  depth_lift.png        L / B against h / D, both solvers, with and without the gradient
  depth_drag.png        C_d = drag / (rho g h D) against h / D
  depth_antisym.png     (sigma_n - sigma_n(no gradient, same h)) / (rho g D) against theta
  depth_sym.png         symmetric part of sigma_n over P0 against theta
  depth_hydrostatic.png whole-width sigma_yy of the DEM bed against the lid + weight balance
and OUT_DIR/depth_study.csv, one row per run, and prints the same table as Markdown, then the
split, the pooled DEM with its checks, and the lift in 20 d windows of travel.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
import numpy as np  # noqa: E402
from bed_balance import bed_balance, overburden  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.beds import line_fit, pool_series, power_law  # noqa: E402
from grainlift.plots import plt  # noqa: E402
from grainlift.stats import pooled_mean  # noqa: E402
from grainlift.windows import window_mean  # noqa: E402

SERIES = ("dem", "dem_rigid", "dem_d6", "dem_d6_s2", "dem_d6_s3", "fem_full", "fem_linearised")
BEDS = ("dem_d6_s2", "dem_d6_s3")  # the other beds of dem_d6, pooled into dem_d6_pooled
TITLES = {"dem": "DEM, 4 D below", "dem_rigid": "DEM, rigid lid", "dem_d6": "DEM, 6 D below",
          "dem_d6_pooled": "DEM, 6 D below, pooled over beds", "fem_full": "FEM (full solves)"}


def rms(v):
    return float(np.sqrt(np.mean(np.square(v))))


def main_dem(runs):
    """The DEM series the collapse and hydrostatic figures show: the box that does not set the
    lift (dem_d6) pooled over its beds where it was run, else the sweep's standard box."""
    for s in ("dem_d6_pooled", "dem_d6"):
        if any(k[0] == s for k in runs):
            return s
    return "dem"


def travel_series(f):
    """A DEM file's force samples against travel (in grain diameters): travel, drag, lift."""
    drag, lift = f.drag_lift()
    return f.travel(), drag, lift


def read_run(path, window=None):
    """The scalars and distributions of one result file; with window = (lo, hi) the DEM's drag
    and lift (and their errors) over that travel window, in grain diameters, instead of the
    file's averaging window (the surface stresses and fields stay the file's)."""
    f = io.read(path)
    g = f.geometry
    m = f.means
    errors = f.block_errors() or m  # the one rule, whichever binary wrote the file
    der = f.derived
    r = {
        "D": float(g["intruder_diameter"]),
        "rho": float(g["bulk_density"]),
        "g_grains": math.hypot(float(g["gravity_x"]), float(g["gravity_y"])),
        "g_ref": float(g.get("reference_gravity", 0.0)),
        "h": float(g.get("equivalent_depth", 0.0)),
        "P0": float(g["pressure_scale"]),
        "width": float(g["domain_xmax"]) - float(g["domain_xmin"]),
        "below": float(g["intruder_y"]) - float(g["domain_ymin"]),
        "top": float(g["domain_ymax"]) - float(g["intruder_y"]),
        "drag": float(m["drag"]),
        "lift": float(m["lift"]),
        "drag_err": float(errors.get("drag_stderr", 0.0)),
        "lift_err": float(errors.get("lift_stderr", 0.0)),
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
        if "area_fraction" in f["fields"]:  # DEM only
            r["fphi"] = f["fields/area_fraction"][:]
    if "diagnostics" in f and "area_fraction" in f["diagnostics"].attrs:
        r["rho_s"] = r["rho"] / float(f["diagnostics"].attrs["area_fraction"])
    r["lift_fields"] = r["lift"]  # over the files' window, as the fields (bed_balance.py)
    if f.solver == "dem":
        r["series_t"] = travel_series(f)  # (travel, drag, lift), for windows
        if window is not None:
            travel, drag, lift = r["series_t"]
            r["drag"], r["drag_err"] = window_mean(travel, drag, *window)
            r["lift"], r["lift_err"] = window_mean(travel, lift, *window)
    r["hD"] = r["h"] / r["D"]
    r["rgD"] = r["rho"] * r["g_ref"] * r["D"]
    if window is not None and r["h"] > 0 and not math.isnan(r["Cd"]):
        r["Cd"] = r["drag"] / (r["rgD"] * r["h"])
    r["path"] = path
    return r


def hydrostatic_weighting(r):
    """Guillard 2014's estimate (Sec. V): the no-gradient sigma_n0(theta) weighted by the local
    hydrostatic pressure, sigma_n = sigma_n0 (1 - rho g R sin(theta) / P0), gives
    L / B = (1 / (pi P0)) * integral of sigma_n0 sin^2(theta) dtheta."""
    dtheta = 2 * math.pi / len(r["theta"])
    return float(np.sum(r["sn"] * np.sin(r["theta"]) ** 2) * dtheta / (math.pi * r["P0"]))


def load(out, window=None):
    runs = {}
    for s in SERIES:
        base = os.path.join(out, s)
        if not os.path.isdir(base):
            continue
        solver = "dem" if s.startswith("dem") else "fem"
        for name in sorted(os.listdir(base)):
            path = os.path.join(base, name, solver + ".h5")
            if os.path.isfile(path):
                runs[(s, name)] = read_run(path, window)
    return runs


def load_pooled(out, window=None):
    """load(), with the beds of dem_d6 pooled as the series dem_d6_pooled (grainlift.beds): what
    the tables are made of, and what studies/one_box and studies/nonlocal compare with."""
    runs = load(out, window)
    pool_series(runs, "dem_d6", BEDS, "dem_d6_pooled")
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
    ("dem", False): dict(color="C0", marker="o", mfc="none", ls="--",
                         label="DEM, no gradient (lid only)"),
    ("dem_rigid", True): dict(color="C7", marker="v", ms=5, label="DEM, gradient, rigid lid"),
    ("dem_rigid", False): dict(color="C7", marker="v", ms=5, mfc="none", ls="--",
                               label="DEM, no gradient, rigid lid"),
    ("dem_d6", True): dict(color="C1", marker="o", ms=5, label="DEM, gradient, 6 D below"),
    ("dem_d6", False): dict(color="C1", marker="o", ms=5, mfc="none", ls="--",
                            label="DEM, no gradient, 6 D below"),
    ("dem_d6_pooled", True): dict(color="C1", marker="o", ms=6,
                                  label="DEM, gradient, 6 D below, 3 beds"),
    ("dem_d6_pooled", False): dict(color="C1", marker="o", ms=6, mfc="none", ls="--",
                                   label="DEM, no gradient, 6 D below, 3 beds"),
    ("fem_full", True): dict(color="C3", marker="s", label="FEM full, gradient"),
    ("fem_full", False): dict(color="C3", marker="s", mfc="none", ls="--",
                              label="FEM, no gradient"),
    ("fem_linearised", True): dict(color="C2", marker="^", ls=":", label="FEM O(eps), gradient"),
}


def plot_scalar(runs, key, err_key, ylabel, path, norm, net=False):
    """key (normalised by norm) against h/D for every series of STYLE: at full gravity joined by
    lines, at reduced gravity (the same P0 as 8 D) as triangles. net: also the main DEM series
    less its no-gradient run at the same P0 (what the gradient adds)."""
    fig, ax = plt.subplots(figsize=(9.6, 4.6))
    full_g = lambda r: r["g_grains"] > 0.99 * 9.81 or not r["gradient"]
    for (s, grad), st in STYLE.items():
        sel = series(runs, s, grad)
        if not sel or (s == "dem_d6" and any(k[0] == "dem_d6_pooled" for k in runs)):
            continue
        dem = s.startswith("dem")
        for reduced in (False, True):
            pts = [r for _, r in sel if full_g(r) != reduced]
            if not pts:
                continue
            kw = dict(st) if not reduced else dict(
                color=st["color"], marker="^", ms=8, ls="none",
                label=f"{st['label'].split(',')[0]}: g/2, g/4 at the P0 of 8 D")
            ax.errorbar([r["hD"] for r in pts], [norm(r, r[key]) for r in pts],
                        yerr=[norm(r, r[err_key]) for r in pts] if dem else None, capsize=3, **kw)
        for name, r in series(runs, s, grad, free_surface=True):
            ax.errorbar(r["hD"], norm(r, r[key]), yerr=norm(r, r[err_key]) if dem else None,
                        color=st["color"], marker="*", ms=12, ls="none", capsize=3)
    if net:
        m = main_dem(runs)
        pts = [(r, nograd_partner(runs, m, r)) for _, r in series(runs, m, True)]
        pts = [(r, p) for r, p in pts if p is not None]
        if pts:
            ax.errorbar([r["hD"] for r, _ in pts], [norm(r, r[key] - p[key]) for r, p in pts],
                        yerr=[norm(r, math.hypot(r[err_key], p[err_key])) for r, p in pts],
                        color="k", marker="D", ms=6, ls=":", capsize=3,
                        label=f"{TITLES[m].split(',')[0]}: gradient less no gradient (same P0)")
    for s in (main_dem(runs), "fem_full"):
        for name, r in series(runs, s, True, bigbox=True):
            ax.errorbar(r["hD"], norm(r, r[key]),
                        yerr=norm(r, r[err_key]) if s.startswith("dem") else None,
                        color=STYLE[(s, True)]["color"], marker="D", ms=8, mfc="none", ls="none",
                        capsize=3,
                        label=(f"{s.split('_')[0].upper()}, box 18 D wide, 6 D below"
                               if name == "heavy_lid_h8_bigbox" else None))
    ax.plot([], [], "k*", ms=11, ls="none", label="free surface (method i), same colours")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_xlabel("h / D")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=7, bbox_to_anchor=(1.02, 1), loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def wrapped_degrees(theta):
    """theta in degrees, in (-180, 180]."""
    return np.degrees(np.angle(np.exp(1j * np.asarray(theta))))


def nograd_partner(runs, s, r):
    """The no-gradient run of the same solver at the same P0 in the same box (FEM: the full
    solves)."""
    src = "fem_full" if s.startswith("fem") else s
    for (s2, _), r2 in runs.items():
        if (s2 == src and not r2["gradient"] and abs(r2["P0"] / r["P0"] - 1) < 1e-6
                and abs(r2["width"] - r["width"]) < 1e-9):
            return r2
    return None


def plot_collapse(runs, path_anti, path_sym):
    cmap = plt.get_cmap("viridis")
    for what, path in (("anti", path_anti), ("sym", path_sym)):
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
        for ax, s in zip(axes, (main_dem(runs), "fem_full")):
            sel = series(runs, s, True) + [t for t in series(runs, s, True, free_surface=True)
                                           if t[0] == "free_surface_h2"]
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
            ax.set_title(TITLES[s])
            ax.set_xlabel("theta (deg; 0 = front, 90 = top, -90 = bottom)")
            ax.axhline(0, color="0.6", lw=0.8)
            ax.legend(fontsize=7)
        axes[0].set_ylabel("(sigma_n - sigma_n(no gradient)) / (rho g D)" if what == "anti"
                           else "symmetric part of sigma_n / P0 (dashed: no gradient)")
        fig.tight_layout()
        fig.savefig(path, dpi=130)
        plt.close(fig)


def plot_hydrostatic(runs, path):
    """Whole-width sigma_yy in the bed's bands (points) against the force balance of
    bed_balance.py (solid) and the case's nominal line P0 - rho g y (dashed)."""
    fig, ax = plt.subplots(figsize=(5.8, 4.6))
    for i, (name, r) in enumerate(series(runs, main_dem(runs), True)):
        bb = bed_balance(r)
        if bb is None:
            continue
        k = r["rgD"]
        ax.plot(bb["syy"] / k, bb["y"] / r["D"], "o", color=f"C{i}", ms=5,
                label=f"{name}: balance within {100 * bb['max_dev']:.1f}%")
        ax.plot(bb["expected"] / k, bb["y"] / r["D"], "-", color=f"C{i}", lw=0.9)
        ax.plot((r["P0"] - r["rho"] * r["g_grains"] * bb["y"]) / k, bb["y"] / r["D"], "--",
                color=f"C{i}", lw=0.7)
    ax.axhspan(-0.5, 0.5, color="0.9")
    ax.set_xlabel("whole-width sigma_yy / (rho g D)")
    ax.set_ylabel("y / D (intruder centre at 0; grey: its height)")
    ax.set_title(f"{TITLES[main_dem(runs)]}: points measured; "
                 "solid lid + weight above (+ lift below);\n"
                 "dashed the case's P0 - rho g y", fontsize=8)
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def table(runs, out):
    rows = []
    for (s, name), r in sorted(runs.items(), key=lambda t: (t[0][0], not t[1]["gradient"],
                                                            t[1]["hD"], t[0][1])):
        bb = bed_balance(r) if s.startswith("dem") else None
        ob = overburden(r) if s.startswith("dem") else None
        rows.append({
            "series": s, "run": name, "h_over_D": round(r["hD"], 3), "gradient": int(r["gradient"]),
            "P0_Pa": r["P0"], "drag_N_per_m": r["drag"], "drag_err": r["drag_err"],
            "lift_N_per_m": r["lift"], "lift_err": r["lift_err"],
            "L_over_B": r["lift"] / r["B"], "L_over_B_err": r["lift_err"] / r["B"],
            "C_d": r["Cd"],
            "C_d_err": r["drag_err"] / (r["rgD"] * r["h"]) if r["h"] > 0 else float("nan"),
            "lid_mean_over_target": (r["lid_mean"] / r["lid_target"] if r["lid_target"] > 0
                                     else float("nan")),
            "far_field_over_P0": r["far_field"] / r["P0"],
            "overburden_over_P0": ob["load"] / r["P0"] if ob else float("nan"),
            "real_bed_above_centre_D": ob["surface"] / r["D"] if ob else float("nan"),
            "balance_max_dev": bb["max_dev"] if bb else float("nan"),
            "gradient_over_bed_rho_g": bb["slope_over_bed"] if bb else float("nan"),
            "gradient_over_nominal_rho_g": bb["slope_over_nominal"] if bb else float("nan"),
            "hydrostatic_weighting_L_over_B": (hydrostatic_weighting(r) if not r["gradient"]
                                               else float("nan")),
            "wall_s": r["wall_s"],
        })
    with open(os.path.join(out, "depth_study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("| series | run | h/D | P0 (Pa) | drag (N/m) | lift (N/m) | L/B | C_d | lid p/target | "
          "far-field p/P0 | overburden/P0 | real bed above centre (D) | force balance: max dev | "
          "gradient / (rho_bed g), / (rho g) | hydrostatic weighting L/B | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for x in rows:
        pm = lambda v, e: f"{v:.4g} +- {e:.2g}" if e > 0 else f"{v:.4g}"
        nan = lambda v, f="{:.3f}": "-" if v != v else f.format(v)
        print(f"| {x['series']} | {x['run']} | {x['h_over_D']:g} | {x['P0_Pa']:.4g} | "
              f"{pm(x['drag_N_per_m'], x['drag_err'])} | {pm(x['lift_N_per_m'], x['lift_err'])} | "
              f"{pm(x['L_over_B'], x['L_over_B_err'])} | {pm(x['C_d'], x['C_d_err'])} | "
              f"{nan(x['lid_mean_over_target'])} | {nan(x['far_field_over_P0'])} | "
              f"{nan(x['overburden_over_P0'])} | "
              f"{nan(x['real_bed_above_centre_D'], '{:.2f}')} | "
              f"{nan(x['balance_max_dev'], '{:.1%}')} | "
              f"{nan(x['gradient_over_bed_rho_g'], '{:.2f}')}, "
              f"{nan(x['gradient_over_nominal_rho_g'], '{:.2f}')} | "
              f"{nan(x['hydrostatic_weighting_L_over_B'], '{:.2f}')} | "
              f"{x['wall_s']:.0f} |")


def collapse_table(runs):
    """How well the split holds: per gradient run, the symmetric part of sigma_n over P0 against
    its no-gradient partner's (rms difference over the partner's rms), and the antisymmetric
    part over rho g D against the h = 8 D run of the same series (rms difference over the 8 D
    curve's rms), as it is and less the antisymmetric part of the no-gradient run at the same
    P0 (what the gradient adds), with the DEM's noise on that scale (rms of sigma_n_stderr /
    (rho g D), of the two runs combined for the difference)."""
    print("\n| series | run | h/D | sym/P0 vs no gradient: rms diff / rms | "
          "anti/(rho g D) vs 8 D: rms diff / rms | "
          "(anti - anti no gradient)/(rho g D) vs 8 D: rms diff / rms | noise of that / rms(8 D) |")
    print("|---|---|---|---|---|---|---|")
    for s in ("dem", "dem_d6", "dem_d6_pooled", "fem_full"):
        ref = dict(series(runs, s, True)).get("heavy_lid_h8")
        if ref is None:
            continue
        a_ref = ref["anti"] / ref["rgD"]
        p_ref = nograd_partner(runs, s, ref)
        g_ref = (ref["anti"] - p_ref["anti"]) / ref["rgD"] if p_ref is not None else None
        for name, r in series(runs, s, True):
            p = nograd_partner(runs, s, r)
            sym = (f"{rms(r['sym'] / r['P0'] - p['sym'] / p['P0']) / rms(p['sym'] / p['P0']):.3f}"
                   if p is not None else "-")
            anti = rms(r["anti"] / r["rgD"] - a_ref) / rms(a_ref)
            grad, noise = "-", "-"
            if p is not None and g_ref is not None:
                grad = f"{rms((r['anti'] - p['anti']) / r['rgD'] - g_ref) / rms(g_ref):.3f}"
                if r["sn_err"] is not None and p["sn_err"] is not None:
                    noise = f"{rms(np.hypot(r['sn_err'], p['sn_err']) / r['rgD']) / rms(g_ref):.3f}"
            print(f"| {s} | {name} | {r['hD']:g} | {sym} | {anti:.3f} | {grad} | {noise} |")


def pooled_table(runs):
    """The DEM in the box that does not set the lift, pooled over beds (pool_beds.py): L/B and
    C_d with the pooled error, the between-bed and within-bed errors of the lift, and the three
    checks the asymptotic predictions need: no lift without the gradient, the same L/B once
    deep, and the lift's power of g at fixed P0."""
    sel = sorted(((n, r) for (s, n), r in runs.items() if s == "dem_d6_pooled"),
                 key=lambda t: (not t[1]["gradient"], t[1]["hD"], t[0]))
    if not sel:
        return
    print("\n| run | h/D | g / 9.81 | beds | L/B | lift error: between beds / within beds (N/m) | "
          "(L - L no gradient) / B | C_d | drag error: between / within (N/m) |")
    print("|---|---|---|---|---|---|---|---|---|")
    g2 = lambda v: "-" if v != v else f"{v:.2g}"
    for n, r in sel:
        cd = r["rgD"] * r["h"]
        p = nograd_partner(runs, "dem_d6_pooled", r) if r["gradient"] else None
        net = (f"{(r['lift'] - p['lift']) / r['B']:.2f} +- "
               f"{math.hypot(r['lift_err'], p['lift_err']) / r['B']:.2f}"
               if p is not None else "-")
        print(f"| {n} | {r['hD']:g} | {r['g_ref'] / 9.81:.3g} | {r['beds']} | "
              f"{r['lift'] / r['B']:.2f} +- "
              f"{r['lift_err'] / r['B']:.2f} | {g2(r['lift_err_between'])} / "
              f"{g2(r['lift_err_within'])} | {net} | "
              f"{r['drag'] / cd:.3f} +- {r['drag_err'] / cd:.3f} | "
              f"{g2(r['drag_err_between'])} / {g2(r['drag_err_within'])} |")
    byname = dict(sel)
    fixed_p0 = [byname[n] for n in ("heavy_lid_h8", "heavy_lid_h16_g2", "heavy_lid_h32_g4")
                if n in byname]
    if len(fixed_p0) >= 2:
        a, ea = power_law([r["g_grains"] for r in fixed_p0], [r["lift"] for r in fixed_p0],
                          [r["lift_err"] for r in fixed_p0])
        print(f"\nlift at the P0 of 8 D against g ({len(fixed_p0)} gravities): "
              f"power {a:.2f} +- {ea:.2f} "
              f"({abs(a - 1) / ea:.1f} errors from 1)")
        # the split at the level of the force: L = L(P0, no gradient) + b g at fixed P0, with
        # the lid-only run at the same P0 as the point g = 0
        pts = fixed_p0 + ([byname["lid_only_h8"]] if "lid_only_h8" in byname else [])
        if len(pts) >= 3:
            a0, ea0, b, eb, chi = line_fit([r["g_grains"] for r in pts], [r["lift"] for r in pts],
                                           [r["lift_err"] for r in pts])
            print(f"lift at the P0 of 8 D = a + b g ({len(pts)} points, g = 0 the lid-only run): "
                  f"a = {a0:.4g} +- "
                  f"{ea0:.2g} N/m, b g(9.81) = {b * 9.81:.4g} +- {eb * 9.81:.2g} N/m "
                  f"({b * 9.81 / fixed_p0[0]['B']:.2f} +- "
                  f"{eb * 9.81 / fixed_p0[0]['B']:.2f} B), chi2/dof {chi:.2f}")
            if "lid_only_h8" in byname:
                base = byname["lid_only_h8"]
                net = [(r["g_grains"], r["lift"] - base["lift"],
                        math.hypot(r["lift_err"], base["lift_err"]))
                       for r in fixed_p0]
                if all(v > 0 for _, v, _ in net):
                    p, ep = power_law(*zip(*net))
                    print("lift minus the lid-only lift at that P0 against g: "
                          f"power {p:.2f} +- {ep:.2f}")
    for n, r in sel:
        if not r["gradient"]:
            print(f"no gradient, {n}: L/B = {r['lift'] / r['B']:.2f} +- "
                  f"{r['lift_err'] / r['B']:.2f} "
                  f"({abs(r['lift']) / r['lift_err']:.1f} errors from 0)")
    for wide in [n for n in byname if n.endswith("_bigbox") and n[:-len("_bigbox")] in byname]:
        r1, r2 = byname[wide[:-len("_bigbox")]], byname[wide]
        for k in ("lift", "drag"):
            d = (r2[k] - r1[k]) / r1["B"]
            e = math.hypot(r1[k + "_err"], r2[k + "_err"]) / r1["B"]
            print(f"box check, {wide[:-len('_bigbox')]}, {k}: 18 D wide ({r2['beds']} beds) "
                  "less 12 D wide "
                  f"({r1['beds']} beds) = {d:+.2f} +- {e:.2f} B ({abs(d) / e:.1f} errors; "
                  f"{100 * (r2[k] / r1[k] - 1):+.0f}%)")
    # the same check on the surface stresses (the files' 20-100 d averages): the split's two
    # parts in the two boxes, rms difference over the 18 D box's rms, with the noise on that scale
    for wide in [n for n in byname if n.endswith("_bigbox") and byname[n]["gradient"]]:
        r1, r2 = byname[wide[:-len("_bigbox")]], byname[wide]
        p1, p2 = (nograd_partner(runs, "dem_d6_pooled", r1),
                  nograd_partner(runs, "dem_d6_pooled", r2))
        if p1 is None or p2 is None or r1["sn_err"] is None:
            continue
        s2 = r2["sym"] / r2["P0"]
        g1, g2 = (r1["anti"] - p1["anti"]) / r1["rgD"], (r2["anti"] - p2["anti"]) / r2["rgD"]
        noise_s = rms(np.hypot(r1["sn_err"], r2["sn_err"]) / r1["P0"]) / rms(s2)
        noise_g = rms(np.sqrt(r1["sn_err"] ** 2 + r2["sn_err"] ** 2 + p1["sn_err"] ** 2
                              + p2["sn_err"] ** 2)
                      / r1["rgD"]) / rms(g2)
        print(f"box check, {wide[:-len('_bigbox')]}, surface stress (20-100 d): "
              "symmetric part / P0 differs by "
              f"{rms(r1['sym'] / r1['P0'] - s2) / rms(s2):.3f} rms (noise {noise_s:.3f}); "
              "the gradient's antisymmetric part / (rho g D) by "
              f"{rms(g1 - g2) / rms(g2):.3f} (noise {noise_g:.3f})")
    deep = [(n, byname[n]) for n in ("heavy_lid_h6", "heavy_lid_h8", "heavy_lid_h12")
            if n in byname]
    for (n1, r1), (n2, r2) in zip(deep, deep[1:]):
        d = r2["lift"] / r2["B"] - r1["lift"] / r1["B"]
        e = math.hypot(r1["lift_err"] / r1["B"], r2["lift_err"] / r2["B"])
        print(f"L/B {n2} - {n1}: {d:+.2f} +- {e:.2f} ({abs(d) / e:.1f} errors)")


def window_table(runs):
    """The pooled DEM's lift in buoyancies over successive 20 d windows of travel (mean over the
    beds, error as in pool_beds.py): how the lift changes as the
    bed ahead of the intruder, which has not yet been crossed, shortens. In a periodic box of
    length W the intruder has W - travel of such bed ahead of it."""
    wins = ((20, 40), (40, 60), (60, 80), (80, 100))
    print("\n| run | box width (D) | beds | "
          + " | ".join(f"L/B, travel {a}-{b} d" for a, b in wins) + " |")
    print("|---|---|---|" + "---|" * len(wins))
    for (s, n), r in sorted(runs.items(), key=lambda t: (not t[1]["gradient"], t[1]["width"],
                                                         t[1]["hD"], t[0][1])):
        if s != "dem_d6":
            continue
        beds = [r] + [runs[(e, n)] for e in BEDS if (e, n) in runs]
        cells = []
        for lo, hi in wins:
            if any(b["series_t"][0][-1] < hi - 1e-6 for b in beds):
                cells.append("-")
                continue
            means = [window_mean(b["series_t"][0], b["series_t"][2], lo, hi) for b in beds]
            p = pooled_mean([m for m, _ in means], [e for _, e in means])
            cells.append(f"{p.mean / r['B']:.1f} +- {p.error / r['B']:.1f}")
        print(f"| {n} | {r['width'] / r['D']:.0f} | {len(beds)} | " + " | ".join(cells) + " |")


def main():
    args = sys.argv[1:]
    window = None
    if "--window" in args:
        k = args.index("--window")
        try:
            window = (float(args[k + 1]), float(args[k + 2]))
        except (IndexError, ValueError):
            print("--window needs two numbers: the travel window in grain diameters",
                  file=sys.stderr)
            return 2
        del args[k:k + 3]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__)
        return 2
    out = args[0]
    img = args[1] if len(args) > 1 else out
    os.makedirs(img, exist_ok=True)
    runs = load_pooled(out, window)
    if not runs:
        print(f"no results under {out}/{{dem,fem_full,fem_linearised}}/*/", file=sys.stderr)
        return 1
    plot_scalar(runs, "lift", "lift_err", "L / B,  B = rho g pi D^2 / 4",
                os.path.join(img, "depth_lift.png"), lambda r, v: v / r["B"], net=True)
    plot_scalar(runs, "drag", "drag_err", "C_d = drag / (rho g h D)",
                os.path.join(img, "depth_drag.png"), lambda r, v: v / (r["rgD"] * r["h"]))
    plot_collapse(runs, os.path.join(img, "depth_antisym.png"), os.path.join(img, "depth_sym.png"))
    plot_hydrostatic(runs, os.path.join(img, "depth_hydrostatic.png"))
    table(runs, out)
    collapse_table(runs)
    pooled_table(runs)
    window_table(runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
