#!/usr/bin/env python3
"""The grains' wall law at the intruder, measured on DEM runs (studies/wall_law/README.md).

    wall_law.py RUNS [--fem-sweep DIR] [--threshold 0.5]

RUNS is a folder of run folders, each with dem/dem.h5 (and fem/fem.h5, the continuum with its
Coulomb wall), as studies/one_box/study_one_box.sh makes them (runs/one_box). Prints, as
Markdown tables:
1. per run: the effective wall friction mu_w = sum |sigma_t| / sum sigma_n over the angles
   with sigma_n >= threshold x its maximum (grainlift.wall.wall_friction: the sigma_n-weighted
   mean of |sigma_t|/sigma_n), its error from the per-angle block errors, the peak ratio
   max |sigma_t| / max sigma_n (docs/crosscheck.md's 0.22), the FEM's same numbers, and from
   /histogram the front's (|theta| < 45 deg) F_T/F_N, slip fraction and mean F_N per contact;
   the torque over R sum F_N with the torque's block error (grainlift.stats.block_mean);
2. the two boxes pooled at each Omega they share (grainlift.stats.pooled_mean);
3. the slip law: the per-angle |sigma_t|/sigma_n of the small-box runs against the nominal
   slip speed |omega R - V sin theta| / V, fitted by mu_a + (mu_b - mu_a) x / (x + x0)
   (grainlift.wall.saturating_fit), and the large-box runs against the fit;
4. with --fem-sweep DIR (folders of `grainlift run ... --solver fem --set
   continuum.wall_friction=...`): the continuum's torque and lift against its wall friction,
   and the wall friction that gives the DEM's torque at each Omega;
5. with --write-wall FILE (runs with /histogram/slip_velocity, grainlift after 67a8481): the
   slip law against the measured slip speed |v_s| (m/s; grainlift.wall.slip_law, at every
   loaded angle of every such run, v_s interpolated from the histogram's bins), and the
   effective friction, the runs' mu_w pooled (grainlift.stats.pooled_mean); both written as
   the [wall] table of the rheology file FILE (replacing one it has), which
   `continuum.wall_law = "measured"` reads."""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
from grainlift import io, wall  # noqa: E402
from grainlift.stats import block_mean, pooled_mean  # noqa: E402


def run_folders(root):
    """(name, folder) of every run folder of @p root that holds dem/dem.h5 and a /histogram."""
    out = []
    for name in sorted(os.listdir(root)):
        p = os.path.join(root, name, "dem", "dem.h5")
        if os.path.isfile(p):
            out.append((name, os.path.join(root, name)))
    return out


def surface(r):
    """theta, sigma_n, sigma_t and their errors (None for the FEM) of a Result."""
    return (r["surface/theta"], r["surface/sigma_n"], r["surface/sigma_t"],
            r.get("surface/sigma_n_stderr"), r.get("surface/sigma_t_stderr"))


def front_histogram(r, half_width=math.pi / 4):
    """F_T/F_N (summed forces), slip fraction (contact-weighted) and mean F_N per contact
    (N/m) of the histogram bins whose centre is within @p half_width of the front."""
    h = r["histogram"]
    c = 0.5 * (h["theta_lo"] + h["theta_hi"])
    s = np.abs(wall.wrap(c)) < half_width
    n, fn, ft = h["contact_count"][s], h["normal_force"][s], h["tangential_force"][s]
    slip = float(np.sum(h["slip_fraction"][s] * n) / np.sum(n))
    return float(np.sum(ft) / np.sum(fn)), slip, float(np.sum(fn) / np.sum(n))


def torque_ratio(r):
    """|torque| / (R sum F_N) with the torque's block error (stats.block_mean over the samples
    after the steady start, the file's blocks): the tangential load on the whole surface over
    the normal load, no threshold."""
    first = int(r.diagnostics["steady_start_sample"])
    bm = block_mean(r["forces/torque"][first:], int(r.means["blocks"]))
    radius = 0.5 * float(r.geometry["intruder_diameter"])
    load = radius * float(np.sum(r["histogram/normal_force"]))
    return abs(bm.mean) / load, bm.stderr_corrected / load


