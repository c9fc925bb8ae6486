#!/usr/bin/python3
"""The analysis scripts (scripts/*.py, studies/*/*.py) against the grainlift package.

Expected, each checked for every script:
- it starts with --help and finds every module it imports (the grainlift package in python/,
  a helper beside it): no Python traceback, exit 0 or 2 (usage);
- it reads result files only through grainlift.io: no script imports h5py itself, so the one
  reader of dem.h5 and fem.h5 is python/grainlift/io.py.
Run by CTest (tests/scripts/CMakeLists.txt); a few seconds.
"""
import glob
import os
import re
import subprocess
import sys
import unittest

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCRIPTS = sorted(glob.glob(os.path.join(ROOT, "scripts", "*.py"))
                 + glob.glob(os.path.join(ROOT, "studies", "*", "*.py")))


class StudyScripts(unittest.TestCase):
    def test_there_are_scripts(self):
        self.assertGreaterEqual(len(SCRIPTS), 15)

    def test_each_starts_and_finds_its_imports(self):
        for path in SCRIPTS:
            with self.subTest(script=os.path.relpath(path, ROOT)):
                p = subprocess.run([sys.executable, path, "--help"], capture_output=True,
                                   text=True, cwd="/", stdin=subprocess.DEVNULL, timeout=120)
                self.assertNotIn("Traceback", p.stderr)
                self.assertIn(p.returncode, (0, 2), p.stderr[-500:])

    def test_no_script_keeps_its_own_hdf5_reader(self):
        for path in SCRIPTS:
            with self.subTest(script=os.path.relpath(path, ROOT)):
                text = open(path, encoding="utf-8").read()
                self.assertIsNone(re.search(r"^\s*(import h5py|from h5py)", text, re.M))


if __name__ == "__main__":
    unittest.main()
