#!/usr/bin/env python3
"""The tables of the cross-check on one box (studies/one_box/study_one_box.sh): for each scene, \
FEM / DEM
for drag, lift, torque and L/D with the difference in units of the combined error (the DEM's
block standard error, the FEM's mesh-error estimate), and the rms difference of sigma_n(theta)
and sigma_t(theta) over P0; the same for the continuum's former box (continuum.box_half_size).
Every number comes from `grainlift compare --json` on the run folders, except the DEM's errors:
those are the one statistics rule's (grainlift.io Result.block_errors(): the correlation-corrected
block error of the file's force series), whichever binary wrote the file.

    python3 studies/one_box/one_box_tables.py build/bin/grainlift runs/one_box [runs/depth_study]

The depth sweep's DEM (pooled over beds, 20-60 d) comes from the depth study's runs (third
argument; default depth_study beside the one-box folder), as plot_depth_study.py makes it.
"""
import functools
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402
from grainlift.windows import window_mean  # noqa: E402

DEPTH_SCENES = ("free_surface_h2", "heavy_lid_h4", "heavy_lid_h6", "heavy_lid_h8", "heavy_lid_h12",
                "lid_only_h4", "lid_only_h6", "lid_only_h8", "lid_only_h12")


def depth_dem_pooled(depth_root):
    """The depth sweep's DEM pooled over beds, forces over 20-60 d of travel, as
    studies/depth/plot_depth_study.py --window 20 60 makes them from DEPTH_ROOT (the study's
    runs): {name: (drag, drag error, lift, lift error)} in N/m; empty without those runs."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "depth"))
    import plot_depth_study as depth  # noqa: E402
    runs = depth.load_pooled(depth_root, (20.0, 60.0))
    return {n: (r["drag"], r["drag_err"], r["lift"], r["lift_err"])
            for (s, n), r in runs.items() if s == "dem_d6_pooled" and n in DEPTH_SCENES}


def compare(grainlift, a, b):
    out = subprocess.run([grainlift, "compare", a, b, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


summary = io.summary


@functools.lru_cache(maxsize=None)
def dem_errors(dem_h5):
    """{"drag_stderr", "lift_stderr", "torque_stderr"} of a DEM result by the one statistics
    rule (Result.block_errors()), in place of the errors the file stores (runs written before
    fa2750a hold the uncorrected block error)."""
    return io.read(dem_h5, "dem").block_errors()


def z(a, ea, b, eb):
    e = math.hypot(ea or 0.0, eb or 0.0)
    return (b - a) / e if e > 0 else float("nan")


def ratio_cell(a, ea, b, eb):
    if a == 0:
        return "-"
    return f"{b / a:.2f} ({z(a, ea, b, eb):+.1f})"


def ld(drag, edrag, lift, elift):
    r = lift / drag
    e = (abs(r) * math.hypot((edrag or 0) / drag, (elift or 0) / lift) if lift != 0
         else (elift or 0) / drag)
    return r, e


def row(grainlift, dem_dir, fem_dir, label):
    dem_h5 = os.path.join(dem_dir, "dem.h5")
    fem_h5 = os.path.join(fem_dir, "fem.h5")
    if not (os.path.exists(dem_h5) and os.path.exists(fem_h5)):
        return None
    c = compare(grainlift, dem_h5, fem_h5)
    for q, e in dem_errors(dem_h5).items():  # the DEM's errors by the one statistics rule
        c[q.replace("_stderr", "_err_a")] = e
    cells = [label]
    for q in ("drag", "lift", "torque"):
        a, b = c[f"{q}_a"], c[f"{q}_b"]
        ea, eb = c.get(f"{q}_err_a"), c.get(f"{q}_err_b")
        cells.append(f"{a:.4g} +- {ea or 0:.2g}")
        cells.append(f"{b:.4g}")
        cells.append(ratio_cell(a, ea, b, eb))
    la, ela = ld(c["drag_a"], c.get("drag_err_a"), c["lift_a"], c.get("lift_err_a"))
    lb, elb = ld(c["drag_b"], c.get("drag_err_b"), c["lift_b"], c.get("lift_err_b"))
    cells.append(f"{la:+.3f} +- {ela:.3f}")
    cells.append(f"{lb:+.3f} ({z(la, ela, lb, elb):+.1f})")
    cells.append(f"{c['sigma_n_l2']:.3f}")
    cells.append(f"{c['sigma_t_l2']:.3f}")
    return "| " + " | ".join(cells) + " |"


HEADER = ("| scene | DEM drag | FEM drag | FEM/DEM (z) | DEM lift | FEM lift | FEM/DEM (z) | "
          "DEM torque | FEM torque | FEM/DEM (z) | DEM L/D | FEM L/D (z) | rms sigma_n / P0 | "
          "rms sigma_t / P0 |\n" + "|---" * 14 + "|")

SCENES = [
    ("demo_o0", "demo, Omega 0"), ("demo_o05", "demo, Omega 0.5"), ("demo_o1", "demo, Omega 1"),
    ("demo_o2", "demo, Omega 2"), ("demo_o4", "demo, Omega 4"), ("demo_o8", "demo, Omega 8"),
    ("big_o0", "16 D x 9.6 D, Omega 0"), ("big_o2", "16 D x 9.6 D, Omega 2"),
    ("big_o4", "16 D x 9.6 D, Omega 4"),
    ("heavy_lid_h8", "depth sweep, h = 8 D"), ("lid_only_h8", "depth sweep, h = 8 D, no gradient"),
    ("gradient", "Guillard gradient, h = 4 D"),
]
VARIANTS = [("fem", "the DEM's box (far field auto)"), ("fem_open", "open far field"),
            ("fem_periodic", "periodic far field"),
            ("fem_settled", "top edge where the DEM's lid settled (continuum.bed_top)"),
            ("fem_noslip", "no-slip intruder"),
            ("fem_old", "the former box (box_half_size)")]


def wake_windows(root):
    """The DEM's means before and after the intruder meets its own wake (its /diagnostics
    wake_travel), from the force samples, with grainlift.windows.window_mean (blocks of 4 d
    of travel): the two states the continuum's open and periodic far fields stand for."""
    print("\n### The DEM before and after its own wake (first crossing: open; after: periodic)\n")
    print("| scene | window (d) | drag | lift | torque | FEM open: drag, lift, torque | "
          "FEM periodic: drag, lift, torque |")
    print("|---" * 7 + "|")
    for name, label in SCENES:
        path = os.path.join(root, name, "dem", "dem.h5")
        if not os.path.exists(path):
            continue
        f = io.read(path)
        d = f.diagnostics
        if "wake_travel" not in d:
            continue
        wake, lo, hi = (float(d["wake_travel"]), float(d["mean_travel_from"]),
                        float(d["mean_travel_to"]))
        travel, (drag, lift), torque = f.travel(), f.drag_lift(), f["forces/torque"]
        fem = {}
        for v in ("fem_open", "fem_periodic", "fem"):
            sp = os.path.join(root, name, v, "summary.json")
            if os.path.exists(sp):
                fem[v] = summary(os.path.dirname(sp), "fem")
        periodic = fem.get("fem_periodic") or (fem.get("fem") if name.startswith("demo") else None)
        open_ = fem.get("fem_open") or (fem.get("fem") if not name.startswith("demo") else None)
        cell = lambda s: f"{s['drag']:.4g}, {s['lift']:.4g}, {s['torque']:.4g}" if s else "-"
        for a, b in ((lo, min(wake, hi)), (max(wake, lo), hi)):
            if b - a < 8:
                continue
            m = [window_mean(travel, x, a, b) for x in (drag, lift, torque)]
            print(f"| {label} | {a:.0f}-{b:.0f} | {m[0][0]:.4g} +- {m[0][1]:.2g} | "
                  f"{m[1][0]:.4g} +- {m[1][1]:.2g} | {m[2][0]:.4g} +- {m[2][1]:.2g} | "
                  f"{cell(open_) if b <= wake else '-'} | {cell(periodic) if a >= wake else '-'} |")


