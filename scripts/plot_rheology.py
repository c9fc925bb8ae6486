#!/usr/bin/env python3
"""Plot a calibrated rheology file (`grainlift calibrate`): mu(I) and Phi(I), points with their
standard errors and the fitted laws, with da Cruz et al. (PRE 72, 021309, 2005) for 2D
frictional disks (mu ~ 0.26 + 1.1 I, Phi ~ 0.81 - 0.3 I) for reference.

    plot_rheology.py RHEOLOGY.toml [OUT.png]     (default: beside the file, .png)
"""
import os
import sys

sys.path[:0] = [os.path.dirname(os.path.realpath(__file__)),  # installed: grainlift/ beside
                os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python")]
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.plots import plt, save  # noqa: E402


def main(path, out):
    law = io.calibration(path)
    p = io.calibration_points(law)
    I, mu, mu_se, phi, phi_se = (p[k] for k in ("I", "mu", "mu_stderr", "phi", "phi_stderr"))
    m, ph = law["mu_i"], law["phi_i"]
    grid = np.logspace(np.log10(min(I.min(), 1e-3)), np.log10(max(I.max(), 0.5)), 200)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].errorbar(I, mu, yerr=mu_se, fmt="o", label="DEM shear cell")
    ax[0].plot(grid, m["mu_s"] + (m["mu_2"] - m["mu_s"]) / (m["I0"] / grid + 1), "-",
               label=f"fit: mu_s {m['mu_s']:.3f}, mu_2 {m['mu_2']:.3f}, I0 {m['I0']:.3f}")
    ax[0].plot(grid, 0.26 + 1.1 * grid, ":", color="0.5", label="da Cruz et al. 2005")
    ax[0].set_xscale("log")
    ax[0].set_xlabel("I")
    ax[0].set_ylabel("mu = tau / P")
    ax[0].legend(fontsize=8)
    ax[1].errorbar(I, phi, yerr=phi_se, fmt="o", label="DEM shear cell")
    ax[1].plot(grid, ph["phi_max"] - ph["a"] * grid, "-",
               label=f"fit: {ph['phi_max']:.3f} - {ph['a']:.3f} I")
    ax[1].plot(grid, 0.81 - 0.3 * grid, ":", color="0.5", label="da Cruz et al. 2005")
    ax[1].set_xscale("log")
    ax[1].set_xlabel("I")
    ax[1].set_ylabel("Phi")
    ax[1].legend(fontsize=8)
    src = law.get("source", {})
    fig.suptitle(f"{src.get('grains', '')}, P {src.get('pressure', '')}", fontsize=9)
    fig.tight_layout()
    save(fig, out)
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        sys.exit(0 if len(sys.argv) > 1 else 2)
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else sys.argv[1].rsplit(".", 1)[0] + ".png")
