#!/usr/bin/env bash
# The continuum studies of docs/results-continuum.md (issue 4), one part at a time or all:
#   studies/continuum/study_continuum.sh
#     [split|split_bg|mesh|delta|hdelta|wellposed|box|box_bg|depth_bg|dem_box|spin|spin_bg|
#      spin_mesh|plots|all] [OUT_DIR]
# Guillard 2014 gradient case (cases/guillard2014/gradient.toml) in a fixed FE box around the
# intruder; the depth h is set by moving the intruder down a tall bed whose top is at y = 0.06 m.
#   split  full nonlinear solves (a) against base state + linear correction (b), h/D = 4..32,
#          and the base states alone (no gravity, same P0)              ~15 min on one core
#   split_bg  the same with the well-posed Barker-Gray law at refinement 3  ~30 min
#   mesh   refinement 0..2 (MESH_MAX=3: and 3) at h = 8 D, 1..3 adaptive cycles from 1
#   delta  regularisation delta at refinement 2, h = 8 D                 ~5 min
#   hdelta mesh levels 0..3 at fixed delta = 0.1, 0.03, 0.015 V/R (h = 8 D), and level 4
#          at 0.1 and 0.03 V/R: the discretisation converging for a fixed regularised
#          problem                                                        ~30 min
#   wellposed  the same with the well-posed Barker-Gray law (regularisation = "barker_gray"):
#          mesh levels 0..5 at h = 8 D (5 on mpirun -np 2), delta 1e-2..1e-4 at
#          refinement 3                                                  ~40 min
#   box    FE box size at h = 16 D                                       ~5 min
#   box_bg the same with the Barker-Gray law, f = 1..6                   ~10 min
#   depth_bg  Barker-Gray at refinement 4 at h = 4, 16, 32 D (mpirun -np 2)  ~20 min
#   dem_box  the shipped gradient case on the DEM's domain, refinements 2-4 (mpirun -np 2) ~7 min
#   spin   L/D against Omega, no-slip and Coulomb walls (Kumar geometry) ~5 min
#   spin_bg  the same with the Barker-Gray law, and refinement 3 at Omega 2 and 10  ~20 min
#   spin_mesh  refinement 4 of spin_bg at Omega 2 and 10 (mpirun -np 2)    ~30 min
#   plots  figures into docs/img from OUT_DIR
set -euo pipefail
cd "$(dirname "$0")/../.."
PART=${1:-all}
O=${2:-runs/continuum_study}
G=${GRAINLIFT:-build/bin/grainlift}
PY=${PYTHON:-/usr/bin/python3}
CASE=cases/guillard2014/gradient.toml
SHIPPED=(--solver fem --threads 1 --set output.fields=false --set output.vtu=false)
S=("${SHIPPED[@]}" --set "domain.y_range=[-0.6,0.06]")  # the tall bed of the depth studies
BOX="continuum.box_half_size=[0.06,0.04]"
D=0.015
RHO_G=$(awk 'BEGIN { print 0.82 * 2.5 * 9.81 }')   # rho g of the case (2D units)
ypos() { awk -v h="$1" -v D=$D 'BEGIN { printf "%.6g", 0.06 - h * D }'; }
p0() { awk -v h="$1" -v D=$D -v rg="$RHO_G" 'BEGIN { printf "%.8g", rg * h * D }'; }

# every part names its law, so that the studies do not depend on the default (Barker-Gray's
# since session 5; the Jop series were run when Jop's law was the default)
JOP='continuum.regularisation="chauchat_medale"'
BGL='continuum.regularisation="barker_gray"'
TWO_RANKS=(mpirun --allow-run-as-root --oversubscribe -np 2)

LAUNCH=()  # a launcher for run(), e.g. (mpirun -np 2)
run() {  # run OUT_SUBDIR ARGS...: skip when the result exists (delete it to rerun); log kept
  local dir="$O/$1"; shift
  [[ -f "$dir/fem.h5" ]] && return 0
  mkdir -p "$dir"
  "${LAUNCH[@]}" "$G" run "$CASE" "${S[@]}" "$@" --out "$dir" > "$dir.log" 2>&1 ||
    echo "FAILED: $dir (see $dir.log)" | tee -a "$O/failures.txt"
  grep -E "^ fem:" "$dir.log" || true
}

