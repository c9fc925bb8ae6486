#!/usr/bin/env python3
"""Figures and tables of the continuum studies (studies/continuum/study_continuum.sh).

    plot_continuum_study.py RUN_DIR IMG_DIR

Reads RUN_DIR/{split,mesh,delta,hdelta,wellposed,box,spin,spin_bg,depth_bg}/*/fem.h5 (the shared \
schema, docs/schema.md), writes
PNG figures into IMG_DIR and prints the markdown tables of docs/results-continuum.md. Parts whose
runs are missing are skipped with a note.
"""
import csv
import glob
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.plots import plt  # noqa: E402
from grainlift.stats import MAX_ORDER, MIN_ORDER, richardson  # noqa: E402


def load(path):
    """Scalars and the surface distributions of one fem.h5 (schema 2: /diagnostics, /derived)."""
    f = io.read(path)
    g = f.geometry
    m = f.means
    meta = f.metadata
    diag = f.diagnostics
    derived = f["derived"] if "derived" in f else None
    r = {
        "drag": float(m["drag"]),
        "lift": float(m["lift"]),
        "torque": float(m["torque"]),
        "seconds": float(meta["wall_seconds"]),
        "theta": f["surface/theta"][:],
        "sigma_n": f["surface/sigma_n"][:],
        "sigma_t": f["surface/sigma_t"][:],
        # the traction itself for force integrals (files before the kernel average: /surface)
        "sigma_n_pointwise": f["surface/sigma_n_pointwise" if "sigma_n_pointwise" in f["surface"]
                               else "surface/sigma_n"][:],
        "D": float(g["intruder_diameter"]),
        "rho": float(g["bulk_density"]),
        "g": math.hypot(float(g["gravity_x"]), float(g["gravity_y"])),
        "P0": float(g["pressure_scale"]),
        "V": math.hypot(float(g["velocity_x"]), float(g["velocity_y"])),
        "omega": float(g["omega"]),
    }
    if derived is not None:
        r["spin_ratio"] = float(derived.attrs["spin_ratio"])
        if "buoyancy" in derived.attrs:
            r["buoyancy"] = float(derived.attrs["buoyancy"])
        if "sigma_n_symmetric" in derived:
            r["sigma_n_split"] = (derived["sigma_n_symmetric"][:],
                                  derived["sigma_n_antisymmetric"][:])

    def get(key, conv=float):
        return conv(diag[key]) if key in diag else None

    r["cells"] = get("cells", int)
    r["dofs"] = get("dofs", int)
    r["iterations"] = get("nonlinear_iterations", int)
    r["correction_s"] = get("correction_seconds")
    r["splits"] = get("continuation_splits", int)
    return r


def buoyancy(r):
    """2D buoyancy rho g pi D^2 / 4, as grainlift wrote it (/derived)."""
    return r["buoyancy"]


def drag_coefficient(r):
    """drag / (P0 D)"""
    return r["drag"] / (r["P0"] * r["D"])


def lift_ratio(r):
    """lift / buoyancy"""
    return r["lift"] / buoyancy(r)


# columns of the study tables: header, value of a run
COLUMNS = {
    "cells": ("cells", lambda r: f"{r['cells']}"),
    "dofs": ("unknowns", lambda r: f"{r['dofs']}"),
    "cd": ("drag / (P0 D)", lambda r: f"{drag_coefficient(r):.4f}"),
    "lb": ("L/B", lambda r: f"{lift_ratio(r):.3f}"),
    "steps": ("nonlinear steps", lambda r: f"{r['iterations']}"),
    "time": ("time", lambda r: f"{r['seconds']:.1f} s"),
}


def print_table(title, key_header, rows, columns):
    """Markdown table: one row per (key, run), the key formatted with :g."""
    print(f"\n### {title}\n")
    heads = [key_header] + [COLUMNS[c][0] for c in columns]
    print("| " + " | ".join(heads) + " |")
    print("|" + "---|" * len(heads))
    for key, r in rows:
        print(f"| {key:g} | " + " | ".join(COLUMNS[c][1](r) for c in columns) + " |")


