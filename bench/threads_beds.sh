#!/usr/bin/env bash
# Two threads against one on the demo and on beds of 2,000-10,000 grains (issue 36: >= 1.5x,
# never slower), the DEM's whole run, the runs alternated: the demo (873 grains, 60 d), the
# reduced Kumar bed (cases/kumar2019/reduced_phi080.toml, 2,295 grains, 30 d) and the same
# widened to 2 m x 1.4 m (6,883 grains, 10 d). Fields off; the bed is packed (and cached)
# before the timed runs. Then the demo's whole command as `make demo` runs it (demo_both: both
# solvers, fields on; with two threads the solvers run at once, docs/architecture.md). Prints
# each run's wall time, the DEM team's share of the steps, and per bed the ratio of the medians.
# After each round, the ceiling this machine puts on any team at that moment: the lockstep rows
# of dem_core_contention (two pinned threads stepping with the team's barrier against one doing
# both halves, at about 3, 12, 50 and 200 us of work per thread per step; the demo's step is
# about 12 us per thread), printed beside the beds' ratios as the median over the rounds.
#
#   bench/threads_beds.sh [build dir (build)] [rounds (3)]
#
# About 3 min per round on the 2-core reference machine; runs in a temporary folder.
set -euo pipefail
. "$(dirname "$0")/lib.sh"  # median, scratch_folder
cd "$(dirname "$0")/.."
G=$(realpath "${1:-build}/bin/grainlift")
CONTENTION=$(realpath "${1:-build}/bin/dem_core_contention")
ROUNDS=${2:-3}
scratch_folder
WIDE=(--set 'domain.x_range=[-1.0,1.0]' --set 'domain.y_range=[-0.7,0.7]')
BEDS="demo kumar2295 kumar6883 demo_both"
declare -A CASE=([demo]=cases/demo/demo.toml [kumar2295]=cases/kumar2019/reduced_phi080.toml
  [kumar6883]=cases/kumar2019/reduced_phi080.toml [demo_both]=cases/demo/demo.toml)
DEM="--solver dem --set output.fields=false"
args() {  # args BED: the bed's settings
  case $1 in
    demo) echo "$DEM" ;;
    kumar2295) echo "$DEM --set dem.travel=30 --set dem.steady_travel=5" ;;
    kumar6883) echo "$DEM --set dem.travel=10 --set dem.steady_travel=5" ;;
    demo_both) echo "--solver both" ;;
  esac
}
run() {  # run BED THREADS
  local bed=$1 t=$2 extra=()
  [[ $bed == kumar6883 ]] && extra=("${WIDE[@]}")
  # shellcheck disable=SC2046
  /usr/bin/time -f "%e" -o "$OUT/t" "$G" run "${CASE[$bed]}" --threads "$t" --quiet \
    $(args "$bed") "${extra[@]}" --out "$OUT/$bed$t" >/dev/null 2>&1 ||
    { echo "$bed failed"; exit 1; }
  cat "$OUT/t" >>"$OUT/$bed$t.times"
  local team
  team=$(/usr/bin/python3 - "$OUT/$bed$t/dem.h5" <<'PY'
import sys
import h5py
d = h5py.File(sys.argv[1], "r")["diagnostics"].attrs
print(f"{100 * d['steps_on_team'] / max(1, d['steps']):.0f}%")
PY
)
  echo "$bed threads $t: $(cat "$OUT/t") s (team on $team of the steps)"
}
"$G" --version | head -1
for bed in $BEDS; do  # pack (and cache) each bed first
  run "$bed" 1 >/dev/null
  rm -f "$OUT/${bed}1.times"
done
ceiling() {  # the lockstep rows' ratios, one file per step length
  "$CONTENTION" 1 lockstep | awk -v out="$OUT" '
    BEGIN { split("3 12 50 200", us) }
    /^lockstep/ { on = 1; next }
    on && NF >= 5 { sub(/x$/, "", $4); print $4 >> (out "/ceiling_" us[++i]) }'
}
for ((k = 1; k <= ROUNDS; ++k)); do
  for bed in $BEDS; do
    run "$bed" 1
    run "$bed" 2
  done
  ceiling
  echo -n "lockstep ceiling, round $k:"
  for us in 3 12 50 200; do echo -n " ~$us us $(tail -1 "$OUT/ceiling_$us")x;"; done
  echo
done
echo
echo "| bed | one thread (s) | two threads (s) | ratio |"
echo "|---|---|---|---|"
for bed in $BEDS; do
  a=$(median <"$OUT/${bed}1.times")
  b=$(median <"$OUT/${bed}2.times")
  echo "| $bed | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", a / b }') |"
done
echo
echo "The machine's ceiling for two threads in lockstep" \
  "(dem_core_contention, medians of the rounds):"
for us in 3 12 50 200; do
  echo "  about $us us per thread per step: $(median <"$OUT/ceiling_$us")x"
done
