#!/usr/bin/env bash
# The DEM's SIMD dispatch and bits on CPUs this machine is not (README.md beside this file).
#
#   bash tests/other_cpus/check_other_cpus.sh BUILD [STEPS]
#
# BUILD: the x86-64 build folder (its bin/dem_state_hash). Expected, on the small benchmark
# beds (dem_state_hash's scale 0.25: dense, dilute and jammed, STEPS steps, default 500):
#   - the reference: this machine's scalar code (GRAINLIFT_SIMD=scalar);
#   - emulated x86-64 CPUs (qemu-x86_64 -cpu): Haswell (AVX2 and FMA, no AVX-512) dispatches to
#     "avx2", Nehalem (SSE4.2, no AVX) to "scalar"; each on one and two threads gives the
#     reference's bits, and `grainlift --version` names that target;
#   - 64-bit Arm (Debian's cross compiler): the engine compiles for every Arm target Highway has
#     (NEON, SVE, SVE2, SVE_256, SVE2_128); with the arm64 libhwy installed it is also linked
#     and run under qemu-aarch64, each target forced at a vector length it runs (SVE at 128 to
#     512 bits), and "auto" must dispatch to sve2: every one gives the reference's bits (one
#     thread: qemu-aarch64 7.2 hangs when a program starts a second thread).
# Exit 0 when all of it holds, 1 on a difference, 77 (skipped) without qemu-user or the cross
# compiler (scripts/install-deps installs both).
set -euo pipefail

build=$(cd "${1:?usage: check_other_cpus.sh BUILD [STEPS]}" && pwd)
steps=${2:-500}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=$build/other_cpus
mkdir -p "$work"
hash_bin=$build/bin/dem_state_hash
[ -x "$hash_bin" ] || { echo "no $hash_bin: build the bench programs first" >&2; exit 1; }
for tool in qemu-x86_64 qemu-aarch64 aarch64-linux-gnu-g++; do
  command -v "$tool" > /dev/null || {
    echo "SKIPPED: $tool is missing (scripts/install-deps installs qemu-user and" \
         "g++-aarch64-linux-gnu)"
    exit 77
  }
done
[ "$(uname -m)" = x86_64 ] || { echo "SKIPPED: the x86-64 checks need an x86-64 machine"; exit 77; }

unset GRAINLIFT_SIMD GRAINLIFT_NO_SIMD  # "auto" means the emulated CPU's choice
# every run reads the beds this machine prepared (one bed for all, whatever each CPU's libm)
export GRAINLIFT_BENCH_CACHE=$work/beds
beds=dense,dilute,jammed
scale=0.25
failed=0

# run LABEL EXPECTED_TARGET THREADS COMMAND...: the target the run names on stderr and its
# hashes (one per bed and thread count) against the reference
run() {
  local label=$1 want=$2 threads=$3
  shift 3
  local out err got
  out=$(mktemp) err=$(mktemp)
  if ! "$@" "$steps" "$beds" "$threads" "$scale" > "$out" 2> "$err"; then
    echo "FAILED  $label: the run failed"; sed 's/^/    /' "$err" "$out"; failed=1
    rm -f "$out" "$err"; return
  fi
  got=$(sed -n 's/^simd target: \([a-z0-9_]*\).*/\1/p' "$err")
  local differ
  differ=$(awk 'NR == FNR { ref[$1] = $NF; next }
                $NF != ref[$1] { printf "%s%s threads %s", sep, $1, $3; sep = ", " }' \
             "$work/reference.txt" "$out")
  if [ "$got" != "$want" ]; then
    echo "FAILED  $label: dispatched to '$got', expected '$want'"; failed=1
  elif [ -n "$differ" ] || [ ! -s "$out" ]; then
    echo "FAILED  $label ($got): bits differ from the scalar reference on: ${differ:-no output}"
    failed=1
  else
    echo "ok      $label: $got, $(wc -l < "$out") runs with the reference's bits"
  fi
  rm -f "$out" "$err"
}

GRAINLIFT_SIMD=scalar "$hash_bin" "$steps" "$beds" 1 "$scale" > "$work/reference.txt" 2> /dev/null
echo "reference: this machine's scalar code, $steps steps of the small beds:"
sed 's/^/    /' "$work/reference.txt"

# x86-64 CPUs without this machine's instruction sets (qemu's notes on CPU features its
# emulator leaves out go to stderr and are dropped)
run "x86-64 Haswell (AVX2, no AVX-512), auto" avx2 1,2 qemu-x86_64 -cpu Haswell "$hash_bin"
run "x86-64 Nehalem (no AVX), auto" scalar 1,2 qemu-x86_64 -cpu Nehalem "$hash_bin"
# ... and the name the user is shown there
if [ -x "$build/bin/grainlift" ]; then
  for cpu_target in Haswell:avx2 Nehalem:scalar; do
    cpu=${cpu_target%:*} want=${cpu_target#*:}
    line=$(qemu-x86_64 -cpu "$cpu" "$build/bin/grainlift" --version 2> /dev/null |
             grep "^DEM SIMD:" || true)
    if [[ "$line" == "DEM SIMD: $want "* ]]; then
      echo "ok      grainlift --version on $cpu: $line"
    else
      echo "FAILED  grainlift --version on $cpu: '$line', expected 'DEM SIMD: $want ...'"
      failed=1
    fi
  done
fi

# 64-bit Arm: cross-compiled (ccache makes the rebuild cheap), linked when the arm64 libhwy is
# there
arm=$work/aarch64
if ! cmake -S "$here/project" -B "$arm" -DCMAKE_TOOLCHAIN_FILE="$here/aarch64-linux-gnu.cmake" \
       > "$work/aarch64-configure.log" 2>&1 ||
   ! cmake --build "$arm" -j2 > "$work/aarch64-build.log" 2>&1; then
  echo "FAILED  aarch64: the cross build failed ($work/aarch64-*.log):"
  grep -E "error|Error" "$work"/aarch64-*.log | head -20 | sed 's/^/    /'
  exit 1
fi
if [ ! -x "$arm/bin/dem_state_hash" ]; then
  echo "ok      aarch64: the engine compiles for every Arm target (not linked: no arm64 libhwy;" \
       "scripts/install-deps adds it where the package mirror has arm64)"
else
  qa=(qemu-aarch64 -L /usr/aarch64-linux-gnu)
  # CPU vector lengths in bytes: SVE_256 needs 32, SVE2_128 16; the others run at any
  run "aarch64 NEON" neon 1 env GRAINLIFT_SIMD=neon "${qa[@]}" "$arm/bin/dem_state_hash"
  for target_vl in sve:16 sve:64 sve2:32 sve_256:32 sve2_128:16; do
    t=${target_vl%:*} vl=${target_vl#*:}
    run "aarch64 $t at $((vl * 8)) bits" "$t" 1 env GRAINLIFT_SIMD="$t" \
        "${qa[@]}" -cpu "max,sve-default-vector-length=$vl" "$arm/bin/dem_state_hash"
  done
  run "aarch64 auto at 512 bits" sve2 1 "${qa[@]}" -cpu max,sve-default-vector-length=64 \
      "$arm/bin/dem_state_hash"
fi
exit $failed
