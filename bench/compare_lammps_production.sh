#!/usr/bin/env bash
# grainlift against LAMMPS on one whole production run of a case, from rest to the end, on the
# same bed (the packing `grainlift run` uses, exported by dem_export_lammps_case), back to back
# on this machine and under its current load, one thread (rank) each. Prints the wall time of
# each whole command, microseconds per step, the inner solver time (grainlift's wall_seconds
# from summary.json, LAMMPS's "Loop time") and the ratios LAMMPS / grainlift; then, as a check
# that both did the same physics, the mean drag, lift and torque on the intruder after the
# steady start of each (grainlift's summary.json; LAMMPS's force file from
# bench/lammps/production.in, averaged the same way) and the intruder's final spin in LAMMPS.
#
#   bench/compare_lammps_production.sh [build dir (build)] [reps (1)]
#
# Environment: CASE (default cases/kumar2019/reduced_phi080.toml of this repository), SETS
# (space-separated --set overrides, default "intruder.velocity=[0.25,0.0] intruder.omega=5.0
# dem.travel=30"), PAUSE (seconds of sleep before every timed run, default 1), OMP_PROC_BIND
# and OMP_PLACES (default true and cores), WORK (data, outputs and logs, default
# /tmp/grainlift_lammps_production), LMP (LAMMPS executable, default lmp; Debian package
# lammps), LMP_NEIGH (LAMMPS neighbor style, default bin). With REPS > 1 the times are medians;
# the forces are those of the last repetition (both codes are deterministic on one thread).
set -euo pipefail
BUILD=${1:-build}
REPS=${2:-1}
HERE=$(cd "$(dirname "$0")" && pwd)
CASE=${CASE:-$(cd "$HERE/.." && pwd)/cases/kumar2019/reduced_phi080.toml}
SETS=${SETS:-"intruder.velocity=[0.25,0.0] intruder.omega=5.0 dem.travel=30"}
WORK=${WORK:-/tmp/grainlift_lammps_production}
LMP=${LMP:-lmp}
mkdir -p "$WORK"
CORES=$(nproc)  # before OMP_NUM_THREADS=1, which nproc would report
# one thread each, bound to a core (LAMMPS runs one MPI-less rank with one OpenMP thread)
export OMP_PROC_BIND=${OMP_PROC_BIND:-true} OMP_PLACES=${OMP_PLACES:-cores} OMP_NUM_THREADS=1

set_args=()
for s in $SETS; do set_args+=(--set "$s"); done

# the bed and the LAMMPS variables ("# ..." note lines, "-var name value" lines)
data="$WORK/bed.data"
export_out=$("$BUILD/bin/dem_export_lammps_case" "$CASE" "$data" "${set_args[@]}")
vars=()
while read -r flag name value; do
  [[ $flag == -var ]] && vars+=(-var "$name" "$value")
done <<<"$export_out"
getvar() { awk -v n="$1" '$1 == "-var" && $2 == n {print $3}' <<<"$export_out"; }
steps=$(getvar steps)
bed_note=$(grep -o 'grains [0-9]* (walls [0-9]*), area fraction [0-9.]*' <<<"$export_out")

. "$(dirname "$0")/lib.sh"  # median
now() { date +%s.%N; }
# the solver's own wall time from a summary.json
wall_py='import json, sys; print(json.load(open(sys.argv[1]))["dem"]["wall_seconds"])'

echo "# $(date -u +%FT%TZ)  $CORES cores  load: $(cut -d' ' -f1-3 /proc/loadavg) " \
  "build: $BUILD  reps: $REPS"
echo "# case: $CASE  --set: $SETS"
echo "# $steps steps of dt $(getvar dt) s; exported bed: $bed_note"
gw=() gi=() lw=() li=()
for ((r = 0; r < REPS; ++r)); do
  rm -rf "$WORK/grainlift"
  sleep "${PAUSE:-1}"
  t0=$(now)
  "$BUILD/bin/grainlift" run "$CASE" --solver dem "${set_args[@]}" --threads 1 \
    --out "$WORK/grainlift" --quiet >"$WORK/grainlift.log" 2>&1
  t1=$(now)
  gw+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')")
  gi+=("$(python3 -c "$wall_py" "$WORK/grainlift/summary.json")")

  sleep "${PAUSE:-1}"
  t0=$(now)
  (cd "$WORK" && "$LMP" -log none -in "$HERE/lammps/production.in" "${vars[@]}" \
     -var forces "$WORK/lammps_forces.txt" -var neigh "${LMP_NEIGH:-bin}" >"$WORK/lammps.log" 2>&1)
  t1=$(now)
  lw+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')")
  li+=("$(grep 'Loop time' "$WORK/lammps.log" | tail -1 | awk '{print $4}')")
