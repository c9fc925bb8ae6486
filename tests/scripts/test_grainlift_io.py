#!/usr/bin/python3
"""grainlift.io against the files the real command writes, and the installed scripts against
the installed package.

One short run of the demo case (--solver both, 6 d of travel, refinement 1, omega set to 10
rad/s on the command line) gives a dem.h5, a fem.h5 and summary.json. Expected, each checked:
- io.read finds dem.h5 in the folder (fem.h5 when asked) and decodes strings;
- the drag and lift io derives from /forces (along -V and V turned +90 degrees), averaged from
  /diagnostics steady_start_sample by grainlift.stats.block_mean with /means blocks, are the
  C++'s /means drag, lift and their standard errors (the correlation-corrected error, the one
  rule), to 1e-9 relative, and so are Result.block_errors(): the Python reader and rule see
  what the C++ wrote;
- Result.case() applies the run's --set overrides: intruder.omega is 10, as /geometry omega;
- the intruder's travel at the last sample is the case's dem.travel (6 d) to 1%;
- a field is a (ny, nx) array on the /fields x, y grid; summary.json's dem drag is /means drag;
- cases/demo/rheology.toml reads as a calibration with one I, mu, phi per point;
- `cmake --install BUILD --prefix P` puts grainlift/ beside P/share/grainlift/report.py, and
  report.py run from there imports the installed package (not python/ in the sources) and
  writes report.html.

Usage: test_grainlift_io.py GRAINLIFT_BINARY DEMO_CASE BUILD_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

BINARY, CASE, BUILD = sys.argv[1], sys.argv[2], sys.argv[3]
del sys.argv[1:4]
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "python"))
from grainlift import io, stats  # noqa: E402

WORK = tempfile.mkdtemp(prefix="grainlift_io_")
RUN = os.path.join(WORK, "run")
RUN_IN_TURN = os.path.join(WORK, "run_in_turn")
TRAVEL = 6.0


def setUpModule():
    # both solvers with two threads: side by side (run_driver.h), then one after the other
    for out, threads in ((RUN, "2"), (RUN_IN_TURN, "1")):
        subprocess.run([BINARY, "run", CASE, "--solver", "both", "--out", out, "--threads",
                        threads, "--quiet", "--set", f"dem.travel={TRAVEL:g}", "--set",
                        "dem.steady_travel=2", "--set", "continuum.refinement=1", "--set",
                        "intruder.omega=10"], check=True, stdout=subprocess.DEVNULL)


def tearDownModule():
    shutil.rmtree(WORK, ignore_errors=True)


class ReadsWhatTheCommandWrote(unittest.TestCase):
    def test_finds_each_solver_and_decodes_strings(self):
        self.assertEqual(set(io.results_in(RUN)), {"dem", "fem"})
        self.assertEqual(io.read(RUN).solver, "dem")
        fem = io.read(RUN, "fem")
        self.assertEqual(fem.solver, "fem")
        self.assertIsInstance(fem.metadata["notes"], str)
        with self.assertRaises(FileNotFoundError):
            io.read(os.path.join(WORK, "nowhere"))

    def test_drag_and_lift_series_give_the_cpp_means(self):
        r = io.read(RUN, "dem")
        drag, lift = r.drag_lift()
        first = int(r.diagnostics["steady_start_sample"])
        blocks = int(r.means["blocks"])
        for name, series in (("drag", drag), ("lift", lift)):
            b = stats.block_mean(series[first:], blocks)
            self.assertEqual(b.samples, int(r.means["samples"]))
            self.assertAlmostEqual(b.mean / r.means[name], 1.0, delta=1e-9, msg=name)
            # one statistics rule: the stored error is the correlation-corrected one
            self.assertAlmostEqual(b.stderr_corrected / r.means[name + "_stderr"], 1.0,
                                   delta=1e-9, msg=name)
        for name, error in r.block_errors().items():
            self.assertAlmostEqual(error / r.means[name], 1.0, delta=1e-9, msg=name)
        self.assertEqual(len(r.block_errors()), 3)
        self.assertGreater(r.means["drag"], 0.0)  # the medium resists the motion

    def test_case_carries_the_overrides(self):
        r = io.read(RUN, "dem")
        self.assertEqual(r.case()["intruder"]["omega"], 10)
        self.assertEqual(float(r.geometry["omega"]), 10.0)
        self.assertEqual(r.case()["dem"]["travel"], TRAVEL)

    def test_travel_reaches_the_case_travel(self):
        self.assertAlmostEqual(io.read(RUN, "dem").travel()[-1], TRAVEL, delta=0.01 * TRAVEL)

    def test_fields_and_summary(self):
        r = io.read(RUN, "fem")
        g = r["fields"]
        self.assertEqual(g["pressure"].shape, (len(g["y"]), len(g["x"])))
        self.assertTrue(r.has("fields/pressure") and not r.has("fields/no_such_field"))
        dem = io.read(RUN, "dem")
        self.assertEqual(io.summary(RUN, "dem")["drag"], float(dem.means["drag"]))

    def test_calibration_file(self):
        law = io.calibration(os.path.join(os.path.dirname(CASE), "rheology.toml"))
        p = io.calibration_points(law)
        self.assertGreater(len(p["I"]), 0)
        self.assertTrue(len(p["I"]) == len(p["mu"]) == len(p["phi"]))
        self.assertIn("mu_s", law["mu_i"])


class BothSolversAtOnce(unittest.TestCase):
    """`--threads 2` runs the DEM and the continuum at once, on threads of one process: each
    solver's numbers are those of the run in turn (`--threads 1`), bit for bit (the DEM gives
    the same bits on one thread or a team, the continuum is deterministic), and each file and
    the summary are complete."""

    def test_same_numbers_as_one_after_the_other(self):
        for solver in ("dem", "fem"):
            at_once, in_turn = io.read(RUN, solver), io.read(RUN_IN_TURN, solver)
            self.assertEqual(int(at_once.metadata["threads"]), 2)
            for key in ("drag", "lift", "torque"):
                self.assertEqual(float(at_once.means[key]), float(in_turn.means[key]),
                                 f"{solver} {key}")
            for name in ("surface/sigma_n", "surface/sigma_t"):
                self.assertTrue((at_once[name] == in_turn[name]).all(), f"{solver} {name}")
            self.assertEqual(io.summary(RUN, solver)["drag"], float(at_once.means["drag"]))


class InstalledScriptsUseTheInstalledPackage(unittest.TestCase):
    def test_report_from_the_prefix(self):
        prefix = os.path.join(WORK, "prefix")
        subprocess.run(["cmake", "--install", BUILD, "--prefix", prefix], check=True,
                       stdout=subprocess.DEVNULL)
        share = os.path.join(prefix, "share", "grainlift")
        for f in ("io.py", "plots.py", "stats.py", "__init__.py"):
            self.assertTrue(os.path.isfile(os.path.join(share, "grainlift", f)), f)
        folder = os.path.join(WORK, "report")
        shutil.copytree(RUN, folder)
        # report.py in a fresh interpreter, as `grainlift report` runs it; print where the
        # package it imported lives
        probe = ("import runpy, sys; sys.argv = [sys.argv[1], sys.argv[2]]; "
                 "code = 0\ntry:\n    runpy.run_path(sys.argv[0], run_name='__main__')\n"
                 "except SystemExit as e:\n    code = e.code or 0\n"
                 "print(sys.modules['grainlift'].__file__); sys.exit(code)")
        out = subprocess.run([sys.executable, "-c", probe, os.path.join(share, "report.py"),
                              folder], check=True, capture_output=True, text=True,
                             cwd=WORK).stdout.split()
        self.assertEqual(os.path.realpath(out[-1]),
                         os.path.realpath(os.path.join(share, "grainlift", "__init__.py")))
        self.assertGreater(os.path.getsize(os.path.join(folder, "report.html")), 0)


if __name__ == "__main__":
    unittest.main()
