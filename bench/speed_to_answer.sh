#!/usr/bin/env bash
# The benchmarks of `make bench`: time to an answer where production runs spend their time,
# as ratios measured back to back on this machine (docs/performance.md quotes them).
#
#   bench/speed_to_answer.sh [build dir (build)]
#     [sections ("lammps threads replicas fields error")]
#
#   cores     what a second core adds on this machine whatever the code (dem_core_contention:
#             compute, cache, memory, store kernels alone and two side by side, and steps in
#             lockstep with the team's barrier): the ceiling of the thread and replica ratios
#   lammps    grainlift against LAMMPS on the whole reduced dense Kumar run from the same bed
#             (bench/compare_lammps_production.sh; skipped with a message without `lmp`)
#   threads   two threads against one: the step on the dense, jammed and dilute 23,000-27,000
#             grain beds (dem_throughput, the same steps on both sides), and the whole reduced
#             run (2,295 grains)
#   replicas  --replicas 2 (on --threads 2) against one run on one and on two threads:
#             statistics per wall second
#   fields    the saving of not accumulating fields (output.fields = false) on the reduced run
#   frictionless  the saving of dem.frictionless_path on the reduced run with grains.friction = 0
#   sleep     the saving of sleeping grains (dem.sleep, speed 0: the same bits) on the reduced
#             dense and dilute runs and on the first 6 d of the full-size Kumar box
#   fem       the FEM's error against time on the demo geometry, refinement 0-4 with nested
#             iteration, 0-3 without (studies/fem_pareto/fem_pareto.py)
#   error     relative error of drag and lift against wall time
#             (studies/dem_error_vs_time/error_vs_time.py) for the reduced Kumar run and
#             cases/guillard2014/gradient.toml
#
# Environment: REPS (repetitions of every timed run, default 3; the two runs of a ratio
# alternate and the median of the paired ratios is printed, beside the medians: on this
# 2-core VM one run of the same binary on the same case took 39 to 56 s), WORK (outputs,
# default /tmp/grainlift_speed), PYTHON (default /usr/bin/python3), OMP_PROC_BIND / OMP_PLACES
# (default true / cores). About 25 minutes on 2 cores with REPS=3.
set -euo pipefail
BUILD=${1:-build}
SECTIONS=${2:-"cores lammps threads replicas fields frictionless sleep fem error"}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
WORK=${WORK:-/tmp/grainlift_speed}
PY=${PYTHON:-/usr/bin/python3}
GL="$BUILD/bin/grainlift"
export OMP_PROC_BIND=${OMP_PROC_BIND:-true} OMP_PLACES=${OMP_PLACES:-cores}
mkdir -p "$WORK"
# the reduced dense Kumar production run: Phi 0.8, 2,295 grains, V0 0.25 m/s, Omega 1, 30 d
KUMAR="$ROOT/cases/kumar2019/reduced_phi080.toml"
KSET=(--set "intruder.velocity=[0.25,0.0]" --set intruder.omega=5.0 --set dem.travel=30)
REPS=${REPS:-3}
export REPS
has() { [[ " $SECTIONS " == *" $1 "* ]]; }
wall() {
  "$PY" -c 'import json, sys; print(json.load(open(sys.argv[1]))["dem"]["wall_seconds"])' \
    "$1/summary.json"
}
. "$(dirname "$0")/lib.sh"  # median
# run_once NAME ARGS...: the reduced run with ARGS once (output in $WORK/NAME); its solver wall
# time (summary.json) is appended to $WORK/NAME.walls. Another case: TCASE (file) and the array
# TSET (its --set options) in place of KUMAR and KSET.
run_once() {
  local name=$1; shift
  local set=("${KSET[@]}")
  [[ -n ${TSET+x} ]] && set=("${TSET[@]}")
  sleep 1
  "$GL" run "${TCASE:-$KUMAR}" --solver dem "${set[@]}" "$@" --out "$WORK/$name" --quiet >/dev/null
  wall "$WORK/$name" >>"$WORK/$name.walls"
}
# timed_ab A B: runs A (options in the array ARGS_A) and B (ARGS_B) alternately, REPS times
# each, so that a slow spell of this VM's host (up to 40%, minutes long) falls on both sides of
# a ratio. Medians into $WORK/A.wall and $WORK/B.wall, the median of the paired ratios A/B
# (each from two runs back to back) into $WORK/A.B.ratio.
timed_ab() {
  local a=$1 b=$2
  rm -f "$WORK/$a.walls" "$WORK/$b.walls"
  for ((r = 0; r < REPS; ++r)); do
    run_once "$a" "${ARGS_A[@]}"
    run_once "$b" "${ARGS_B[@]}"
  done
  median <"$WORK/$a.walls" >"$WORK/$a.wall"
  median <"$WORK/$b.walls" >"$WORK/$b.wall"
  paste "$WORK/$a.walls" "$WORK/$b.walls" | awk '{print $1 / $2}' | median >"$WORK/$a.$b.ratio"
  echo "# $a: $(tr '\n' ' ' <"$WORK/$a.walls")s; $b: $(tr '\n' ' ' <"$WORK/$b.walls")s;" \
    "paired $a/$b: $(paste "$WORK/$a.walls" "$WORK/$b.walls" | awk '{printf "%.2f ", $1 / $2}')"
}
# the packing once, so that no timed run prepares it (sections that run the reduced case)
if has threads || has replicas || has fields || has frictionless || has sleep || has error; then
  "$GL" run "$KUMAR" --solver dem "${KSET[@]}" --set dem.travel=16 --out "$WORK/prep" \
    --quiet >/dev/null
