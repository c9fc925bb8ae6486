#!/usr/bin/python3
"""Kumar 2019 Fig. 7 from grainlift runs: the flow fields around the intruder, 3 x 3.

  plot_fields_fig7.py [--mirror] OUT.png RUN_DIR[+RUN_DIR...] ...
                                  (one column per argument: a dem.h5 with fields/, or several
                                   independent beds joined by '+', pooled)

Rows: velocity relative to the intruder |<V*>|/V0 with streamlines; area fraction <Phi*>;
granular temperature <T_g*>/(V0^2 (1 + Omega^2)). Columns: the runs in the order given
(Omega from each file's geometry: Omega = omega R / V0).

Drawn in grainlift's frame: the intruder moves along +x, so the grains flow from right to left
as in the paper's figure, and omega > 0 is COUNTER-clockwise. Kumar's Fig. 7 spins clockwise,
so with --mirror the fields are reflected y -> -y (v_y -> -v_y) to be drawn as the paper draws.
The printed descriptors are always in grainlift's (unmirrored) frame.
The printed L/D's error is the one statistics rule's (grainlift.io Result.block_errors(): the
correlation-corrected block error of each run's forces), whichever binary wrote the runs.

Sides (the paper's definition, Sec. III D: "the retreating side of the intruder (the side whose
surface moves against the flow)"). In the intruder frame the grains come at the intruder along
-V. With e = z x V/|V| (the +lift direction, +y here) the surface point at +R e moves at
-omega R V/|V|, i.e. WITH the flow for omega > 0. So for omega > 0:
    retreating side = -e (y < 0 here): surface moves against the oncoming grains,
    advancing side  = +e (y > 0 here): surface moves with them,
and the inverse-Magnus lift -omega x V points to the retreating side.

Descriptors printed per run (lengths in D, y relative to the intruder centre):
  wake       cells behind the intruder (x < 0, outside it) with <Phi*> < Phi_b / 2, the
             connected region touching the intruder; Phi_b is the mean <Phi*> in the window's
             upstream strip (x > 2 D). Its area, y-centroid, and the centroid of the
             deficit (Phi_b - Phi)+ at x = -1, -2, -3 D.
  width      y-extent of the wake (Phi < Phi_b/2) and the deficit width
             int (1 - Phi/Phi_b)+ dy, at x = -1, -2, -3 D.
  core       min <Phi*> behind the intruder, mean <Phi*> in the box 0.5 < -x < 1 D, |y| < 0.2 D,
             area with <Phi*> < 0.05.
  symmetry   sum |Phi(x,y) - Phi(x,-y)| / sum 2 (Phi_b - Phi)+ over the wake window x < 0
             (0: mirror-symmetric wake, 1: the wake and its mirror do not overlap).
  T_g max    position and polar angle (from V, counter-clockwise) of the maximum of
             T_g/(V0^2(1+Omega^2)) over cells with <Phi*> > 0.2 Phi_b within 2 D of the centre,
             the side it is on, and the ratio of the maxima on the two sides.
"""
import os
import sys
import warnings

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.plots import plt  # noqa: E402
from grainlift.stats import pooled_mean  # noqa: E402
from scipy import ndimage  # noqa: E402


def load(spec):
    """One column: RUN_DIR, or RUN_DIR1+RUN_DIR2+... (independent beds, pooled: area fraction
    averaged, velocity weighted by area fraction, temperature including the spread of the beds'
    mean velocities, as if all snapshots had been averaged together)."""
    beds = [load_one(d) for d in spec.split("+")]
    if len(beds) == 1:
        return beds[0]
    r = dict(beds[0])
    phis = [np.nan_to_num(b["area_fraction"]) for b in beds]
    w = sum(phis)
    safe = np.where(w > 0, w, 1.0)
    vx = sum(p * np.nan_to_num(b["velocity_x"]) for p, b in zip(phis, beds)) / safe
    vy = sum(p * np.nan_to_num(b["velocity_y"]) for p, b in zip(phis, beds)) / safe
    tg = sum(p * (np.nan_to_num(b["granular_temperature"])
                  + 0.5 * ((np.nan_to_num(b["velocity_x"]) - vx) ** 2
                           + (np.nan_to_num(b["velocity_y"]) - vy) ** 2))
             for p, b in zip(phis, beds)) / safe
    nanmask = np.isnan(beds[0]["area_fraction"])
    r["area_fraction"] = np.where(nanmask, np.nan, w / len(beds))
    r["velocity_x"], r["velocity_y"], r["granular_temperature"] = vx, vy, tg
    m = {}
    for k in ("drag", "lift"):  # grainlift.stats.pooled_mean over the beds
        p = pooled_mean([b["means"][k] for b in beds],
                        [b["means"].get(k + "_stderr", 0) for b in beds])
        m[k], m[k + "_stderr"] = p.mean, p.error
    r["means"] = m
    r["wall_seconds"] = sum(b["wall_seconds"] for b in beds)
    r["path"] = " + ".join(b["path"] for b in beds)
    r["beds"] = beds
    r["snapshots"] = sum(snapshots(b["path"]) for b in beds)
    return r


