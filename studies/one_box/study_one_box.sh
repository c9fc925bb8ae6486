#!/usr/bin/env bash
# The cross-check on one box (docs/crosscheck.md, "Current answer"; docs/results-guillard2014.md,
# the FEM column): the continuum on the DEM's own domain against the particles, case by case,
# with the continuum's former box (continuum.box_half_size, symmetric about the intruder) beside
# it so that the part of the old disagreement that was the box can be read off.
#   studies/one_box/study_one_box.sh [dem|fem|tables|all] [OUT_DIR]   (default all, runs/one_box)
# dem: 12 DEM runs, two at a time, one thread each (~15 min on 2 cores): the demo at six spin
#   ratios, the 16 D x 9.6 D box at Omega 0, 2, 4, the depth sweep's h = 8 D with and without
#   the gradient, Guillard's gradient case. fem: ~40 solves (~10 min). tables: python3
#   studies/one_box/one_box_tables.py OUT_DIR.
# A run whose result exists is skipped (delete its folder to rerun).
set -euo pipefail
cd "$(dirname "$0")/../.."
PART=${1:-all}
O=${2:-runs/one_box}
G=$(realpath "${GRAINLIFT:-build/bin/grainlift}")
PY=${PYTHON:-/usr/bin/python3}
DEMO=cases/demo/demo.toml
DEPTH=cases/guillard2014/depth_sweep.toml
BIG="--set domain.x_range=[-0.8,0.8] --set domain.y_range=[-0.48,0.48]"
D6="--set domain.y_range=[-0.09,0.03]"   # 6 D of bed below the centre (the sweep's box)

# NAME CASE ARGS... ; the demo's spin sweep names carry Omega x 10 (o05 = 0.5)
scenes() {
  for om in "0 0.0" "05 5.0" "1 10.0" "2 20.0" "4 40.0" "8 80.0"; do
    set -- $om
    echo "demo_o$1 $DEMO --set intruder.omega=$2"
  done
  for om in "0 0.0" "2 20.0" "4 40.0"; do
    set -- $om
    echo "big_o$1 $DEMO $BIG --set intruder.omega=$2"
  done
  for h in 4 6 8 12; do
    echo "heavy_lid_h$h $DEPTH $D6 --set scene.depth=$(awk -v h=$h 'BEGIN{printf "%.6g", h*0.015}')"
    echo "lid_only_h$h $DEPTH $D6 --set 'scene.depth_mode=\"lid_only\"'" \
      "--set scene.depth=$(awk -v h=$h 'BEGIN{printf "%.6g", h*0.015}')"
  done
  # Guillard's gradient case (free surface 4 D above, a wall 4 D below), its calibrated law, ref 3
  echo "gradient cases/guillard2014/gradient.toml" \
    "--set 'continuum.rheology_file=\"rheology.toml\"' --set continuum.refinement=3"
  echo "free_surface_h2 $DEPTH $D6 --set 'scene.depth_mode=\"free_surface\"'" \
    "--set 'domain.walls=[\"bottom\"]' --set scene.depth=0.03"
}
# the scenes the DEM runs (the rest of the depth sweep's DEM is docs/results-guillard2014.md's)
dem_scenes() { scenes | grep -E '^(demo_|big_|heavy_lid_h8 |lid_only_h8 |gradient )'; }
# the former box of each scene: half sizes from the nearer end and wall of domain.x/y_range
old_box() {
  case $1 in
    demo_*) echo "--set continuum.box_half_size=[0.4,0.24]" ;;
    big_*) echo "--set continuum.box_half_size=[0.8,0.48]" ;;
    gradient) echo "--set continuum.box_half_size=[0.09,0.06]" ;;
    *) echo "--set continuum.box_half_size=[0.09,0.03]" ;;
  esac
}

run_one() {  # run_one DIR SOLVER CASE ARGS...
  local dir=$1 solver=$2 case=$3; shift 3
  [[ -f "$dir/$solver.h5" ]] && return 0
  # the FEM at refinement 2 where the scene states no level (the cases' default is a 1% target)
  [[ $solver == fem && $* != *continuum.refinement* ]] &&
    set -- "$@" --set continuum.refinement=2 --set continuum.target_error=0
  # the FEM incompressible, the law of its tables (the default is dilatant where calibrated)
  [[ $solver == fem && $* != *continuum.dilatancy* ]] &&
    set -- "$@" --set "'continuum.dilatancy=\"none\"'"
  mkdir -p "$dir"
  if ! eval "\"$G\" run $case --solver $solver --threads 1 --quiet --out \"$dir\" $*" \
      > "$dir/log.txt" 2>&1; then
    echo "FAILED: $dir (see $dir/log.txt)" >&2
    return 0
  fi
  echo "done: $dir"
}

if [[ $PART == dem || $PART == all ]]; then
  dem_scenes | {
    while read -r name case args; do
      run_one "$O/$name/dem" dem "$case" "$args" &
      # two at a time
      while [[ $(jobs -r | wc -l) -ge 2 ]]; do sleep 2; done
    done
    wait
  }
fi

if [[ $PART == fem || $PART == all ]]; then
  scenes | while read -r name case args; do
    # the DEM's box, far field auto
    run_one "$O/$name/fem" fem "$case" "$args"
    case $name in demo_o0|demo_o2|big_*|heavy_lid_h8|lid_only_h8|gradient)
      run_one "$O/$name/fem_old" fem "$case" "$args $(old_box "$name")" ;;      # the former box
    esac
    case $name in
      demo_*)
        run_one "$O/$name/fem_open" fem "$case" "$args --set continuum.far_field=open"
        run_one "$O/$name/fem_noslip" fem "$case" "$args --set continuum.wall=no_slip" ;;
      big_*|heavy_lid_h8)
        run_one "$O/$name/fem_periodic" fem "$case" "$args --set continuum.far_field=periodic" ;;
    esac
    # the top edge where the DEM's lid settled: its disks' mean height over the averaged travel,
    # less a grain radius (the FE box's top is otherwise the lid's starting edge)
    if [[ $name == *_h8 && -f "$O/$name/dem/dem.h5" ]]; then
      top=$("$PY" -c "
import h5py, sys
with h5py.File(sys.argv[1], 'r') as f:
    t, y = f['lid/time'][:], f['lid/y'][:]
    g = f['geometry'].attrs
    start = f['diagnostics'].attrs['mean_travel_from'] * g['grain_diameter'] / g['velocity_x']
    print('%.6g' % (y[t >= start].mean() - 0.5 * g['grain_diameter']))" "$O/$name/dem/dem.h5")
      run_one "$O/$name/fem_settled" fem "$case" "$args --set continuum.bed_top=$top"
    fi
  done
fi

if [[ $PART == tables || $PART == all ]]; then
  "$PY" studies/one_box/one_box_tables.py "$G" "$O"
fi
