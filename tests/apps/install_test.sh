#!/usr/bin/env bash
# `cmake --install BUILD --prefix DIR` gives a DIR/bin/grainlift that runs and whose `report`
# runs the script installed in DIR/share/grainlift, not the source tree's: a sentinel
# report.py put there must be the one that runs; then the real one makes report.html.
#   tests/apps/install_test.sh BUILD_DIR
set -euo pipefail
build=$1
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > "$prefix/install.log"
g="$prefix/bin/grainlift"
for f in report.py plot_results.py plot_rheology.py; do
  [[ -f "$prefix/share/grainlift/$f" ]] || { echo "FAIL: $f not installed"; exit 1; }
done
cat > "$prefix/case.toml" <<'CASE'
[domain]
x_range = [-0.2, 0.2]
y_range = [-0.14, 0.14]
walls = ["bottom", "top"]
[intruder]
diameter = 0.1
velocity = [2.0, 0.0]
omega = 80.0
[grains]
diameter = 0.02
density = 20.0
area_fraction = 0.6
[dem]
travel = 4.0
steady_travel = 1.0
sample_every = 20
packing_cache = ""
[output]
blocks = 3
CASE
"$g" run "$prefix/case.toml" --solver dem --quiet --out "$prefix/out"
cp "$prefix/share/grainlift/report.py" "$prefix/report.py.real"
printf 'import sys\nopen(sys.argv[1] + "/installed_script_ran", "w").write("yes")\n' \
  > "$prefix/share/grainlift/report.py"
"$g" report "$prefix/out" > /dev/null || true
[[ -f "$prefix/out/installed_script_ran" ]] || { echo "FAIL: report did not run PREFIX/share/grainlift/report.py"; exit 1; }
cp "$prefix/report.py.real" "$prefix/share/grainlift/report.py"
"$g" report "$prefix/out" > /dev/null
[[ -s "$prefix/out/report.html" ]] || { echo "FAIL: the installed report wrote no report.html"; exit 1; }
echo "installed grainlift: report ran from $prefix/share/grainlift"
echo "1 passed, 0 failed"
