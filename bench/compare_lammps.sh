#!/usr/bin/env bash
# grainlift against LAMMPS on the same beds, back to back, on this machine and under its
# current load. Prints, for each bed and thread (rank) count, grain-steps per second of wall
# time and per CPU-second (mobile grains x steps; wall disks and the intruder are not counted
# for either code) and the ratios grainlift / LAMMPS.
#
#   bench/compare_lammps.sh [build dir (build-dem)] [beds ("dense dilute jammed")] [threads ("1 2")]
#
# Environment: PAUSE (seconds of sleep before every timed run, default 1), OMP_PROC_BIND and
# OMP_PLACES (default true and cores),
# STEPS (timed steps, default 2000), REPS (repetitions of every run,
# default 1; medians are printed), WORK (data files, default /tmp/grainlift_lammps),
# SAME_STEPS (default 1: grainlift times the same STEPS steps after the same 500 warm-up
# steps as LAMMPS, GRAINLIFT_BENCH_STEPS; 0: grainlift runs its 100-step iterations for at
# least 3 s, i.e. tens of thousands of steps, in which the intruder ploughs on and the dense
# bed gathers several times more contacts than in LAMMPS's 2000 steps).
# grainlift: bench/dem_throughput (100-step iterations after 500 warm-up steps),
# "real_time" and "cpu_time" (process CPU time, all threads). LAMMPS (Debian package lammps,
# `lmp`; Open MPI for two ranks, bound to cores): bench/lammps/bed.in on the same bed
# (exported by dem_export_lammps_bed), "Loop time" of the timed run and its "% CPU use"
# (CPU time = loop time x CPU use x ranks).
set -euo pipefail
BUILD=${1:-build-dem}
BEDS=${2:-"dense dilute jammed"}
THREADS=${3:-"1 2"}
STEPS=${STEPS:-2000}
REPS=${REPS:-1}
WORK=${WORK:-/tmp/grainlift_lammps}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"
# grainlift's threads bound one per core, as LAMMPS's ranks are (mpirun --bind-to core): left
# to the scheduler, about one short two-thread run in two started with both threads on one
# core and stayed there (half the rate for the whole run; docs/performance.md)
export OMP_PROC_BIND=${OMP_PROC_BIND:-true} OMP_PLACES=${OMP_PLACES:-cores}
if [[ ${SAME_STEPS:-1} == 1 ]]; then
  export GRAINLIFT_BENCH_STEPS=$STEPS
else
  unset GRAINLIFT_BENCH_STEPS
fi

declare -A BM=([dense]=BM_DenseBed [dilute]=BM_DiluteBed [jammed]=BM_JammedBed)
declare -A PHI=([dense]=0.82 [dilute]=0.35 [jammed]=0.86)

. "$(dirname "$0")/lib.sh"  # median

echo "# $(date -u +%FT%TZ)  $(nproc) cores " "load: $(cut -d' ' -f1-3 /proc/loadavg) " \
  "build: $BUILD " "grainlift timed steps: ${GRAINLIFT_BENCH_STEPS:->= 3 s}"
echo "# M grain-steps/s: wall = per second of wall time, cpu = per CPU-second"
printf '%-7s %3s | %9s %9s | %9s %9s | %10s %10s\n' bed thr "gl wall" "gl cpu" "lmp wall" \
  "lmp cpu" "ratio wall" "ratio cpu"
for bed in $BEDS; do
  data="$WORK/$bed.data"
  [[ -s "$data" ]] || "$BUILD/bin/dem_export_lammps_bed" "${PHI[$bed]}" "$data" >/dev/null
  grains=$(awk '$2 == 1 && NF == 7 {n++} END {print n}' "$data")
  for t in $THREADS; do
    gw=() gc=() lw=() lc=()
    for ((r = 0; r < REPS; ++r)); do
      sleep "${PAUSE:-1}"
      json=$("$BUILD/bin/dem_throughput" --benchmark_filter="^${BM[$bed]}/$t/" \
               --benchmark_format=json 2>/dev/null)
      read -r w c < <(python3 -c '
import json, sys
b = json.load(sys.stdin)["benchmarks"][0]
g = b["grains"]
print(g * 100 / (b["real_time"] * 1e-3), g * 100 / (b["cpu_time"] * 1e-3))' <<<"$json")
      gw+=("$w") gc+=("$c")
      sleep "${PAUSE:-1}"
      if [[ $t == 1 ]]; then
        out=$(cd "$WORK" && lmp -log none -in "$HERE/lammps/bed.in" -var data "$data" \
              -var steps "$STEPS")
      else
        out=$(cd "$WORK" && mpirun --allow-run-as-root --bind-to core -np "$t" lmp -log none \
              -in "$HERE/lammps/bed.in" -var data "$data" -var steps "$STEPS")
      fi
      lt=$(grep 'Loop time' <<<"$out" | tail -1 | awk '{print $4}')
      cpu=$(grep '% CPU use' <<<"$out" | tail -1 | awk '{sub("%", "", $1); print $1}')
      lw+=("$(awk -v g="$grains" -v s="$STEPS" -v t="$lt" 'BEGIN {print g * s / t}')")
      lc+=("$(awk -v g="$grains" -v s="$STEPS" -v t="$lt" -v c="$cpu" -v n="$t" \
                'BEGIN {print g * s / (t * c / 100 * n)}')")
    done
    a=$(printf '%s\n' "${gw[@]}" | median); b=$(printf '%s\n' "${gc[@]}" | median)
    c=$(printf '%s\n' "${lw[@]}" | median); d=$(printf '%s\n' "${lc[@]}" | median)
    awk -v bed="$bed" -v t="$t" -v a="$a" -v b="$b" -v c="$c" -v d="$d" 'BEGIN {
      printf "%-7s %3d | %9.1f %9.1f | %9.1f %9.1f | %9.2fx %9.2fx\n", bed, t, a / 1e6, b / 1e6,
             c / 1e6, d / 1e6, a / c, b / d }'
  done
done
echo "# load after: $(cut -d' ' -f1-3 /proc/loadavg)"
