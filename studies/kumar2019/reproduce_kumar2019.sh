#!/usr/bin/env bash
# Reproduces docs/results-kumar2019.md: the reduced Kumar 2019 sweeps and their plots.
#   studies/kumar2019/reproduce_kumar2019.sh [OUT_DIR] [PART]
# PART = dense (the Phi 0.8 sweeps), dilute (Phi 0.35 and 0.135), fields (Fig. 7 flow fields),
# fields_slow (the same at V0 = 0.25 m/s), phi0585 (Fig. 3b), seeds080 (two more Phi 0.8
# beds), plots, or all (default, which leaves out fields_slow);
# dense and dilute can run at the same time on two cores. About 15 minutes each on one core;
# fields about 10 minutes, fields_slow 6, phi0585 9, seeds080 18 (times in
# docs/results-kumar2019.md).
# Plots and tables go to OUT_DIR (default runs/kumar2019); docs/img/ holds the committed copies.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-runs/kumar2019}
PART=${2:-all}
G=${GRAINLIFT:-build/bin/grainlift}
PY=/usr/bin/python3
[ -x "$G" ] || { echo "build first: make build" >&2; exit 2; }
run() { "$G" sweep "$@" --solver dem --quiet --threads 1; }
SEEDS="1 2 3 4"

dense() {
  # L/D against Omega (Kumar Fig. 3c): V0 = 1 m/s, R = 0.05 m, so Omega = omega / 20
  run cases/kumar2019/reduced_phi080.toml --vary intruder.omega=0,10,20,40,80,200,400 \
      --out "$OUT/omega_phi080"
  # Drag against V0 at Omega = 0 (Kumar Fig. 2a): log-log slope near 2
  run cases/kumar2019/reduced_phi080.toml --set intruder.omega=0 \
      --vary "intruder.velocity=[0.5,0.0],[1.0,0.0],[2.0,0.0],[4.0,0.0]" --out "$OUT/speed_phi080"
}

dilute() {
  # L/D against Omega (Kumar Fig. 3a), four independent beds pooled
  for s in $SEEDS; do
    run cases/kumar2019/reduced_phi035.toml --set dem.seed=$s \
        --vary intruder.omega=0,10,20,40,80,200,400 --out "$OUT/omega_phi035/seed$s"
  done
  # L_inf/D_inf against mu (Kumar Fig. 8, Phi = 0.135) at Omega = 10, V0 = 2 m/s, in a
  # 120 d x 80 d box, four independent beds pooled
  for s in $SEEDS; do
    run cases/kumar2019/reduced_phi035.toml --set grains.area_fraction=0.135 --set dem.seed=$s \
        --set "domain.x_range=[-1.2,1.2]" --set "domain.y_range=[-0.8,0.8]" \
        --set "intruder.velocity=[2.0,0.0]" --set intruder.omega=400 \
        --set dem.travel=240 --set dem.steady_travel=30 \
        --vary grains.friction=0.0,0.1,0.25,0.5,0.75,1.0 --out "$OUT/mu_phi0135/seed$s"
  done
}

fields() {
  # Flow fields of Kumar Fig. 7 at Omega = 0, 1, 10 on the reduced Phi 0.8 bed, V0 = 1 m/s
  # (omega = 20 Omega). The paper's Phi 0.818 at V0 = 0.25 m/s jams in the reduced box (drag
  # 2088 N/m, no wake; see docs/results-kumar2019.md), hence Phi 0.8 and the case's V0.
  # 45 d of travel, fields averaged over the last 30 d: one snapshot every 300 steps
  # (0.6 ms, 0.03 d) gives 1000 snapshots, as theirs.
  # Four beds (seeds 1-4); plot_fields_fig7.py pools them (DIR1+DIR2+...).
  local s dir
  for s in $SEEDS; do
    dir="$OUT/fields_phi080"; [ $s = 1 ] || dir="$OUT/fields_phi080_seed$s"
    run cases/kumar2019/reduced_phi080.toml --set dem.seed=$s --set dem.travel=45 \
        --set dem.steady_travel=15 --set output.fields=true --set dem.field_every=300 \
        --set output.field_spacing=0.25 --set "output.field_half_size=[4.0,3.0]" \
        --set output.vtu=false --vary intruder.omega=0,20,200 --out "$dir"
  done
}

fields_slow() {
  # The same fields at the paper's V0 = 0.25 m/s (omega = 5 Omega), Phi 0.8, one bed: checks
  # that the normalised fields do not depend on V0. 1000 snapshots, one every 1200 steps.
  run cases/kumar2019/reduced_phi080.toml --set "intruder.velocity=[0.25,0.0]" \
      --set dem.travel=45 --set dem.steady_travel=15 --set output.fields=true \
      --set dem.field_every=1200 --set output.field_spacing=0.25 \
      --set "output.field_half_size=[4.0,3.0]" --set output.vtu=false \
      --vary intruder.omega=0,5,50 --out "$OUT/fields_phi080_v025"
}