def hydrostatic_weighting_lift(base, g, rho):
    """Lift of the g = 0 normal stress weighted by the local hydrostatic pressure
    (P0 - rho g R sin(theta)) / P0 (Guillard 2014's estimate, about 3.6 buoyancies in their DEM)."""
    R = 0.5 * base["D"]
    th = base["theta"]
    w = (base["P0"] - rho * g * R * np.sin(th)) / base["P0"]
    sn = base["sigma_n_pointwise"] * w
    dth = 2 * np.pi / len(th)
    # the normal stress pushes on the surface along -n: force_y = -sum sigma_n sin(theta) R dtheta
    return -np.sum(sn * np.sin(th)) * R * dth


def part_split(run_dir, img_dir, sub="split", title=""):
    """The asymptotic split from RUN_DIR/SUB; figures continuum_SUB_*.png."""
    rows = []
    for h in (4, 8, 16, 32):
        paths = {k: os.path.join(run_dir, sub, f"{k}_h{h}", "fem.h5")
                 for k in ("full", "linearised", "base")}
        if not all(os.path.exists(p) for p in paths.values()):
            print(f"({sub}: h = {h} D incomplete, skipped)")
            continue
        rows.append((h, {k: load(p) for k, p in paths.items()}))
    if not rows:
        print(f"({sub}: no runs)")
        return
    print(f"\n### Asymptotic split{title}: (a) full nonlinear solve, "
          "(b) base state + one linear solve\n")
    print("| h/D | eps | P0 (Pa) | C_d (a) | C_d (b) | L/B (a) | L/B (b) | (b)-(a) in L/B | "
          "drag base | hydrostatic weighting L/B | time (a) | time (b) | of which correction |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for h, r in rows:
        a, b, base = r["full"], r["linearised"], r["base"]
        B = buoyancy(a)
        P0 = base["P0"]
        hw = hydrostatic_weighting_lift(base, a["g"], a["rho"]) / B
        print(f"| {h} | 1/{h} | {P0:.4g} | {a['drag'] / (P0 * a['D']):.3f} | "
              f"{b['drag'] / (P0 * a['D']):.3f} | "
              f"{a['lift'] / B:.2f} | {b['lift'] / B:.2f} | {(b['lift'] - a['lift']) / B:+.2f} | "
              f"{base['drag'] / (P0 * a['D']):.3f} | {hw:.2f} | {a['seconds']:.1f} s | "
              f"{b['seconds']:.1f} s | "
              f"{(b['correction_s'] or 0):.2f} s |")

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    hs = [h for h, _ in rows]
    ax[0].plot(hs, [r["full"]["lift"] / buoyancy(r["full"]) for _, r in rows], "o-",
               label="(a) full nonlinear")
    ax[0].plot(hs, [r["linearised"]["lift"] / buoyancy(r["full"]) for _, r in rows], "s--",
               label="(b) base + linear correction")
    ax[0].plot(hs, [hydrostatic_weighting_lift(r["base"], r["full"]["g"], r["full"]["rho"])
                    / buoyancy(r["full"])
                    for _, r in rows], "^:", label="g = 0 stress x hydrostatic weight")
    ax[0].set_xscale("log", base=2)
    ax[0].set_xlabel("h / D")
    ax[0].set_ylabel("lift / buoyancy")
    ax[0].legend()
    ax[0].set_title("lift against depth")
    for key, style, lab in (("full", "o-", "(a)"), ("linearised", "s--", "(b)"),
                            ("base", "^:", "no gravity")):
        ax[1].plot(hs, [r[key]["drag"] / (r["base"]["P0"] * r["full"]["D"]) for _, r in rows],
                   style, label=lab)
    ax[1].set_xscale("log", base=2)
    ax[1].set_xlabel("h / D")
    ax[1].set_ylabel("drag / (P0 D)")
    ax[1].legend()
    ax[1].set_title("drag coefficient")
    fig.suptitle(title.strip(" ,"))
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, f"continuum_{sub}_forces.png"), dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for h, r in rows:
        base, a, b = r["base"], r["full"], r["linearised"]
        th = np.degrees(base["theta"])
        order = np.argsort(np.mod(th + 180, 360))
        thp = (np.mod(th + 180, 360) - 180)[order]
        rgD = a["rho"] * a["g"] * a["D"]
        sym_a, anti_a = a["sigma_n_split"]
        sym_b, anti_b = b["sigma_n_split"]
        line, = ax[0].plot(thp, (sym_a / base["P0"])[order], label=f"(a) h = {h} D")
        ax[0].plot(thp, (base["sigma_n"] / base["P0"])[order], ":", color=line.get_color())
        line, = ax[1].plot(thp, (anti_a / rgD)[order], label=f"(a) h = {h} D")
        ax[1].plot(thp, (anti_b / rgD)[order], "--", color=line.get_color())
        ax[2].plot(thp, ((sym_a - base["sigma_n"]) / rgD)[order], label=f"(a) h = {h} D")
    ax[0].set_title("symmetric part of sigma_n / P0")
    ax[0].text(0.02, 0.92, "solid (a) full, dotted no gravity", transform=ax[0].transAxes,
               fontsize=8)
    ax[1].set_title("antisymmetric part of sigma_n / (rho g D)")
    ax[1].text(0.02, 0.02, "solid (a) full, dashed (b) linearised", transform=ax[1].transAxes,
               fontsize=8)
    ax[2].set_title("(a): symmetric part minus g = 0 stress, / (rho g D)")
    for x in ax:
        x.set_xlabel("theta from V (deg)")
        x.axhline(0, color="k", lw=0.5)
        x.legend(fontsize=7, loc="upper right")
    fig.suptitle(title.strip(" ,"))
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, f"continuum_{sub}_sigma_n.png"), dpi=120)
    plt.close(fig)


