#!/usr/bin/python3
"""Where each solver is stable: runs grids of harsh parameters through `grainlift run` and
records, for every run, how it ended: finished (with finite outputs), refused before running
(exit 2, with the message) or stopped with a diagnosis (exit 1: the step, the grain and the
cause for the DEM; the residual history for the FEM). A NaN anywhere in an output file, a crash
(any other exit code, a signal) or a failure without a diagnosis is a defect and makes the
script exit 1 (the `stress` test runs it with --quick).

  studies/stability_map/stability_map.py BINARY OUT_DIR [--quick] [--doc docs/stability.md \
--figure docs/img/stability_map.png]

DEM grid (cases/kumar2019/reduced_phi080.toml, V0 1 m/s, Omega 2, a few d of travel): dt from
0.01 to 0.5 of the binary collision time; contacts 10x and 100x stiffer at the case's dt; Omega
up to 50; Phi from 0.5 to 0.9; a lid pressure step (cases/demo/demo.toml's lid from 20 Pa to
2e5 Pa on a bed prepared free). FEM grid (cases/guillard2014/gradient.toml geometry with a
heavy lid, refinement 1): delta over 4 decades, Omega 0 to 20, eps = D/h from 1/2 to 1/64, both
regularisations and both walls, the free-surface scene where the pressure vanishes above
the intruder, and a solve cut to 5 Newton steps (to show its diagnosis).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "python"))
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
KUMAR = os.path.join(ROOT, "cases/kumar2019/reduced_phi080.toml")
DEMO = os.path.join(ROOT, "cases/demo/demo.toml")
GUILLARD = os.path.join(ROOT, "cases/guillard2014/gradient.toml")
TC = 1.415e-4  # s: the Kumar grains' binary collision time at the case's 3 m/s (the dt check)
DIAGNOSES = ("overlap", "NaN", "energy growth")
# What the quick grid must give (the `stress` test): velocity Verlet is stable at 0.01 and 0.1
# of the collision time and not at 0.5; a bed at Phi 0.9 is refused before the run (compressed
# beyond jamming); the FEM converges on every quick point (docs/stability.md).
EXPECTED_QUICK = {("dem", "dt / t_c", 0.01): "finished", ("dem", "dt / t_c", 0.1): "finished",
                  ("dem", "dt / t_c", 0.5): "stopped", ("dem", "Phi", 0.9): "refused",
                  ("dem", "Phi", 0.86): "finished", ("fem", "Newton steps allowed", 5): "stopped"}


def dem_grid(quick):
    # 2 d of averaging in the quick grid (it asks how each run ends), 6 d in the full one
    # (whose forces are compared across the grid)
    travel = ["dem.travel=3", "dem.steady_travel=1"] if quick else ["dem.travel=8",
                                                                      "dem.steady_travel=2"]
    base = (["intruder.velocity=[1.0,0.0]", "intruder.omega=40.0", "dem.max_dt_fraction=1.0"]
            + travel)
    runs = []
    for f in ([0.01, 0.1, 0.5] if quick else [0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5]):
        runs.append(("dt / t_c", f, KUMAR, base + [f"dem.dt={f * TC:.6g}"]))
    for k in ([100] if quick else [10, 100]):
        runs.append(("Kn, Kt x", k, KUMAR, base + [f"grains.contact.kn={2e9 * k:g}",
                                                   f"grains.contact.kt={2.45e9 * k:g}"]))
    for om in ([50] if quick else [0, 10, 25, 50]):
        runs.append(("Omega", om, KUMAR, base + [f"intruder.omega={om * 1.0 / 0.05:g}"]))
    for phi in ([0.86, 0.9] if quick else [0.5, 0.7, 0.8, 0.84, 0.86, 0.88, 0.9]):
        runs.append(("Phi", phi, KUMAR, base + [f"grains.area_fraction={phi}"]))
    for p in ([2e5] if quick else [20, 2e3, 2e4, 2e5]):
        runs.append(("lid pressure step (Pa)", p, DEMO,
                     ["dem.travel=2", "dem.steady_travel=0.5", f"domain.lid_pressure={p:g}"]))
    return [("dem",) + r for r in runs]


def fem_grid(quick):
    D = 0.015
    # refinement 1 in the full map; the quick grid asks the same questions on the coarsest
    # mesh (refinement 0: a fifth of the time, the same outcomes; docs/stability.md)
    level = f"continuum.refinement={0 if quick else 1}"
    base = ["scene.depth_mode=\"heavy_lid\"", f"scene.depth={4 * D}", level,
            "continuum.mesh_error_estimate=false", 'domain.walls=["bottom","top"]',
            "domain.y_range=[-0.04,0.02]"]
    runs = []
    for delta in ([1e-5, 1e-1] if quick else [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1]):
        runs.append(("delta (1/s)", delta, base + [f"continuum.delta={delta:g}"]))
    for om in ([20] if quick else [0, 5, 10, 20, 50]):
        # Omega = omega R / V with V = 0.05 m/s, R = 0.0075 m
        runs.append(("Omega", om, base + [f"intruder.omega={om * 0.05 / 0.0075:.6g}"]))
    for inv in ([2, 64] if quick else [2, 8, 32, 64]):
        runs.append(("h / D (eps = D/h)", inv, [b for b in base if not b.startswith("scene.depth=")]
                     + [f"scene.depth={inv * D:g}"]))
    if not quick:
        for law in ("chauchat_medale", "barker_gray"):
            for wall in ("no_slip", "coulomb"):
                runs.append((f"law, wall", f"{law}, {wall}", base + [
                    f"continuum.regularisation=\"{law}\"", f"continuum.wall=\"{wall}\""]))
    # a solve cut short: the diagnosis a non-converged solve gives (exit 1, residual history)
    runs.append(("Newton steps allowed", 5, base + ["continuum.max_iterations=5"]))
    # the pressure vanishes at the surface and in the wake (1.5 D: the shallowest box that fits)
    for h in ([2] if quick else [1.5, 2]):
        runs.append(("free surface (no lid), h / D", h, ["scene.depth_mode=\"free_surface\"",
                                                         f"scene.depth={h * D:g}", level,
                                                         "continuum.mesh_error_estimate=false"]))
    return [("fem", what, value, GUILLARD, sets) for what, value, sets in runs]


def non_finite(path):
    """Names of the datasets and attributes of an output file holding a NaN or an infinity,
    except the NaN that marks field cells inside the intruder or outside the FE mesh
    (docs/schema.md): in /fields, only infinities count."""
    bad = []
    datasets, groups = io.read(path).items()
    for name, attrs in groups:
        for k, v in attrs.items():
            if isinstance(v, (float, np.floating)) and not math.isfinite(v):
                bad.append(f"{name}@{k}")
    for name, v in datasets:
        if isinstance(v, np.ndarray) and v.dtype.kind == "f":
            masked = name.startswith("fields/")
            if np.any(np.isinf(v)) or (not masked and np.any(np.isnan(v))):
                bad.append(name)
    return bad


def run_one(binary, out_dir, solver, what, value, case, sets, timeout):
    tag = f"{solver}_{what}_{value}".replace(" ", "_").replace("/", "_").replace(",", "")
    out = os.path.join(out_dir, tag)
    cmd = [binary, "run", case, "--solver", solver, "--quiet", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        code, err = p.returncode, p.stderr.strip()
    except subprocess.TimeoutExpired:
        code, err = None, f"still running after {timeout} s"
    rec = {"solver": solver, "what": what, "value": value, "exit": code,
           "seconds": round(time.time() - t0, 2), "message": err[-600:], "defect": ""}
    h5 = os.path.join(out, f"{solver}.h5")
    if code == 0:
        rec["outcome"] = "finished"
        bad = non_finite(h5) if os.path.exists(h5) else ["no output file"]
        if bad:
            rec["defect"] = "non-finite output: " + ", ".join(bad[:5])
        f = io.read(h5)
        d = f.diagnostics
        if solver == "fem":
            rec["steps"] = int(d.get("nonlinear_iterations", -1))
        m = f.means
        for k in ("drag", "lift", "drag_stderr", "lift_stderr"):
            if k in m:
                rec[k] = float(m[k])
    elif code == 2:
        rec["outcome"] = "refused"
    elif code == 1:
        rec["outcome"] = "stopped"
        if solver == "dem" and not (any(k in err for k in DIAGNOSES) and "step" in err
                                    and "grain" in err):
            rec["defect"] = "stopped without a diagnosis naming the step, the grain and the cause"
        if solver == "fem" and "residual" not in err:
            rec["defect"] = "stopped without the residual history"
    elif code is None:
        rec["outcome"] = "timed out"
    else:
        rec["outcome"] = "crashed"
        rec["defect"] = f"exit code {code}"
    if code in (1, 2) and os.path.exists(h5):
        bad = non_finite(h5)
        if bad:
            rec["defect"] = "non-finite output: " + ", ".join(bad[:5])
    return rec


def short(msg):
    """The diagnosis of a failure message, one line."""
    m = " ".join(msg.split())
    for key in ("run failed: ", "bad input:", "failed:"):
        if key in m:
            m = m.split(key, 1)[1]
    return (m[:230] + "...") if len(m) > 230 else m


def table(records):
    lines = ["| solver | parameter | value | outcome | s | result or diagnosis |",
             "| --- | --- | --- | --- | --- | --- |"]
    for r in records:
        if r["outcome"] == "finished":
            def val(k):
                v = f"{r.get(k, float('nan')):.4g}"
                return v + (f" +- {r[k + '_stderr']:.2g}" if k + "_stderr" in r else "")
            res = f"drag {val('drag')}, lift {val('lift')} N/m"
            if "steps" in r:
                res += f", {r['steps']} Newton steps"
        else:
            res = short(r["message"]).replace("|", "\\|")
        if r["defect"]:
            res = "**DEFECT: " + r["defect"] + "** " + res
        lines.append(f"| {r['solver']} | {r['what']} | {r['value']} | {r['outcome']} | "
                     f"{r['seconds']} | {res} |")
    return "\n".join(lines)


def figure(records, path):
    from grainlift.plots import plt
    from matplotlib.patches import Rectangle
    groups = []
    for r in records:
        key = (r["solver"], r["what"])
        if key not in groups:
            groups.append(key)
    colour = {"finished": "tab:green", "refused": "tab:orange", "stopped": "tab:red",
              "timed out": "tab:purple", "crashed": "black"}
    fig, ax = plt.subplots(figsize=(9, 0.45 * len(groups) + 1.2))
    for row, key in enumerate(groups):
        rs = [r for r in records if (r["solver"], r["what"]) == key]
        for col, r in enumerate(rs):
            ax.add_patch(Rectangle((col - 0.45, row - 0.3), 0.9, 0.6, color=colour[r["outcome"]]))
            v = r["value"]
            label = f"{v:g}" if isinstance(v, (int, float)) else "\n".join(
                w.replace("chauchat_medale", "Chauchat-M.").replace("barker_gray", "Barker-Gray")
                for w in str(v).split(", "))
            ax.annotate(label, (col, row), ha="center", va="center", fontsize=7, color="white")
    ax.set_yticks(range(len(groups)))
    ax.set_yticklabels([f"{s.upper()}: {w}" for s, w in groups], fontsize=8)
    ax.set_xticks([])
    ax.set_xlim(-0.6, max(sum(1 for r in records if (r["solver"], r["what"]) == k)
                          for k in groups) - 0.4)
    ax.set_ylim(-0.6, len(groups) - 0.4)
    ax.invert_yaxis()
    for name, c in colour.items():
        ax.scatter([], [], color=c, marker="s", label=name)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.01), fontsize=7, ncol=5, frameon=False)
    ax.set_title("grainlift stability map (value in each square; left to right as in the table)")
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("out_dir")
    ap.add_argument("--quick", action="store_true", help="the small grid of the `stress` test")
    ap.add_argument("--solvers", default="dem,fem")
    ap.add_argument("--timeout", type=float, default=900)
    ap.add_argument("--doc", help="write the Markdown table into this file between the markers")
    ap.add_argument("--figure", help="PNG of the map")
    ap.add_argument("--from-json", action="store_true",
                    help="run nothing: table and figure from OUT_DIR/stability_map.json")
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    grid = []
    if "dem" in a.solvers:
        grid += dem_grid(a.quick)
    if "fem" in a.solvers:
        grid += fem_grid(a.quick)
    records = []
    if a.from_json:  # only the table and the figure again, from an earlier run's records
        grid = []
        records = json.load(open(os.path.join(a.out_dir, "stability_map.json")))
    for solver, what, value, case, sets in grid:
        r = run_one(a.binary, a.out_dir, solver, what, value, case, sets, a.timeout)
        print(f"{solver} {what} = {value}: {r['outcome']} ({r['seconds']} s)"
              f"{' DEFECT ' + r['defect'] if r['defect'] else ''}",
              flush=True)
        records.append(r)
    with open(os.path.join(a.out_dir, "stability_map.json"), "w") as f:
        json.dump(records, f, indent=1)
    text = table(records)
    print(text)
    if a.doc:
        doc = open(a.doc).read()
        b, e = "<!-- map:begin -->\n", "<!-- map:end -->"
        i, j = doc.index(b) + len(b), doc.index(e)
        open(a.doc, "w").write(doc[:i] + text + "\n" + doc[j:])
    if a.figure:
        figure(records, a.figure)
    if a.quick:
        for r in records:
            want = EXPECTED_QUICK.get((r["solver"], r["what"], r["value"]),
                                      "finished" if r["solver"] == "fem" else None)
            if want and r["outcome"] != want and not r["defect"]:
                r["defect"] = f"expected {want}, got {r['outcome']}"
    defects = [r for r in records if r["defect"]]
    for r in defects:
        print(f"DEFECT: {r['solver']} {r['what']} = {r['value']}: {r['defect']}", file=sys.stderr)
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main())
