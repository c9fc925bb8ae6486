#!/usr/bin/python3
"""Which continuum follows the particles (issue 35): the DEM against the local mu(I), the wall
law measured on the grains, nonlocal fluidity (A = 0.5, and A calibrated on the grains by
`grainlift calibrate --nonlocal`) and both, on the cross-check set.

    model_table.py NONLOCAL_RUNS ONE_BOX_RUNS DEPTH_RUNS

NONLOCAL_RUNS: studies/nonlocal/nonlocal_study.sh OUT models (FEM runs named SCENE_local,
SCENE_wall, SCENE_A0.5, SCENE_wall_A0.5, and SCENE_Acal, SCENE_wall_Acal where the grains'
rheology file has a [nonlocal] table: the demo's, not the depth sweep's, and SCENE_dil,
SCENE_wall_dil, the local law with continuum.dilatancy = "phi_i", alone and with the wall
law); ONE_BOX_RUNS:
studies/one_box's runs (the DEM of the demo at Omega 0, 2, 4, 8 and of the 16 D box at 0, 2, 4,
one bed each, means over 10-60 d);
DEPTH_RUNS: studies/depth's runs (the heavy lid at 4, 8, 12 D pooled over three beds, forces
over 20-60 d, as plot_depth_study.py --window 20 60).

Each cell: the FEM value and, in brackets, z = (FEM - DEM) / combined error. The DEM's error
is its block error by the one statistics rule (grainlift.io Result.block_errors(), pooled
errors for the depth sweep); the FEM's the mesh-error estimate of its solve (/diagnostics
*_mesh_error, refinement 2 against 1: for the nonlocal runs the nonlocal nested levels, from
fa4096d + 1) and, for the nonlocal runs, 0.5% of the value on top: the
splitting's precision (stopping ten times tighter moved the demo's forces by at most 0.2%;
studies/nonlocal/README.md, "Precision"). A row counts for a
model when |z| <= 2; the summary gives each model's rows, those within 2 combined errors and
those where it is the closest of the models that converged there. A run that did not converge
(its file PARTIAL) is "did not converge".
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path[:0] = [os.path.join(HERE, "..", "..", "python"), os.path.join(HERE, "..", "depth")]
from grainlift import io  # noqa: E402

MODELS = [("local", "local mu(I)"), ("wall", "+ wall law"), ("A0.5", "+ NGF A 0.5"),
          ("wall_A0.5", "+ both"), ("Acal", "+ NGF A cal"), ("wall_Acal", "+ both, A cal"),
          ("dil", "+ dilatancy"), ("wall_dil", "+ wall law, dilatancy")]
NONLOCAL_PRECISION = 0.005
SCENES = [("demo", 0, "demo_o0"), ("demo", 2, "demo_o2"), ("demo", 4, "demo_o4"),
          ("demo", 8, "demo_o8"), ("big", 0, "big_o0"), ("big", 2, "big_o2"),
          ("big", 4, "big_o4")]


def fem(runs, name):
    """{quantity: (value, error)} of one FEM run, or None when it is missing."""
    path = os.path.join(runs, name, "fem.h5")
    if not os.path.isfile(path):
        return None
    r = io.read(path)
    if int(r.metadata.get("partial", 0)):  # a run that failed: its last converged level only
        return "failed"
    m, d, dv = r.means, r.diagnostics, r.derived
    nonlocal_run = "nonlocal_iterations" in d
    out = {}
    for q in ("drag", "lift", "torque"):
        v = float(m[q])
        e = float(d.get(q + "_mesh_error", 0.0) or 0.0)
        if nonlocal_run:
            e = math.hypot(e, NONLOCAL_PRECISION * v)
        out[q] = (v, e)
    if "drag_coefficient" in dv:
        scale_cd = float(dv["drag_coefficient"]) / out["drag"][0]
        scale_lb = float(dv["lift_over_buoyancy"]) / out["lift"][0] if out["lift"][0] else 0
        out["C_d"] = (out["drag"][0] * scale_cd, out["drag"][1] * scale_cd)
        out["L/B"] = (out["lift"][0] * scale_lb, out["lift"][1] * abs(scale_lb))
    out["L/D"] = ratio(out["lift"], out["drag"])
    return out


def ratio(a, b):
    """(a / b, its error) from (value, error) pairs: d(a/b) = da / b - (a / b) db / b."""
    r = a[0] / b[0]
    return r, math.hypot(a[1] / b[0], r * b[1] / b[0])


def dem(one_box, name):
    r = io.read(os.path.join(one_box, name, "dem"), "dem")
    e = r.block_errors()
    out = {q: (float(r.means[q]), float(e[q + "_stderr"])) for q in ("drag", "lift", "torque")}
    out["L/D"] = ratio(out["lift"], out["drag"])
    return out


def depth_dem(depth_runs):
    """{h: {"C_d": (v, e), "L/B": (v, e)}} of the heavy lid at 4, 8, 12 D, pooled."""
    import plot_depth_study as depth  # noqa: E402
    runs = depth.load_pooled(depth_runs, (20.0, 60.0))
    out = {}
    for h in (4, 8, 12):
        r = runs.get(("dem_d6_pooled", f"heavy_lid_h{h}"))
        if r is None:
            continue
        cd = r["rgD"] * r["h"]
        out[h] = {"C_d": (r["drag"] / cd, r["drag_err"] / cd),
                  "L/B": (r["lift"] / r["B"], r["lift_err"] / r["B"])}
    return out


def surface_z(one_box, dem_name, runs, name):
    """(rms z of sigma_n, of sigma_t) over the 64 angles of the surface traces, z = (FEM - DEM)
    / the DEM's standard error at that angle (both traces smoothed by the same 8 deg kernel on
    the same angles; the FEM's own error of the trace is not stored and not included), or
    None when the FEM run is missing or failed."""
    path = os.path.join(runs, name, "fem.h5")
    if not os.path.isfile(path):
        return None
    f = io.read(path)
    if int(f.metadata.get("partial", 0)):
        return None
    d = io.read(os.path.join(one_box, dem_name, "dem"), "dem")
    out = []
    for q in ("sigma_n", "sigma_t"):
        zs = [(a - b) / e for a, b, e in zip(f["surface/" + q], d["surface/" + q],
                                            d["surface/" + q + "_stderr"]) if e > 0]
        out.append(math.sqrt(sum(v * v for v in zs) / len(zs)))
    return out


def print_surface_table(one_box, nonlocal_runs):
    """The surface stresses against theta: per scene and model, the rms z of sigma_n and
    sigma_t over the intruder's surface, and per model the scenes where it is the closest."""
    print("\nSurface stress against theta: rms over 64 angles of (FEM - DEM) / DEM standard "
          "error, sigma_n / sigma_t\n")
    print("| scene | " + " | ".join(t for _, t in MODELS) + " |")
    print("|---|" + "---|" * len(MODELS))
    closest = {k: [0, 0] for k, _ in MODELS}
    for box, W, dem_name in SCENES:
        if not os.path.isdir(os.path.join(one_box, dem_name, "dem")):
            continue
        zs = {k: surface_z(one_box, dem_name, nonlocal_runs, f"{box}_O{W}_{k}")
              for k, _ in MODELS}
        zs = {k: v for k, v in zs.items() if v}
        for i in (0, 1):
            if zs:
                closest[min(zs, key=lambda k: zs[k][i])][i] += 1
        label = f"{'demo' if box == 'demo' else '16 D box'}, Omega {W}"
        print(f"| {label} | " + " | ".join(
            f"{zs[k][0]:.1f} / {zs[k][1]:.1f}" if k in zs else "-" for k, _ in MODELS) + " |")
    print("\nscenes where each model is the closest, sigma_n / sigma_t")
    for k, t in MODELS:
        print(f"{t}: {closest[k][0]} / {closest[k][1]}")


