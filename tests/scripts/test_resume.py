#!/usr/bin/python3
"""No long run is lost (issue 15), through the real command on a small dense Kumar bed.

Expected behaviour, each checked exactly:
- a run killed with SIGKILL after a checkpoint, then `run --resume DIR`, writes the forces,
  contacts, surface stresses and histograms of the uninterrupted run bit for bit (same
  thread count; the checkpoint holds the whole state between two steps);
- SIGTERM stops the run at the next step boundary: exit 143, a dem.h5 that h5py opens, marked
  partial in its /metadata and in summary.json, shorter than the whole run, and a message that
  names the --resume command; resuming it gives the uninterrupted bits too;
- a corrupt (one flipped byte), truncated or foreign (another case) checkpoint is refused with
  exit 2 and a message naming the file, and leaves the folder's results as they were.

Usage: test_resume.py GRAINLIFT_BINARY CASE_FILE
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402  (reads with h5py)

BINARY, CASE = sys.argv[1], sys.argv[2]
# the reduced dense Kumar bed (contacts everywhere: springs and accelerations matter), V0
# 0.25 m/s, 3 d of travel (120,000 steps, a few seconds), a checkpoint every 20,000 steps
SETS = ["intruder.velocity=[0.25,0.0]", "intruder.omega=5.0", "dem.travel=3",
        "dem.steady_travel=1", "dem.checkpoint_steps=20000"]


def command(out, *extra, sets=SETS):
    args = [BINARY, "run", CASE, "--solver", "dem", "--quiet", "--threads", "1"]
    for s in sets:
        args += ["--set", s]
    return args + ["--out", out] + list(extra)


def datasets(path):
    """Every dataset of a result file except the run's own diagnostics, by name."""
    datasets, _ = io.read(path).items()
    return {name: v for name, v in datasets
            if not name.startswith(("diagnostics", "metadata", "case"))}


class Resume(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="grainlift_resume_")
        cls.sets = SETS + [f'dem.packing_cache="{cls.tmp}/cache"']
        cls.whole = os.path.join(cls.tmp, "whole")
        subprocess.run(cls.cmd(cls.whole), check=True, capture_output=True)
        cls.reference = datasets(os.path.join(cls.whole, "dem.h5"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def cmd(cls, out, *extra, sets=None):
        return command(out, *extra, sets=sets or cls.sets)

    def resume_cmd(self, out):
        args = self.cmd(out)
        i = args.index("--out")
        return args[:i] + ["--resume", out]

    def start_and_stop(self, out, sig):
        """Starts a run, waits for its first checkpoint, sends @p sig; returns the exit code."""
        p = subprocess.Popen(self.cmd(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
        ckpt = os.path.join(out, "dem.checkpoint")
        deadline = time.time() + 60
        while not os.path.exists(ckpt) and p.poll() is None and time.time() < deadline:
            time.sleep(0.005)
        self.assertIsNone(p.poll(), "the run ended before its first checkpoint")
        p.send_signal(sig)
        _, err = p.communicate(timeout=60)
        self.stderr = err
        return p.returncode

    def assert_bits_of_whole(self, out):
        got = datasets(os.path.join(out, "dem.h5"))
        self.assertEqual(sorted(got), sorted(self.reference))
        for name in self.reference:
            self.assertTrue(np.array_equal(got[name], self.reference[name], equal_nan=True),
                            f"{name} differs from the uninterrupted run")

    def test_sigkill_then_resume_gives_the_bits_of_the_uninterrupted_run(self):
        out = os.path.join(self.tmp, "killed")
        self.assertEqual(self.start_and_stop(out, signal.SIGKILL), -signal.SIGKILL)
        self.assertTrue(os.path.exists(os.path.join(out, "dem.checkpoint")))
        subprocess.run(self.resume_cmd(out), check=True, capture_output=True)
        self.assert_bits_of_whole(out)
        self.assertFalse(os.path.exists(os.path.join(out, "dem.checkpoint")),
                         "a completed run removes its checkpoint")

    def test_sigterm_leaves_a_readable_partial_output_and_resumes(self):
        out = os.path.join(self.tmp, "terminated")
        self.assertEqual(self.start_and_stop(out, signal.SIGTERM), 128 + signal.SIGTERM)
        self.assertIn("--resume", self.stderr)
        f = io.read(out, "dem")
        self.assertEqual(int(f.metadata["partial"]), 1)
        n = f["forces/fx"].shape[0]
        self.assertLess(n, self.reference["forces/fx"].shape[0])
        self.assertGreater(n, 0)
        with open(os.path.join(out, "summary.json")) as s:
            self.assertIn('"partial": true', s.read())
        subprocess.run(self.resume_cmd(out), check=True, capture_output=True)
        self.assert_bits_of_whole(out)
        self.assertEqual(int(io.read(out, "dem").metadata["partial"]), 0)

    def test_a_damaged_or_foreign_checkpoint_is_refused_with_exit_2(self):
        out = os.path.join(self.tmp, "damaged")
        self.start_and_stop(out, signal.SIGTERM)
        ckpt = os.path.join(out, "dem.checkpoint")
        good = open(ckpt, "rb").read()
        before = open(os.path.join(out, "dem.h5"), "rb").read()
        flipped = bytearray(good)
        flipped[len(good) // 2] ^= 0x01
        for what, data in (("flipped", bytes(flipped)), ("truncated", good[: len(good) // 2]),
                           ("empty", b"")):
            with open(ckpt, "wb") as f:
                f.write(data)
            r = subprocess.run(self.resume_cmd(out), capture_output=True, text=True)
            self.assertEqual(r.returncode, 2, f"{what}: {r.stderr}")
            self.assertIn("dem.checkpoint", r.stderr, what)
        with open(ckpt, "wb") as f:
            f.write(good)
        other = self.cmd(out, sets=self.sets + ["dem.seed=2"])
        i = other.index("--out")
        r = subprocess.run(other[:i] + ["--resume", out], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("another case", r.stderr)
        self.assertEqual(open(os.path.join(out, "dem.h5"), "rb").read(), before,
                         "a refused resume must not touch the results")


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], "-v"])
