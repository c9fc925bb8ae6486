#!/usr/bin/env bash
# grainlift against LAMMPS on the same beds, back to back, on this machine and under its
# current load. Prints grain-steps per second (mobile grains x steps / wall time; wall disks
# and the intruder are not counted, for either code) and the ratio grainlift / LAMMPS.
#
#   bench/compare_lammps.sh [build dir (build-dem)] [beds (dense dilute jammed)] [threads (1 2)]
#
# Environment: STEPS (LAMMPS timed steps, default 2000), REPS (repetitions of every run,
# default 1; the median is printed), WORK (data files, default /tmp/grainlift_lammps).
# Needs the Debian package lammps (lmp) and Open MPI (mpirun) for the two-rank runs.
set -euo pipefail
BUILD=${1:-build-dem}
BEDS=${2:-"dense dilute jammed"}
THREADS=${3:-"1 2"}
STEPS=${STEPS:-2000}
REPS=${REPS:-1}
WORK=${WORK:-/tmp/grainlift_lammps}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"

declare -A BM=([dense]=BM_DenseBed [dilute]=BM_DiluteBed [jammed]=BM_JammedBed)
declare -A PHI=([dense]=0.82 [dilute]=0.35 [jammed]=0.86)

median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : 0.5*(a[NR/2]+a[NR/2+1])}'; }

echo "# $(date -u +%FT%TZ)  $(nproc) cores  load: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-7s %3s | %14s %14s | %14s | %6s\n' bed thr "grainlift wall" "grainlift cpu" "LAMMPS wall" ratio
for bed in $BEDS; do
  data="$WORK/$bed.data"
  [[ -s "$data" ]] || "$BUILD/bin/dem_export_lammps_bed" "${PHI[$bed]}" "$data" >/dev/null
  grains=$(awk '$2 == 1 && NF == 7 {n++} END {print n}' "$data")
  for t in $THREADS; do
    gl_wall=() gl_cpu=() lm=()
    for ((r = 0; r < REPS; ++r)); do
      # grainlift: Google Benchmark, real time and CPU time of the process per 100 steps
      json=$("$BUILD/bin/dem_throughput" --benchmark_filter="^${BM[$bed]}/$t/" --benchmark_format=json 2>/dev/null)
      read -r w c < <(python3 -c '
import json, sys
b = json.load(sys.stdin)["benchmarks"][0]
g = b["grains"]
print(g * 100 / (b["real_time"] * 1e-3), g * 100 / (b["cpu_time"] * 1e-3))' <<<"$json")
      gl_wall+=("$w") gl_cpu+=("$c")
      # LAMMPS: "Loop time of T on P procs for N steps" of the timed run (the last one)
      if [[ $t == 1 ]]; then
        out=$(cd "$WORK" && lmp -log none -in "$HERE/lammps/bed.in" -var data "$data" -var steps "$STEPS")
      else
        out=$(cd "$WORK" && mpirun --allow-run-as-root --bind-to core -np "$t" lmp -log none \
              -in "$HERE/lammps/bed.in" -var data "$data" -var steps "$STEPS")
      fi
      lt=$(grep 'Loop time' <<<"$out" | tail -1 | awk '{print $4}')
      lm+=("$(awk -v g="$grains" -v s="$STEPS" -v t="$lt" 'BEGIN {print g * s / t}')")
    done
    w=$(printf '%s\n' "${gl_wall[@]}" | median)
    c=$(printf '%s\n' "${gl_cpu[@]}" | median)
    l=$(printf '%s\n' "${lm[@]}" | median)
    awk -v b="$bed" -v t="$t" -v w="$w" -v c="$c" -v l="$l" 'BEGIN {
      printf "%-7s %3d | %12.1f M %12.1f M | %12.1f M | %5.2fx\n", b, t, w / 1e6, c / 1e6, l / 1e6, w / l }'
  done
done
echo "# load after: $(cut -d' ' -f1-3 /proc/loadavg)"
