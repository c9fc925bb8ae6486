#!/usr/bin/python3
"""Faults of the machine other than a full disk (issue 37), through the command on the demo case.

Expected behaviour, each checked:
- too little memory for the continuum (a real address-space limit, `ulimit -v` 1.4 GB, on
  refinement 4): refinements 0-3 fit (about 1.1 GB of address space with MUMPS's factors of
  44,944 unknowns), refinement 4 does not (177,440 unknowns: MUMPS's own estimate 519 MB, the
  measured rule 540 MB, on top of 1.1 GB); the run ends with exit 1 (not MPI_ABORT's 157) and
  one sentence naming the need, the limit ("ulimit -v") and the ways out, and fem.h5 holds
  refinement 3, marked partial;
- the same limit with the check fooled (GRAINLIFT_TEST_MEMORY_MB=1000000): MUMPS's factorisation
  itself fails (INFOG(1) = -13, an allocation), and that ends in the same sentence;
- an allocation that fails inside the continuum (std::bad_alloc, injected at level 2 by the
  hook GRAINLIFT_TEST_BAD_ALLOC_AT_LEVEL): exit 1, the sentence, level 1 kept;
- a DEM bed too large for the memory left (the hook GRAINLIFT_TEST_MEMORY_MB=1 stands for the
  limit; the demo's 873 grains need 1.3 MB by the measured rule): refused before it is
  prepared, exit 1, the sentence;
- a second process on the same --out while the first writes there: exit 1, one sentence that
  names the other's pid; the first finishes untouched;
- the --out folder deleted while a run goes on: the folder is made again and the result is
  written there, with a warning; exit 0.

Usage: test_machine_faults_run.py GRAINLIFT_BINARY CASE_FILE
"""
import errno
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from grainlift import io  # noqa: E402

BINARY, CASE = sys.argv[1], sys.argv[2]


def command(out, solver, sets):
    args = [BINARY, "run", CASE, "--solver", solver, "--threads", "1", "--out", out]
    for s in sets:
        args += ["--set", s]
    return args


# The memory tests solve the demo's levels 0-3 before the one that cannot fit: with the
# incompressible law (the same meshes and unknowns as the default dilatant one, a fifth
# quicker) and a regularisation delta of 1 1/s (a shorter continuation: levels 0-3 in half
# the time); the memory paths depend on neither
QUICK_LAW = ['continuum.dilatancy="none"', "continuum.delta=1.0"]
TO_LEVEL_4 = ["continuum.refinement=4", "continuum.target_error=0"] + QUICK_LAW


def run(out, solver, sets, env=None, limit_bytes=None):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))
    return subprocess.run(command(out, solver, sets), capture_output=True, text=True,
                          env=dict(os.environ, **(env or {})), timeout=600,
                          preexec_fn=limit if limit_bytes else None)


def remove_folder_being_written(path):
    """Delete PATH as `rm -rf` does while a run writes into it: a temporary file the run
    renames away between the listing and the unlink, or writes after the listing (the
    folder is then not empty at its rmdir), is not an error; go again until the folder is
    gone."""
    for _ in range(50):
        if not os.path.exists(path):
            return
        try:
            shutil.rmtree(path)
        except OSError as err:
            if err.errno not in (errno.ENOENT, errno.ENOTEMPTY):
                raise
    raise AssertionError(path + " could not be removed while the run wrote into it")


