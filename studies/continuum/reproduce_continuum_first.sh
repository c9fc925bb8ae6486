#!/usr/bin/env bash
# Reproduces the tables of docs/results-continuum.md (first measurements, not converged studies).
#   studies/continuum/reproduce_continuum_first.sh [OUT_DIR]      about 6 minutes on one core
set -euo pipefail
cd "$(dirname "$0")/../.."
O=${1:-runs/continuum}
G=${GRAINLIFT:-build/bin/grainlift}
S=(--solver fem --quiet --threads 1 --set output.fields=false --set output.vtu=false)
# Guillard gradient case: depth series (fixed FE box), mesh levels, the same P0 without gradient
"$G" sweep cases/guillard2014/gradient.toml "${S[@]}" --set "continuum.box_half_size=[0.05,0.025]" \
  --set "domain.y_range=[-0.3,0.06]" \
  --vary "intruder.position=[0.0,0.03],[0.0,0.0],[0.0,-0.03],[0.0,-0.09],[0.0,-0.21]" \
  --out "$O/depth"
"$G" sweep cases/guillard2014/gradient.toml "${S[@]}" --set "continuum.box_half_size=[0.06,0.04]" \
  --vary continuum.refinement=0,1,2 --out "$O/mesh"
"$G" run cases/guillard2014/no_gradient.toml "${S[@]}" --set "continuum.box_half_size=[0.06,0.04]" \
  --out "$O/no_gradient" || echo "no_gradient: did not converge (see docs/results-continuum.md)"
# Spin (Kumar geometry, P0 = 1000 Pa): L/D against Omega for both wall conditions
for wall in no_slip coulomb; do
  "$G" sweep cases/kumar2019/reduced_phi080.toml "${S[@]}" --set continuum.wall=\"$wall\" \
    --set "continuum.box_half_size=[0.5,0.35]" --vary intruder.omega=0,10,20,40,80,200 \
    --out "$O/omega_$wall"
done
/usr/bin/python3 studies/kumar2019/plot_sweep.py ld-omega "$O/ld_omega.png" \
  "runs/kumar2019/omega_phi080/sweep.csv:DEM, Phi 0.8" \
  "$O/omega_no_slip/sweep.csv:mu(I), no-slip wall" \
  "$O/omega_coulomb/sweep.csv:mu(I), Coulomb wall mu_w 0.5"
# Regularisation: delta at h = 4 D (box 0.12 m x 0.08 m, refinement 1)
"$G" sweep cases/guillard2014/gradient.toml "${S[@]}" --set "continuum.box_half_size=[0.06,0.04]" \
  --set continuum.refinement=1 --vary continuum.delta=1e-1,1e-2,1e-3,1e-4,1e-5 --out "$O/delta"
