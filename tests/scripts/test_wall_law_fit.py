#!/usr/bin/python3
"""The wall-friction fit of python/grainlift/wall.py on synthetic surface stresses whose wall
friction is known (studies/wall_law/README.md).

Physics: a Coulomb wall of friction mu_w that slides everywhere carries
sigma_t(theta) = -mu_w sigma_n(theta) sign(slip(theta)), slip = omega R - V sin(theta), on a
front-loaded sigma_n = P0 (1 + 3 cos theta) (zero behind |theta| > 109 deg), the shape of the
DEM's intruder (peak 4 P0). Each angle gets Gaussian noise of a stated standard error, 0.1 P0
on sigma_n and 0.03 P0 on sigma_t (about the DEM demo's per-angle block errors over P0).
Expected, with the default threshold (sigma_n >= 0.5 of its peak):
- wall_friction recovers mu_w = 0.22 within 3 of its stated errors (the correlated bound,
  error) in every one of 200 noisy draws, and the draws' spread of mu lies between its two
  error bounds (independent <= spread <= correlated), so the stated errors are honest;
- it does so for a spin that makes the slip change sign on the loaded front (Omega = 0.5),
  where a signed average would cancel, and without noise it is exact (1e-12);
- a wall that slides only where the slip is fast (|sigma_t| = mu_w sigma_n |x| / (|x| + x0))
  is fitted by saturating_fit back to its mu_a = 0, mu_b = mu_w and x0 within 5 errors.
Under 1 s; run by CTest (tests/scripts/CMakeLists.txt)."""
import os
import sys
import unittest

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "python"))
from grainlift import wall  # noqa: E402

P0, MU_W, M = 2000.0, 0.22, 64
THETA = (np.arange(M) + 0.5) * 2 * np.pi / M
SN_ERR, ST_ERR = 0.1 * P0, 0.03 * P0


def synthetic(spin_ratio, rng=None, mu=MU_W):
    """sigma_n, sigma_t (Pa) of a sliding Coulomb wall, with noise when rng is given."""
    sn = P0 * np.maximum(0.0, 1 + 3 * np.cos(THETA))
    st = -mu * sn * np.sign(wall.slip_speed(THETA, spin_ratio))
    if rng is not None:
        sn = sn + rng.normal(0, SN_ERR, M)
        st = st + rng.normal(0, ST_ERR, M)
    return sn, st


class WallFrictionFit(unittest.TestCase):
    def test_exact_without_noise(self):
        for om in (0.0, 0.5, 2.0, 8.0):
            sn, st = synthetic(om)
            w = wall.wall_friction(THETA, sn, st)
            self.assertAlmostEqual(w.mu, MU_W, delta=1e-12)
            self.assertAlmostEqual(wall.directed_friction(THETA, sn, st, om), MU_W,
                                   delta=1e-12)

    def test_recovers_mu_within_its_error(self):
        rng = np.random.default_rng(1)
        errs_n, errs_t = np.full(M, SN_ERR), np.full(M, ST_ERR)
        for om in (0.5, 2.0):
            mus, fits = [], []
            for _ in range(200):
                sn, st = synthetic(om, rng)
                w = wall.wall_friction(THETA, sn, st, errs_n, errs_t)
                self.assertLess(abs(w.mu - MU_W), 3 * w.error)
                self.assertLess(w.error, 0.05)  # the test has teeth: not a vacuous error
                mus.append(w.mu)
                fits.append(w)
            spread = float(np.std(mus, ddof=1))
            self.assertLess(abs(np.mean(mus) - MU_W), 3 * spread / np.sqrt(len(mus)) + 2e-3)
            self.assertLessEqual(0.8 * np.mean([f.error_independent for f in fits]), spread)
            self.assertLessEqual(spread, np.mean([f.error for f in fits]))

    def test_slip_law_fit(self):
        rng = np.random.default_rng(2)
        x0 = 1.5
        xs, ys = [], []
        for om in (0.5, 1.0, 2.0, 4.0, 8.0):
            x = np.abs(wall.slip_speed(THETA, om))
            xs.append(x)
            ys.append(MU_W * x / (x + x0) + rng.normal(0, 0.01, M))
        x, y = np.concatenate(xs), np.concatenate(ys)
        a, b, c, ae, be, _ = wall.saturating_fit(x, y, np.full(len(x), 0.01))
        self.assertLess(abs(a), 5 * ae)
        self.assertLess(abs(b - MU_W), 5 * be)
        self.assertLess(abs(c - x0), 0.3 * x0)


if __name__ == "__main__":
    unittest.main()