part_split() {  # part_split SUBDIR EXTRA_ARGS...
  local sub=$1
  shift
  for h in 4 8 16 32; do
    local pos="intruder.position=[0.0,$(ypos $h)]"
    run "$sub/full_h$h" --set "$BOX" --set "$pos" "$@"
    run "$sub/linearised_h$h" --set "$BOX" --set "$pos" \
      --set 'continuum.gravity_treatment="linearised"' "$@"
    run "$sub/base_h$h" --set "$BOX" --set "$pos" --set "scene.gravity=[0.0,0.0]" \
      --set "continuum.ambient_pressure=$(p0 $h)" "$@"
  done
}
part_split_bg() {  # the split with the well-posed Barker-Gray law, refinement 3
  part_split split_bg --set "$BGL" --set continuum.refinement=3
}
part_mesh() {
  for r in 0 1 2 ${MESH_MAX:+$(seq -s ' ' 3 "$MESH_MAX")}; do
    run "mesh/full_r$r" --set "$BOX" --set "intruder.position=[0.0,$(ypos 8)]" --set "$JOP" \
      --set continuum.refinement=$r
    run "mesh/linearised_r$r" --set "$BOX" --set "intruder.position=[0.0,$(ypos 8)]" --set "$JOP" \
      --set continuum.refinement=$r --set 'continuum.gravity_treatment="linearised"'
  done
  for a in 1 2 3; do
    run "mesh/adaptive_a$a" --set "$BOX" --set "intruder.position=[0.0,$(ypos 8)]" --set "$JOP" \
      --set continuum.refinement=1 --set continuum.adaptive_cycles=$a
  done
}
part_delta() {
  for d in 1e-1 1e-2 1e-3 1e-4; do
    run "delta/delta_$d" --set "$BOX" --set "intruder.position=[0.0,$(ypos 8)]" --set "$JOP" \
      --set continuum.delta=$d
  done
}
part_hdelta() {
  # V/R = 0.05 / 0.0075 = 6.667 1/s
  local spec d top
  for spec in 0.6667:4 0.2:4 0.1:3; do  # delta:finest level
    d=${spec%:*}
    top=${spec#*:}
    for r in $(seq 0 "$top"); do
      run "hdelta/delta_${d}_r$r" --set "$BOX" --set "intruder.position=[0.0,$(ypos 8)]" \
        --set "$JOP" --set continuum.delta=$d --set continuum.refinement=$r
    done
  done
}
part_wellposed() {
  local bg=(--set "$BOX" --set "intruder.position=[0.0,$(ypos 8)]" --set "$BGL")
  for r in 0 1 2 3 4; do
    run "wellposed/bg_r$r" "${bg[@]}" --set continuum.refinement=$r
  done
  # refinement 5 (705,088 unknowns): MUMPS on two ranks, 10 min and 2.7 GB per rank
  LAUNCH=("${TWO_RANKS[@]}")
  run "wellposed/bg_r5" "${bg[@]}" --set continuum.refinement=5
  LAUNCH=()
  for d in 1e-2 1e-4; do
    run "wellposed/bg_delta_$d" "${bg[@]}" --set continuum.refinement=3 --set continuum.delta=$d
  done
  for r in 2 3 4; do  # the Coulomb wall (mu_w = intruder.friction = 0.5); 4 on two ranks
    [[ $r == 4 ]] && LAUNCH=("${TWO_RANKS[@]}")
    run "wellposed/bg_coulomb_r$r" "${bg[@]}" --set continuum.refinement=$r \
      --set 'continuum.wall="coulomb"'
  done
  LAUNCH=()
}
box_of() { awk -v f="$1" 'BEGIN { printf "[%.4g,%.4g]", 0.06 * f, 0.04 * f }'; }
part_box() {
  for f in 1 1.5 2 3; do
    run "box/box_x$f" --set "continuum.box_half_size=$(box_of $f)" \
      --set "intruder.position=[0.0,$(ypos 16)]" --set "$JOP"
  done
}
# the box study with the Barker-Gray law, to f = 6 (the box top at the free surface)
part_box_bg() {
  for f in 1 2 3 4 6; do
    run "box_bg/box_x$f" --set "continuum.box_half_size=$(box_of $f)" \
      --set "intruder.position=[0.0,$(ypos 16)]" --set "$BGL"
  done
}
part_depth_bg() {  # the mesh limit at the other depths: Barker-Gray, refinement 4 on two ranks
  LAUNCH=("${TWO_RANKS[@]}")
  for h in 4 16 32; do
    run "depth_bg/full_h${h}_r4" --set "$BOX" --set "intruder.position=[0.0,$(ypos $h)]" \
      --set "$BGL" --set continuum.refinement=4
  done
  LAUNCH=()
}
part_dem_box() {  # the shipped case on the DEM's own domain (h = 4 D, box to the free surface)
  local tall=("${S[@]}")
  S=("${SHIPPED[@]}")
  LAUNCH=("${TWO_RANKS[@]}")
  for r in 2 3 4; do
    run "dem_box/r$r" --set "$BGL" --set continuum.refinement=$r
  done
  LAUNCH=()
  S=("${tall[@]}")
}
spin_run() {  # spin_run OUT_SUBDIR WALL OMEGA ARGS...: the Kumar geometry, P0 = 1000 Pa, no gravity
  local dir="$O/$1" wall=$2 om=$3
  shift 3
  [[ -f "$dir/fem.h5" ]] && return 0
  "${LAUNCH[@]}" "$G" run cases/kumar2019/reduced_phi080.toml --solver fem --quiet --threads 1 \
    --set output.fields=false --set output.vtu=false --set continuum.wall=\"$wall\" \
    --set "continuum.box_half_size=[0.5,0.35]" --set intruder.omega=$om "$@" --out "$dir" ||
    echo "FAILED: $dir" | tee -a "$O/failures.txt"
}
part_spin() {  # Jop's law at refinement 2
  for wall in no_slip coulomb; do
    for om in 0 10 20 40 80 200; do
      spin_run "spin/${wall}_omega$om" $wall $om --set "$JOP"
    done
  done
}
part_spin_bg() {  # L/D against Omega with the Barker-Gray law; refinement 3 at Omega 2 and 10
  for wall in no_slip coulomb; do
    for r_om in 2:0 2:10 2:20 2:40 2:80 2:200 3:40 3:200; do
      local r=${r_om%%:*} om=${r_om##*:}
      spin_run "spin_bg/${wall}_r${r}_omega$om" $wall $om --set "$BGL" --set continuum.refinement=$r
    done
  done
}
part_spin_mesh() {  # the spin case's mesh limit: refinement 4 at Omega 2 and 10, two ranks (MUMPS)
  LAUNCH=("${TWO_RANKS[@]}")
  for wall in no_slip coulomb; do
    for om in 40 200; do
      spin_run "spin_bg/${wall}_r4_omega$om" $wall $om --set "$BGL" --set continuum.refinement=4
    done
  done
  LAUNCH=()
}
part_plots() {
  "$PY" studies/continuum/plot_continuum_study.py "$O" docs/img
}

mkdir -p "$O"
case "$PART" in
  split) part_split split --set "$JOP" ;;
  split_bg) part_split_bg ;;
  mesh) part_mesh ;;
  delta) part_delta ;;
  hdelta) part_hdelta ;;
  wellposed) part_wellposed ;;
  box) part_box ;;
  box_bg) part_box_bg ;;
  spin) part_spin ;;
  depth_bg) part_depth_bg ;;
  dem_box) part_dem_box ;;
  spin_bg) part_spin_bg ;;
  spin_mesh) part_spin_mesh ;;
  plots) part_plots ;;
  all)
    part_split split --set "$JOP"; part_split_bg; part_mesh; part_delta; part_hdelta
    part_wellposed; part_box; part_box_bg; part_depth_bg; part_dem_box; part_spin; part_spin_bg
    part_spin_mesh; part_plots ;;
  *)
    usage="usage: $0 [split|split_bg|mesh|delta|hdelta|wellposed|box|box_bg|depth_bg|dem_box|"
    usage+="spin|spin_bg|spin_mesh|plots|all] [OUT_DIR]"
    echo "$usage" >&2; exit 2 ;;
esac
