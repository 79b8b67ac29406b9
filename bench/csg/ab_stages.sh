#!/usr/bin/env bash
# Alternates two bench_stages binaries (say main's and a change's) on one case, round after
# round, and prints per round each one's CPU ms and the sum of its stages' wall ms (each stage's
# minimum over the repeats), summed over the case's booleans. On a machine whose speed moves by
# 30% from one minute to the next only such side-by-side rounds compare two builds.
# Usage: bench/csg/ab_stages.sh A_BIN B_BIN CASE [THREADS=1] [ROUNDS=4] [REPEATS=3]
#   e.g. bench/csg/ab_stages.sh /tmp/bench_stages.main build-bench/bench/csg/bench_stages classic 2
set -euo pipefail
[[ $# -ge 3 ]] || { sed -n '2,7p' "$0" >&2; exit 2; }
a=$1 b=$2 kase=$3 threads=${4:-1} rounds=${5:-4} repeats=${6:-3}
for bin in "$a" "$b"; do [[ -x "$bin" ]] || { echo "ab_stages: $bin is not an executable" >&2; exit 2; }; done
# CPU ms and the stages' wall ms of every table row, summed.
sums() {
  awk -F'|' 'NF > 8 && $3 + 0 > 0 { n = split($4, w, ","); for (k = 1; k <= n; ++k) wall += w[k]; cpu += $3 }
             END { printf "%d/%.1f", cpu, wall }'
}
echo "round  A cpu/wall ms  B cpu/wall ms  ($kase, $threads thread(s), min of $repeats runs each)"
for ((i = 1; i <= rounds; ++i)); do
  ra=$("$a" "$kase" "$threads" "$repeats" | sums)
  rb=$("$b" "$kase" "$threads" "$repeats" | sums)
  printf "%5d  %13s  %13s\n" "$i" "$ra" "$rb"
done
