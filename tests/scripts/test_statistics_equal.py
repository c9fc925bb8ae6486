#!/usr/bin/python3
"""The C++ statistics module (shared/include/grainlift/shared/statistics/statistics.h) and its
Python mirror (python/grainlift/stats.py) give the same numbers on the same input (issue 34).

Expected, each checked to 1e-12 relative (both run the same sums in the same order; the margin
is for a libm that rounds pow or log differently), NaN where the other has NaN, equal counts:
- block means of a seeded AR(1) series (phi = 0.95, 10,000 samples) in 10 and in 97 blocks,
  of a series whose length is not a multiple of B (1,003 samples in 10 blocks: 3 dropped),
  of a series in 1 block (no error: NaN) and of 2 samples in 5 blocks (2 blocks, no lag-1);
- pooled means of 5 beds with errors, of 3 beds without, of 1 bed;
- Richardson of f = 1.5 + 0.7 h^1.5 (accepted: limit 1.5, order 1.5, checked against the
  known values too), of a non-monotone sequence and of an order-4 one (both refused).

Usage: test_statistics_equal.py STATISTICS_JSON_BINARY
"""
import json
import math
import os
import random
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from grainlift import stats  # noqa: E402

BINARY = sys.argv[1] if len(sys.argv) > 1 else None


def ar1(n, phi, seed):
    rng = random.Random(seed)
    v = rng.gauss(0.0, 1.0) / math.sqrt(1 - phi * phi)
    x = []
    for _ in range(n):
        v = phi * v + rng.gauss(0.0, 1.0)
        x.append(5.0 + v)
    return x


def line(*parts):
    return " ".join(repr(float(p)) if isinstance(p, float) else str(p) for p in parts)


def run_cpp(lines):
    out = subprocess.run([BINARY], input="\n".join(lines) + "\n", capture_output=True,
                         text=True, check=True).stdout
    return [json.loads(s) for s in out.splitlines()]


class StatisticsEqual(unittest.TestCase):
    def assertSame(self, cpp, py, what):
        for key, want in py._asdict().items():
            got = cpp[key]
            msg = f"{what}: {key} C++ {got} Python {want}"
            if isinstance(want, bool) or isinstance(want, int):
                self.assertEqual(got, want, msg)
            elif math.isnan(want):
                self.assertIsNone(got, msg)
            else:
                self.assertIsNotNone(got, msg)
                self.assertLessEqual(abs(got - want), 1e-12 * max(abs(want), 1e-300), msg)

    def test_block_means(self):
        cases = [("AR(1), 10 blocks", ar1(10000, 0.95, 1), 10),
                 ("AR(1), 97 blocks", ar1(10000, 0.95, 2), 97),
                 ("1003 samples, 10 blocks", ar1(1003, 0.5, 3), 10),
                 ("1 block", ar1(50, 0.5, 4), 1),
                 ("2 samples, 5 blocks", [1.25, 3.5], 5)]
        cpp = run_cpp([line("block_mean", b, len(x), *x) for _, x, b in cases])
        for (what, x, b), c in zip(cases, cpp):
            self.assertSame(c, stats.block_mean(x, b), what)
        self.assertEqual(cpp[2]["samples"], 1000)
        self.assertIsNone(cpp[3]["stderr"])
        self.assertEqual(cpp[4]["blocks"], 2)

    def test_pooled_means(self):
        rng = random.Random(9)
        m5 = [10 + rng.gauss(0, 2) for _ in range(5)]
        e5 = [abs(rng.gauss(1, 0.2)) for _ in range(5)]
        cases = [("5 beds", m5, e5), ("3 beds without errors", m5[:3], None),
                 ("1 bed", m5[:1], e5[:1])]
        cpp = run_cpp([line("pooled_mean", len(m), 0 if e is None else 1, *m, *(e or []))
                       for _, m, e in cases])
        for (what, m, e), c in zip(cases, cpp):
            self.assertSame(c, stats.pooled_mean(m, e), what)
        self.assertEqual(cpp[2]["error"], e5[0])

    def test_richardson(self):
        h = [0.4, 0.2, 0.1]
        cases = [("power law", [1.5 + 0.7 * a ** 1.5 for a in h]),
                 ("not monotone", [1.0, 2.0, 1.5]),
                 ("order 4", [1 + a ** 4 for a in h])]
        cpp = run_cpp([line("richardson", *h, *f) for _, f in cases])
        for (what, f), c in zip(cases, cpp):
            self.assertSame(c, stats.richardson(h, f), what)
        self.assertTrue(cpp[0]["accepted"])
        self.assertAlmostEqual(cpp[0]["limit"], 1.5, delta=1e-12)
        self.assertAlmostEqual(cpp[0]["order"], 1.5, delta=1e-10)
        self.assertFalse(cpp[1]["accepted"] or cpp[2]["accepted"])


if __name__ == "__main__":
    if BINARY is None:
        sys.exit("usage: test_statistics_equal.py STATISTICS_JSON_BINARY")
    unittest.main(argv=sys.argv[:1] + sys.argv[2:])
