#!/usr/bin/python3
"""A nested level whose final stage stalls from the interpolated coarser level is reached
through the last two continuation stages from that same state, and gives the forces of the
whole continuation on its mesh (docs/continuum-model.md, "Nested iteration").

Case: Kumar's dilute bed (cases/kumar2019/reduced_phi035.toml: no-slip, V0 1 m/s, I up to
about 0.5) at refinement 2, through the real command (about 11 s for both runs).

Expected behaviour, each checked:
- the nested run converges, level 0 by the whole continuation (approach 2), level 1 by the
  final stage from the interpolated level 0 (approach 0), and level 2, whose final stage stalls
  there (Newton steps of 1/16-1/1024), through the last two stages (approach 1);
- it solves the same discrete problem as the whole continuation on the refinement-2 mesh
  (`continuum.nested = false`): drag and lift equal to 1e-6 of the drag, torque to 1e-6 of
  itself (the nonlinear tolerance is 1e-8 of the first residual);
- level 2 takes at most 50 nonlinear steps: fewer than the 50-step final stage that used to
  run before the whole continuation did (87 steps on this level at d8530c6).

Usage: test_fem_stalled_level.py GRAINLIFT_BINARY CASE_FILE
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402  (reads with h5py)

BINARY, CASE = sys.argv[1], sys.argv[2]


def run(out, nested):
    args = [BINARY, "run", CASE, "--solver", "fem", "--threads", "1", "--quiet",
            "--set", "continuum.refinement=2", "--set", "continuum.target_error=0",
            "--set", "continuum.mesh_error_estimate=false",
            "--set", f"continuum.nested={'true' if nested else 'false'}", "--out", out]
    subprocess.run(args, check=True, capture_output=True)
    f = io.read(out, "fem")
    levels = {k: [float(x) for x in v] for k, v in f.datasets("diagnostics").items()
              if k.startswith("level_")}
    return {"converged": int(f.diagnostics["converged"]), "drag": float(f.means["drag"]),
            "lift": float(f.means["lift"]), "torque": float(f.means["torque"]),
            "levels": levels}


class FemStalledLevel(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="grainlift_fem_stalled_")
        cls.nested = run(os.path.join(cls.tmp, "nested"), True)
        cls.whole = run(os.path.join(cls.tmp, "whole"), False)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_levels_reached_by_their_approaches(self):
        self.assertEqual(self.nested["converged"], 1)
        levels = self.nested["levels"]
        self.assertEqual(levels["level_refinement"], [0, 1, 2])
        self.assertEqual(levels["level_approach"], [2, 0, 1])
        self.assertLessEqual(levels["level_nonlinear_steps"][2], 50)

    def test_same_forces_as_the_whole_continuation(self):
        self.assertEqual(self.whole["converged"], 1)
        drag = self.whole["drag"]
        self.assertAlmostEqual(self.nested["drag"], drag, delta=1e-6 * abs(drag))
        self.assertAlmostEqual(self.nested["lift"], self.whole["lift"], delta=1e-6 * abs(drag))
        self.assertAlmostEqual(self.nested["torque"], self.whole["torque"],
                               delta=1e-6 * abs(self.whole["torque"]))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
