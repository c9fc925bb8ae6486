#!/usr/bin/env bash
# The depth sweep of docs/results-guillard2014.md (issue 13): Guillard et al. 2014's lift and drag
# against depth in 2D, DEM and FEM on the same domains, with the gradient (heavy lid, free surface)
# and without it (gravity on the lid only).
#   studies/depth/study_depth.sh [dem|fem|plots|all|rigid|d6|d6beds|box] [OUT_DIR]
#     (default all, runs/depth_study)
# rigid: the lid scenes again with a rigid lid (domain.lid = "rigid"), into OUT_DIR/dem_rigid.
# d6: the whole DEM sweep again with 6 D of bed below the centre instead of 4 D (the box of
# docs/results-guillard2014.md, its forces read over 20-60 d of travel: plots passes --window),
# plus three runs in a box 18 D wide, into OUT_DIR/dem_d6; 15 runs, ~60 min.
# d6beds: the lid scenes of d6 on two more beds (dem.seed = 2, 3), into OUT_DIR/dem_d6_s2 and
# dem_d6_s3 (20 runs, ~50 min): the bed-to-bed scatter next to the block errors.
# box: h = 8 D in a box 24 D wide, and one with 6 D of bed below (two DEM runs, ~10 min), into
# OUT_DIR/../box_study; compare with heavy_lid_h8 and heavy_lid_h8_bigbox of the sweep.
# dem: 15 DEM runs of 100 d travel, two at a time, ~40 min on 2 cores; fem: 25 solves, ~5 min.
# A run whose result exists is skipped (delete its folder to rerun). Case:
# cases/guillard2014/depth_sweep.toml (a 2 D real bed above the intruder, 4 D below, 12 D wide).
set -euo pipefail
cd "$(dirname "$0")/../.."
PART=${1:-all}
O=${2:-runs/depth_study}
G=$(realpath "${GRAINLIFT:-build/bin/grainlift}")
PY=${PYTHON:-/usr/bin/python3}
CASE=cases/guillard2014/depth_sweep.toml
D=0.015
depth() { awk -v h="$1" -v D=$D 'BEGIN { printf "%.6g", h * D }'; }

# One line per configuration: NAME  ARGS... (ARGS are --set overrides of the case)
configs() {
  for h in 4 6 8 12; do
    echo "heavy_lid_h$h --set scene.depth=$(depth $h)"
  done
  # deeper at the pressure of h = 8 D: g / 2 and g / 4 (at g itself, h = 16 D loads the front
  # contacts of the intruder past 10% overlap with these soft grains, E = 5 MPa: the run stops)
  echo "heavy_lid_h16_g2 --set scene.depth=$(depth 16) --set scene.gravity=[0.0,-4.905]"
  echo "heavy_lid_h32_g4 --set scene.depth=$(depth 32) --set scene.gravity=[0.0,-2.4525]"
  echo "free_surface_h2 --set 'scene.depth_mode=\"free_surface\"'" \
    "--set 'domain.walls=[\"bottom\"]' --set scene.depth=$(depth 2)"
  # mode i against mode ii at h = 4 D: a real 4 D bed above the intruder (gradient.toml's box)
  echo "free_surface_h4 --set 'scene.depth_mode=\"free_surface\"'" \
    "--set 'domain.walls=[\"bottom\"]' --set scene.depth=$(depth 4)"
  for h in 2 4 6 8 12; do
    echo "lid_only_h$h --set 'scene.depth_mode=\"lid_only\"' --set scene.depth=$(depth $h)"
  done
  # the box check: h = 8 D on a box 1.5 times wider with 6 D of bed below instead of 4 D
  echo "heavy_lid_h8_bigbox --set scene.depth=$(depth 8) --set 'domain.x_range=[-0.135,0.135]'" \
    "--set 'domain.y_range=[-0.09,0.03]'"
  # and in that box: the shallowest lid depth, and the no-gradient lift at the P0 of 8 D
  echo "heavy_lid_h4_bigbox --set scene.depth=$(depth 4) --set 'domain.x_range=[-0.135,0.135]'" \
    "--set 'domain.y_range=[-0.09,0.03]'"
  echo "lid_only_h8_bigbox --set 'scene.depth_mode=\"lid_only\"' --set scene.depth=$(depth 8)" \
    "--set 'domain.x_range=[-0.135,0.135]' --set 'domain.y_range=[-0.09,0.03]'"
}

