#!/usr/bin/env python3
"""Plot the creeping-layer profile of `grainlift calibrate --nonlocal` (its .creep.csv): the
grains' velocity against height with its error, the nonlocal fluidity fitted (v_fit, at the
pooled profile's A) and the local mu(I) with the same floor and factor (v_local), on a log scale
so that the creep below the yield height shows; beside it mu = tau / p and the velocity
fluctuation delta v, and (files that have it) the grains' hexatic order |psi6|, near 1 where
the layer has crystallised.

    plot_creep.py PROFILE.creep.csv [OUT.png]     (default: beside the file, .png)
"""
import os
import sys
import textwrap

sys.path[:0] = [os.path.dirname(os.path.realpath(__file__)),  # installed: grainlift/ beside
                os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python")]
import numpy as np  # noqa: E402
from grainlift.plots import plt, save  # noqa: E402


def main(path, out):
    with open(path) as fh:
        title = fh.readline().lstrip("# ").strip()
    d = np.genfromtxt(path, delimiter=",", names=True, skip_header=1)
    y = d["y_m"]
    order = "psi6" in d.dtype.names
    fig, ax = plt.subplots(1, 3 if order else 2, figsize=(13 if order else 10, 4.5), sharey=True)
    v, e = d["vx_m_per_s"], d["vx_stderr"]
    top = max(v.max(), 1e-12)
    ax[0].errorbar(np.maximum(v, 1e-6 * top), y, xerr=e, fmt="o", ms=3, label="DEM, pooled beds")
    ax[0].plot(d["v_fit"], y, "-", label="nonlocal fluidity, fitted A")
    ax[0].plot(d["v_local"], y, "--", label="local mu(I), same floor and factor")
    ax[0].set_xscale("log")
    ax[0].set_xlim(1e-5 * top, 2 * top)
    ax[0].set_xlabel("v_x (m/s)")
    ax[0].set_ylabel("height above the bottom wall (m)")
    ax[0].legend(fontsize=8)
    ax[1].plot(d["mu"], y, "-", label="mu = tau / p")
    mu_s = float(title.split("mu_s = ")[1].split(";")[0]) if "mu_s = " in title else None
    if mu_s:
        ax[1].axvline(mu_s, color="0.5", ls=":", label=f"mu_s {mu_s:.3f}")
    ax[1].set_xlabel("mu")
    twin = ax[1].twiny()
    twin.errorbar(d["dv_m_per_s"], y, xerr=d["dv_stderr"], fmt="s", ms=2, color="C3",
                  label="delta v")
    twin.set_xlabel("delta v (m/s)", color="C3")
    ax[1].legend(fontsize=8, loc="lower right")
    if order:
        ax[2].plot(d["psi6"], y, "o-", ms=3, color="C2")
        ax[2].set_xlim(0, 1)
        ax[2].set_xlabel("grains' hexatic order |psi6| (1: triangular crystal)")
    fig.suptitle("\n".join(textwrap.wrap(title, 120)), fontsize=8)
    fig.tight_layout()
    save(fig, out)
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        sys.exit(0 if len(sys.argv) > 1 else 2)
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else sys.argv[1].rsplit(".", 1)[0] + ".png")
