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
  is fitted by saturating_fit back to its mu_a = 0, mu_b = mu_w and x0 within 5 errors;
- the slip law against a measured slip speed v (m/s), mu_w(v) = mu_a + (mu_b - mu_a) |v| /
  (|v| + v0) with mu_a = 0.03, mu_b = 0.33, v0 = 0.08 m/s (the study's demo values) and noise
  0.02 per point: slip_law recovers all three within 4 of its stated errors in each of 100
  draws, the draws' spread of each parameter is within a factor 1.5 of its mean stated error
  (the errors are honest, v0's included), and without noise it is exact to the grid of x0;
  the `[wall]` table it writes reads back as TOML with the same numbers.
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



class SlipLawFit(unittest.TestCase):
    LAW = dict(mu_a=0.03, mu_b=0.33, v0=0.08)
    NOISE = 0.02

    def draw(self, rng):
        v = rng.uniform(0.0, 1.5, 150) * rng.choice([-1, 1], 150)  # signed slip, m/s
        law = wall.SlipLaw(self.LAW["mu_a"], self.LAW["mu_b"], self.LAW["v0"], 0, 0, 0, 0, 0)
        y = wall.slip_law_value(law, v)
        if rng is not None:
            y = y + rng.normal(0, self.NOISE, len(v))
        return v, y, np.full(len(v), self.NOISE)

    def test_exact_without_noise(self):
        v, _, e = self.draw(np.random.default_rng(3))
        law = wall.SlipLaw(self.LAW["mu_a"], self.LAW["mu_b"], self.LAW["v0"], 0, 0, 0, 0, 0)
        fit = wall.slip_law(v, wall.slip_law_value(law, v), e)
        self.assertAlmostEqual(fit.mu_a, 0.03, delta=2e-3)
        self.assertAlmostEqual(fit.mu_b, 0.33, delta=2e-3)
        self.assertLess(abs(fit.v0 / 0.08 - 1), 0.02)  # the grid of x0: 1.5% per step

    def test_recovers_parameters_within_their_errors(self):
        rng = np.random.default_rng(4)
        fits = []
        for _ in range(100):
            v, y, e = self.draw(rng)
            f = wall.slip_law(v, y, e)
            fits.append(f)
            for name, err in (("mu_a", f.mu_a_err), ("mu_b", f.mu_b_err), ("v0", f.v0_err)):
                self.assertLess(abs(getattr(f, name) - self.LAW[name]), 4 * err, name)
            self.assertLess(f.v0_err, 0.5 * self.LAW["v0"])  # not a vacuous error
            self.assertEqual(f.points, 150)
        for name in ("mu_a", "mu_b", "v0"):
            spread = float(np.std([getattr(f, name) for f in fits], ddof=1))
            stated = float(np.mean([getattr(f, name + "_err") for f in fits]))
            self.assertLess(spread, 1.5 * stated, name)
            self.assertGreater(spread, stated / 1.5, name)

    def test_wall_table_reads_back(self):
        try:
            import tomllib
        except ImportError:  # Python < 3.11
            self.skipTest("no tomllib")
        v, y, e = self.draw(np.random.default_rng(5))
        f = wall.slip_law(v, y, e)
        t = tomllib.loads(wall.wall_table(f, 0.2, 0.03, "synthetic"))["wall"]
        self.assertEqual(t["mu_b"], f.mu_b)
        self.assertEqual(t["v0_err"], f.v0_err)
        self.assertEqual(t["friction"], 0.2)
        self.assertEqual(t["points"], 150)


class FitFromRuns(unittest.TestCase):
    """wall.fit on DEM-like results (the fields grainlift.io gives: surface stresses with
    their errors, a 32-bin /histogram with slip_velocity), four spin ratios, a wall that obeys
    mu_w(v) = 0.03 + 0.30 |v| / (|v| + 0.08 m/s) at the bins' slip, noise 0.02 P0 on sigma_t:
    the slip law comes back within 4 of its errors, the pooled friction is the sigma_n-weighted
    mean ratio of the runs within 3 errors; a result without the slip histogram is skipped,
    none raises ValueError; with_wall_table replaces an old [wall] and its comment, and keeps
    the comment of a table after it."""

    @staticmethod
    def result(spin_ratio, rng):
        V = 0.5
        edges = np.linspace(-np.pi, np.pi, 33)
        centre = 0.5 * (edges[:-1] + edges[1:])
        slip = V * (spin_ratio - np.sin(centre))  # m/s at the bins
        th = np.angle(np.exp(1j * THETA))
        v = np.abs(np.interp(th, centre, slip, period=2 * np.pi))
        mu = 0.03 + 0.30 * v / (v + 0.08)
        sn = P0 * np.maximum(0.0, 1 + 3 * np.cos(THETA))
        st = -mu * sn + rng.normal(0, 0.02 * P0, M)
        return {"surface/theta": THETA, "surface/sigma_n": sn, "surface/sigma_t": st,
                "surface/sigma_n_stderr": np.full(M, 1e-9 * P0),
                "surface/sigma_t_stderr": np.full(M, 0.02 * P0),
                "histogram/slip_velocity": slip,
                "histogram": {"theta_lo": edges[:-1], "theta_hi": edges[1:],
                              "slip_velocity": slip}}

    def test_recovers_the_law_of_several_runs(self):
        rng = np.random.default_rng(7)
        runs = [self.result(om, rng) for om in (0.0, 1.0, 2.0, 4.0)]
        no_slip = {k: v for k, v in runs[0].items() if k != "histogram/slip_velocity"}
        f = wall.fit(runs + [no_slip])
        self.assertEqual(f.runs, 4)
        law = f.law
        for got, err, want in ((law.mu_a, law.mu_a_err, 0.03), (law.mu_b, law.mu_b_err, 0.33),
                               (law.v0, law.v0_err, 0.08)):
            self.assertLess(abs(got - want), 4 * err, (got, err, want))
        ws = [wall.wall_friction(r["surface/theta"], r["surface/sigma_n"],
                                 r["surface/sigma_t"]).mu for r in runs]
        self.assertLess(abs(f.friction - np.mean(ws)), 3 * f.friction_err)
        self.assertEqual(wall.table_problem(f), "")
        with self.assertRaises(ValueError):
            wall.fit([no_slip])

    def test_with_wall_table_replaces_the_old_one(self):
        text = "[mu_i]\nmu_s = 0.3\n\n# old source\n[wall]\nfriction = 9\n"
        out = wall.with_wall_table(text, "\n# new\n[wall]\nfriction = 0.2\n")
        self.assertNotIn("friction = 9", out)
        self.assertNotIn("old source", out)
        self.assertEqual(out.count("[wall]"), 1)
        self.assertIn("mu_s = 0.3", out)
        # a table after [wall] keeps its own comment ([nonlocal] of calibrate --nonlocal)
        text = ("[mu_i]\nmu_s = 0.3\n\n# old\n[wall]\nfriction = 9\n\n# the A\n[nonlocal]\n"
                "amplitude = 0.2\n")
        out = wall.with_wall_table(text, "\n# new\n[wall]\nfriction = 0.2\n")
        self.assertIn("# the A\n[nonlocal]\namplitude = 0.2", out)
        self.assertNotIn("friction = 9", out)


if __name__ == "__main__":
    unittest.main()
