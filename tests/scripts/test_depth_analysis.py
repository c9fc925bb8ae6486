"""The depth study's analysis helpers (python/grainlift/beds.py, studies/depth/bed_balance.py)
on inputs whose answer is known in closed form. Run by CTest (tests/scripts/CMakeLists.txt)."""
import math
import os
import sys
import unittest

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path[:0] = [os.path.join(ROOT, "python"), os.path.join(ROOT, "studies", "depth")]
from bed_balance import bed_balance, overburden  # noqa: E402
from grainlift.beds import line_fit, pool, power_law  # noqa: E402


def bed_run(scale_syy=1.0, lift=0.0):
    """A 12 D x 4 D field grid over a hydrostatic column: phi = 0.8 up to 1.5 D above the centre,
    empty above; sigma_yy = lid + rho_s g (weight above) + lift / W below the centre."""
    D, rho_s, g, lid, W = 0.015, 2.5, 9.81, 0.6, 12 * 0.015
    h = D / 20
    y = -2 * D + h * (np.arange(80) + 0.5)
    x = -6 * D + h * (np.arange(240) + 0.5)
    phi_y = np.where(y < 1.5 * D, 0.8, 0.0)
    above = np.array([rho_s * g * 0.8 * max(0.0, 1.5 * D - yy) for yy in y])
    syy_y = lid + above + np.where(y < 0, lift / W, 0.0)
    return {
        "D": D, "fx": x, "fy": y, "rho": 2.05, "rho_s": rho_s, "g_grains": g, "width": W,
        "lift": lift,
        "lid_mean": lid, "top": 2 * D,
        "fphi": np.repeat(phi_y[:, None], len(x), axis=1),
        "fsyy": scale_syy * np.repeat(syy_y[:, None], len(x), axis=1),
    }


class PoolBeds(unittest.TestCase):
    def member(self, drag, lift, err):
        return {"drag": drag, "lift": lift, "drag_err": err, "lift_err": err, "wall_s": 1.0,
                "far_field": 1.0, "lid_mean": 1.0, "rgD": 1.0, "h": 1.0,
                "sn": np.array([drag, lift]), "sn_err": np.array([err, err])}

    def test_error_is_the_larger_of_between_and_within_beds(self):
        # bed means 1 and 3 with block errors 0.1: between-bed standard error
        # std(ddof=1) / sqrt(2) = 1.0 exactly, within-bed sqrt(0.01 + 0.01) / 2 = 0.0707
        r = pool([self.member(1.0, 1.0, 0.1), self.member(3.0, 3.0, 0.1)])
        self.assertAlmostEqual(r["lift"], 2.0, places=12)
        self.assertAlmostEqual(r["lift_err_between"], 1.0, places=12)
        self.assertAlmostEqual(r["lift_err_within"], math.sqrt(0.02) / 2, places=12)
        self.assertAlmostEqual(r["lift_err"], 1.0, places=12)
        self.assertAlmostEqual(r["Cd"], 2.0, places=12)  # drag / (rho g D h) with rho g D = h = 1
        np.testing.assert_allclose(r["sn_err"], [1.0, 1.0], rtol=1e-12)

    def test_agreeing_beds_keep_their_block_error(self):
        # identical bed means: no between-bed spread, the error is the within-bed one
        r = pool([self.member(2.0, 2.0, 0.3)] * 3)
        self.assertAlmostEqual(r["lift_err"], math.sqrt(3 * 0.09) / 3, places=12)

    def test_one_bed_is_itself(self):
        r = pool([self.member(2.0, 5.0, 0.4)])
        self.assertEqual(r["beds"], 1)
        self.assertEqual(r["lift_err"], 0.4)
        self.assertTrue(math.isnan(r["lift_err_between"]))


class Fits(unittest.TestCase):
    def test_line_recovers_intercept_and_slope(self):
        # y = 0.005 + 0.003 x exactly: a and b to 1e-12, chi2 / dof 0
        x = [0.0, 2.45, 4.9, 9.81]
        a, ea, b, eb, chi = line_fit(x, [0.005 + 0.003 * v for v in x], [0.001] * 4)
        self.assertAlmostEqual(a, 0.005, places=12)
        self.assertAlmostEqual(b, 0.003, places=12)
        self.assertLess(chi, 1e-12)
        self.assertGreater(ea, 0)
        self.assertGreater(eb, 0)

    def test_power_law_recovers_exponent(self):
        # y = 2 x^0.5 exactly: the fitted power is 0.5 to 1e-10
        x = [2.45, 4.9, 9.81]
        p, ep = power_law(x, [2 * v ** 0.5 for v in x], [0.05] * 3)
        self.assertAlmostEqual(p, 0.5, places=10)
        self.assertGreater(ep, 0)


class BedBalance(unittest.TestCase):
    def test_hydrostatic_column_balances(self):
        # a column in equilibrium: the whole-width stress is the lid plus the weight above
        # (plus the intruder's lift below its centre) to quadrature error, well under 0.5%,
        # and its gradient below the intruder is the bed's weight rho_s phi g within 1%
        bb = bed_balance(bed_run(lift=0.02))
        self.assertLess(bb["max_dev"], 0.005)
        self.assertAlmostEqual(bb["slope_over_bed"], 1.0, delta=0.01)

    def test_a_stress_off_by_ten_percent_is_seen(self):
        # the check can fail: a stress field 10% too large reads 10% off the balance
        bb = bed_balance(bed_run(scale_syy=1.1))
        self.assertAlmostEqual(bb["max_dev"], 0.1, delta=0.005)

    def test_a_missing_lift_is_seen_below_the_intruder(self):
        # the balance below the centre includes the lift: a lift the stress does not carry
        # (0.05 N/m over W = 0.18 m, against a load of about 1 Pa) shows as a deviation above 10%
        r = bed_run(lift=0.0)
        r["lift"] = 0.05
        self.assertGreater(bed_balance(r)["max_dev"], 0.1)

    def test_overburden_is_lid_plus_weight_above_the_centre(self):
        # 1.5 D of bed at phi 0.8 above the centre: load = lid + rho_s g 0.8 (1.5 D) within
        # quadrature error (0.1%), and the real bed above the centre is 1.5 D
        r = bed_run()
        ob = overburden(r)
        expected = 0.6 + 2.5 * 9.81 * 0.8 * 1.5 * 0.015
        self.assertAlmostEqual(ob["load"] / expected, 1.0, delta=1e-3)
        self.assertAlmostEqual(ob["surface"] / 0.015, 1.5, delta=1e-3)

    def test_a_grid_short_of_the_box_is_refused(self):
        # the weight above a line and the force across it need every grain: no answer from a
        # grid that stops below the box top or spans less than the periodic width
        r = bed_run()
        r["top"] = 3 * r["D"]
        self.assertIsNone(bed_balance(r))
        self.assertIsNone(overburden(r))
        r = bed_run()
        r["width"] = 18 * r["D"]
        self.assertIsNone(bed_balance(r))
        self.assertIsNone(overburden(r))


if __name__ == "__main__":
    unittest.main()
