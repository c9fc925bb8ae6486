#!/usr/bin/env bash
# Reproduces docs/results-kumar2019.md: the reduced Kumar 2019 sweeps and their plots.
#   scripts/reproduce_kumar2019.sh [OUT_DIR] [THREADS]
# About 30-40 minutes on one core of a 2-core machine. Plots and tables go to OUT_DIR
# (default runs/kumar2019); copy the PNGs to docs/img/ to update the docs.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-runs/kumar2019}
THREADS=${2:-1}
G=build/bin/grainlift
PY=/usr/bin/python3
[ -x "$G" ] || { echo "build first: make build" >&2; exit 2; }
run() { $G sweep "$@" --solver dem --quiet --threads "$THREADS"; }

# L/D against Omega (Kumar Fig. 3a, 3c): V0 = 1 m/s, R = 0.05 m, Omega = omega / 20
run cases/kumar2019/reduced_phi080.toml --vary intruder.omega=0,10,20,40,80,200,400 --out "$OUT/omega_phi080"
run cases/kumar2019/reduced_phi035.toml --vary intruder.omega=0,10,20,40,80,200,400 --out "$OUT/omega_phi035"
# Drag against V0 at Omega = 0 (Kumar Fig. 2a): slope near 2 on log-log
run cases/kumar2019/reduced_phi080.toml --set intruder.omega=0 \
    --vary "intruder.velocity=[0.5,0.0],[1.0,0.0],[2.0,0.0],[4.0,0.0]" --out "$OUT/speed_phi080"
# L_inf/D_inf against mu, dilute bed at saturated spin (Kumar Fig. 8, Phi = 0.135, Omega = 20)
run cases/kumar2019/reduced_phi035.toml --set grains.area_fraction=0.135 --set intruder.omega=400 \
    --set dem.travel=120 --vary grains.friction=0.1,0.25,0.5,0.75,1.0 --out "$OUT/mu_phi0135"

$PY scripts/plot_sweep.py ld-omega "$OUT/ld_omega.png" \
    "$OUT/omega_phi080/sweep.csv:Phi 0.8" "$OUT/omega_phi035/sweep.csv:Phi 0.35"
$PY scripts/plot_sweep.py drag-speed "$OUT/drag_speed.png" "$OUT/speed_phi080/sweep.csv:Phi 0.8, Omega 0"
$PY scripts/plot_sweep.py ld-mu "$OUT/ld_mu.png" "$OUT/mu_phi0135/sweep.csv:Phi 0.135, Omega 20"