class MachineFaults(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="grainlift_machine_faults_")
        self.out = os.path.join(self.tmp, "out")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def assert_partial_level(self, refinement):
        res = io.read(os.path.join(self.out, "fem.h5"))
        self.assertEqual(res.attrs("metadata")["partial"], 1)
        self.assertEqual(int(res["diagnostics/level_refinement"][-1]), refinement)
        self.assertGreater(res.attrs("means")["drag"], 0.0)

    def test_continuum_level_that_cannot_fit_is_refused_the_last_one_kept(self):
        p = run(self.out, "fem", TO_LEVEL_4,
                limit_bytes=1400 * 1024 * 1024)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertNotIn("MPI_ABORT", p.stderr)
        self.assertIn("the continuum ran out of memory: the direct solve (MUMPS) of 177440 "
                      "unknowns needs about", p.stderr)
        self.assertIn("(the limit: ulimit -v, the address space)", p.stderr)
        self.assertIn('continuum.linear_solver = "amg"', p.stderr)
        self.assertIn("continuum.refinement = 3 or lower", p.stderr)
        self.assert_partial_level(3)

    def test_factorisation_out_of_memory_is_the_same_sentence(self):
        # the same limit, but the memory check is told there is plenty (the hook stands for a
        # limit of 1 TB): MUMPS's own allocation fails (INFOG(1) = -13), which Amesos hands
        # back as an error code; it ends in the same sentence
        p = run(self.out, "fem", TO_LEVEL_4,
                limit_bytes=1400 * 1024 * 1024,
                env={"GRAINLIFT_TEST_MEMORY_MB": "1000000"})
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertNotIn("MPI_ABORT", p.stderr)
        self.assertIn("the continuum ran out of memory: MUMPS's factorisation failed "
                      "(INFOG(1) = -13", p.stderr)
        self.assertIn("continuum.refinement = 3 or lower", p.stderr)
        self.assert_partial_level(3)

    def test_failed_allocation_in_the_continuum_keeps_the_last_level(self):
        p = run(self.out, "fem", ["continuum.refinement=2"] + QUICK_LAW,
                env={"GRAINLIFT_TEST_BAD_ALLOC_AT_LEVEL": "2"})
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("the continuum ran out of memory: an allocation failed (std::bad_alloc)",
                      p.stderr)
        self.assertIn(os.path.join(self.out, "fem.h5") + " holds the converged mesh", p.stderr)
        self.assert_partial_level(1)

    def test_dem_bed_too_large_is_refused_before_it_is_prepared(self):
        p = run(self.out, "dem", ['dem.packing_cache=""'],
                env={"GRAINLIFT_TEST_MEMORY_MB": "1"})
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("not enough memory: the bed of 873 grains (1.5 kB per grain) needs about "
                      "1.3 MB where 1.0 MB are left", p.stderr)
        self.assertNotIn("packing", p.stderr.split("not enough memory")[0].lower()
                         .replace("packing_cache", ""))
        self.assertFalse(os.path.exists(os.path.join(self.out, "dem.h5")))

    def test_second_process_on_the_same_out_is_refused(self):
        first = subprocess.Popen(command(self.out, "fem", ["continuum.refinement=2"]),
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.time() + 60
        while not os.path.exists(os.path.join(self.out, ".grainlift.lock")):
            self.assertLess(time.time(), deadline, "the first run never took its lock")
            time.sleep(0.05)
        second = run(self.out, "fem", ["continuum.refinement=0"])
        _, err = first.communicate(timeout=600)
        self.assertEqual(second.returncode, 1, second.stderr)
        self.assertIn(self.out + ": another grainlift is writing its results there (pid "
                      + str(first.pid), second.stderr)
        self.assertEqual(first.returncode, 0, err)
        self.assertEqual(io.read(os.path.join(self.out, "fem.h5")).attrs("metadata")["partial"],
                         0)
        self.assertFalse(os.path.exists(os.path.join(self.out, ".grainlift.lock")))

    def test_out_folder_deleted_during_the_run_is_made_again(self):
        first = subprocess.Popen(command(self.out, "fem", ["continuum.refinement=2"]),
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.time() + 60
        while not os.path.exists(os.path.join(self.out, "fem.h5")):  # level 0's partial file
            self.assertLess(time.time(), deadline, "no intermediate result")
            time.sleep(0.05)
        remove_folder_being_written(self.out)
        _, err = first.communicate(timeout=600)
        self.assertEqual(first.returncode, 0, err)
        self.assertIn("was removed during the run; made again for the result", err)
        self.assertEqual(io.read(os.path.join(self.out, "fem.h5")).attrs("metadata")["partial"],
                         0)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + ["-v"])