def series(run_dir, sub, pattern, key_of):
    out = []
    for p in sorted(glob.glob(os.path.join(run_dir, sub, pattern, "fem.h5"))):
        out.append((key_of(os.path.basename(os.path.dirname(p))), load(p)))
    return sorted(out, key=lambda x: x[0])


def part_mesh(run_dir, img_dir):
    for kind in ("full", "linearised"):
        rows = series(run_dir, "mesh", f"{kind}_r*", lambda n: int(n.split("_r")[1]))
        if not rows:
            print(f"(mesh {kind}: no runs)")
            continue
        print_table(f"Mesh levels ({kind}), h = 8 D", "refinement", rows,
                    ("cells", "dofs", "cd", "lb", "steps", "time"))
    ad = series(run_dir, "mesh", "adaptive_a*", lambda n: int(n.split("_a")[-1]))
    if ad:
        print_table("Adaptive cycles from refinement 1, h = 8 D", "cycles", ad,
                    ("cells", "dofs", "cd", "lb", "steps", "time"))
    rows = series(run_dir, "mesh", "full_r*", lambda n: int(n.split("_r")[1]))
    if len(rows) >= 2:
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        lev = [x for x, _ in rows]
        ax[0].plot(lev, [drag_coefficient(r) for _, r in rows], "o-", label="drag / (P0 D)")
        ax[0].plot(lev, [lift_ratio(r) for _, r in rows], "s-", label="lift / buoyancy")
        lin = series(run_dir, "mesh", "linearised_r*", lambda n: int(n.split("_r")[1]))
        if lin:
            ax[0].plot([x for x, _ in lin], [lift_ratio(r) for _, r in lin], "s--",
                       label="lift / buoyancy, (b)")
        ax[0].set_xlabel("refinement level")
        ax[0].set_title("Guillard gradient case, h = 8 D")
        ax[1].semilogy([r["dofs"] for _, r in rows], [r["seconds"] for _, r in rows], "o-",
                       label="uniform")
        if ad:
            ax[1].semilogy([r["dofs"] for _, r in ad], [r["seconds"] for _, r in ad], "s--",
                           label="adaptive")
            ax[0].plot([1 + 0.5 * k for k, _ in ad], [drag_coefficient(r) for _, r in ad], "x",
                       color="C0", label="adaptive (x at 1 + cycles/2)")
            ax[0].plot([1 + 0.5 * k for k, _ in ad], [lift_ratio(r) for _, r in ad], "x",
                       color="C1")
        ax[0].legend()
        ax[1].legend()
        ax[1].set_xscale("log")
        ax[1].set_xlabel("unknowns")
        ax[1].set_ylabel("wall time (s), one core")
        ax[1].set_title("cost")
        fig.tight_layout()
        fig.savefig(os.path.join(img_dir, "continuum_mesh.png"), dpi=120)
        plt.close(fig)


