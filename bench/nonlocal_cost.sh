#!/usr/bin/env bash
# The nonlocal fluidity's cost against the local mu(I) solve (issue 35: within 3x), on the demo
# (cases/demo/demo.toml, Omega 2), one thread, the runs alternated so that each ratio is of
# runs under one load: at the demo's own target_error (0.01), at refinement 3 and at
# refinement 2, the nonlocal model at the A of the case's rheology file and at A = 0.5.
# Prints each run's wall time (the whole command) and, per setting, the ratio of the medians.
#
#   bench/nonlocal_cost.sh [build dir (build)] [repetitions (3)]
#
# About 2 min per repetition on the 2-core reference machine; runs in a temporary folder.
set -euo pipefail
. "$(dirname "$0")/lib.sh"  # median, scratch_folder
cd "$(dirname "$0")/.."
G=$(realpath "${1:-build}/bin/grainlift")
REPS=${2:-3}
scratch_folder
NGF=(--set 'continuum.model="nonlocal_fluidity"')
A05=(--set continuum.nonlocal_amplitude=0.5)
R3=(--set continuum.refinement=3 --set continuum.target_error=1e-5)
R2=(--set continuum.refinement=2 --set continuum.target_error=0)
run() {  # run NAME ARGS...: one solve, its wall time appended to OUT/NAME
  local name=$1
  shift
  # the local law incompressible ("none"; the nonlocal model is incompressible anyway)
  /usr/bin/time -f "%e" -o "$OUT/t" "$G" run cases/demo/demo.toml --solver fem --threads 1 \
    --quiet --out "$OUT/$name" --set 'continuum.dilatancy="none"' "$@" >/dev/null 2>&1 ||
    { echo "$name failed"; exit 1; }
  cat "$OUT/t" >>"$OUT/$name.times"
  echo "$name $(cat "$OUT/t") s"
}
"$G" --version | head -1
for ((rep = 1; rep <= REPS; ++rep)); do
  run local_default
  run nonlocal_default "${NGF[@]}"
  run nonlocal_A0.5_default "${NGF[@]}" "${A05[@]}"
  run local_r3 "${R3[@]}"
  run nonlocal_r3 "${NGF[@]}" "${R3[@]}"
  run local_r2 "${R2[@]}"
  run nonlocal_r2 "${NGF[@]}" "${R2[@]}"
  run nonlocal_A0.5_r2 "${NGF[@]}" "${R2[@]}" "${A05[@]}"
done
echo
echo "| setting | local (s) | nonlocal (s) | ratio |"
echo "|---|---|---|---|"
for pair in "default:local_default:nonlocal_default" \
  "default, A 0.5:local_default:nonlocal_A0.5_default" "refinement 3:local_r3:nonlocal_r3" \
  "refinement 2:local_r2:nonlocal_r2" "refinement 2, A 0.5:local_r2:nonlocal_A0.5_r2"; do
  IFS=: read -r label l n <<<"$pair"
  a=$(median <"$OUT/$l.times")
  b=$(median <"$OUT/$n.times")
  echo "| $label | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", b / a }') |"
done
