#!/usr/bin/python3
"""An interrupted continuum study keeps what it had (issue 15), through the real command on the
demo case (nested iteration to refinement 2: levels 0, 1, 2, a few seconds in all).

Expected behaviour, each checked:
- each converged level is written to fem.h5 (marked partial) before its mesh is refined: a run
  killed with SIGKILL while level 2 is being solved leaves a fem.h5 that h5py opens, marked
  partial in its /metadata and in summary.json, holding level 1's mesh and forces: its drag and
  lift equal the level-1 entries of the uninterrupted run's /diagnostics level_* series to
  1e-12 relative (the same converged state, post-processed by the same code);
- SIGTERM during level 1 lets that level finish and refines no further: exit 143, fem.h5 is
  level 1's result, marked partial, with the fields written (finite somewhere: the grid is
  sampled, not left empty);
- the uninterrupted run's fem.h5 is not partial.

Usage: test_fem_levels_kept.py GRAINLIFT_BINARY CASE_FILE
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402  (reads with h5py)

BINARY, CASE = sys.argv[1], sys.argv[2]
SETS = ["continuum.refinement=2", "continuum.nested=true"]


def command(out):
    args = [BINARY, "run", CASE, "--solver", "fem", "--threads", "1"]
    for s in SETS:
        args += ["--set", s]
    return args + ["--out", out]


def read(out):
    f = io.read(out, "fem")
    series = {k: v for k, v in f.datasets("diagnostics").items() if k.startswith("level_")}
    return {"partial": int(f.metadata["partial"]),
            "drag": float(f.means["drag"]), "lift": float(f.means["lift"]),
            "cells": int(f.diagnostics["cells"]), "levels": series,
            "vx": f.get("fields/velocity_x")}


class FemLevelsKept(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="grainlift_fem_levels_")
        cls.whole = os.path.join(cls.tmp, "whole")
        subprocess.run(command(cls.whole), check=True, capture_output=True)
        cls.reference = read(cls.whole)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def stop_at(self, out, line, sig):
        """Runs until a progress line contains @p line, sends @p sig; returns the exit code."""
        p = subprocess.Popen(command(out), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             text=True)
        seen = False
        for text in p.stderr:
            if line in text:
                p.send_signal(sig)
                seen = True
                break
        p.stderr.read()
        p.stderr.close()
        p.wait(timeout=120)
        self.assertTrue(seen, f"the run never printed '{line}'")
        return p.returncode

    def assert_level_one(self, got):
        ref = self.reference["levels"]
        self.assertEqual(got["partial"], 1)
        self.assertEqual(list(got["levels"]["level_refinement"]), [0, 1])
        self.assertAlmostEqual(got["drag"], ref["level_drag"][1],
                               delta=1e-12 * abs(ref["level_drag"][1]))
        self.assertAlmostEqual(got["lift"], ref["level_lift"][1],
                               delta=1e-12 * abs(ref["level_drag"][1]))
        self.assertLess(got["cells"], self.reference["cells"])

    def test_uninterrupted_run_is_complete(self):
        self.assertEqual(self.reference["partial"], 0)
        self.assertEqual(list(self.reference["levels"]["level_refinement"]), [0, 1, 2])

    def test_sigkill_during_the_last_level_leaves_the_level_below(self):
        out = os.path.join(self.tmp, "killed")
        self.assertEqual(self.stop_at(out, "nested level 2", signal.SIGKILL), -signal.SIGKILL)
        self.assert_level_one(read(out))
        with open(os.path.join(out, "summary.json")) as s:
            self.assertTrue(json.load(s)["fem"]["partial"])

    def test_sigterm_finishes_the_level_and_refines_no_further(self):
        out = os.path.join(self.tmp, "terminated")
        self.assertEqual(self.stop_at(out, "nested level 1", signal.SIGTERM),
                         128 + signal.SIGTERM)
        got = read(out)
        self.assert_level_one(got)
        self.assertIsNotNone(got["vx"])
        self.assertTrue(np.isfinite(got["vx"]).any())


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