def part_delta(run_dir, img_dir):
    rows = series(run_dir, "delta", "delta_*", lambda n: float(n.split("_")[1]))
    if not rows:
        print("(delta: no runs)")
        return
    print_table("Regularisation delta, refinement 2, h = 8 D", "delta (1/s)", rows,
                ("cd", "lb", "steps", "time"))
    fig, ax = plt.subplots(figsize=(5, 4))
    ds = [d for d, _ in rows]
    ax.semilogx(ds, [drag_coefficient(r) for _, r in rows], "o-", label="drag / (P0 D)")
    ax.semilogx(ds, [lift_ratio(r) for _, r in rows], "s-", label="lift / buoyancy")
    ax.set_xlabel("delta (1/s)")
    ax.legend()
    ax.set_title("regularisation, refinement 2, h = 8 D")
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, "continuum_delta.png"), dpi=120)
    plt.close(fig)


def convergence_verdict(values):
    """grainlift.stats.richardson over the last three of a sequence of halvings of the cell
    size, in words."""
    if len(values) < 3:
        return "fewer than three mesh levels"
    est = richardson((4.0, 2.0, 1.0), values[-3:])
    if math.isnan(est.order):
        return "no monotone convergence over the last three levels"
    if not est.accepted:
        return (f"observed order {est.order:.2f}: outside [{MIN_ORDER:g}, {MAX_ORDER:g}], "
                "not in the asymptotic range (no extrapolation)")
    return f"observed order {est.order:.2f}, extrapolated {est.limit:.4g}"


def print_convergence(rows):
    """Observed order and extrapolation of drag and lift over the last three mesh levels."""
    for name, f in (("drag / (P0 D)", drag_coefficient), ("L/B", lift_ratio)):
        print(f"{name}: {convergence_verdict([f(r) for _, r in rows])}")


def part_wellposed(run_dir, img_dir):
    """Barker-Gray (well-posed) law: mesh levels and delta (study_continuum.sh wellposed),
    beside Jop's law with Chauchat-Medale (the mesh part)."""
    bg = series(run_dir, "wellposed", "bg_r*", lambda n: int(n.split("_r")[1]))
    if not bg:
        print("(wellposed: no runs)")
        return
    print_table("Mesh levels, Barker-Gray law (delta = 1e-3 1/s), h = 8 D", "refinement", bg,
                ("cells", "dofs", "cd", "lb", "steps", "time"))
    print_convergence(bg)
    deltas = series(run_dir, "wellposed", "bg_delta_*", lambda n: float(n.split("_")[-1]))
    r3 = [r for lev, r in bg if lev == 3]
    if r3:
        deltas = sorted(deltas + [(1e-3, r3[0])], key=lambda x: x[0])
    if deltas:
        print_table("Barker-Gray law, delta at refinement 3, h = 8 D", "delta (1/s)", deltas,
                    ("cd", "lb", "steps", "time"))
    coulomb = series(run_dir, "wellposed", "bg_coulomb_r*", lambda n: int(n.split("_r")[1]))
    if coulomb:
        print_table("Barker-Gray law, Coulomb wall (mu_w = 0.5), h = 8 D", "refinement", coulomb,
                    ("cells", "cd", "lb", "steps", "time"))
    jop = series(run_dir, "mesh", "full_r*", lambda n: int(n.split("_r")[1]))
    fig, ax = plt.subplots(1, 4, figsize=(19, 4))
    for rows, style, lab in ((bg, "o-", "Barker-Gray (well posed)"),
                             (jop, "s--", "Jop + Chauchat-Medale (ill posed for I < 0.019)")):
        if not rows:
            continue
        lev = [x for x, _ in rows]
        ax[0].plot(lev, [drag_coefficient(r) for _, r in rows], style, label=lab)
        ax[1].plot(lev, [lift_ratio(r) for _, r in rows], style, label=lab)
        ax[2].loglog([r["dofs"] for _, r in rows], [r["seconds"] for _, r in rows], style,
                     label=lab)
    ax[0].set_title("drag / (P0 D)")
    ax[1].set_title("lift / buoyancy")
    for a in ax[:2]:
        a.set_xlabel("refinement level")
        a.legend(fontsize=8)
    ax[2].set_xlabel("unknowns")
    ax[2].set_ylabel("wall time (s); level 5 on two ranks")
    ax[2].set_title("cost of each level (loaded machine)")
    ax[2].legend(fontsize=8)
    if deltas:
        ds = [d for d, _ in deltas]
        ax[3].semilogx(ds, [drag_coefficient(r) for _, r in deltas], "o-", label="drag / (P0 D)")
        ax[3].semilogx(ds, [lift_ratio(r) for _, r in deltas], "s-", label="lift / buoyancy")
        ax[3].set_xlabel("regularisation delta (1/s)")
        ax[3].set_title("Barker-Gray, refinement 3: delta")
        ax[3].legend(fontsize=8)
    fig.suptitle("Guillard gradient case, h = 8 D, delta = 1e-3 1/s (Jop's law fails at level 3)")
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, "continuum_wellposed.png"), dpi=120)
    plt.close(fig)


