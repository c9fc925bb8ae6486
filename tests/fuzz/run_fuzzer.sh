#!/usr/bin/env bash
# The Fuzz.* tests (tests/fuzz/CMakeLists.txt, README.md).
#   run_fuzzer.sh build BUILD_DIR
#       configure (once) and build the fuzz project of tests/fuzz/project with clang
#   run_fuzzer.sh run BUILD_DIR TARGET CORPUS SECONDS SCRATCH [libFuzzer options...]
#       run BUILD_DIR/TARGET for SECONDS over tests/fuzz/corpus/CORPUS; new inputs and any
#       reproducer go to SCRATCH, never into the source tree
# Exit codes: 0 no finding, 1 a finding (the reproducer's path is printed) or a build error,
# 77 skipped (no clang or no libFuzzer: install the Debian packages clang libclang-rt-dev).
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
skip=77
cxx="${GRAINLIFT_FUZZ_CXX:-clang++}"
cc="${GRAINLIFT_FUZZ_CC:-clang}"

mode="${1:-}"
build="${2:-}"
[ -n "$mode" ] && [ -n "$build" ] || { echo "usage: $0 build|run BUILD_DIR ..." >&2; exit 2; }

if [ "$mode" = build ]; then
  if ! command -v "$cxx" >/dev/null 2>&1; then
    echo "SKIP: $cxx not found; the fuzz tests need clang and libFuzzer" \
      "(Debian: clang libclang-rt-dev)"
    exit $skip
  fi
  if [ ! -f "$build/CMakeCache.txt" ]; then
    mkdir -p "$build"
    if ! cmake -S "$here/project" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_C_COMPILER="$cc" \
        >"$build/configure.log" 2>&1; then
      if grep -q "cannot link -fsanitize=fuzzer" "$build/configure.log"; then
        echo "SKIP: $cxx cannot link libFuzzer (Debian: libclang-rt-dev); see $build/configure.log"
        rm -f "$build/CMakeCache.txt"
        exit $skip
      fi
      cat "$build/configure.log"
      rm -f "$build/CMakeCache.txt"
      exit 1
    fi
  fi
  exec cmake --build "$build" -j"${GRAINLIFT_FUZZ_JOBS:-2}"
fi

[ "$mode" = run ] || { echo "unknown mode $mode" >&2; exit 2; }
target="$3" corpus="$4" seconds="$5" scratch="$6"
shift 6
binary="$build/$target"
if [ ! -x "$binary" ]; then
  echo "SKIP: $binary was not built (see the Fuzz.Build test: no clang or no libFuzzer)"
  exit $skip
fi
rm -rf "$scratch"
mkdir -p "$scratch/new" "$scratch/artifacts" "$scratch/work"
# a relative continuum.rheology_file of a fuzzed case is looked for in the working directory
cp "$root/cases/demo/rheology.toml" "$scratch/work/"
cd "$scratch/work" || exit 1
export GRAINLIFT_FUZZ_SCRATCH="$scratch/work"
log="$scratch/fuzz.log"
# -timeout: one input taking seconds is a finding (a hang); -error_exitcode=1: libFuzzer's
# default, 77, is the skip code of these tests; -rss_limit_mb also bounds any one
# allocation (malloc_limit_mb defaults to it)
# the seeds, then (where there is one) the corpus grown by long runs and merged to the inputs
# that add coverage (README.md, "Grown corpus"): the bounded run starts where those ended
corpora=("$root/tests/fuzz/corpus/$corpus")
[ -d "$root/tests/fuzz/grown/$corpus" ] && corpora+=("$root/tests/fuzz/grown/$corpus")
"$binary" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -error_exitcode=1 \
  -print_final_stats=1 -artifact_prefix="$scratch/artifacts/" "$@" "$scratch/new" \
  "${corpora[@]}" </dev/null >"$log" 2>&1
status=$?
# the result: executions, coverage, corpus
summary_re="^#[0-9]+[[:space:]]+(INITED|DONE)"
summary_re+="|^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)"
grep -E "$summary_re" "$log"
found=$(find "$scratch/artifacts" -type f | head -5)
if [ $status -ne 0 ] || [ -n "$found" ]; then
  grep -E "ERROR|runtime error|SUMMARY|==[0-9]+==|^ +#[0-9]+ " "$log" | head -40
  echo "FAIL: $target found an input that breaks the reader (exit $status); full log: $log"
  for f in $found; do
    echo "reproducer: $f"
    echo "  replay: $binary $f"
  done
  echo "Fix the reader, then keep the reproducer as tests/fuzz/corpus/$corpus/crash-<what>.<ext>"
  echo "with a line in tests/fuzz/README.md."
  exit 1
fi
echo "PASS: $target ran ${seconds}s over tests/fuzz/corpus/$corpus with no finding"