def measure(name, folder, threshold):
    """One row of table 1 as a dict."""
    r = io.read(os.path.join(folder, "dem"), "dem")
    om = float(r.derived["spin_ratio"])
    th, sn, st, en, et = surface(r)
    w = wall.wall_friction(th, sn, st, en, et, threshold)
    row = {"name": name, "omega": om, "w": w, "peak": wall.peak_ratio(sn, st),
           "directed": wall.directed_friction(th, sn, st, om, threshold),
           "front": front_histogram(r), "torque": torque_ratio(r), "dem": r}
    fem = os.path.join(folder, "fem", "fem.h5")
    if os.path.isfile(fem):
        f = io.read(fem)
        fth, fsn, fst, _, _ = surface(f)
        row["fem"] = (wall.wall_friction(fth, fsn, fst, threshold=threshold).mu,
                      wall.peak_ratio(fsn, fst))
    return row


def print_runs(rows):
    print("| run | Omega | mu_w (DEM) | [indep.] | loaded theta (deg) | peak ratio DEM | "
          "mu_w, peak FEM | front F_T/F_N | front slip | F_N/contact (N/m) | "
          "|T|/(R sum F_N) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for x in rows:
        w = x["w"]
        fem = "%.3f, %.3f" % x["fem"] if "fem" in x else "-"
        ratio, slip, fn = x["front"]
        t, te = x["torque"]
        print(f"| {x['name']} | {x['omega']:g} | {w.mu:.3f} +- {w.error:.3f} | "
              f"{w.error_independent:.3f} | {math.degrees(w.theta_lo):.0f} to "
              f"{math.degrees(w.theta_hi):.0f} | {x['peak']:.3f} | {fem} | {ratio:+.3f} | "
              f"{slip:.2f} | {fn:.3g} | {t:.3f} +- {te:.3f} |")


def print_pooled(rows):
    """The small and large boxes at the Omega they share, pooled as two beds of one scene."""
    demo = {x["omega"]: x for x in rows if x["name"].startswith("demo_")}
    big = {x["omega"]: x for x in rows if x["name"].startswith("big_")}
    print("\n| Omega | mu_w small box | mu_w large box | pooled (stats.pooled_mean) | between |")
    print("|---|---|---|---|---|")
    for om in sorted(set(demo) & set(big)):
        a, b = demo[om]["w"], big[om]["w"]
        p = pooled_mean([a.mu, b.mu], [a.error, b.error])
        print(f"| {om:g} | {a.mu:.3f} +- {a.error:.3f} | {b.mu:.3f} +- {b.error:.3f} | "
              f"{p.mean:.3f} +- {p.error:.3f} | {p.between:.3f} |")


def local_points(rows, prefix, threshold):
    """(x, ratio, error) of every loaded angle of the runs named prefix*: x = |slip| / V,
    ratio = |sigma_t| / sigma_n, error from the per-angle block errors."""
    xs, ys, es = [], [], []
    for x in rows:
        if not x["name"].startswith(prefix):
            continue
        th, sn, st, en, et = surface(x["dem"])
        s = wall.loaded(sn, threshold)
        xs.append(np.abs(wall.slip_speed(th[s], x["omega"])))
        ys.append(np.abs(st[s]) / sn[s])
        es.append(np.hypot(et[s], ys[-1] * en[s]) / sn[s])
    if not xs:
        return np.array([]), np.array([]), np.array([])
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(es)


def print_slip_law(rows, threshold):
    x, y, e = local_points(rows, "demo_", threshold)
    a, b, x0, ae, be, chi = wall.saturating_fit(x, y, e)
    r = rows[0]["dem"]
    scale = float(np.hypot(*r.velocity())) / math.sqrt(
        float(r.geometry["pressure_scale"]) / float(r.case()["grains"]["density"]))
    print(f"\nslip law (small box, {len(x)} angles, x = |omega R - V sin theta| / V):")
    print(f"  |sigma_t|/sigma_n = mu_a + (mu_b - mu_a) x / (x + x0): mu_a = {a:.3f} +- {ae:.3f},"
          f" mu_b = {b:.3f} +- {be:.3f}, x0 = {x0:.2f}, chi2/dof = {chi:.2f}")
    print(f"  x0 as a wall inertial number u / sqrt(P0 / rho_s): {x0 * scale:.4f}")
    print("\n| x range | points | mean ratio | fit at mean x |")
    print("|---|---|---|---|")
    for lo, hi in ((0, 0.25), (0.25, 0.5), (0.5, 1), (1, 2), (2, 3), (3, 5), (5, 10)):
        s = (x >= lo) & (x < hi)
        if np.any(s):
            xm = float(np.mean(x[s]))
            print(f"| {lo:g}-{hi:g} | {int(np.sum(s))} | {np.mean(y[s]):.3f} | "
                  f"{a + (b - a) * xm / (xm + x0):.3f} |")
    xb, yb, eb = local_points(rows, "big_", threshold)
    if len(xb):
        fit = a + (b - a) * xb / (xb + x0)
        print(f"\nlarge box against the fit: {len(xb)} angles, mean (ratio - fit) = "
              f"{np.mean(yb - fit):+.3f}, rms {np.sqrt(np.mean((yb - fit) ** 2)):.3f}")


def write_wall(path, rows, threshold):
    """Fits the wall law of the runs (grainlift.wall.fit) and writes the [wall] table of the
    rheology file @p path (replacing its [wall])."""
    try:
        f = wall.fit([x["dem"] for x in rows], threshold)
    except ValueError as e:
        sys.exit(f"--write-wall: {e}")
    law = f.law
    print(f"\nslip law on the measured slip ({law.points} angles of {f.runs} runs): "
          f"mu_a = {law.mu_a:.3f} +- {law.mu_a_err:.3f}, mu_b = {law.mu_b:.3f} +- "
          f"{law.mu_b_err:.3f}, v0 = {law.v0:.4f} +- {law.v0_err:.4f} m/s, chi2/dof = "
          f"{law.chi2_per_dof:.2f}; friction (pooled mu_w) {f.friction:.3f} +- "
          f"{f.friction_err:.3f}")
    with open(path) as fh:
        text = fh.read()
    src = f"studies/wall_law/wall_law.py: {f.runs} runs, threshold {threshold}"
    with open(path, "w") as fh:
        fh.write(wall.with_wall_table(text, wall.wall_table(law, f.friction, f.friction_err,
                                                             src)))
    print(f"wrote the [wall] table of {path}")


def print_fem_sweep(folder, rows):
    """The continuum's torque and lift against continuum.wall_friction, per Omega."""
    dem = {x["omega"]: {**x["dem"].means, **x["dem"].block_errors()} for x in rows
           if x["name"].startswith("demo_")}
    table = {}
    for name in sorted(os.listdir(folder)):
        p = os.path.join(folder, name, "fem.h5")
        if not os.path.isfile(p):
            continue
        f = io.read(p)
        mw = float(f.case()["continuum"]["wall_friction"])
        table.setdefault(float(f.derived["spin_ratio"]), []).append(
            (mw, float(f.means["torque"]), float(f.means["lift"]), float(f.means["drag"])))
    print("\n| Omega | DEM torque, lift, drag | FEM torque, lift, drag at wall friction "
          "mu | mu giving the DEM's torque |")
    print("|---|---|---|---|")
    for om in sorted(table):
        pts = sorted(table[om])
        mws, tq = np.array([p[0] for p in pts]), np.array([p[1] for p in pts])
        d = dem.get(om)
        match = "-"
        if d is not None and np.min(np.abs(tq)) <= abs(d["torque"]) <= np.max(np.abs(tq)):
            match = "%.3f" % np.interp(abs(d["torque"]), np.abs(tq), mws)
        dt = "-" if d is None else "%.1f +- %.1f, %.0f +- %.0f, %.0f +- %.0f" % (
            d["torque"], d["torque_stderr"], d["lift"], d["lift_stderr"], d["drag"],
            d["drag_stderr"])
        fem = "; ".join(f"{m:g}: {t:.1f}, {li:.0f}, {dr:.0f}" for m, t, li, dr in pts)
        print(f"| {om:g} | {dt} | {fem} | {match} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", help="folder of run folders with dem/dem.h5 (runs/one_box)")
    ap.add_argument("--fem-sweep", help="folder of FEM runs at several continuum.wall_friction")
    ap.add_argument("--threshold", type=float, default=wall.THRESHOLD,
                    help="fraction of the largest sigma_n an angle must carry (default 0.5)")
    ap.add_argument("--write-wall", metavar="RHEOLOGY_FILE",
                    help="fit the slip law on the measured slip and write it as the file's "
                         "[wall] table (continuum.wall_law = \"measured\")")
    a = ap.parse_args()
    rows = [measure(n, f, a.threshold) for n, f in run_folders(a.runs)]
    rows = [x for x in rows if "histogram" in x["dem"]]
    if not rows:
        sys.exit(f"{a.runs}: no run folder with dem/dem.h5")
    print_runs(rows)
    print_pooled(rows)
    print_slip_law(rows, a.threshold)
    if a.fem_sweep:
        print_fem_sweep(a.fem_sweep, rows)
    if a.write_wall:
        write_wall(a.write_wall, rows, a.threshold)


if __name__ == "__main__":
    main()
