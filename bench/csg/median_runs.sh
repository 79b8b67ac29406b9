#!/usr/bin/env bash
# Runs bench_boolean N times and prints, per (case, engine, threads), the median ms with the
# smallest and largest run, the median ratios to wedge at 1 and 2 threads (peer ms / wedge ms, per
# run: above 1 means wedge is faster), the triangles, the validity of every run (or the first
# failure) and the median peak memory: the form of the Booleans tables in bench/RESULTS.md. Times on
# a shared machine move from one process to the next, so one run says little.
# Usage: bench/csg/median_runs.sh [N=3] [path to bench_boolean] [bench_boolean options...]
set -euo pipefail
n=${1:-3}
bin=${2:-build-bench/bench/csg/bench_boolean}
shift $(( $# < 2 ? $# : 2 ))
[[ -x "$bin" ]] || { echo "median_runs: no bench_boolean at $bin (cmake --preset bench && cmake --build build-bench --target bench_boolean)" >&2; exit 1; }
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
for ((i = 0; i < n; ++i)); do
  # Table rows only: case, engine, threads, ms, r1, r2, triangles, volume, valid, MB.
  "$bin" "$@" | awk -F' [|] ' '/^\| / && $3 ~ /^[0-9]+$/ {
    sub(/^\| /, "", $1); sub(/ \|$/, "", $10); print $1 "\t" $2 "\t" $3 "\t" $4 "\t" $5 "\t" $6 "\t" $7 "\t" $8 "\t" $9 "\t" $10 }' >> "$tmp"
done
echo "| case | engine | threads | ms (min-max) | / wedge 1t | / wedge 2t | triangles | valid | peak MB |"
echo "|---|---|---|---|---|---|---|---|---|"
# Median of the numbers in a column ("-" and "x" suffixes dropped), with min and max.
stats() { sed 's/x$//' | grep -E '^[0-9.]+$' | sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) { print "- - -"; exit }
  m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%s %s %s", m, v[1], v[NR] }'; }
cut -f1,2,3 "$tmp" | awk '!seen[$0]++' | while IFS=$'\t' read -r kase engine t; do
  rows=$(awk -F'\t' -v c="$kase" -v e="$engine" -v t="$t" '$1 == c && $2 == e && $3 == t' "$tmp")
  read -r mm ml mh <<< "$(cut -f4 <<< "$rows" | stats)"
  read -r r1 _ _ <<< "$(cut -f5 <<< "$rows" | stats)"
  read -r r2 _ _ <<< "$(cut -f6 <<< "$rows" | stats)"
  read -r mb _ _ <<< "$(cut -f10 <<< "$rows" | stats)"
  tris=$(cut -f7 <<< "$rows" | sort -u | paste -sd/)
  valid=$(cut -f9 <<< "$rows" | sort -u | paste -sd/)
  fmt() { [[ "$1" == "-" ]] && echo "-" || printf "$2" "$1"; }
  printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n" "$kase" "$engine" "$t" \
    "$( [[ "$mm" == "-" ]] && echo "-" || printf "%.1f (%.1f-%.1f)" "$mm" "$ml" "$mh")" \
    "$(fmt "$r1" "%.2fx")" "$(fmt "$r2" "%.2fx")" "$tris" "$valid" "$(fmt "$mb" "%.0f")"
done
