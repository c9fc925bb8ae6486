#!/usr/bin/env bash
# The nonlocal fluidity model against the local mu(I) and the particles (issue 35): the FEM of
# cases/demo/demo.toml (its box, and the 16 D x 9.6 D box of docs/crosscheck.md) at spin ratios
# 0, 2, 4, local and nonlocal_fluidity at A = 0.25, 0.5, 1 (the splitting stopped at the default
# continuum.nonlocal_tolerance, the forces moving by less than 0.2% in two iterations
# running). The DEM's numbers are those of
# docs/crosscheck.md (same case, same boxes). Prints one table row per run.
#   studies/nonlocal/nonlocal_study.sh [OUT_DIR] [boxes|depth|models|all]
#     (default runs/nonlocal, all; boxes ~25 min, depth ~10 min, models ~15 min on one core)
# models: the wall law measured on the grains, alone and with A = 0.5, and A calibrated on the
#   demo's grains alone and with the wall law (issue 35's table):
#   the demo's grains: continuum.wall_law = "measured_slip" from OUT_DIR/demo_wall.toml (the
#   demo's rheology.toml with the [wall] table that scripts/fit_wall.py fits on
#   runs/wall_law/demo_o*/dem: the demo's DEM at Omega 0-8, made first if absent); the
#   depth sweep's grains (no slip histogram there): a Coulomb wall with their measured mu_w,
#   0.117 (studies/wall_law: the three gravity runs' mu_w 0.128, 0.113, 0.114 averaged).
#   Then studies/nonlocal/model_table.py prints the comparison with the DEM.
# depth: the heavy-lid scenes of the depth sweep at h = 4, 8, 12 D (studies/depth, its box with
# 6 D of bed below), local and A = 0.5.
set -euo pipefail
cd "$(dirname "$0")/../.."
O=${1:-runs/nonlocal}
PART=${2:-all}
mkdir -p "$O"
G=$(realpath "${GRAINLIFT:-build/bin/grainlift}")
CASE=cases/demo/demo.toml
BIG=(--set 'domain.x_range=[-0.8,0.8]' --set 'domain.y_range=[-0.48,0.48]')
run() {  # run NAME ARGS...
  local name=$1; shift
  local dir="$O/$name"
  mkdir -p "$dir"
  if [[ ! -f "$dir/fem.h5" ]]; then
    "$G" run "$CASE" --solver fem --quiet --out "$dir" --set continuum.refinement=2 \
      --set continuum.target_error=0 --set 'continuum.dilatancy="none"' "$@" \
      > "$dir/log.txt" 2>&1 ||
      { echo "| $name | failed: $(tail -1 "$dir/log.txt" | cut -c1-160) |"; return 0; }
  fi
  /usr/bin/python3 - "$dir" "$name" <<'PY'
import sys
sys.path.insert(0, "python")
from grainlift import io
r = io.read(sys.argv[1], "fem")
m, d, dv = r.attrs("means"), r.attrs("diagnostics"), r.attrs("derived")
it = d.get("nonlocal_iterations", "-")
if it != "-":
    it = f"{it} (last change {100 * d['nonlocal_force_change']:.2g}%)"
def g(v, digits=4, scale=None):  # "-" when absent, 0 below 1e-9 of the scale (symmetry)
    if v is None:
        return "-"
    return "0" if scale and abs(v) < 1e-9 * scale else f"{v:.{digits}g}"
D = abs(m["drag"])
print(f"| {sys.argv[2]} | {g(m['drag'])} | {g(m['lift'], scale=D)} | "
      f"{g(m['torque'], scale=D * 0.05)} | {g(dv.get('drag_coefficient'), 3)} | "
      f"{g(dv.get('lift_over_buoyancy'), 3)} | {it} | {r.wall_seconds:.0f} |")
PY
}
echo "| run | drag (N/m) | lift (N/m) | torque (N) | C_d | L/B | splitting iterations | wall (s) |"
echo "|---|---|---|---|---|---|---|---|"
if [[ $PART == depth || $PART == all ]]; then
  CASE=cases/guillard2014/depth_sweep.toml
  for h in 4 8 12; do
    depth=$(awk -v h=$h 'BEGIN { printf "%.6g", h * 0.015 }')
    d6=(--set 'domain.y_range=[-0.09,0.03]' --set "scene.depth=$depth")
    run "depth_h${h}_local" "${d6[@]}"
    run "depth_h${h}_A0.5" "${d6[@]}" --set 'continuum.model="nonlocal_fluidity"' \
      --set continuum.nonlocal_amplitude=0.5
  done
  CASE=cases/demo/demo.toml
