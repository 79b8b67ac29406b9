#!/usr/bin/env bash
# Runs bench_render N times per thread count (LP_NUM_THREADS=1 and 2) and prints, per scene, the
# median wall ms of wedge and of llvmpipe with the smallest and largest run, the median speed-up
# (llvmpipe / wedge, per run) with its range, and the median CPU ms of each: the form of the
# tables in bench/RESULTS.md. Frame times on a shared machine move from one process to the next,
# so one run says little. Usage: bench/render/median_runs.sh [N=8] [path to bench_render]
set -euo pipefail
n=${1:-8}
bin=${2:-build-bench/bench/render/bench_render}
[[ -x "$bin" ]] || { echo "median_runs: no bench_render at $bin (cmake --preset bench && cmake --build build-bench --target bench_render)" >&2; exit 1; }
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
for t in 1 2; do
  for ((i = 0; i < n; ++i)); do
    LP_NUM_THREADS=$t "$bin" | awk -F' [|] ' -v t="$t" '/^\| [a-z]/ && $2 ~ /^[0-9.]+$/ {
      sub(/^\| /, "", $1); sub(/x$/, "", $4); sub(/ \|$/, "", $6); print $1 "\t" t "\t" $2 "\t" $3 "\t" $4 "\t" $5 "\t" $6 }' >> "$tmp"
  done
done
echo "| scene | threads | wedge ms | llvmpipe ms | speed-up | CPU ms |"
echo "|---|---|---|---|---|---|"
# Median of a column (sorted numerically), with min and max.
stats() { sort -g | awk '{ v[NR] = $1 } END { m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%s %s %s", m, v[1], v[NR] }'; }
cut -f1,2 "$tmp" | awk '!seen[$0]++' | while IFS=$'\t' read -r scene t; do
  rows=$(awk -F'\t' -v s="$scene" -v t="$t" '$1 == s && $2 == t' "$tmp")
  read -r wm wl wh <<< "$(cut -f3 <<< "$rows" | stats)"
  read -r gm gl gh <<< "$(cut -f4 <<< "$rows" | stats)"
  read -r rm rl rh <<< "$(cut -f5 <<< "$rows" | stats)"
  read -r cw _ _ <<< "$(cut -f6 <<< "$rows" | stats)"
  read -r cg _ _ <<< "$(cut -f7 <<< "$rows" | stats)"
  printf "| %s | %s | %.2f (%.2f-%.2f) | %.2f (%.2f-%.2f) | %.2fx (%.2f-%.2f) | %.1f / %.1f |\n" \
    "$scene" "$t" "$wm" "$wl" "$wh" "$gm" "$gl" "$gh" "$rm" "$rl" "$rh" "$cw" "$cg"
done
