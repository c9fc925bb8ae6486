#!/usr/bin/python3
"""The grains' wall law from DEM runs, written into a rheology file:
    python3 scripts/fit_wall.py RHEOLOGY_FILE RUN...   (or `grainlift calibrate CASE --wall RUN...`)

RUN: a result folder with dem.h5, or the dem.h5 itself, of runs whose intruder is made of the
case's grains' contact law (grainlift run CASE --solver dem), with /histogram/slip_velocity.
Fits the slip law mu_w(v) = mu_a + (mu_b - mu_a) |v| / (|v| + v0) on the measured slip at every
loaded angle and pools the runs' effective friction (grainlift.wall.fit), then replaces the
[wall] table of RHEOLOGY_FILE (written atomically: a failed write keeps the old file).
Exit 2 on bad input (no run, no slip histogram), 1 when the file cannot be written."""
import os
import sys

sys.path[:0] = [os.path.dirname(os.path.realpath(__file__)),  # installed: grainlift/ beside
                os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python")]
from grainlift import files, io, wall  # noqa: E402


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    path, runs = argv[1], argv[2:]
    try:
        results = [io.read(r, "dem") for r in runs]
        f = wall.fit(results)
    except (OSError, KeyError, ValueError) as e:
        print(f"fit_wall: {e}", file=sys.stderr)
        return 2
    law = f.law
    if wall.table_problem(f):
        print(f"fit_wall: the runs do not determine the wall law ({wall.table_problem(f)}: "
              f"mu_a {law.mu_a:.3g} +- {law.mu_a_err:.2g}, mu_b {law.mu_b:.3g} +- "
              f"{law.mu_b_err:.2g}, v0 {law.v0:.3g} +- {law.v0_err:.2g} m/s from {f.runs} "
              f"runs); add runs at other spin ratios; {path} is left as it was",
              file=sys.stderr)
        return 2
    source = f"grainlift calibrate --wall: {f.runs} runs ({', '.join(runs)})"
    with open(path) as fh:
        text = wall.with_wall_table(fh.read(), wall.wall_table(law, f.friction, f.friction_err,
                                                               source))

    def write(tmp):
        with open(tmp, "w") as fh:
            fh.write(text)
    try:
        files.write_atomically(path, write)
    except OSError as e:
        print(f"{path}: cannot write the file: {e.strerror} ({files.advice(e)})",
              file=sys.stderr)
        return 1
    print(f"wall law ({law.points} angles of {f.runs} runs): mu_a {law.mu_a:.3f} +- "
          f"{law.mu_a_err:.3f}, mu_b {law.mu_b:.3f} +- {law.mu_b_err:.3f}, v0 {law.v0:.4f} +- "
          f"{law.v0_err:.4f} m/s (chi2/dof {law.chi2_per_dof:.2f}); friction {f.friction:.3f} "
          f"+- {f.friction_err:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