done
a=$(printf '%s\n' "${gw[@]}" | median); b=$(printf '%s\n' "${gi[@]}" | median)
c=$(printf '%s\n' "${lw[@]}" | median); d=$(printf '%s\n' "${li[@]}" | median)
printf '%-10s | %9s %9s | %9s %9s\n' code "wall s" "us/step" "inner s" "us/step"
awk -v s="$steps" -v a="$a" -v b="$b" -v c="$c" -v d="$d" 'BEGIN {
  printf "%-10s | %9.2f %9.2f | %9.2f %9.2f\n", "grainlift", a, a / s * 1e6, b, b / s * 1e6
  printf "%-10s | %9.2f %9.2f | %9.2f %9.2f\n", "lammps", c, c / s * 1e6, d, d / s * 1e6
  printf "%-10s | %8.2fx %9s | %8.2fx\n", "lmp/gl", c / a, "", d / b }'
echo "# inner: grainlift summary.json wall_seconds (solver only), LAMMPS Loop time"
# each repetition runs the two codes back to back: their ratio sees the same state of the host
paired=$(for ((r = 0; r < REPS; ++r)); do
  awk -v a="${gw[r]}" -v c="${lw[r]}" 'BEGIN {print c / a}'
done)
echo "# paired wall ratios lmp/gl: $(echo "$paired" | awk '{printf "%.2f ", $1}')->" \
  "median $(echo "$paired" | median | awk '{printf "%.2fx", $1}')"

# physics check: the means after the steady start, LAMMPS's samples averaged as grainlift does
python3 - "$WORK/grainlift/summary.json" "$WORK/lammps_forces.txt" "$(getvar t_steady)" \
  "$(getvar blocks)" "$(getvar vx)" "$(getvar vy)" <<'EOF'
import json, math, sys
summary, forces, t_steady, blocks, vx, vy = sys.argv[1:]
t_steady, blocks, vx, vy = float(t_steady), int(blocks), float(vx), float(vy)
g = json.load(open(summary))["dem"]
v = math.hypot(vx, vy); ex, ey = vx / v, vy / v
drag, lift, torque = [], [], []
for line in open(forces):
    if line.startswith("#"):
        continue
    step, t, fx, fy, tq = map(float, line.split())
    if step > 0 and t >= t_steady * (1 - 1e-12):
        drag.append(-(fx * ex + fy * ey)); lift.append(-fx * ey + fy * ex); torque.append(tq)

def block_mean(x):  # blocks of equal length, the first n mod B samples left out
    n = len(x); B = max(1, min(blocks, n)); k = n // B; s = n - k * B
    m = [sum(x[s + b * k:s + (b + 1) * k]) / k for b in range(B)]
    mu = sum(m) / B
    se = math.sqrt(sum((q - mu) ** 2 for q in m) / (B - 1) / B) if B > 1 else float("nan")
    return mu, se

print(f"# means after t >= {t_steady:g} s (the steady start): force on the intruder, "
      "drag = -F.V/|V|,"
      f" lift = F_y in the frame of V, N/m; torque N; +- block standard error ({blocks} blocks)")
print(f"{'code':<10} | {'drag':>18} | {'lift':>18} | {'torque':>20} | samples")
print(f"{'grainlift':<10} | {g['drag']:8.4g} +- {g['drag_stderr']:<6.2g} | {g['lift']:8.4g} +- "
      f"{g['lift_stderr']:<6.2g} | {g['torque']:9.4g} +- {g['torque_stderr']:<7.2g} | "
      f"{g['samples']}")
(d, sd), (l, sl), (q, sq) = block_mean(drag), block_mean(lift), block_mean(torque)
n = len(drag) // max(1, min(blocks, len(drag))) * max(1, min(blocks, len(drag)))
print(f"{'lammps':<10} | {d:8.4g} +- {sd:<6.2g} | {l:8.4g} +- {sl:<6.2g} | "
      f"{q:9.4g} +- {sq:<7.2g} | {n}")
def ratio(a, b):
    return f"{a / b:.3f}x" if b != 0 else "n/a"
print(f"{'lmp/gl':<10} | {ratio(d, g['drag']):>18} | {ratio(l, g['lift']):>18} | "
      f"{ratio(q, g['torque']):>20} |")
print("# grainlift: " + g["notes"])
EOF
gl_bed=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["dem"]["notes"])' \
           "$WORK/grainlift/summary.json" |
           grep -o 'grains [0-9]* (walls [0-9]*), area fraction [0-9.]*')
if [[ $gl_bed != "$bed_note" ]]; then
  echo "# WARNING: the exported bed ($bed_note) is not grainlift's ($gl_bed)"
fi
grep 'intruder omega_z' "$WORK/lammps.log" | sed 's/^/# lammps: /'
echo "# load after: $(cut -d' ' -f1-3 /proc/loadavg)"