def part_hdelta(run_dir, img_dir):
    """Mesh levels at fixed regularisation delta (study_continuum.sh hdelta)."""
    runs = {}
    for p in glob.glob(os.path.join(run_dir, "hdelta", "delta_*_r*", "fem.h5")):
        m = re.match(r"delta_([0-9.eE+-]+)_r(\d+)", os.path.basename(os.path.dirname(p)))
        runs.setdefault(float(m.group(1)), []).append((int(m.group(2)), load(p)))
    if not runs:
        print("(hdelta: no runs)")
        return
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    for k, delta in enumerate(sorted(runs, reverse=True)):
        rows = sorted(runs[delta], key=lambda x: x[0])
        print_table(f"Mesh levels at delta = {delta:g} 1/s, h = 8 D", "refinement", rows,
                    ("cells", "dofs", "cd", "lb", "steps", "time"))
        print_convergence(rows)
        lev = [x for x, _ in rows]
        lab = f"delta = {delta:g} 1/s"
        ax[0].plot(lev, [drag_coefficient(r) for _, r in rows], "o-", color=f"C{k}", label=lab)
        ax[1].plot(lev, [lift_ratio(r) for _, r in rows], "s-", color=f"C{k}", label=lab)
        ax[2].loglog([r["dofs"] for _, r in rows], [r["seconds"] for _, r in rows], "o-",
                     color=f"C{k}", label=lab)
    ax[0].set_title("drag / (P0 D)")
    ax[1].set_title("lift / buoyancy")
    for a in ax[:2]:
        a.set_xlabel("refinement level (cell size halves per level)")
        a.legend()
    ax[2].set_xlabel("unknowns")
    ax[2].set_ylabel("wall time (s)")
    ax[2].set_title("cost")
    ax[2].legend()
    fig.suptitle("Guillard gradient case, h = 8 D: mesh levels at fixed regularisation")
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, "continuum_hdelta.png"), dpi=120)
    plt.close(fig)


def part_box(run_dir, img_dir, sub="box", title=""):
    rows = series(run_dir, sub, "box_x*", lambda n: float(n.split("_x")[1]))
    if not rows:
        print(f"({sub}: no runs)")
        return
    print_table(f"FE box size{title}, h = 16 D (half sizes f x [0.06, 0.04] m = f x [4, 2.67] D)",
                "f", rows, ("cd", "lb", "cells", "time"))
    # a 2D viscous fluid has no drag limit in an unbounded domain (Stokes' paradox): the drag
    # falls as 1 / ln(L / R) with the box size L; constant products below are that behaviour
    print("drag / (P0 D) x ln(L / R), L = box half width: " + ", ".join(
        f"f = {f:g}: {drag_coefficient(r) * math.log(f * 0.06 / (0.5 * r['D'])):.2f}"
        for f, r in rows))


def part_spin(run_dir, img_dir):
    walls = {}
    for wall in ("no_slip", "coulomb"):
        rows = series(run_dir, "spin", f"{wall}_omega*", lambda n: float(n.split("omega")[1]))
        if rows:
            walls[wall] = rows
    if not walls:
        print("(spin: no runs)")
        return
    print("\n### Spinning cylinder (Kumar geometry, P0 = 1000 Pa), L/D against Omega\n")
    for wall, rows in walls.items():
        print(f"{wall}: " + ", ".join(
            f"Omega {r['spin_ratio']:g}: L/D {r['lift'] / r['drag']:+.3f} "
            f"(drag {r['drag']:.0f} N/m, {r['seconds']:.0f} s)" for _, r in rows))
    # Jop's law is drawn beside Barker-Gray's and the DEM in part_spin_bg's figure


