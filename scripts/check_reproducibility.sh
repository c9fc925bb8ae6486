#!/usr/bin/env bash
# What a result depends on besides the case file (docs/reliability.md, "Reproducible"): runs a
# case's DEM, or FEM, under conditions that change the machine code or the libraries' kernels
# but not the physics, and prints the mean forces to 17 digits with a hash of every force
# sample, so equal bits show as equal lines.
#
#   scripts/check_reproducibility.sh BUILD_DIR CASE [dem|fem] [WORK_DIR]
#
# DEM conditions: 1 thread; 2 threads; the scalar loops instead of the vector ones
# (GRAINLIFT_NO_SIMD=1); glibc's libm without its FMA variants, as on a CPU without FMA
# (GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4: exp, log, pow, sin, ... then differ in the
# last bit for some arguments). FEM: the same libm change, and OpenBLAS's kernels for another
# CPU (OPENBLAS_CORETYPE=Haswell, then Prescott) under UMFPACK.
set -euo pipefail
BUILD=${1:?usage: check_reproducibility.sh BUILD_DIR CASE [dem|fem] [WORK_DIR]}
CASE=${2:?usage: check_reproducibility.sh BUILD_DIR CASE [dem|fem] [WORK_DIR]}
SOLVER=${3:-dem}
WORK=${4:-/tmp/grainlift_reproducibility}
BIN="$BUILD/bin/grainlift"
PY=/usr/bin/python3
mkdir -p "$WORK"

one() {  # one NAME THREADS [ENV=VALUE ...]: run and print the forces of the run
  local name=$1 threads=$2
  shift 2
  local out="$WORK/$SOLVER-$name"
  env "$@" "$BIN" run "$CASE" --solver "$SOLVER" --threads "$threads" --quiet --out "$out" \
    > /dev/null
  "$PY" - "$out/$SOLVER.h5" "$name" <<'EOF'
import hashlib, sys
import h5py
with h5py.File(sys.argv[1], "r") as f:
    m = f["means"].attrs
    h = hashlib.sha256()
    for k in ("fx", "fy", "torque"):
        h.update(f["forces"][k][()].tobytes())
    err = ""
    if "drag_stderr" in m:
        err = f"  (errors {m['drag_stderr']:.3g}, {m['lift_stderr']:.3g})"
    print(f"{sys.argv[2]:<24} drag {m['drag']!r:<22} lift {m['lift']!r:<23} forces sha256 "
          f"{h.hexdigest()[:16]}{err}")
EOF
}

NOFMA="GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4"
echo "$SOLVER of $CASE ($(git -C "$(dirname "$0")/.." rev-parse --short HEAD)," \
  "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
if [ "$SOLVER" = dem ]; then
  one threads-1 1
  one threads-2 2
  one no-simd 1 GRAINLIFT_NO_SIMD=1
  one libm-without-fma 1 "$NOFMA"
else
  one default 1
  one libm-without-fma 1 "$NOFMA"
  one openblas-haswell 1 OPENBLAS_CORETYPE=Haswell
  one openblas-prescott 1 OPENBLAS_CORETYPE=Prescott
fi
