#!/usr/bin/python3
"""A full disk under a real run (issue 37), through the command on the demo case; the fault is
injected at the write by the hook GRAINLIFT_TEST_WRITE_FAULT=ENOSPC:<--out folder> (the path a
real ENOSPC takes), so that the system's temporary folder still works.

Expected behaviour, each checked:
- the continuum (refinement 1): its intermediate result is a warning and the solve goes on
  (the VTU, written by the engine, does not see the hook; on a real full disk it is a warning
  too: docs/reliability.md); the result that cannot be written in --out ends the run with
  exit 1 (never a signal: the former crash in HDF5's exit handler was exit 139) and one message
  naming
  OUT/fem.h5, "No space left on device" and where the result was written instead; that file
  opens with h5py through grainlift.io and holds the forces; the fem.h5 already in --out is
  byte for byte as it was;
- the DEM (0.6 d of travel, a checkpoint every 500 steps): every checkpoint that cannot be
  written is a warning and the run goes on to its end; its result is rescued the same way.

Usage: test_write_faults_run.py GRAINLIFT_BINARY CASE_FILE
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402

BINARY, CASE = sys.argv[1], sys.argv[2]


def run_on_full_disk(out, solver, sets, rescue_root):
    env = dict(os.environ, GRAINLIFT_TEST_WRITE_FAULT="ENOSPC:" + out, TMPDIR=rescue_root)
    args = [BINARY, "run", CASE, "--solver", solver, "--threads", "1", "--out", out]
    for s in sets:
        args += ["--set", s]
    return subprocess.run(args, capture_output=True, text=True, env=env, timeout=600)


class FullDisk(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="grainlift_faults_")
        self.out = os.path.join(self.tmp, "out")
        self.rescue_root = os.path.join(self.tmp, "rescue")
        os.makedirs(self.out)
        os.makedirs(self.rescue_root)

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def rescued(self, stderr, name):
        m = re.search(r"written instead to (\S+/" + name + r")", stderr)
        self.assertIsNotNone(m, stderr)
        self.assertTrue(m.group(1).startswith(self.rescue_root), m.group(1))
        return m.group(1)

    def test_continuum_result_rescued_and_previous_file_kept(self):
        old = os.path.join(self.out, "fem.h5")
        with open(old, "wb") as f:
            f.write(b"the previous result")
        p = run_on_full_disk(self.out, "fem", ["continuum.refinement=1"], self.rescue_root)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn(old + ": cannot write the file: No space left on device", p.stderr)
        self.assertIn("warning: intermediate result not written, the run goes on", p.stderr)
        res = io.read(self.rescued(p.stderr, "fem.h5"))
        self.assertGreater(res.attrs("means")["drag"], 0.0)
        with open(old, "rb") as f:
            self.assertEqual(f.read(), b"the previous result")

    def test_dem_checkpoints_fail_the_run_goes_on(self):
        p = run_on_full_disk(self.out, "dem", ["dem.travel=0.6", "dem.steady_travel=0.2",
                                               "dem.checkpoint_steps=500"], self.rescue_root)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("warning: checkpoint not written, the run goes on", p.stderr)
        res = io.read(self.rescued(p.stderr, "dem.h5"))
        self.assertGreater(len(res["forces/fx"]), 0)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