def part_depth_bg(run_dir, img_dir):
    """Lift over buoyancy and drag against h/D with the Barker-Gray law at refinements 3
    (split_bg) and 4 (depth_bg; h = 8 D from wellposed), beside Jop's law at refinement 2."""
    def depth(name):
        return int(re.match(r"full_h(\d+)", name).group(1))

    levels = {3: series(run_dir, "split_bg", "full_h*", depth),
              4: series(run_dir, "depth_bg", "full_h*_r4", depth)}
    r4_h8 = glob.glob(os.path.join(run_dir, "wellposed", "bg_r4", "fem.h5"))
    if r4_h8:
        levels[4] = sorted(levels[4] + [(8, load(r4_h8[0]))], key=lambda x: x[0])
    if not levels[4]:
        print("(depth_bg: no runs)")
        return
    print("\n### Barker-Gray law against depth: refinements 3 and 4\n")
    print("| h/D | L/B, ref 3 | L/B, ref 4 | change | drag/(P0 D), ref 3 | drag/(P0 D), ref 4 | "
          "change | time ref 4 |")
    print("|---|---|---|---|---|---|---|---|")
    r3 = dict(levels[3])
    for h, r in levels[4]:
        a = r3.get(h)
        if a is None:
            continue
        print(f"| {h} | {lift_ratio(a):.3f} | {lift_ratio(r):.3f} | "
              f"{100 * (lift_ratio(r) / lift_ratio(a) - 1):+.1f}% | {drag_coefficient(a):.3f} | "
              f"{drag_coefficient(r):.3f} | "
              f"{100 * (drag_coefficient(r) / drag_coefficient(a) - 1):+.1f}% | "
              f"{r['seconds']:.0f} s |")
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for k, (lev, rows) in enumerate(sorted(levels.items())):
        hs = [h for h, _ in rows]
        ax[0].semilogx(hs, [lift_ratio(r) for _, r in rows], "os"[k] + "-", color=f"C{k}",
                       label=f"Barker-Gray, refinement {lev}")
        ax[1].semilogx(hs, [drag_coefficient(r) for _, r in rows], "os"[k] + "-", color=f"C{k}",
                       label=f"Barker-Gray, refinement {lev}")
    jop = series(run_dir, "split", "full_h*", depth)
    if jop:
        ax[0].semilogx([h for h, _ in jop], [lift_ratio(r) for _, r in jop], "x:", color="grey",
                       label="Jop's law (ill posed), refinement 2")
        ax[1].semilogx([h for h, _ in jop], [drag_coefficient(r) for _, r in jop], "x:",
                       color="grey", label="Jop's law (ill posed), refinement 2")
    r5 = glob.glob(os.path.join(run_dir, "wellposed", "bg_r5", "fem.h5"))
    if r5:
        ax[0].plot([8], [lift_ratio(load(r5[0]))], "k*", label="refinement 5 (h = 8 D)")
        ax[1].plot([8], [drag_coefficient(load(r5[0]))], "k*", label="refinement 5 (h = 8 D)")
    ax[0].axhspan(20 * 0.8, 20 * 1.2, color="grey", alpha=0.15,
                  label="Guillard et al.: ~20 (experiments)")
    ax[0].set_ylabel("lift / buoyancy")
    ax[1].set_ylabel("drag / (P0 D)")
    for a in ax:
        a.set_xlabel("h / D")
        a.minorticks_off()
        a.set_xticks([4, 8, 16, 32])
        a.set_xticklabels(["4", "8", "16", "32"])
        a.legend(fontsize=7)
    fig.suptitle("Guillard gradient case, no-slip wall, FE box [4, 2.7] D")
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, "continuum_depth_bg.png"), dpi=120)
    plt.close(fig)


def spin_ratio(r):
    """Omega = omega R / V"""
    return r["spin_ratio"]


def dem_ld_omega(csv_path):
    """(Omega, L/D, its standard error) of a DEM sweep.csv
    (studies/kumar2019/reproduce_kumar2019.sh)."""
    out = []
    with open(csv_path) as f:
        for row in csv.DictReader(f):
            if row["solver"] != "dem":
                continue
            drag, lift = float(row["drag"]), float(row["lift"])
            se = abs(lift / drag) * math.hypot(float(row["lift_stderr"]) / max(abs(lift), 1e-300),
                                               float(row["drag_stderr"]) / drag)
            out.append((float(row["spin_ratio"]), lift / drag, se))
    return sorted(out)