def load_one(run_dir):
    path = run_dir if run_dir.endswith(".h5") else run_dir.rstrip("/") + "/dem.h5"
    f = io.read(path, "dem")
    g, geo = f["fields"], f.geometry
    r = {k: g[k] for k in ("x", "y", "velocity_x", "velocity_y", "area_fraction",
                           "granular_temperature")}
    r["attrs"] = dict(g.attrs)
    D = float(geo["intruder_diameter"])
    V = np.array([geo["velocity_x"], geo["velocity_y"]], float)
    omega = float(geo["omega"])
    means = dict(f.means)
    means.update(f.block_errors())  # the errors by the one statistics rule, whatever wrote it
    r["wall_seconds"] = f.wall_seconds
    V0 = float(np.hypot(*V))
    if abs(V[1]) > 1e-12 * V0 or V[0] <= 0:
        raise SystemExit(f"{path}: the descriptors assume V along +x")
    r.update(path=path, D=D, V0=V0, omega=omega, Omega=omega * D / 2 / V0, means=means)
    return r


def descriptors(r):
    D, x, y = r["D"], r["x"] / r["D"], r["y"] / r["D"]
    X, Y = np.meshgrid(x, y)
    R2 = X ** 2 + Y ** 2
    phi = np.nan_to_num(r["area_fraction"], nan=0.0)
    outside = R2 > 0.25 * (1 + 1e-9)
    h = x[1] - x[0]
    phib = float(np.mean(phi[(X > 2.0) & outside]))
    out = {"Omega": r["Omega"], "phi_b": phib}
    # wake: connected low-Phi region behind the intruder, touching its rear half
    low = (phi < 0.5 * phib) & outside & (X < 0.3)
    lab, _ = ndimage.label(low)
    rim = (R2 < (0.5 + 1.5 * h) ** 2) & outside & (X < 0)
    ids = np.unique(lab[rim & low])
    wake = np.isin(lab, ids[ids > 0])
    out["wake_area"] = float(wake.sum() * h * h)
    out["wake_yc"] = float(Y[wake].mean()) if wake.any() else float("nan")
    out["wake_xmin"] = float(X[wake].min()) if wake.any() else float("nan")
    deficit = np.clip(1 - phi / phib, 0, None) * outside
    out["wake_ylo"] = float(Y[wake].min()) if wake.any() else float("nan")
    out["wake_yhi"] = float(Y[wake].max()) if wake.any() else float("nan")
    near = (X < -0.5) & (X > -2.5) & (abs(Y) < 1.5)
    out["def_yc"] = float((deficit * Y)[near].sum() / deficit[near].sum())
    # mean flow behind the intruder and far from it (relative velocity / V0)
    vx = np.nan_to_num(r["velocity_x"]) / r["V0"]
    vy = np.nan_to_num(r["velocity_y"]) / r["V0"]
    has = phi > 0.05
    beh = (X < -0.5) & (X > -2.0) & (abs(Y) < 1.0) & has & outside
    out["vy_behind"] = float(vy[beh].mean())
    far = (abs(Y) > 2.0) & has
    out["vx_far"] = float(vx[far].mean())
    for xs in (-0.6, -0.8, -1.0, -2.0):
        i = int(np.argmin(abs(x - xs)))
        col, lowc = deficit[:, i], low[:, i] & wake[:, i]
        out[f"yc_def@{xs:g}"] = float((col * y).sum() / col.sum()) if col.sum() > 0 else np.nan
        out[f"width@{xs:g}"] = float(lowc.sum() * h)
        out[f"defwidth@{xs:g}"] = float(col.sum() * h)
        out[f"ylow@{xs:g}"] = float(y[lowc].min()) if lowc.any() else np.nan
        out[f"yhigh@{xs:g}"] = float(y[lowc].max()) if lowc.any() else np.nan
    behind = outside & (X < 0)
    out["core_min"] = float(phi[behind & (X > x[0] + h)].min())
    box = (X < -0.5) & (X > -1.0) & (abs(Y) < 0.2)
    out["core_box"] = float(phi[box].mean())
    out["core_area_005"] = float(((phi < 0.05) & behind).sum() * h * h)
    # symmetry of the wake about y = 0 (the grid is symmetric in y)
    win = X < 0
    mirror = phi[::-1, :]
    num = np.abs(phi - mirror)[win & outside & (mirror > -1)].sum()
    den = 2 * deficit[win].sum()
    out["asym"] = float(num / den) if den > 0 else np.nan
    # granular temperature maximum
    tg = np.nan_to_num(r["granular_temperature"], nan=0.0) / (r["V0"] ** 2 * (1 + r["Omega"] ** 2))
    ok = outside & (phi > 0.2 * phib) & (R2 < 4.0)
    t = np.where(ok, tg, -1.0)
    j, i = np.unravel_index(int(np.argmax(t)), t.shape)
    out["tg_max"] = float(t[j, i])
    out["tg_x"], out["tg_y"] = float(x[i]), float(y[j])
    out["tg_theta_deg"] = float(np.degrees(np.arctan2(y[j], x[i])))
    up, dn = t[Y > 0].max(), t[Y < 0].max()
    out["tg_up_over_down"] = float(up / dn) if dn > 0 else np.nan
    ring = outside & (R2 < 1.0) & (phi > 0.05)  # R < r < 2 R
    out["tg_ring_up_over_down"] = float(tg[ring & (Y > 0)].mean() / tg[ring & (Y < 0)].mean())
    # angular profile of T_g in the first layer R < r < 1.5 R (about 1.25 d), 15 degree bins
    th = np.degrees(np.arctan2(Y, X))
    shell = outside & (R2 < 0.5625) & (phi > 0.05)
    edges = np.arange(-180, 181, 15)
    prof = np.array([tg[shell & (th >= a) & (th < b)].mean()
                     for a, b in zip(edges[:-1], edges[1:])])
    k = int(np.nanargmax(prof))
    out["tg_shell_theta"] = float(0.5 * (edges[k] + edges[k + 1]))
    out["tg_shell_max"] = float(prof[k])
    out["tg_shell_up_over_down"] = float(tg[shell & (Y > 0)].mean() / tg[shell & (Y < 0)].mean())
    front = (X > 0.5) & (X < 2.0) & (abs(Y) < 1.0) & has & outside
    out["vy_front"] = float(vy[front].mean())
    for name, sgn in (("up", 1), ("dn", -1)):
        box = (abs(X) < 0.75) & (sgn * Y > 0.5) & (sgn * Y < 1.5) & has
        out[f"vy_side_{name}"] = float(vy[box].mean())
    down = (X < -1.0) & (X > -3.0) & (abs(Y) < 1.5) & has
    out["vy_down"] = float(vy[down].mean())
    return out