fi

echo "# $(date -u +%FT%TZ)  $(nproc) cores  load: $(cut -d' ' -f1-3 /proc/loadavg) " \
  "$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')"

if has cores; then
  echo; echo "## What a second core adds here (any code; 2.00x = two independent cores)"
  if [[ -x "$BUILD/bin/dem_core_contention" ]]; then "$BUILD/bin/dem_core_contention" 2; fi
fi

if has lammps; then
  echo; echo "## DEM against LAMMPS, whole production run (one thread each)"
  if command -v "${LMP:-lmp}" >/dev/null && [[ -x "$BUILD/bin/dem_export_lammps_case" ]]; then
    WORK="$WORK/lammps" bash "$HERE/compare_lammps_production.sh" "$BUILD" "$REPS"
  else
    echo "skipped: needs LAMMPS (\`lmp\`, Debian package lammps) and" \
      "$BUILD/bin/dem_export_lammps_case"
  fi
fi

if has threads; then
  echo; echo "## Two threads against one"
  if [[ -x "$BUILD/bin/dem_throughput" ]]; then
    # The same steps on both sides (20,000 dense and dilute, 3,000 jammed, after a 500-step
    # warm-up: with a minimum time instead, the faster side ploughs further and meets more
    # contacts), one and two threads alternately, REPS times; the team runs every step.
    rm -f "$WORK"/throughput.*.json
    for ((r = 0; r < REPS; ++r)); do
      for bed in Dense:20000 Jammed:3000 Dilute:20000; do
        for th in 1 2; do
          GRAINLIFT_BENCH_STEPS=${bed#*:} GRAINLIFT_TEAM=fixed "$BUILD/bin/dem_throughput" \
            --benchmark_filter="^BM_${bed%:*}Bed/$th/" --benchmark_format=json \
            >"$WORK/throughput.${bed%:*}.$th.$r.json" 2>/dev/null
        done
      done
    done
    "$PY" - "$WORK" "$REPS" <<'PYEOF'
import json, statistics, sys
work, reps = sys.argv[1], int(sys.argv[2])
def rate(bed, th, r):
    x = json.load(open(f"{work}/throughput.{bed}.{th}.{r}.json"))["benchmarks"][0]
    return x["grains"], x["particle_steps_per_s"] / 1e6
print("| bed | grains | 1 thread (M grain-steps/s, median) | 2 threads | paired ratios | median | "
      "target |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for bed in ("Dense", "Jammed", "Dilute"):
    one = [rate(bed, 1, r) for r in range(reps)]
    two = [rate(bed, 2, r) for r in range(reps)]
    ratios = [b[1] / a[1] for a, b in zip(one, two)]
    m = statistics.median(ratios)
    target = ("met" if m >= 1.85 else "not met") + " (1.85x)" if bed != "Dilute" else "(none)"
    print(f"| {bed.lower()} | {int(one[0][0])} | {statistics.median(a[1] for a in one):.1f} | "
          f"{statistics.median(b[1] for b in two):.1f} | {', '.join(f'{x:.2f}' for x in ratios)} | "
          f"{m:.2f}x | {target} |")
PYEOF
  else
    echo "dem_throughput not built (Google Benchmark, libbenchmark-dev): step rates skipped"
  fi
  ARGS_A=(--threads 1) ARGS_B=(--threads 2)
  timed_ab threads1 threads2
  PYTHONPATH="$ROOT/python" "$PY" - "$WORK/threads1" "$WORK/threads2" <<'PYEOF'
import sys
from grainlift import io
w = [io.summary(d, "dem") for d in sys.argv[1:]]
t = [float(open(d + ".wall").read()) for d in sys.argv[1:]]
ratio = float(open(sys.argv[1] + ".threads2.ratio").read())
same = w[0]["drag"] == w[1]["drag"] and w[0]["lift"] == w[1]["lift"]
team = io.read(sys.argv[2], "dem").diagnostics
print(f"whole reduced run, 2,295 grains (medians): 1 thread {t[0]:.1f} s, --threads 2 "
      f"{t[1]:.1f} s (paired ratio {ratio:.2f}x; "
      f"target: never slower than one, >= 1.00x within timing noise); "
      f"steps on the team {int(team['steps_on_team'])} of {int(team['steps'])}; same bits: {same}")
PYEOF
fi

if has replicas; then
  echo; echo "## Replicas against one run on one and on two threads"
  # the second replica's bed (seed dem.seed + 1) once, so that no timed run prepares it
  "$GL" run "$KUMAR" --solver dem "${KSET[@]}" --set dem.seed=2 --set dem.travel=0.1 \
    --set dem.steady_travel=0 --out "$WORK/prep_seed2" --quiet >/dev/null
  # one run on one thread, one run on two, two replicas: in turn, REPS times
  rm -f "$WORK/threads1r.walls" "$WORK/threads2r.walls" "$WORK/replicas2.walls"
  for ((r = 0; r < REPS; ++r)); do
    run_once threads1r --threads 1
    run_once threads2r --threads 2
    run_once replicas2 --threads 2 --replicas 2
  done
  for n in threads1r threads2r replicas2; do median <"$WORK/$n.walls" >"$WORK/$n.wall"; done
  echo "# threads1r: $(tr '\n' ' ' <"$WORK/threads1r.walls")s;" \
    "threads2r: $(tr '\n' ' ' <"$WORK/threads2r.walls")s;" \
    "replicas2: $(tr '\n' ' ' <"$WORK/replicas2.walls")s"
  for n in threads1r threads2r; do
    r=$(paste "$WORK/$n.walls" "$WORK/replicas2.walls" | awk '{print 2 * $1 / $2}' | median)
    pairs=$(paste "$WORK/$n.walls" "$WORK/replicas2.walls" | awk '{printf "%.2f ", 2 * $1 / $2}')
    awk -v n="${n:7:1}" -v a="$(cat "$WORK/$n.wall")" -v b="$(cat "$WORK/replicas2.wall")" \
        -v r="$r" -v p="$pairs" 'BEGIN {
      f = "2 replicas (1 thread each, median %.1f s) against one run on %s thread(s) "
      f = f "(median %.1f s): %.2fx the samples per wall second (paired: %s; target: close to 2x)\n"
      printf f, b, n, a, r, p }'
  done
fi

if has fields; then
  echo; echo "## Fields off against on (one thread)"
  ARGS_A=(--threads 1 --set output.fields=true) ARGS_B=(--threads 1 --set output.fields=false)
  timed_ab fields_on fields_off
  on=$(cat "$WORK/fields_on.wall"); off=$(cat "$WORK/fields_off.wall")
  r=$(cat "$WORK/fields_on.fields_off.ratio")
  awk -v a="$on" -v b="$off" -v r="$r" 'BEGIN {
    f = "medians: fields on %.1f s, off %.1f s: off saves %.0f%% "
    f = f "(paired; the case default is off for the reduced Kumar case)\n"
    printf f, a, b, 100 * (1 - 1 / r) }'