def z(f, d):
    e = math.hypot(f[1], d[1])
    return (f[0] - d[0]) / e if e > 0 else float("nan")


def main(argv):
    if len(argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    nonlocal_runs, one_box, depth_runs = argv[1:]
    rows = []  # (scene, quantity, dem (v, e), {model: (v, e)})
    for box, W, dem_name in SCENES:
        if not os.path.isdir(os.path.join(one_box, dem_name, "dem")):
            continue
        d = dem(one_box, dem_name)
        models = {k: fem(nonlocal_runs, f"{box}_O{W}_{k}") for k, _ in MODELS}
        failed = {k for k, m in models.items() if m == "failed"}
        models = {k: m for k, m in models.items() if m and m != "failed"}
        label = f"{'demo' if box == 'demo' else '16 D box'}, Omega {W}"
        quantities = ["drag"] if W == 0 else ["drag", "lift", "torque", "L/D"]
        for q in quantities:
            rows.append((label, q, d[q], {k: m[q] for k, m in models.items()}, failed))
    for h, d in depth_dem(depth_runs).items():
        models = {k: fem(nonlocal_runs, f"depth_h{h}_{k}") for k, _ in MODELS}
        failed = {k for k, m in models.items() if m == "failed"}
        models = {k: m for k, m in models.items() if m and m != "failed"}
        for q in ("C_d", "L/B"):
            rows.append((f"depth sweep, h = {h} D", q, d[q],
                         {k: m[q] for k, m in models.items() if q in m}, failed))
    print("| scene | quantity | DEM | " + " | ".join(t for _, t in MODELS) + " |")
    print("|---|---|---|" + "---|" * len(MODELS))
    within = {k: 0 for k, _ in MODELS}
    closest = {k: 0 for k, _ in MODELS}
    converged = {k: 0 for k, _ in MODELS}
    for scene, q, d, models, failed in rows:
        cells = []
        zs = {}
        for k, _ in MODELS:
            if k not in models:
                cells.append("did not converge" if k in failed else "-")
                continue
            zs[k] = z(models[k], d)
            cells.append(f"{models[k][0]:.4g} ({zs[k]:+.1f})")
        for k, v in zs.items():
            converged[k] += 1
            within[k] += abs(v) <= 2
        if zs:
            closest[min(zs, key=lambda k: abs(zs[k]))] += 1
        print(f"| {scene} | {q} | {d[0]:.4g} +- {d[1]:.2g} | " + " | ".join(cells) + " |")
    print(f"\n{len(rows)} rows; per model: rows it converged on, rows within 2 combined errors, "
          "rows where it is the closest of the models that converged")
    for k, t in MODELS:
        print(f"{t}: {converged[k]} rows, within 2 on {within[k]}, closest on {closest[k]}")
    print_surface_table(one_box, nonlocal_runs)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
