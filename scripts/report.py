#!/usr/bin/python3
"""One page on a result folder: python3 scripts/report.py DIR  (or `grainlift report DIR`)

Reads DIR/dem.h5 and/or DIR/fem.h5 and DIR/summary.json and writes DIR/report.html, a
self-contained page (inline CSS, no scripts, no external addresses) with its PNGs beside it:
  report_surface.png  sigma_n(theta)/P0 and sigma_t(theta)/P0 of both solvers
  report_split.png    their symmetric and antisymmetric parts (/derived)
  report_fields.png   speed, pressure, area fraction: one row per field, columns dem / fem,
                      one colour scale per row
and a table of drag, lift, torque, L/D, L/B, the DEM's standard errors and far field, the FEM's
convergence and mesh, and summary.json's "compare" numbers. A solver that did not run is a
column that says "not run". Exit 2 when DIR holds neither file."""
import html
import math
import os
import sys

sys.path[:0] = [os.path.dirname(os.path.realpath(__file__)),  # installed: grainlift/ beside
                os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python")]
import numpy as np  # noqa: E402
from grainlift import files, io  # noqa: E402
from grainlift.plots import field_extent, plt, save_in, theta_degrees  # noqa: E402

SOLVERS = io.SOLVERS
COLOURS = {"dem": "C0", "fem": "C3"}
NOT_RUN = "not run"
text = io.text


def read_solver(path):
    """The parts of one result file the report uses, as plain numpy / Python values."""
    f = io.read(path)
    r = {}
    geo = f.geometry
    r["P0"] = float(geo.get("pressure_scale", 0.0))
    r["D"] = float(geo["intruder_diameter"])
    r["means"] = f.means
    r["derived"] = f.derived
    r["diag"] = f.diagnostics
    r["meta"] = {k: text(v) for k, v in f.metadata.items()}
    r["far_field"] = f.attrs("far_field") if f.has("far_field") else None
    if f.has("surface"):
        s = f.datasets("surface")
        r["theta"] = s["theta"]
        for k in ("sigma_n", "sigma_t"):
            r[k] = s[k]
            # per-angle standard error: not in schema_version 2; drawn when a file has it
            if k + "_stderr" in s:
                r[k + "_stderr"] = s[k + "_stderr"]
        if "derived/sigma_n_symmetric" in f:
            for k in ("sigma_n", "sigma_t"):
                for part in ("symmetric", "antisymmetric"):
                    r[f"{k}_{part}"] = f[f"derived/{k}_{part}"]
    if f.has("fields"):
        g = f.datasets("fields")
        fields = {"x": g["x"], "y": g["y"]}
        if "velocity_x" in g and "velocity_y" in g:
            fields["speed"] = np.hypot(g["velocity_x"], g["velocity_y"])
        for n in ("pressure", "area_fraction"):
            if n in g:
                fields[n] = g[n]
        r["fields"] = fields
    return r


def pressure_source(solver, r):
    key = "pressure_source" if solver == "fem" else "pressure_scale_source"
    return r["diag"].get(key, "source not recorded in /diagnostics")


def save(fig, out, name, dpi=100):
    """Writes @p fig as DIR/name, closes it; the path."""
    return save_in(fig, out, name, dpi)


def plot_surface(runs, out):
    """sigma_n/P0 and sigma_t/P0 of every solver present, one panel each."""
    have = {s: r for s, r in runs.items() if r and "theta" in r}
    if not have:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, k, name in zip(axes, ("sigma_n", "sigma_t"), ("sigma_n", "sigma_t")):
        for s, r in have.items():
            P = r["P0"] or 1.0
            deg, o = theta_degrees(r["theta"])
            ax.plot(deg[o], r[k][o] / P, color=COLOURS[s], label=f"{s} (P0 = {r['P0']:.4g} Pa)")
            if k + "_stderr" in r:
                e = r[k + "_stderr"][o] / P
                ax.fill_between(deg[o], r[k][o] / P - e, r[k][o] / P + e, color=COLOURS[s],
                                alpha=0.25, lw=0, label=f"{s} ± standard error")
        ax.axhline(0, color="0.6", lw=0.5)
        ax.set_xlim(-180, 180)
        ax.set_xticks(range(-180, 181, 60))
        ax.set_xlabel("theta from V (deg)")
        ax.set_ylabel(f"{name} / P0")
        ax.set_title(f"{name}(theta) / P0")
        ax.legend(fontsize=8)
    fig.tight_layout()
    return save(fig, out, "report_surface.png")


def plot_split(runs, out):
    """Symmetric and antisymmetric parts of sigma_n/P0 and sigma_t/P0 (2 x 2 panels)."""
    have = {s: r for s, r in runs.items() if r and "sigma_n_symmetric" in r}
    if not have:
        return None
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    for i, k in enumerate(("sigma_n", "sigma_t")):
        for j, part in enumerate(("symmetric", "antisymmetric")):
            ax = axes[i, j]
            for s, r in have.items():
                P = r["P0"] or 1.0
                deg, o = theta_degrees(r["theta"])
                ax.plot(deg[o], r[f"{k}_{part}"][o] / P, color=COLOURS[s], label=s)
            ax.axhline(0, color="0.6", lw=0.5)
            ax.set_xlim(-180, 180)
            ax.set_xticks(range(-180, 181, 60))
            ax.set_title(f"{k} / P0, {part} part")
            if i == 1:
                ax.set_xlabel("theta from V (deg)")
            ax.legend(fontsize=8)
    fig.tight_layout()
    return save(fig, out, "report_split.png")


FIELD_ROWS = (("speed", "speed |u| (m/s)"), ("pressure", "pressure (Pa)"),
              ("area_fraction", "area fraction"))


def plot_fields(runs, out):
    """One row per field present in any solver, columns dem / fem, one colour scale per row."""
    rows = [(n, label) for n, label in FIELD_ROWS
            if any(r and "fields" in r and n in r["fields"] for r in runs.values())]
    if not rows:
        return None, []
    fig, axes = plt.subplots(len(rows), 2, figsize=(10, 4.0 * len(rows)), squeeze=False,
                             layout="constrained")
    for (name, label), row in zip(rows, axes):
        data = {s: r["fields"][name] for s, r in runs.items()
                if r and "fields" in r and name in r["fields"]}
        vmin = min(float(np.nanmin(d)) for d in data.values())
        vmax = max(float(np.nanmax(d)) for d in data.values())
        im = None
        for ax, s in zip(row, SOLVERS):
            ax.set_title(f"{s}: {label}")
            if s not in data:
                ax.text(0.5, 0.5, NOT_RUN if not runs.get(s) else "not produced by " + s,
                        ha="center", va="center", transform=ax.transAxes)
                ax.set_xticks([])
                ax.set_yticks([])
                continue
            r = runs[s]
            ext = field_extent(r["fields"]["x"], r["fields"]["y"], r["D"])
            im = ax.imshow(data[s], origin="lower", extent=ext, cmap="viridis", vmin=vmin,
                           vmax=vmax)
            ax.add_patch(plt.Circle((0, 0), 0.5, color="k", fill=False))
            ax.set_xlabel("x / D")
            ax.set_ylabel("y / D")
        fig.colorbar(im, ax=list(row), shrink=0.9)
    return save(fig, out, "report_fields.png", dpi=90), [n for n, _ in rows]


def fmt(v, digits=6):
    if v is None:
        return "–"
    if isinstance(v, str):
        return v
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    v = float(v)
    if not math.isfinite(v):
        return "–"
    return f"{v:.{digits}g}"


def with_se(v, se):
    return fmt(v) + ("" if se is None else f" ± {fmt(se, 3)}")


def solver_rows(runs):
    """(label, {solver: cell text}) rows of the results table."""
    def cell(fn):
        return {s: (fn(r) if r else NOT_RUN) for s, r in runs.items()}

    def mean(key, unit):
        def one(r):
            if key not in r["means"]:
                return "–"
            se = r["means"].get(key + "_stderr")
            if se is not None:
                return with_se(r["means"][key], se) + f" {unit} (standard error)"
            if key + "_mesh_error" in r["diag"]:  # a FE solution: its change from a coarser mesh
                return (with_se(r["means"][key], r["diag"][key + "_mesh_error"]) + f" {unit} "
                        f"(mesh-error estimate: refinement "
                        f"{fmt(r['diag'].get('coarser_refinement'))} gave "
                        f"{fmt(r['diag'].get(key + '_coarser'))})")
            return fmt(r["means"][key]) + f" {unit}"
        return cell(one)

    rows = [("drag D", mean("drag", "N/m")), ("lift L", mean("lift", "N/m")),
            ("torque", mean("torque", "N")),
            ("L/D", cell(lambda r: fmt(r["derived"].get("lift_over_drag"))))]
    if any(r and "lift_over_buoyancy" in r["derived"] for r in runs.values()):
        rows.append(("L/B (B = rho |g| pi D^2/4)",
                     cell(lambda r: fmt(r["derived"].get("lift_over_buoyancy")) +
                          (f" (B = {fmt(r['derived']['buoyancy'])} N/m)"
                           if "buoyancy" in r["derived"] else ""))))
    rows.append(("spin ratio omega R/|V|", cell(lambda r: fmt(r["derived"].get("spin_ratio")))))
    rows.append(("pressure scale P0", cell(
        lambda r: f"{fmt(r['P0'])} Pa ({pressure_source(s_of(runs, r), r)})")))

    def far(r):
        ff = r["far_field"]
        if ff is None:
            return "not measured" if s_of(runs, r) == "dem" else "– (continuum: P0 is imposed)"
        return with_se(ff.get("mean"), ff.get("mean_stderr")) + " Pa"

    rows.append(("far-field pressure (/far_field)", cell(far)))
    def box(r):
        # the FE's box against the DEM's (docs/continuum-model.md, "The box"); the DEM's
        # averaging window and whether its intruder had met its own wake by then
        d = r["diag"]
        if "box" in d:
            return str(d["box"])
        if "mean_travel_from" in d:
            window = (f"means over {fmt(d['mean_travel_from'])}-{fmt(d['mean_travel_to'])} "
                      "d of travel")
            if "wake_travel" in d:
                crossed = "after" if int(d.get("crossed_own_wake", 0)) else "before"
                window += (f"; the intruder meets its own wake at {fmt(d['wake_travel'])} d: "
                           f"the run ends {crossed} it")
            return window
        return "–"

    rows.append(("box, far field", cell(box)))
    rows.append(("converged", cell(lambda r: ("yes" if int(r["diag"]["converged"]) else "no")
                                   if "converged" in r["diag"] else "–")))
    rows.append(("mesh: cells, dofs", cell(
        lambda r: f"{fmt(r['diag']['cells'])} cells, {fmt(r['diag']['dofs'])} dofs"
        if "cells" in r["diag"] else "–")))
    rows.append(("DEM: grains, contacts", cell(
        lambda r: f"{fmt(r['diag']['grains'])} grains, {fmt(r['means'].get('contacts'), 3)} "
                  "contacts on average" if "grains" in r["diag"] else "–")))
    rows.append(("wall time", cell(lambda r: fmt(float(r["meta"]["wall_seconds"]), 3) + " s"
                                   if "wall_seconds" in r["meta"] else "–")))
    return rows


def s_of(runs, r):
    return next(s for s, x in runs.items() if x is r)


COMPARE_KEYS = (
    ("drag_rel", "drag (B - A)/|A|"), ("lift_rel", "lift (B - A)/|A|"),
    ("torque_rel", "torque (B - A)/|A|"),
    ("drag_z", "drag difference / combined error"),
    ("lift_z", "lift difference / combined error"),
    ("torque_z", "torque difference / combined error"),
    ("error_kind_a", "error of A"), ("error_kind_b", "error of B"),
    ("pressure_scale", "P used for the stress differences (Pa)"),
    ("sigma_n_l2", "sigma_n: rms |B - A| / P"), ("sigma_n_max", "sigma_n: max |B - A| / P"),
    ("sigma_t_l2", "sigma_t: rms |B - A| / P"), ("sigma_t_max", "sigma_t: max |B - A| / P"))
for _k in ("sigma_n", "sigma_t"):
    for _p in ("symmetric", "antisymmetric"):
        COMPARE_KEYS += ((f"{_k}_{_p}_l2", f"{_k} {_p} part: rms / P"),
                         (f"{_k}_{_p}_max", f"{_k} {_p} part: max / P"))

CSS = """
body { font-family: sans-serif; max-width: 1150px; margin: 1em auto; color: #222; }
h1 { font-size: 1.4em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { border: 1px solid #bbb; padding: 3px 8px; text-align: left; font-size: 0.92em; }
th { background: #eee; } td.notrun { color: #888; font-style: italic; }
figure { margin: 0.5em 0 1.2em 0; } img { max-width: 100%; }
figcaption { font-size: 0.9em; color: #444; max-width: 1000px; }
code { background: #f4f4f4; padding: 0 2px; }
"""


def write_html(out, runs, summary, images):
    e = html.escape
    parts = ["<!DOCTYPE html>", "<html lang=\"en\"><head><meta charset=\"utf-8\">",
             f"<title>grainlift report: {e(os.path.basename(os.path.abspath(out)))}</title>",
             f"<style>{CSS}</style></head><body>",
             f"<h1>grainlift report: <code>{e(os.path.abspath(out))}</code></h1>"]
    meta = [f"{s}: grainlift {e(r['meta'].get('grainlift_version', '?'))} "
            f"({e(r['meta'].get('git_revision', '?'))}), {e(r['meta'].get('created_utc', '?'))}"
            for s, r in runs.items() if r]
    hashes = {summary.get(s, {}).get("case_hash") for s in runs if runs[s]} - {None}
    parts.append("<p>" + "; ".join(meta) + (f". Case hash {e(', '.join(sorted(hashes)))}."
                                            if hashes else ".") + "</p>")

    parts.append("<h2>Forces and runs</h2><table><tr><th></th>" +
                 "".join(f"<th>{s}</th>" for s in SOLVERS) + "</tr>")
    for label, cells in solver_rows(runs):
        parts.append(f"<tr><th>{e(label)}</th>" + "".join(
            f"<td class=\"notrun\">{NOT_RUN}</td>" if cells[s] == NOT_RUN
            else f"<td>{e(cells[s])}</td>" for s in SOLVERS) + "</tr>")
    parts.append("</table><p>Drag and lift as in docs/conventions.md (D = -F.V/|V|, L = "
                 "F.(z x V/|V|)); forces per unit length. DEM: means after the steady-state "
                 "start with block-average standard errors; FEM: the steady solution.</p>")

    cmp = summary.get("compare")
    parts.append("<h2>Comparison (summary.json \"compare\")</h2>")
    if cmp:
        parts.append(f"<p>A = {e(str(cmp.get('solver_a', 'dem')))}, "
                     f"B = {e(str(cmp.get('solver_b', 'fem')))}; the same numbers as "
                     "<code>grainlift compare dem.h5 fem.h5 --json</code>"
                     + (f"; P from {e(str(cmp['pressure_scale_from']))}"
                        if "pressure_scale_from" in cmp else "") + ".</p>")
        parts.append("<table><tr><th>field</th><th>meaning</th><th>value</th></tr>")
        for k, meaning in COMPARE_KEYS:
            if k in cmp:
                parts.append(f"<tr><td><code>{k}</code></td><td>{e(meaning)}</td>"
                             f"<td>{e(fmt(cmp[k]))}</td></tr>")
        parts.append("</table>")
    else:
        parts.append("<p>No \"compare\" object in summary.json: both solvers must run into "
                     "the same folder with the same case.</p>")

    band = [s for s, r in runs.items() if r and "sigma_n_stderr" in r]
    sources = "; ".join(
        f"{s}: P0 = {fmt(r['P0'])} Pa from /geometry pressure_scale, source "
        f"\"{e(pressure_source(s, r))}\" (/diagnostics "
        f"{'pressure_source' if s == 'fem' else 'pressure_scale_source'})"
        for s, r in runs.items() if r and "theta" in r)
    if images.get("surface"):
        parts.append("<h2>Surface stress</h2><figure>"
                     "<img src=\"report_surface.png\" alt=\"sigma_n and sigma_t against theta\">"
                     f"<figcaption>Normal (compressive positive) and tangential stress on the "
                     f"intruder against the angle from V, each solver divided by its own P0: "
                     f"{sources}. Both are the Gaussian kernel average of Guillard eq. (A4). "
                     + (f"Bands: ± one standard error per angle ({', '.join(band)})."
                        if band else "No error band: the files hold no per-angle standard "
                        "error of the DEM traces (not in schema_version 2).")
                     + "</figcaption></figure>")
    if images.get("split"):
        parts.append("<figure><img src=\"report_split.png\" alt=\"symmetric and antisymmetric "
                     "parts\"><figcaption>Symmetric (s(theta) + s(-theta))/2 and antisymmetric "
                     "(s(theta) - s(-theta))/2 parts from /derived, each over its solver's P0. "
                     "The drag comes from the symmetric sigma_n and the antisymmetric sigma_t, "
                     "lift and torque from the other two.</figcaption></figure>")
    if images.get("fields"):
        names = ", ".join(images["field_names"])
        parts.append("<h2>Fields</h2><figure><img src=\"report_fields.png\" alt=\"fields\">"
                     f"<figcaption>Intruder frame, cell averages on the /fields grid ({names}); "
                     "one colour scale per row, shared by both columns. Cells inside the "
                     "intruder or outside the FE mesh are blank.</figcaption></figure>")
    parts.append("</body></html>\n")
    path = os.path.join(out, "report.html")

    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as f:
            f.write("\n".join(parts))
    return files.write_atomically(path, write)


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    out = argv[1]
    runs = {s: None for s in SOLVERS}
    for s in SOLVERS:
        p = os.path.join(out, s + ".h5")
        if os.path.exists(p):
            runs[s] = read_solver(p)
    if not any(runs.values()):
        print(f"{out}: no dem.h5 or fem.h5 here", file=sys.stderr)
        return 2
    summary = {}
    sp = os.path.join(out, "summary.json")
    if os.path.exists(sp):
        summary = io.summary(out)
    try:
        images = {"surface": plot_surface(runs, out), "split": plot_split(runs, out)}
        images["fields"], images["field_names"] = plot_fields(runs, out)
        print(write_html(out, runs, summary, images))
    except OSError as e:  # a full disk, a read-only folder: one sentence, the old files kept
        print(f"{e.filename or out}: cannot write the report: {e.strerror} "
              f"({files.advice(e)}); the previous files are kept as they were", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