fi

if has frictionless; then
  echo; echo "## Frictionless path against the general law (grains.friction = 0, one thread)"
  F0=(--set grains.friction=0.0)
  "$GL" run "$KUMAR" --solver dem "${KSET[@]}" "${F0[@]}" --set dem.travel=16 \
    --out "$WORK/prep_mu0" --quiet >/dev/null
  ARGS_A=("${F0[@]}" --set dem.frictionless_path=false) \
    ARGS_B=("${F0[@]}" --set dem.frictionless_path=true)
  timed_ab mu0_general mu0_path
  "$PY" - "$WORK/mu0_general" "$WORK/mu0_path" <<'PYEOF'
import json, sys
w = [json.load(open(d + "/summary.json"))["dem"] for d in sys.argv[1:]]
t = [float(open(d + ".wall").read()) for d in sys.argv[1:]]
same = w[0]["drag"] == w[1]["drag"] and w[0]["lift"] == w[1]["lift"]
r = float(open(sys.argv[1] + ".mu0_path.ratio").read())
print(f"medians: general law {t[0]:.1f} s, frictionless path {t[1]:.1f} s: saves "
      f"{100 * (1 - 1 / r):.0f}% (paired); same drag and lift bits: {same}")
PYEOF
fi

if has sleep; then
  echo; echo "## Sleeping grains (dem.sleep at speed 0) against none (one thread)"
  ARGS_A=(--threads 1 --set dem.sleep=false) ARGS_B=(--threads 1 --set dem.sleep=true)
  timed_ab sleep_dense_off sleep_dense_on
  TCASE="$ROOT/cases/kumar2019/reduced_phi035.toml"
  timed_ab sleep_dilute_off sleep_dilute_on
  # the full-size box (61,640 grains, V0 1 m/s, Omega 2): its first 6 d; the packing once
  TCASE="$ROOT/cases/kumar2019/full_phi0818.toml"
  TSET=(--set dem.travel=6 --set dem.steady_travel=1)
  "$GL" run "$TCASE" --solver dem --set dem.travel=0.1 --set dem.steady_travel=0 \
    --out "$WORK/prep_full" --quiet >/dev/null
  timed_ab sleep_full_off sleep_full_on
  unset TCASE TSET
  PYTHONPATH="$ROOT/python" "$PY" - "$WORK" <<'PYEOF'