def omega_table(root):
    """The demo's spin sweep: the DEM's drag, lift and L/D against the FEM's on the shared box
    (periodic, the case's Coulomb wall, and no slip) and with the open far field."""
    print("\n### The demo against Omega\n")
    print("| Omega | DEM drag | DEM lift | DEM L/D | FEM Coulomb: drag, lift, L/D | "
          "FEM no-slip: drag, lift, L/D | FEM open (Coulomb): drag, lift, L/D |")
    print("|---" * 7 + "|")
    for tag, omega in (("0", 0), ("05", 0.5), ("1", 1), ("2", 2), ("4", 4), ("8", 8)):
        d = os.path.join(root, f"demo_o{tag}")
        if not os.path.exists(os.path.join(d, "dem", "summary.json")):
            continue
        s = summary(os.path.join(d, "dem"), "dem")
        s.update(dem_errors(os.path.join(d, "dem", "dem.h5")))  # the one statistics rule
        r, e = ld(s["drag"], s["drag_stderr"], s["lift"], s["lift_stderr"])
        cells = [f"{omega:g}", f"{s['drag']:.0f} +- {s['drag_stderr']:.0f}",
                 f"{s['lift']:+.0f} +- {s['lift_stderr']:.0f}", f"{r:+.2f} +- {e:.2f}"]
        for v in ("fem", "fem_noslip", "fem_open"):
            p = os.path.join(d, v)
            if os.path.exists(os.path.join(p, "summary.json")):
                f = summary(p, "fem")
                cells.append(f"{f['drag']:.0f}, {f['lift']:+.0f}, {f['lift'] / f['drag']:+.2f}")
            else:
                cells.append("-")
        print("| " + " | ".join(cells) + " |")