def part_spin_bg(run_dir, img_dir, dem_csv="runs/kumar2019/omega_phi080/sweep.csv"):
    """L/D against Omega with the Barker-Gray law at mesh levels 2..4 (study_continuum.sh
    spin_bg, spin_mesh), Jop's law at level 2 (spin) and the DEM beside them."""
    runs = {}  # (wall, level) -> {Omega: run}
    for p in glob.glob(os.path.join(run_dir, "spin_bg", "*_r*_omega*", "fem.h5")):
        m = re.match(r"(no_slip|coulomb)_r(\d+)_omega", os.path.basename(os.path.dirname(p)))
        r = load(p)
        runs.setdefault((m.group(1), int(m.group(2))), {})[round(spin_ratio(r), 6)] = r
    if not runs:
        print("(spin_bg: no runs)")
        return
    print("\n### Spinning cylinder, Barker-Gray law (Kumar geometry, P0 = 1000 Pa): "
          "L/D by mesh level\n")
    omegas = sorted({om for by_omega in runs.values() for om in by_omega})
    for wall in ("no_slip", "coulomb"):
        levels = sorted(lev for w, lev in runs if w == wall)
        if not levels:
            continue
        print(f"{wall} wall: L/D (drag N/m, time)\n")
        print("| Omega | " + " | ".join(f"refinement {lev}" for lev in levels) + " |")
        print("|" + "---|" * (len(levels) + 1))
        verdicts = []
        for om in omegas:
            hits = [runs[(wall, lev)].get(om) for lev in levels]
            print(f"| {om:g} | " + " | ".join(
                f"{r['lift'] / r['drag']:+.4f} ({r['drag']:.1f}, {r['seconds']:.0f} s)" if r else ""
                for r in hits) + " |")
            seq = [r["lift"] / r["drag"] for r in hits if r]
            if len(seq) >= 3:
                verdicts.append(f"Omega {om:g}, L/D: {convergence_verdict(seq)}")
        print("\n".join(verdicts) + "\n")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    markers = {2: "o", 3: "s", 4: "D", 5: "^"}
    for k, wall in enumerate(("no_slip", "coulomb")):
        for lev in sorted(lev for w, lev in runs if w == wall):
            rows = [runs[(wall, lev)][om] for om in sorted(runs[(wall, lev)])]
            ax.plot([spin_ratio(r) for r in rows], [r["lift"] / r["drag"] for r in rows],
                    markers.get(lev, "x") + ("-" if lev == 2 else ""), color=f"C{k}",
                    label=f"mu(I) Barker-Gray, {wall.replace('_', '-')} wall, refinement {lev}")
        jop = series(run_dir, "spin", f"{wall}_omega*", lambda n: float(n.split("omega")[1]))
        if jop:
            ax.plot([spin_ratio(r) for _, r in jop], [r["lift"] / r["drag"] for _, r in jop], ":",
                    color=f"C{k}", label=f"Jop's mu(I), {wall.replace('_', '-')}, refinement 2")
    if os.path.exists(dem_csv):
        dem = dem_ld_omega(dem_csv)
        ax.errorbar([d[0] for d in dem], [d[1] for d in dem], yerr=[d[2] for d in dem], fmt="k^",
                    capsize=3, label="DEM, Phi 0.8 (docs/results-kumar2019.md)")
    ax.axhline(-0.25, color="grey", lw=0.8, ls="--")
    ax.text(0.02, -0.24, "Kumar eq. 15: |L/D| = 0.25 (Phi 0.82)", color="grey", fontsize=8)
    ax.set_xscale("symlog", linthresh=0.5)
    ax.set_xlim(-0.05, 25)
    ax.set_xlabel("Omega = omega R / V")
    ax.set_ylabel("L / D")
    ax.set_title("Spinning cylinder (Kumar geometry, no gravity)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(img_dir, "continuum_ld_omega_bg.png"), dpi=120)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    run_dir, img_dir = sys.argv[1:]
    os.makedirs(img_dir, exist_ok=True)
    part_split(run_dir, img_dir)
    part_split(run_dir, img_dir, "split_bg", ", Barker-Gray law, refinement 3")
    part_mesh(run_dir, img_dir)
    part_delta(run_dir, img_dir)
    part_hdelta(run_dir, img_dir)
    part_wellposed(run_dir, img_dir)
    part_box(run_dir, img_dir)
    part_box(run_dir, img_dir, "box_bg", ", Barker-Gray law")
    part_spin(run_dir, img_dir)
    part_depth_bg(run_dir, img_dir)
    part_spin_bg(run_dir, img_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
