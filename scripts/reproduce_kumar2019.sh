#!/usr/bin/env bash
# Reproduces docs/results-kumar2019.md: the reduced Kumar 2019 sweeps and their plots.
#   scripts/reproduce_kumar2019.sh [OUT_DIR] [PART]
# PART = dense (the Phi 0.8 sweeps), dilute (Phi 0.35 and 0.135), plots, or all (default);
# dense and dilute can run at the same time on two cores. About 15 minutes each on one core.
# Plots and tables go to OUT_DIR (default runs/kumar2019); docs/img/ holds the committed copies.
set -euo pipefail
cd "$(dirname "$0")/.."
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

plots() {
  local phi035=() mu=()
  for s in $SEEDS; do
    phi035+=("$OUT/omega_phi035/seed$s/sweep.csv:Phi 0.35")
    mu+=("$OUT/mu_phi0135/seed$s/sweep.csv:Phi 0.135, Omega 10")
  done
  $PY scripts/plot_sweep.py ld-omega "$OUT/ld_omega.png" "$OUT/omega_phi080/sweep.csv:Phi 0.8" "${phi035[@]}"
  $PY scripts/plot_sweep.py drag-speed "$OUT/drag_speed.png" "$OUT/speed_phi080/sweep.csv:Phi 0.8, Omega 0"
  $PY scripts/plot_sweep.py ld-mu "$OUT/ld_mu.png" "${mu[@]}"
  local r="$OUT/omega_phi080"
  $PY scripts/plot_distributions.py "$OUT/distributions_phi080.png" "$r/intruder.omega=0:Omega 0" \
      "$r/intruder.omega=20:Omega 1" "$r/intruder.omega=80:Omega 4" "$r/intruder.omega=400:Omega 20"
}

case "$PART" in
  dense) dense ;;
  dilute) dilute ;;
  plots) plots ;;
  all) dense; dilute; plots ;;
  *) echo "PART must be dense, dilute, plots or all" >&2; exit 2 ;;
esac
