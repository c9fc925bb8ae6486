#!/usr/bin/env python3
"""Share of the sheared medium in each range of the inertial number, from a continuum result.

    inertial_number_share.py FEM_H5 [I_LOW]

Reads the field grid of FEM_H5 (the shared schema, docs/schema.md; needs output.fields = true),
estimates the local effective friction mu_eff = |tau| / p from the stress, and inverts Jop's
mu(I) (mu_s 0.38, mu_2 0.64, I_0 0.279, the continuum defaults) where mu_eff > mu_s. Prints the
share of the grid points that are sheared (mu_eff >= 0.99 mu_s) and, of those, the share below
I_LOW (default 0.0191, the lower end of mu(I)'s well-posed range, docs/continuum-model.md).
The inversion is Jop's law: for a run with Barker-Gray's (the default since session 5) it holds
only above I_N = 0.0287, so use it on runs with continuum.regularisation = "chauchat_medale".
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "python"))
import numpy as np  # noqa: E402
from grainlift import io  # noqa: E402

MU_S, MU_2, I_0 = 0.38, 0.64, 0.279


def main():
    if len(sys.argv) not in (2, 3) or sys.argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        return 2
    i_low = float(sys.argv[2]) if len(sys.argv) == 3 else 0.0191
    g = io.read(sys.argv[1])["fields"]
    p = g["pressure"]
    sxx, syy, sxy = g["stress_xx"] + p, g["stress_yy"] + p, g["stress_xy"]
    inside = np.isfinite(p) & (p > 0)
    tau = np.sqrt((sxx ** 2 + syy ** 2 + 2 * sxy ** 2) / 2)[inside]
    mu = tau / p[inside]
    sheared = mu >= 0.99 * MU_S
    inertial = I_0 * (mu[sheared] - MU_S).clip(0) / np.maximum(MU_2 - mu[sheared], 1e-12)
    q = np.quantile(inertial, [0.5, 0.9, 0.99])
    print(f"{inside.sum()} grid points in the medium; sheared (mu_eff >= 0.99 mu_s): "
          f"{sheared.mean():.1%}")
    print(f"of the sheared: I < {i_low:g}: {np.mean(inertial < i_low):.1%}; "
          f"I median {q[0]:.3g}, 90% {q[1]:.3g}, 99% {q[2]:.3g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