import sys
from grainlift import io
work = sys.argv[1]
print("| run | grains | no sleeping (s) | sleeping (s) | saving | grain-steps asleep | woken | "
      "same drag, lift bits |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for tag, what in (("dense", "reduced Phi 0.8, 30 d"), ("dilute", "reduced Phi 0.35, 30 d"),
                  ("full", "full box Phi 0.818, first 6 d")):
    off, on = (f"{work}/sleep_{tag}_{s}" for s in ("off", "on"))
    t = [float(open(d + ".wall").read()) for d in (off, on)]
    r = float(open(off + f".sleep_{tag}_on.ratio").read())
    w = [io.summary(d, "dem") for d in (off, on)]
    same = w[0]["drag"] == w[1]["drag"] and w[0]["lift"] == w[1]["lift"]
    diag = io.read(on, "dem").diagnostics
    grains = int(diag.get("grains", 0))
    print(f"| {what} | {grains} | {t[0]:.2f} | {t[1]:.2f} | {100 * (1 - 1 / r):.0f}% | "
          f"{100 * float(diag['sleeping_fraction']):.0f}% | {int(diag['sleep_wakes'])} | {same} |")
PYEOF
fi

if has fem; then
  echo; echo "## FEM: error against time on the demo geometry" \
    "(2 threads; nested iteration on and off)"
  # nested up to refinement 4 (177,440 unknowns, ~50 s), the whole continuation per mesh to 3;
  # incompressible ("none": the dilatant default's refinement 4 is another study)
  for r in 0 1 2 3 4; do
    "$GL" run "$ROOT/cases/demo/demo.toml" --solver fem --threads 2 --quiet \
      --set continuum.refinement=$r --set continuum.mesh_error_estimate=false \
      --set 'continuum.dilatancy="none"' --set output.fields=false --out "$WORK/fem_nested_$r" \
      >/dev/null
    ((r == 4)) && continue
    "$GL" run "$ROOT/cases/demo/demo.toml" --solver fem --threads 2 --quiet \
      --set continuum.refinement=$r --set continuum.mesh_error_estimate=false \
      --set continuum.nested=false --set 'continuum.dilatancy="none"' --set output.fields=false \
      --out "$WORK/fem_flat_$r" >/dev/null
  done
  "$PY" "$ROOT/studies/fem_pareto/fem_pareto.py" "$WORK"/fem_nested_{0,1,2,3,4} -- \
    "$WORK"/fem_flat_{0,1,2,3}
fi

if has error; then
  echo; echo "## Error against wall time"
  [[ -s "$WORK/threads1/summary.json" ]] || "$GL" run "$KUMAR" --solver dem "${KSET[@]}" \
    --out "$WORK/threads1" --quiet >/dev/null
  "$GL" run "$ROOT/cases/guillard2014/gradient.toml" --solver dem --out "$WORK/guillard" \
    --quiet >/dev/null
  "$PY" "$ROOT/studies/dem_error_vs_time/error_vs_time.py" "$WORK/threads1" "$WORK/guillard"
fi
echo "# load after: $(cut -d' ' -f1-3 /proc/loadavg)"
