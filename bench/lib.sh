# Shell helpers of the bench scripts (sourced: . "$(dirname "$0")/lib.sh").

# OUT: a new temporary folder, removed when the script exits.
scratch_folder() {
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
}

# The median of the numbers on stdin, one per line (an even count: the mean of the middle two).
median() {
  sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : 0.5*(a[NR/2]+a[NR/2+1])}'
}