def side(yv, omega):
    """Side of y (grainlift frame, V along +x) by the paper's definition."""
    if not np.isfinite(yv) or abs(yv) < 1e-12:
        return "on the axis"
    if omega == 0:
        return "above the axis" if yv > 0 else "below the axis"
    retreating_sign = -np.sign(omega)  # retreating side = -sign(omega) e, e = +y
    return "retreating" if np.sign(yv) == retreating_sign else "advancing"


def snapshots(path):
    """Number of field snapshots averaged, from the case and its overrides (the engine takes
    one every dem.field_every steps once the intruder has travelled dem.steady_travel)."""
    f = io.read(path, "dem")
    case = f.case()
    d = float(f.geometry["grain_diameter"])
    V0 = float(np.hypot(*f.velocity()))
    dem = case.get("dem", {})
    dt, every = dem.get("dt", 2e-6), dem.get("field_every", 500)
    span = (dem.get("travel", 300.0) - dem.get("steady_travel", 30.0)) * d / V0
    return int(span / dt) // every + 1


def main(argv):
    if len(argv) < 3 or argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        return 0 if argv[1:2] in (["-h"], ["--help"]) else 2
    warnings.filterwarnings("ignore", category=RuntimeWarning)  # empty bins of the T_g profile
    mirror = "--mirror" in argv
    argv = [a for a in argv if a != "--mirror"]
    if len(argv) < 3:
        raise SystemExit(__doc__)
    out_png, runs = argv[1], [load(d) for d in argv[2:]]
    n = len(runs)
    fig, axes = plt.subplots(3, n, figsize=(4.3 * n, 10.2), squeeze=False)
    for c, r in enumerate(runs):
        D = r["D"]
        x, y = r["x"] / D, r["y"] / D
        s = -1.0 if mirror else 1.0
        vx, vy = r["velocity_x"] / r["V0"], s * r["velocity_y"] / r["V0"]
        phi = r["area_fraction"]
        tg = r["granular_temperature"] / (r["V0"] ** 2 * (1 + r["Omega"] ** 2))
        if mirror:
            vx, vy, phi, tg = vx[::-1], vy[::-1], phi[::-1], tg[::-1]
            y = -y[::-1]
        X, Y = np.meshgrid(x, y)
        inside = X ** 2 + Y ** 2 < 0.25
        empty = np.nan_to_num(phi) < 0.02
        speed = np.ma.masked_where(inside | empty, np.hypot(vx, vy))
        h = x[1] - x[0]
        ext = [x[0] - h / 2, x[-1] + h / 2, y[0] - h / 2, y[-1] + h / 2]
        a = axes[0, c]
        im = a.imshow(speed, origin="lower", extent=ext, cmap="jet", vmin=0, vmax=1.2)
        u = np.ma.masked_where(inside | empty, vx).filled(np.nan)
        v = np.ma.masked_where(inside | empty, vy).filled(np.nan)
        a.streamplot(x, y, u, v, color="k", linewidth=0.6, density=1.4, arrowsize=0.7)
        fig.colorbar(im, ax=a, shrink=0.8, label=r"$\langle V^*\rangle / V_0$")
        spin = ("clockwise" if (r["omega"] > 0) == mirror else "counter-clockwise") \
            if r["omega"] != 0 else "no spin"
        a.set_title(f"Omega = {r['Omega']:g} ({spin})")
        a = axes[1, c]
        im = a.imshow(np.ma.masked_where(inside, phi), origin="lower", extent=ext,
                      cmap="jet", vmin=0, vmax=0.9)
        fig.colorbar(im, ax=a, shrink=0.8, label=r"$\langle \Phi^*\rangle$")
        a = axes[2, c]
        tmax = np.nanpercentile(np.where(inside, np.nan, tg), 99.8)
        im = a.imshow(np.ma.masked_where(inside, tg), origin="lower", extent=ext, cmap="jet",
                      vmin=0, vmax=tmax)
        fig.colorbar(im, ax=a, shrink=0.8, label=r"$\langle T_g^*\rangle / V_0^2(1+\Omega^2)$")
        for row in range(3):
            a = axes[row, c]
            a.add_patch(plt.Circle((0, 0), 0.5, color="y" if row == 1 else "k"))
            a.set_xlim(ext[0], ext[1])
            a.set_ylim(ext[2], ext[3])
            a.set_aspect("equal")
            a.set_xlabel("x / D")
            a.set_ylabel("y / D")
    fig.suptitle("grainlift, Kumar 2019 Fig. 7 set-up: grains flow right to left"
                 + (" (mirrored y -> -y to spin clockwise as the paper)" if mirror else ""),
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    print(f"wrote {out_png}")

    print("\nDescriptors (grainlift frame: V along +x, omega > 0 counter-clockwise; lengths in D;"
          " for omega > 0 the retreating side, surface moving against the flow, is y < 0 and the"
          " lift -omega x V points to it):")
    rows = [descriptors(r) for r in runs]
    for r, d in zip(runs, rows):
        nsnap = r.get("snapshots") or snapshots(r["path"])
        m = r["means"]
        ld_err = abs(m["lift"] / m["drag"]) * np.hypot(m.get("lift_stderr", 0) / m["lift"],
                                                       m.get("drag_stderr", 0) / m["drag"])
        print(f"\nOmega = {d['Omega']:g}  ({r['path']}; snapshots {nsnap}; "
              f"wall {r['wall_seconds']:.0f} s; L/D = {m['lift'] / m['drag']:+.3f} "
              f"+- {ld_err:.3f})")
        print(f"  Phi_b (upstream) {d['phi_b']:.3f}")
        print(f"  far field (|y| > 2 D): mean v_x*/V0 {d['vx_far']:+.3f} "
              "(-1 if the bed stayed at rest)")
        print(f"  wake (Phi < Phi_b/2, connected to the rear): area {d['wake_area']:.2f} D^2, "
              f"y from {d['wake_ylo']:+.2f} to {d['wake_yhi']:+.2f} D, y-centroid "
              f"{d['wake_yc']:+.3f} D ({side(d['wake_yc'], r['omega'])}), reaches x = "
              f"{d['wake_xmin']:.2f} D")
        print(f"  deficit (1 - Phi/Phi_b)+ centroid over -2.5 < x < -0.5 D, |y| < 1.5 D: "
              f"y {d['def_yc']:+.3f} D ({side(d['def_yc'], r['omega'])})")
        print(f"  mean v_y*/V0: in front (0.5 < x < 2 D, |y| < 1 D) {d['vy_front']:+.3f}; behind "
              f"(-2 < x < -0.5 D, |y| < 1 D) {d['vy_behind']:+.3f}; downstream (-3 < x < -1 D, "
              f"|y| < 1.5 D) {d['vy_down']:+.3f}; beside (|x| < 0.75 D, 0.5 < |y| < 1.5 D): "
              f"y > 0 {d['vy_side_up']:+.3f}, y < 0 {d['vy_side_dn']:+.3f}")
        for xs in (-0.6, -0.8, -1.0, -2.0):
            print(f"  x = {xs:g} D: deficit centroid y {d[f'yc_def@{xs:g}']:+.3f} D, "
                  f"Phi < Phi_b/2 over {d[f'width@{xs:g}']:.2f} D (y {d[f'ylow@{xs:g}']:+.2f} to "
                  f"{d[f'yhigh@{xs:g}']:+.2f}), deficit width {d[f'defwidth@{xs:g}']:.2f} D")
        print(f"  core: min Phi behind {d['core_min']:.3f}, mean Phi at 0.5<-x<1 D, |y|<0.2 D "
              f"{d['core_box']:.3f}, area with Phi < 0.05: {d['core_area_005']:.2f} D^2")
        print(f"  wake asymmetry index {d['asym']:.3f}")
        print(f"  T_g/(V0^2(1+Omega^2)) max {d['tg_max']:.4f} at (x, y) = ({d['tg_x']:+.2f}, "
              f"{d['tg_y']:+.2f}) D, theta = {d['tg_theta_deg']:+.0f} deg, "
              f"{side(d['tg_y'], r['omega'])} side; max(y>0)/max(y<0) = "
              f"{d['tg_up_over_down']:.2f}; ring R < r < 2R mean (y>0)/(y<0) = "
              f"{d['tg_ring_up_over_down']:.2f}")
        print(f"  T_g/(V0^2(1+Omega^2)) in the first layer R < r < 1.5 R: largest 15-degree bin "
              f"at theta = {d['tg_shell_theta']:+.1f} deg ({d['tg_shell_max']:.4f}, "
              f"{side(np.sin(np.radians(d['tg_shell_theta'])), r['omega'])} side); "
              f"mean (y>0)/(y<0) = {d['tg_shell_up_over_down']:.2f}")
        for k, b in enumerate(r.get("beds", [])):
            e = descriptors(b)
            print(f"  bed {k + 1}: wake area {e['wake_area']:.2f} D^2, wake y-centroid "
                  f"{e['wake_yc']:+.3f} D, deficit centroid {e['def_yc']:+.3f} D, deficit width at "
                  f"x = -1 D {e['defwidth@-1']:.2f} D, v_y*/V0 behind {e['vy_behind']:+.3f}, T_g "
                  f"first layer: max bin at {e['tg_shell_theta']:+.1f} deg, (y>0)/(y<0) "
                  f"{e['tg_shell_up_over_down']:.2f}; "
                  f"L/D {b['means']['lift'] / b['means']['drag']:+.3f}")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