phi0585() {
  # L/D against Omega at Phi 0.585 (Kumar Fig. 3b); the bed is compressed to 0.78 and thinned
  # by random removal (the engine's preparation for 0.5 <= Phi <= 0.75); four beds pooled
  for s in $SEEDS; do
    run cases/kumar2019/reduced_phi080.toml --set grains.area_fraction=0.585 --set dem.seed=$s \
        --vary intruder.omega=0,10,20,40,80,200,400 --out "$OUT/omega_phi0585/seed$s"
  done
}

seeds080() {
  # Two more independent beds for the Phi 0.8 L/D-Omega sweep (seed 1 is part dense)
  for s in 2 3; do
    run cases/kumar2019/reduced_phi080.toml --set dem.seed=$s \
        --vary intruder.omega=0,10,20,40,80,200,400 --out "$OUT/omega_phi080_seed$s"
  done
}

plots() {
  local phi035=() mu=()
  for s in $SEEDS; do
    phi035+=("$OUT/omega_phi035/seed$s/sweep.csv:Phi 0.35")
    mu+=("$OUT/mu_phi0135/seed$s/sweep.csv:Phi 0.135, Omega 10")
  done
  # Phi 0.8: seed 1 (part dense) pooled with seeds 2 and 3 (part seeds080) where present
  local phi080=("$OUT/omega_phi080/sweep.csv:Phi 0.8") phi0585=()
  for s in 2 3; do
    [ -f "$OUT/omega_phi080_seed$s/sweep.csv" ] &&
      phi080+=("$OUT/omega_phi080_seed$s/sweep.csv:Phi 0.8")
  done
  for s in $SEEDS; do
    [ -f "$OUT/omega_phi0585/seed$s/sweep.csv" ] &&
      phi0585+=("$OUT/omega_phi0585/seed$s/sweep.csv:Phi 0.585")
  done
  $PY studies/kumar2019/plot_sweep.py ld-omega "$OUT/ld_omega.png" "${phi080[@]}" "${phi035[@]}" \
      "${phi0585[@]}"
  $PY studies/kumar2019/plot_sweep.py drag-speed "$OUT/drag_speed.png" \
      "$OUT/speed_phi080/sweep.csv:Phi 0.8, Omega 0"
  $PY studies/kumar2019/plot_sweep.py ld-mu "$OUT/ld_mu.png" "${mu[@]}"
  local r="$OUT/omega_phi080"
  $PY studies/kumar2019/plot_distributions.py "$OUT/distributions_phi080.png" \
      "$r/intruder.omega=0:Omega 0" "$r/intruder.omega=20:Omega 1" \
      "$r/intruder.omega=80:Omega 4" "$r/intruder.omega=400:Omega 20"
  if [ -d "$OUT/fields_phi080" ]; then
    local cols=() w
    for w in 0 20 200; do  # Omega 0, 1, 10; the beds present pooled
      local c="$OUT/fields_phi080/intruder.omega=$w" s
      for s in 2 3 4; do
        [ -d "$OUT/fields_phi080_seed$s/intruder.omega=$w" ] &&
          c+="+$OUT/fields_phi080_seed$s/intruder.omega=$w"
      done
      cols+=("$c")
    done
    $PY studies/kumar2019/plot_fields_fig7.py "$OUT/fields_fig7.png" "${cols[@]}"
    $PY studies/kumar2019/plot_fields_fig7.py --mirror "$OUT/fields_fig7_mirrored.png" \
        "${cols[@]}" > /dev/null
  fi
  local fs="$OUT/fields_phi080_v025"
  if [ -d "$fs/intruder.omega=50" ]; then
    $PY studies/kumar2019/plot_fields_fig7.py "$OUT/fields_fig7_v025.png" "$fs/intruder.omega=0" \
        "$fs/intruder.omega=5" "$fs/intruder.omega=50"
  fi
}

case "$PART" in
  dense) dense ;;
  dilute) dilute ;;
  fields) fields ;;
  fields_slow) fields_slow ;;
  phi0585) phi0585 ;;
  seeds080) seeds080 ;;
  plots) plots ;;
  all) dense; dilute; fields; phi0585; seeds080; plots ;;
  *) echo "PART must be dense, dilute, fields, fields_slow, phi0585, seeds080, plots or all" >&2
     exit 2 ;;
esac
