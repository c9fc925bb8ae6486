#!/usr/bin/python3
"""Plots of grainlift result files: python3 scripts/plot_results.py OUT_DIR [OUT_DIR...]

For every <solver>.h5 in each folder writes, next to it:
  <solver>_forces.png   drag and lift against time, averaging window shaded (DEM)
  <solver>_surface.png  sigma_n(theta), sigma_t(theta), with the symmetric / antisymmetric split
  <solver>_fields.png   the fields present on the intruder-frame grid
Datasets a solver did not produce are absent from the file and from the plots."""
import os
import sys

sys.path[:0] = [os.path.dirname(os.path.realpath(__file__)),  # installed: grainlift/ beside
                os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python")]
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.plots import field_extent, plt, theta_degrees  # noqa: E402


def plot_forces(f, solver, out):
    if "forces" not in f or len(f["forces/time"]) < 2:
        return None
    t = f["forces/time"][:]
    d, l = f.drag_lift()
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, d, lw=0.6, label="drag D")
    ax.plot(t, l, lw=0.6, label="lift L")
    if "means" in f:
        m = f["means"].attrs
        n = int(m["samples"])
        if 0 < n < len(t):
            ax.axvspan(t[-n], t[-1], color="0.9", zorder=0, label="averaged")
        for key, c in (("drag", "C0"), ("lift", "C1")):
            se = m.get(key + "_stderr", float("nan"))
            ax.axhline(m[key], color=c, ls="--", lw=1,
                       label=f"mean {key} {m[key]:.4g} ± {se:.2g} N/m")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("force per unit length (N/m)")
    ax.legend(fontsize=8)
    ax.set_title(f"{solver}: forces on the intruder")
    fig.tight_layout()
    path = os.path.join(out, f"{solver}_forces.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_surface(f, solver, out):
    if "surface" not in f:
        return None
    deg, order = theta_degrees(f["surface/theta"][:])
    P = f["geometry"].attrs["pressure_scale"] or 1.0
    sn, st = f["surface/sigma_n"][:] / P, f["surface/sigma_t"][:] / P
    if "derived" in f and "sigma_n_symmetric" in f["derived"]:  # schema 2: split by grainlift
        sym = f["derived/sigma_n_symmetric"][:] / P
        anti = f["derived/sigma_n_antisymmetric"][:] / P
    else:  # schema 1 files: theta_{M-1-m} is the mirror image of theta_m
        sym, anti = 0.5 * (sn + sn[::-1]), 0.5 * (sn - sn[::-1])
    ncol = 3 if "histogram" in f else 2
    fig, axes = plt.subplots(1, ncol, figsize=(4.5 * ncol, 4))
    ax = axes[0]
    ax.plot(deg[order], sn[order], label="sigma_n / P")
    ax.plot(deg[order], st[order], label="sigma_t / P")
    ax.set_xlabel("theta from V (deg)")
    ax.set_title(f"surface stress, P = {P:.4g} Pa")
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(deg[order], sym[order], label="symmetric part")
    ax.plot(deg[order], anti[order], label="antisymmetric part")
    ax.set_xlabel("theta from V (deg)")
    ax.set_title("sigma_n / P split about the axis of motion")
    ax.legend(fontsize=8)
    if "histogram" in f:
        h = f["histogram"]
        c = np.degrees(0.5 * (h["theta_lo"][:] + h["theta_hi"][:]))
        w = np.degrees(h["theta_hi"][0] - h["theta_lo"][0])
        ax = axes[2]
        ax.bar(c, h["contact_count"][:], width=0.9 * w, label="contacts per sample")
        ax2 = ax.twinx()
        ax2.plot(c, h["slip_fraction"][:], "k.-", label="slip fraction")
        ax2.set_ylim(0, 1.05)
        ax.set_xlabel("theta from V (deg)")
        ax.set_title("contacts (bins of pi/12)")
        ax.legend(loc="upper left", fontsize=8)
        ax2.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, f"{solver}_surface.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_fields(f, solver, out):
    if "fields" not in f:
        return None
    g = f["fields"]
    x, y = g["x"][:], g["y"][:]
    D = f["geometry"].attrs["intruder_diameter"]
    names = [n for n in ("area_fraction", "pressure", "granular_temperature") if n in g]
    speed = None
    if "velocity_x" in g and "velocity_y" in g:
        speed = np.hypot(g["velocity_x"][:], g["velocity_y"][:])
    panels = names + (["speed"] if speed is not None else [])
    if not panels:
        return None
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.8), squeeze=False)
    ext = field_extent(x, y, D)
    for ax, name in zip(axes[0], panels):
        data = speed if name == "speed" else g[name][:]
        im = ax.imshow(data, origin="lower", extent=ext, cmap="viridis")
        if name == "speed":
            skip = max(1, len(x) // 16)
            X, Y = np.meshgrid(x / D, y / D)
            ax.quiver(X[::skip, ::skip], Y[::skip, ::skip], g["velocity_x"][::skip, ::skip],
                      g["velocity_y"][::skip, ::skip], color="w", scale=None, width=0.004)
        ax.add_patch(plt.Circle((0, 0), 0.5, color="k", fill=False))
        ax.set_title(name + (" (m/s, intruder frame)" if name == "speed" else ""))
        ax.set_xlabel("x / D")
        ax.set_ylabel("y / D")
        fig.colorbar(im, ax=ax, shrink=0.8)
    fig.tight_layout()
    path = os.path.join(out, f"{solver}_fields.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    status = 0
    for out in argv[1:]:
        found = False
        for solver in ("dem", "fem"):
            path = os.path.join(out, solver + ".h5")
            if not os.path.exists(path):
                continue
            found = True
            f = io.read(path)
            for fn in (plot_forces, plot_surface, plot_fields):
                p = fn(f, solver, out)
                if p:
                    print("wrote", p)
        if not found:
            print(f"{out}: no dem.h5 or fem.h5 here", file=sys.stderr)
            status = 2
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
