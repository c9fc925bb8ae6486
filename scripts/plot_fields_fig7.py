#!/usr/bin/python3
"""Kumar 2019 Fig. 7 from grainlift runs: the flow fields around the intruder, 3 x 3.

  plot_fields_fig7.py OUT.png RUN_DIR ...        (one dem.h5 with fields/ per column)

Rows: velocity relative to the intruder |<V*>|/V0 with streamlines; area fraction <Phi*>;
granular temperature <T_g*>/(V0^2 (1 + Omega^2)). Columns: the runs in the order given
(Omega from each file's geometry: Omega = omega R / V0).

Drawn in grainlift's frame: the intruder moves along +x, so the grains flow from right to left
as in the paper's figure, and omega > 0 is COUNTER-clockwise. Kumar's Fig. 7 spins clockwise,
so with --mirror the fields are reflected y -> -y (v_y -> -v_y) to be drawn as the paper draws.
The printed descriptors are always in grainlift's (unmirrored) frame.

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
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import ndimage  # noqa: E402


def load(run_dir):
    path = run_dir if run_dir.endswith(".h5") else run_dir.rstrip("/") + "/dem.h5"
    with h5py.File(path, "r") as f:
        g, geo = f["fields"], f["geometry"].attrs
        r = {k: g[k][:] for k in ("x", "y", "velocity_x", "velocity_y", "area_fraction",
                                   "granular_temperature")}
        r["attrs"] = dict(g.attrs)
        D = float(geo["intruder_diameter"])
        V = np.array([geo["velocity_x"], geo["velocity_y"]], float)
        omega = float(geo["omega"])
        means = dict(f["means"].attrs)
        r["wall_seconds"] = float(f["metadata"].attrs["wall_seconds"])
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
    for xs in (-1.0, -2.0, -3.0):
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
    return out


def side(yv, omega):
    """Side of y (grainlift frame, V along +x) by the paper's definition."""
    if omega == 0 or not np.isfinite(yv) or yv == 0:
        return "on the axis" if omega != 0 else ("above" if yv > 0 else "below")
    retreating_sign = -np.sign(omega)  # retreating side = -sign(omega) e, e = +y
    return "retreating" if np.sign(yv) == retreating_sign else "advancing"


def main(argv):
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
        nsnap = r["attrs"].get("snapshots", "?")
        m = r["means"]
        print(f"\nOmega = {d['Omega']:g}  ({r['path']}; snapshots {nsnap}; "
              f"wall {r['wall_seconds']:.0f} s; L/D = {m['lift'] / m['drag']:+.3f} "
              f"+- {abs(m['lift'] / m['drag']) * np.hypot(m.get('lift_stderr', 0) / m['lift'], m.get('drag_stderr', 0) / m['drag']):.3f})")
        print(f"  Phi_b (upstream) {d['phi_b']:.3f}")
        print(f"  wake (Phi < Phi_b/2): area {d['wake_area']:.2f} D^2, y-centroid "
              f"{d['wake_yc']:+.3f} D ({side(d['wake_yc'], r['omega'])}), reaches x = "
              f"{d['wake_xmin']:.2f} D")
        for xs in (-1, -2, -3):
            print(f"  x = {xs} D: deficit centroid y {d[f'yc_def@{xs:g}']:+.3f} D, Phi<Phi_b/2 "
                  f"from y {d[f'ylow@{xs:g}']:+.2f} to {d[f'yhigh@{xs:g}']:+.2f} "
                  f"(width {d[f'width@{xs:g}']:.2f} D), deficit width "
                  f"{d[f'defwidth@{xs:g}']:.2f} D")
        print(f"  core: min Phi behind {d['core_min']:.3f}, mean Phi at 0.5<-x<1 D, |y|<0.2 D "
              f"{d['core_box']:.3f}, area with Phi < 0.05: {d['core_area_005']:.2f} D^2")
        print(f"  wake asymmetry index {d['asym']:.3f}")
        print(f"  T_g/(V0^2(1+Omega^2)) max {d['tg_max']:.4f} at (x, y) = ({d['tg_x']:+.2f}, "
              f"{d['tg_y']:+.2f}) D, theta = {d['tg_theta_deg']:+.0f} deg, "
              f"{side(d['tg_y'], r['omega'])} side; max(y>0)/max(y<0) = "
              f"{d['tg_up_over_down']:.2f}")


if __name__ == "__main__":
    main(sys.argv)
