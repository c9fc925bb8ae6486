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


class TinyFileSystem(unittest.TestCase):
    """The same on a real full disk: a 100 KB tmpfs, mounted where the machine allows it (as
    root; CI runs so). The continuum's result is rescued as above, from a full and from a
    read-only folder; a packing cache there is a warning and the run goes on; `grainlift
    report` on a result folder there ends with exit 1 and one sentence, the previous
    report.html kept."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="grainlift_tinyfs_")
        self.disk = os.path.join(self.tmp, "disk")
        os.makedirs(self.disk)
        p = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=100k", "tmpfs", self.disk],
                           capture_output=True, text=True)
        if p.returncode != 0:
            shutil.rmtree(self.tmp, ignore_errors=True)
            self.skipTest("mounting a tmpfs is not allowed here (" + p.stderr.strip() +
                          "); FullDisk covers the same paths through the hook")

    def tearDown(self):
        subprocess.run(["umount", self.disk], capture_output=True)
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_continuum_result_rescued_from_a_full_disk(self):
        rescue_root = os.path.join(self.tmp, "rescue")
        os.makedirs(rescue_root)
        out = os.path.join(self.disk, "out")
        p = subprocess.run([BINARY, "run", CASE, "--solver", "fem", "--out", out, "--set",
                            "continuum.refinement=1"], capture_output=True, text=True,
                           env=dict(os.environ, TMPDIR=rescue_root), timeout=600)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("No space left on device", p.stderr)
        m = re.search(r"written instead to (\S+/fem.h5)", p.stderr)
        self.assertIsNotNone(m, p.stderr)
        self.assertGreater(io.read(m.group(1)).attrs("means")["drag"], 0.0)

    def test_result_rescued_from_a_read_only_folder(self):
        out = os.path.join(self.disk, "out")
        os.makedirs(out)
        subprocess.run(["mount", "-o", "remount,ro", self.disk], check=True)
        rescue_root = os.path.join(self.tmp, "rescue")
        os.makedirs(rescue_root)
        p = subprocess.run([BINARY, "run", CASE, "--solver", "fem", "--out", out, "--set",
                            "continuum.refinement=0"], capture_output=True, text=True,
                           env=dict(os.environ, TMPDIR=rescue_root), timeout=600)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("Read-only file system (the file system is read-only: choose another "
                      "--out)", p.stderr)
        m = re.search(r"written instead to (\S+/fem.h5)", p.stderr)
        self.assertIsNotNone(m, p.stderr)
        self.assertGreater(io.read(m.group(1)).attrs("means")["drag"], 0.0)

    def test_packing_cache_on_a_full_disk_is_a_warning(self):
        # the disk filled first: the prepared bed cannot be cached; the run goes on to its end
        with open(os.path.join(self.disk, "filler"), "wb", buffering=0) as f:
            try:
                while True:
                    f.write(b"x" * 4096)
            except OSError:
                pass
        cache = os.path.join(self.disk, "cache")
        out = os.path.join(self.tmp, "out")
        p = subprocess.run([BINARY, "run", CASE, "--solver", "dem", "--out", out, "--threads",
                            "1", "--set", "dem.travel=0.3", "--set", "dem.steady_travel=0.1",
                            "--set", f'dem.packing_cache="{cache}"'],
                           capture_output=True, text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("warning: the prepared bed was not cached", p.stderr)
        self.assertIn("No space left on device", p.stderr)
        self.assertEqual([n for n in os.listdir(cache) if ".tmp." in n], [])
        self.assertGreater(len(io.read(os.path.join(out, "dem.h5"))["forces/fx"]), 0)

    def test_report_on_a_full_disk_keeps_the_previous_page(self):
        scratch = os.path.join(self.tmp, "scratch")
        p = subprocess.run([BINARY, "run", CASE, "--solver", "fem", "--out", scratch, "--set",
                            "continuum.refinement=0", "--quiet"],
                           capture_output=True, text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stderr)
        folder = os.path.join(self.disk, "result")
        os.makedirs(folder)
        shutil.copy(os.path.join(scratch, "fem.h5"), folder)
        old = os.path.join(folder, "report.html")
        with open(old, "w") as f:
            f.write("the previous report")
        p = subprocess.run([BINARY, "report", folder], capture_output=True, text=True,
                           timeout=600)
        self.assertNotEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("cannot write the report: No space left on device", p.stderr)
        self.assertIn("the previous files are kept as they were", p.stderr)
        with open(old) as f:
            self.assertEqual(f.read(), "the previous report")
        self.assertEqual([n for n in os.listdir(folder) if ".tmp." in n], [])


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