run_one() {  # run_one SOLVER GRAVITY_TREATMENT NAME ARGS...
  local solver=$1 treat=$2 name=$3; shift 3
  local dir="$O/$solver${treat:+_$treat}/$name"
  [[ -f "$dir/$solver.h5" ]] && return 0
  mkdir -p "$dir"
  local extra=()
  if [[ $treat == rigid ]]; then extra=(--set 'domain.lid="rigid"')
  elif [[ $treat == d6 ]]; then extra=(--set 'domain.y_range=[-0.09,0.03]')
  elif [[ $treat == d6_s* ]]; then
    extra=(--set 'domain.y_range=[-0.09,0.03]' --set "dem.seed=${treat#d6_s}")
  elif [[ -n "$treat" ]]; then extra=(--set "continuum.gravity_treatment=\"$treat\""); fi
  # the FEM at refinement 2, the level the tables are of (the case states none: the default
  # would be a 1% target), incompressible as in the tables (the default is dilatant here)
  [[ $solver == fem ]] && extra+=(--set continuum.refinement=2 --set 'continuum.dilatancy="none"')
  if ! "$G" run "$CASE" --solver "$solver" --threads 1 --quiet --out "$dir" "$@" "${extra[@]}" \
      > "$dir/log.txt" 2>&1; then
    echo "FAILED: $dir (see $dir/log.txt)"; return 1
  fi
  echo "done: $dir"
}
export -f run_one depth
export O G CASE D

case $PART in
  dem|all) configs | xargs -d '\n' -P 2 -I{} bash -c 'run_one dem "" {}' ;;&
  fem|all)
    configs | xargs -d '\n' -P 2 -I{} bash -c 'run_one fem full {}'
    # the O(eps) route needs gravity: not for the lid-only scenes
    configs | grep -v lid_only | xargs -d '\n' -P 2 -I{} bash -c 'run_one fem linearised {}' ;;&
  plots|all) "$PY" studies/depth/plot_depth_study.py "$O" docs/img --window 20 60 ;;
  rigid)  # the lid scenes with a rigid lid (domain.lid = "rigid"), into OUT_DIR/dem_rigid
    configs | grep -v free_surface | xargs -d '\n' -P 2 -I{} bash -c 'run_one dem rigid {}' ;;
  d6)  # docs/results-guillard2014.md's box: 6 D of bed below.
    # The bigbox runs keep their width (18 D; the same 6 D below); free_surface_h4 (a 10 D tall
    # bed) is the mode check of the standard series.
    configs | grep -v -E '^free_surface_h4 ' |
      xargs -d '\n' -P 2 -I{} bash -c 'run_one dem d6 {}' ;;
  d6beds)
    for seed in 2 3; do
      configs | grep -E '^(heavy_lid_h(4|6|8|12|16_g2|32_g4|8_bigbox)|lid_only_h(4|8|12)) ' |
        xargs -d '\n' -P 2 -I{} bash -c "run_one dem d6_s$seed {}"
    done ;;
  box)
    O=$(dirname "$O")/box_study; export O
    printf '%s\n' "heavy_lid_h8_w24 --set 'domain.x_range=[-0.18,0.18]'" \
      "heavy_lid_h8_d6 --set 'domain.y_range=[-0.09,0.03]'" |
      xargs -d '\n' -P 2 -I{} bash -c 'run_one dem "" {}' ;;
  dem|fem) ;;
  *) echo "unknown part $PART (dem|fem|plots|all|rigid|d6|d6beds|box)"; exit 2 ;;
esac
