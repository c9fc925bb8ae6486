#!/usr/bin/python3
"""Forces against the bed-preparation protocol (issue 17, studies/preparation/README.md).

Runs the reduced Kumar case (V0 0.25 m/s, 30 d of travel, means over 12.5-30 d) with
dem.preparation = radius_growth and wall_compression, at the given area fractions, spins and
seeds, one thread each, and prints a Markdown table per run (drag, lift with block errors and
the bed's fingerprint: contacts per grain, share of grains within 0.001 d of a neighbour, the
area fraction of the central band and of the first ring round the intruder) and the pooled
means per protocol (error = bed-to-bed standard deviation / sqrt(beds)).

    studies/preparation/preparation_study.py build/bin/grainlift WORK [--phi 0.8 0.818] \
[--omega 0 5]
        [--seeds 1 2 3] [--protocols radius_growth wall_compression] [--set KEY=VALUE ...]
        [--doc studies/preparation/README.md --marker preparation]
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [os.path.join(ROOT, "python"), os.path.join(ROOT, "scripts")]
from doc_markers import replace_between_markers  # noqa: E402
from grainlift import io  # noqa: E402
from grainlift.beds import mean_and_between  # noqa: E402
CASES = {0.35: "cases/kumar2019/reduced_phi035.toml"}
DENSE = "cases/kumar2019/reduced_phi080.toml"


def fingerprint(h5):
    f = io.read(h5)
    b = f["bed"]
    edges = list(b["gap_edges"][:])
    frac = list(b["gap_fraction"][:])
    near = sum(x for e, x in zip(edges[:-1], frac) if e < 0.001)  # gap below 0.001 d
    band_y = list(b["band_y"][:])
    bands = list(b["band_area_fraction"][:])
    yi = f.geometry["intruder_y"]
    k = min(range(len(band_y)), key=lambda i: abs(band_y[i] - yi))
    centre = sum(bands[max(0, k - 1):k + 2]) / len(bands[max(0, k - 1):k + 2])
    ring = list(b["ring_area_fraction"][:])
    return dict(z=b.attrs["contacts_per_grain"], near=near, centre=centre, ring1=ring[0],
                ring3=sum(ring[:3]) / 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("grainlift")
    ap.add_argument("work")
    ap.add_argument("--phi", type=float, nargs="+", default=[0.8, 0.818])
    ap.add_argument("--omega", type=float, nargs="+", default=[0.0, 5.0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--protocols", nargs="+", default=["radius_growth", "wall_compression"])
    ap.add_argument("--set", dest="extra", action="append", default=[],
                    help="a case override for every run (repeatable), e.g. "
                         "dem.compression_speed=0.05")
    ap.add_argument("--doc")
    ap.add_argument("--marker", default="preparation")
    a = ap.parse_args()
    rows, pools = [], {}
    for phi in a.phi:
        case = os.path.join(ROOT, CASES.get(phi, DENSE))
        for omega in a.omega:
            for prot in a.protocols:
                for seed in a.seeds:
                    out = os.path.join(a.work, f"phi{phi}_omega{omega:g}_{prot}_seed{seed}")
                    sets = [f"grains.area_fraction={phi}", "intruder.velocity=[0.25,0.0]",
                            f"intruder.omega={omega}", "dem.travel=30", "dem.steady_travel=12.5",
                            f"dem.seed={seed}", f"dem.preparation={prot}"] + a.extra
                    cmd = [a.grainlift, "run", case, "--solver", "dem", "--threads", "1",
                           "--quiet", "--out", out] + [x for s in sets for x in ("--set", s)]
                    rc = subprocess.call(cmd, stdout=subprocess.DEVNULL,
                                         env=dict(os.environ, OMP_NUM_THREADS="1"))
                    if rc != 0:
                        sys.exit(f"failed ({rc}): {' '.join(cmd)}")
                    s = io.summary(out, "dem")
                    fp = fingerprint(os.path.join(out, "dem.h5"))
                    row = dict(phi=phi, omega=omega, prot=prot, seed=seed, s=s, fp=fp)
                    rows.append(row)
                    pools.setdefault((phi, omega, prot), []).append(row)
                    print(f"{os.path.basename(out)}: drag {s['drag']:.4g} lift {s['lift']:.4g} "
                          f"Z {fp['z']:.3g} near {fp['near']:.2f} centre {fp['centre']:.3f} "
                          f"ring1 {fp['ring1']:.3f}", flush=True)
    t = ["Per run (+- block standard error, N/m); bed: contacts per grain Z, share of grains "
         "within 0.001 d of a neighbour, area fraction of the three bands round the intruder's "
         "height and of the first ring (1 d) round it:\n",
         "| Phi | Omega | protocol | bed | drag | lift | Z | near | centre bands | ring 1 |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        s, f = r["s"], r["fp"]
        t.append(f"| {r['phi']} | {r['omega']:g} | {r['prot']} | {r['seed']} | {s['drag']:.3g} +- "
                 f"{s['drag_stderr']:.2g} | {s['lift']:.3g} +- {s['lift_stderr']:.2g} | "
                 f"{f['z']:.3g} | {f['near']:.2f} | {f['centre']:.3f} | {f['ring1']:.3f} |")
    t += ["\nPooled over the beds (mean +- bed-to-bed standard deviation / sqrt(beds)):\n",
          "| Phi | Omega | protocol | beds | drag | lift | L/D | centre bands | ring 1 |",
          "|---|---|---|---|---|---|---|---|---|"]
    for (phi, omega, prot), rs in pools.items():
        d, de = mean_and_between([r["s"]["drag"] for r in rs])
        l, le = mean_and_between([r["s"]["lift"] for r in rs])
        ld, _ = mean_and_between([r["s"]["lift"] / r["s"]["drag"] for r in rs])
        c, _ = mean_and_between([r["fp"]["centre"] for r in rs])
        g, _ = mean_and_between([r["fp"]["ring1"] for r in rs])
        t.append(f"| {phi} | {omega:g} | {prot} | {len(rs)} | {d:.3g} +- {de:.2g} | {l:.3g} +- "
                 f"{le:.2g} | {ld:.3f} | {c:.3f} | {g:.3f} |")
    text = "\n".join(t) + "\n"
    print(text)
    if a.doc:
        replace_between_markers(a.doc, a.marker, text)


if __name__ == "__main__":
    main()
