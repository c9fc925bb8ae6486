#!/usr/bin/python3
"""grainlift's DEM against LAMMPS on the same exported beds (docs/lammps.md, issue 16).

For each area fraction, spin and seed: `grainlift export lammps` writes the bed and script,
LAMMPS runs it (`lmp -in in.grainlift`, one rank) and `grainlift import lammps` reads it back;
`grainlift run --solver dem` (one thread) runs the same case on the same bed (the packing
cache). Prints one Markdown table row per run and the pooled means per configuration (mean
over beds, error = bed-to-bed standard deviation / sqrt(beds)), with each code's wall time for
the whole run.

    studies/lammps/lammps_study.py build/bin/grainlift WORK [--phi 0.35 0.8] [--omega 0 5]
        [--seeds 1 2 3] [--travel 30] [--steady 12.5] [--speed 0.25] [--lmp lmp]
        [--set KEY=VALUE ...] [--doc docs/lammps.md --marker study]

--set adds case overrides to every run of both codes (an experiment: damping off, ...).
--doc replaces the text between "<!-- MARKER:begin -->" and "<!-- MARKER:end -->" there.
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [os.path.join(ROOT, "python"), os.path.join(ROOT, "scripts")]
from doc_markers import replace_between_markers  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.beds import mean_and_between  # noqa: E402
CASES = {0.35: "cases/kumar2019/reduced_phi035.toml", 0.8: "cases/kumar2019/reduced_phi080.toml"}


def timed(cmd, cwd=None, log=None):
    t0 = time.monotonic()
    with open(log, "w") if log else open(os.devnull, "w") as out:
        rc = subprocess.call(cmd, cwd=cwd, stdout=out, stderr=subprocess.STDOUT,
                             env=dict(os.environ, OMP_NUM_THREADS="1"))
    if rc != 0:
        sys.exit(f"failed ({rc}): {' '.join(cmd)}" + (f"; see {log}" if log else ""))
    return time.monotonic() - t0


def dem_summary(folder):
    return io.summary(folder, "dem")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("grainlift")
    ap.add_argument("work")
    ap.add_argument("--phi", type=float, nargs="+", default=[0.35, 0.8])
    ap.add_argument("--omega", type=float, nargs="+", default=[0.0, 5.0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--travel", type=float, default=30.0)
    ap.add_argument("--steady", type=float, default=12.5)
    ap.add_argument("--speed", type=float, default=0.25)
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--set", dest="extra", action="append", default=[],
                    help="a case override for every run (repeatable)")
    ap.add_argument("--doc")
    ap.add_argument("--marker", default="study")
    a = ap.parse_args()
    if shutil.which(a.lmp) is None:
        sys.exit(f"{a.lmp} not found (Debian: apt install lammps)")
    gl = os.path.abspath(a.grainlift)
    os.makedirs(a.work, exist_ok=True)
    rows, pools = [], {}
    for phi in a.phi:
        for omega in a.omega:
            for seed in a.seeds:
                tag = f"phi{phi}_omega{omega:g}_seed{seed}"
                sets = [f"intruder.velocity=[{a.speed},0.0]", f"intruder.omega={omega}",
                        f"dem.travel={a.travel}", f"dem.steady_travel={a.steady}",
                        f"dem.seed={seed}"] + a.extra
                set_args = [x for s in sets for x in ("--set", s)]
                case = os.path.join(ROOT, CASES[phi])
                exp = os.path.join(a.work, tag, "lammps")
                shutil.rmtree(os.path.join(a.work, tag), ignore_errors=True)
                timed([gl, "export", "lammps", case, exp] + set_args,
                      log=os.path.join(a.work, f"{tag}.export.log"))
                t_lmp = timed([a.lmp, "-in", "in.grainlift"], cwd=exp,
                              log=os.path.join(exp, "lmp.out"))
                timed([gl, "import", "lammps", exp, "--out", os.path.join(a.work, tag, "imported")],
                      log=os.path.join(a.work, f"{tag}.import.log"))
                os.remove(os.path.join(exp, "contacts.dump"))  # 100-200 MB on a dense bed
                t_gl = timed([gl, "run", case, "--solver", "dem", "--threads", "1", "--quiet",
                              "--out", os.path.join(a.work, tag, "grainlift")] + set_args,
                             log=os.path.join(a.work, f"{tag}.run.log"))
                L = dem_summary(os.path.join(a.work, tag, "imported"))
                G = dem_summary(os.path.join(a.work, tag, "grainlift"))
                row = dict(phi=phi, omega=omega, seed=seed, t_lmp=t_lmp, t_gl=t_gl,
                           L=L, G=G)
                rows.append(row)
                pools.setdefault((phi, omega), []).append(row)
                print(f"{tag}: lammps drag {L['drag']:.4g} lift {L['lift']:.4g} ({t_lmp:.0f} s); "
                      f"grainlift drag {G['drag']:.4g} lift {G['lift']:.4g} ({t_gl:.0f} s)",
                      flush=True)

    out = []
    out.append(f"Reduced Kumar cases (60 d x 40 d), V0 = {a.speed} m/s, {a.travel:g} d of travel, "
               f"means over {a.steady:g}-{a.travel:g} d; one thread / one rank each, run one "
               f"after the other" + (f"; every run with {', '.join(a.extra)}" if a.extra else "") +
               ". Per run (+- block standard error, N/m):\n")
    out.append("| Phi | Omega | bed | LAMMPS drag | grainlift drag | LAMMPS lift | grainlift lift "
               "| LAMMPS s | grainlift s |")
    out.append("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        L, G = r["L"], r["G"]
        out.append(f"| {r['phi']} | {r['omega']:g} | {r['seed']} | {L['drag']:.4g} +- "
                   f"{L['drag_stderr']:.2g} | {G['drag']:.4g} +- {G['drag_stderr']:.2g} | "
                   f"{L['lift']:.3g} +- {L['lift_stderr']:.2g} | {G['lift']:.3g} +- "
                   f"{G['lift_stderr']:.2g} | {r['t_lmp']:.0f} | {r['t_gl']:.0f} |")
    out.append("\nPooled over the beds (mean +- bed-to-bed standard deviation / sqrt(beds)); "
               "difference in units of the combined error; wall-time ratio LAMMPS / grainlift:\n")
    out.append("| Phi | Omega | beds | LAMMPS drag | grainlift drag | diff/err | LAMMPS lift | "
               "grainlift lift | diff/err | LAMMPS L/D | grainlift L/D | time ratio |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for (phi, omega), rs in pools.items():
        ld, le = mean_and_between([r["L"]["drag"] for r in rs])
        gd, ge = mean_and_between([r["G"]["drag"] for r in rs])
        ll, lle = mean_and_between([r["L"]["lift"] for r in rs])
        gll, gle = mean_and_between([r["G"]["lift"] for r in rs])
        lr, _ = mean_and_between([r["L"]["lift"] / r["L"]["drag"] for r in rs])
        gr, _ = mean_and_between([r["G"]["lift"] / r["G"]["drag"] for r in rs])
        dz = (ld - gd) / math.hypot(le, ge) if math.hypot(le, ge) > 0 else float("nan")
        lz = (ll - gll) / math.hypot(lle, gle) if math.hypot(lle, gle) > 0 else float("nan")
        tr = sum(r["t_lmp"] for r in rs) / sum(r["t_gl"] for r in rs)
        out.append(f"| {phi} | {omega:g} | {len(rs)} | {ld:.4g} +- {le:.2g} | {gd:.4g} +- "
                   f"{ge:.2g} | {dz:+.1f} | {ll:.3g} +- {lle:.2g} | {gll:.3g} +- {gle:.2g} | "
                   f"{lz:+.1f} | {lr:.3f} | {gr:.3f} | {tr:.2f}x |")
    text = "\n".join(out) + "\n"
    print(text)
    if a.doc:
        replace_between_markers(a.doc, a.marker, text)


if __name__ == "__main__":
    main()
