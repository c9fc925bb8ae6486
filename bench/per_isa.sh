#!/usr/bin/env bash
# The speed targets per SIMD target (issue 36), on this machine: for every target the build and
# CPU run (`grainlift --version`), forced with GRAINLIFT_SIMD, one after the other:
#   1. the whole production run against LAMMPS, one thread each, same bed
#      (bench/compare_lammps_production.sh: reduced dense Kumar, 1,200,000 steps);
#   2. the jammed bed against LAMMPS, one thread each (bench/compare_lammps.sh build jammed 1);
#   3. the demo's DEM on one thread and on two (cases/demo/demo.toml --solver dem);
#   4. `make demo`'s three commands on 2 cores (run --solver both, plots, report).
# LAMMPS runs beside each target's own runs, so each ratio is of one pair under one load.
#
#   bench/per_isa.sh [build dir (build)] [targets (all this CPU runs)]
#
# Needs LAMMPS (`lmp`, scripts/install-deps) for 1 and 2 (skipped with a message without it).
# About 5 min per target on the 2-core reference machine. Prints one block per target and a
# summary table.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
G=$BUILD/bin/grainlift
targets=${2:-$("$G" --version | sed -n 's/.*this build and CPU: \([^;]*\);.*/\1/p' | tr -d ',')}
WORK=${WORK:-/tmp/grainlift_per_isa}
mkdir -p "$WORK"
isa=$(grep -o -m1 'avx512f' /proc/cpuinfo || grep -o -m1 'avx2' /proc/cpuinfo || echo "none")
echo "# $(date -u +%FT%TZ) $(nproc) cores, CPU's widest x86 extension: $isa;" \
  "$("$G" --version | head -1); targets: $targets"
have_lmp=0
command -v "${LMP:-lmp}" > /dev/null && have_lmp=1
summary=()
for t in $targets; do
  echo; echo "## GRAINLIFT_SIMD=$t"
  export GRAINLIFT_SIMD=$t
  prod="-" jam="-"
  if [[ $have_lmp == 1 ]]; then
    out=$(WORK=$WORK/prod_$t bash bench/compare_lammps_production.sh "$BUILD" 1 2>&1)
    echo "$out" | grep -E "^(code|grainlift|lammps|lmp/gl) " || echo "$out" | tail -5
    prod=$(echo "$out" | awk '$1 == "lmp/gl" && $2 == "|" { print $3; exit }')
    out=$(WORK=$WORK/jam_$t bash bench/compare_lammps.sh "$BUILD" jammed 1 2>&1)
    echo "$out" | grep -E "^(bed|jammed)"
    jam=$(echo "$out" | awk '$1 == "jammed" { print $(NF - 1); exit }')
  else
    echo "skipped the LAMMPS comparisons: no lmp (Debian package lammps)"
  fi
  demo=()
  for th in 1 2; do
    s=$(date +%s.%N)
    "$G" run cases/demo/demo.toml --solver dem --threads $th --quiet --out "$WORK/demo_$t" \
      > /dev/null
    demo+=("$(echo "$(date +%s.%N) - $s" | bc)")
  done
  s=$(date +%s.%N)
  rm -rf "$WORK/make_demo_$t"
  "$G" run cases/demo/demo.toml --solver both --threads 2 --quiet --out "$WORK/make_demo_$t" \
    > /dev/null
  /usr/bin/python3 scripts/plot_results.py "$WORK/make_demo_$t" > /dev/null
  "$G" report "$WORK/make_demo_$t" > /dev/null
  mk=$(echo "$(date +%s.%N) - $s" | bc)
  printf 'demo DEM: %.1f s (1 thread), %.1f s (2 threads); make demo (built): %.1f s\n' \
    "${demo[0]}" "${demo[1]}" "$mk"
  summary+=("$(printf '| %s | %s | %s | %.1f | %.1f | %.1f |' "$t" "$prod" "$jam" \
    "${demo[0]}" "${demo[1]}" "$mk")")
done
echo
echo "| target | production run, LAMMPS / grainlift | jammed bed, grainlift / LAMMPS |" \
  "demo DEM 1 thread (s) | 2 threads (s) | make demo, built (s) |"
echo "|---|---|---|---|---|---|"
printf '%s\n' "${summary[@]}"