fi
if [[ $PART == models || $PART == all ]]; then
  for o in 0 0.5 1 2 4 8; do  # the demo's DEM with the slip histogram, for the wall law
    d=runs/wall_law/demo_o${o/./}/dem
    [[ -f $d/dem.h5 ]] || "$G" run cases/demo/demo.toml --solver dem --threads 1 --quiet \
      --set "intruder.omega=$(awk -v o="$o" 'BEGIN { printf "%g", 10 * o }')" --out "$d" >/dev/null
  done
  WALL=$(realpath -m "$O/demo_wall.toml")
  if [[ ! -f $WALL ]]; then
    cp cases/demo/rheology.toml "$WALL"
    /usr/bin/python3 scripts/fit_wall.py "$WALL" runs/wall_law/demo_o*/dem
  fi
  MEASURED=(--set "continuum.rheology_file=\"$WALL\"" --set 'continuum.wall_law="measured_slip"')
  NGF=(--set 'continuum.model="nonlocal_fluidity"' --set continuum.nonlocal_amplitude=0.5)
  # A measured on the demo's grains (`grainlift calibrate cases/demo/demo.toml --nonlocal`, the
  # [nonlocal] table of cases/demo/rheology.toml), stated so that the wall-law runs (whose
  # rheology file is demo_wall.toml) use it too; no runs without the table
  ACAL=$(awk '/^\[/ { t = $0 } t == "[nonlocal]" && $1 == "amplitude" { print $3 }' \
    cases/demo/rheology.toml)
  NGF_CAL=(--set 'continuum.model="nonlocal_fluidity"' --set "continuum.nonlocal_amplitude=$ACAL")
  # the calibrated Phi(I) of the case's rheology (every other run: incompressible, "none")
  DIL=(--set 'continuum.dilatancy="phi_i"')
  for box in demo big; do
    extra=()
    [[ $box == big ]] && extra=("${BIG[@]}")
    for W in 0 2 4 8; do
      [[ $box == big && $W == 8 ]] && continue  # no DEM run of the 16 D box at Omega 8
      omega=$((10 * W))
      run "${box}_O${W}_local" "${extra[@]}" --set "intruder.omega=$omega"
      run "${box}_O${W}_A0.5" "${extra[@]}" --set "intruder.omega=$omega" "${NGF[@]}"
      run "${box}_O${W}_wall" "${extra[@]}" --set "intruder.omega=$omega" "${MEASURED[@]}"
      run "${box}_O${W}_dil" "${extra[@]}" --set "intruder.omega=$omega" "${DIL[@]}"
      run "${box}_O${W}_wall_dil" "${extra[@]}" --set "intruder.omega=$omega" \
        "${MEASURED[@]}" "${DIL[@]}"
      run "${box}_O${W}_wall_A0.5" "${extra[@]}" --set "intruder.omega=$omega" \
        "${MEASURED[@]}" "${NGF[@]}"
      [[ -n $ACAL ]] || continue
      run "${box}_O${W}_Acal" "${extra[@]}" --set "intruder.omega=$omega" "${NGF_CAL[@]}"
      run "${box}_O${W}_wall_Acal" "${extra[@]}" --set "intruder.omega=$omega" \
        "${MEASURED[@]}" "${NGF_CAL[@]}"
    done
  done
  CASE=cases/guillard2014/depth_sweep.toml
  for h in 4 8 12; do
    depth=$(awk -v h=$h 'BEGIN { printf "%.6g", h * 0.015 }')
    d6=(--set 'domain.y_range=[-0.09,0.03]' --set "scene.depth=$depth")
    coulomb=(--set 'continuum.wall="coulomb"' --set continuum.wall_friction=0.117)
    run "depth_h${h}_wall" "${d6[@]}" "${coulomb[@]}"
    run "depth_h${h}_wall_A0.5" "${d6[@]}" "${coulomb[@]}" "${NGF[@]}"
    run "depth_h${h}_dil" "${d6[@]}" "${DIL[@]}"
    run "depth_h${h}_wall_dil" "${d6[@]}" "${coulomb[@]}" "${DIL[@]}"
  done
  CASE=cases/demo/demo.toml
fi
[[ $PART == boxes || $PART == all ]] || exit 0
for box in demo big; do
  extra=()
  [[ $box == big ]] && extra=("${BIG[@]}")
  for W in 0 2 4; do
    omega=$((10 * W))
    run "${box}_O${W}_local" "${extra[@]}" --set "intruder.omega=$omega"
    for A in 0.25 0.5 1.0; do
      run "${box}_O${W}_A${A}" "${extra[@]}" --set "intruder.omega=$omega" \
        --set 'continuum.model="nonlocal_fluidity"' --set "continuum.nonlocal_amplitude=$A"
    done
  done
done
