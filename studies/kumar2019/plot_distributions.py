#!/usr/bin/python3
"""Angular distributions of intruder contacts, as Kumar et al. 2019 Fig. 6.

  plot_distributions.py OUT.png RUN_DIR[:LABEL] ...

Each RUN_DIR holds a dem.h5. Panels: (a) F_N(theta) / D(first run), (b) F_T(theta) / (mu F_N(theta))
with F_T counter-clockwise positive on the intruder (-1: every contact slips against a
counter-clockwise spin), (c) N(theta) / N, (d) slip fraction. The first run is the
normalisation of (a) (give the Omega = 0 run first, as the paper does). Prints the table."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.plots import plt  # noqa: E402


def intruder_friction(f):
    """mu between grains and intruder: the case file with its --set overrides."""
    case = f.case()
    mu = case.get("grains", {}).get("friction", 0.5)
    mu_i = case.get("intruder", {}).get("friction")
    return float(mu_i if mu_i is not None else mu)


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    out, runs = argv[1], argv[2:]
    fig, axes = plt.subplots(1, 4, figsize=(18, 4))
    d0 = None
    for spec in runs:
        path, _, label = spec.partition(":")
        f = io.read(path, "dem")
        h = f["histogram"]
        c = np.degrees(0.5 * (h["theta_lo"][:] + h["theta_hi"][:]))
        fn, ft, n = h["normal_force"][:], h["tangential_force"][:], h["contact_count"][:]
        slip = h["slip_fraction"][:]
        mu = intruder_friction(f)
        drag = f["means"].attrs["drag"]
        omega_ratio = f["derived"].attrs["spin_ratio"]
        d0 = drag if d0 is None else d0
        label = label or f"Omega = {omega_ratio:g}"
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(fn > 0, ft / (mu * fn), np.nan)
        front = np.abs(c) < 90
        axes[0].plot(c, fn / d0, "o-", ms=3, label=label)
        axes[1].plot(c, ratio, "o-", ms=3, label=label)
        axes[2].plot(c, n / n.sum() if n.sum() > 0 else n, "o-", ms=3, label=label)
        axes[3].plot(c, slip, "o-", ms=3, label=label)
        w = n[front] / n[front].sum()
        print(f"{label}: mu {mu}, contacts per sample {n.sum():.3f}, front share "
              f"{n[front].sum() / max(n.sum(), 1e-300):.3f}, contact-weighted front mean of "
              f"F_T/(mu F_N) {np.nansum(w * ratio[front]):+.3f}, front slip fraction "
              f"{np.nansum(w * slip[front]):.3f}")
    titles = ["(a) F_N(theta) / D(first run)", "(b) F_T / (mu F_N), ccw positive",
              "(c) N(theta) / N", "(d) slip fraction"]
    for ax, t in zip(axes, titles):
        ax.set_title(t)
        ax.set_xlabel("theta from V (deg)")
        ax.set_xlim(-180, 180)
        ax.axvline(-90, color="0.8", lw=0.5)
        ax.axvline(90, color="0.8", lw=0.5)
    axes[1].axhline(0, color="k", lw=0.5)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