def main():
    if len(sys.argv) not in (3, 4) or sys.argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        return 0 if sys.argv[1:2] in (["-h"], ["--help"]) else 2
    grainlift, root = sys.argv[1], sys.argv[2]
    depth_root = sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(root),
                                                                    "depth_study")
    wake_windows(root)
    omega_table(root)
    for variant, title in VARIANTS:
        rows = []
        for name, label in SCENES:
            r = row(grainlift, os.path.join(root, name, "dem"), os.path.join(root, name, variant),
                    label)
            if r:
                rows.append(r)
        if rows:
            print(f"\n### FEM: {title} ({variant})\n")
            print(HEADER)
            print("\n".join(rows))
    # the depth sweep: lift in buoyancies and C_d, FEM against the DEM's pooled beds
    print("\n### Depth sweep: FEM (the DEM's box, far field auto) against the DEM pooled "
          "over beds\n")
    print("| scene | P0 (Pa) | DEM L/B | FEM L/B | FEM/DEM lift (z) | DEM C_d | FEM C_d | "
          "FEM/DEM drag (z) | FEM far field | FEM former box: L/B, C_d |")
    print("|---" * 10 + "|")
    pooled = depth_dem_pooled(depth_root)
    for name in DEPTH_SCENES:
        if name not in pooled:
            continue
        dd, edd, dl, edl = pooled[name]
        fem_dir = os.path.join(root, name, "fem")
        if not os.path.exists(os.path.join(fem_dir, "summary.json")):
            continue
        s = summary(fem_dir, "fem")
        buoy = s.get("buoyancy")
        cd_scale = s["drag"] / s["drag_coefficient"] if s.get("drag_coefficient") else None
        old = os.path.join(root, name, "fem_old", "summary.json")
        old_cell = "-"
        if os.path.exists(old):
            so = summary(os.path.dirname(old), "fem")
            old_cell = (f"{so.get('lift_over_buoyancy', float('nan')):.2f}, "
                        f"{so.get('drag_coefficient', float('nan')):.2f}")
        lb = s.get("lift_over_buoyancy", float("nan"))
        d = io.read(fem_dir, "fem").diagnostics
        far = io.text(d["far_field"])
        # the mesh-error estimate (the change from the next coarser level)
        mesh_d, mesh_l = float(d.get("drag_mesh_error", 0.0)), float(d.get("lift_mesh_error", 0.0))
        print(f"| {name} | {s['pressure_scale']:.4g} | {dl / buoy:.2f} +- {edl / buoy:.2f} | "
              f"{lb:.2f} | "
              f"{ratio_cell(dl, edl, s['lift'], mesh_l)} | "
              f"{dd / cd_scale:.2f} +- {edd / cd_scale:.2f} | "
              f"{s['drag_coefficient']:.2f} | {ratio_cell(dd, edd, s['drag'], mesh_d)} | "
              f"{far} | {old_cell} |")


if __name__ == "__main__":
    sys.exit(main())
