#!/usr/bin/env bash
# Wall time of one continuum solve on one process and on `mpirun -np 2`, same case, same
# options, run one after the other on this machine; prints both times, the speed-up and the
# 1-minute load before each run (the ratio means something only on otherwise idle cores).
#   bench/continuum_ranks.sh CASE [--set KEY=VALUE ...]
# e.g. bench/continuum_ranks.sh cases/kumar2019/reduced_phi080.toml \
#        --set continuum.refinement=2 --set 'continuum.linear_solver="amg"'
set -euo pipefail
. "$(dirname "$0")/lib.sh"  # scratch_folder
cd "$(dirname "$0")/.."
G=${GRAINLIFT:-build/bin/grainlift}
CASE=$1; shift
scratch_folder
common=(--solver fem --threads 1 --quiet --set output.fields=false --set output.vtu=false "$@")
load() { cut -d' ' -f1 /proc/loadavg; }
run() {  # run LABEL COMMAND...: prints "LABEL wall_s load"
  local label=$1; shift
  local l; l=$(load)
  local t0 t1
  t0=$(date +%s.%N)
  "$@" > "$OUT/$label.log" 2>&1 || {
    echo "FAILED: $label (see below)"; tail -5 "$OUT/$label.log"; exit 1
  }
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" -v l="$l" -v n="$label" \
    'BEGIN { printf "%-8s %8.2f s   load before %s\n", n, b - a, l }'
  grep -E "^ fem:" "$OUT/$label.log" || true
}
sleep 1
r1=$(run 1rank "$G" run "$CASE" "${common[@]}" --out "$OUT/one")
echo "$r1"
sleep 1
r2=$(run 2ranks mpirun --allow-run-as-root --oversubscribe -np 2 "$G" run "$CASE" "${common[@]}" \
       --out "$OUT/two")
echo "$r2"
t1=$(echo "$r1" | awk 'NR == 1 { print $2 }')
t2=$(echo "$r2" | awk 'NR == 1 { print $2 }')
awk -v a="$t1" -v b="$t2" 'BEGIN { printf "speed-up of 2 ranks: %.2fx\n", a / b }'
