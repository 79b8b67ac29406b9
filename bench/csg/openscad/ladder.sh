#!/usr/bin/env bash
# wedge against OpenSCAD 2021 (Debian `openscad`, CGAL Nef polyhedra) on bench_tree's models, in
# the same run: the plate with k x k drilled bosses for each k given, and the 60-tooth gear. Each
# program runs whole-process (parse, evaluate, write an STL), wedge on tree.lua, OpenSCAD on
# tree.scad, alternately, `runs` times; the table gives medians, the ratio (OpenSCAD / wedge), and
# the growth of each program's time with the bosses (least-squares slope of log time on log bosses).
# Each OpenSCAD run is stopped after `limit` seconds (its time grows fast: the 400-boss plate would
# take hours). The STL each program wrote is read back by wedge for its volume (the same model).
#
# Usage: bench/csg/openscad/ladder.sh [runs=3] [wedge binary=build/wedge] [limit s=300] [k ...=2 3 4 5]
set -uo pipefail
echo -15 > /proc/self/autogroup 2>/dev/null || true  # others' builds yield to the measurement
here=$(cd "$(dirname "$0")" && pwd)
runs=${1:-3}
wedge=$(realpath "${2:-build/wedge}")
limit=${3:-300}
shift $(( $# < 3 ? $# : 3 ))
sides=("$@")
[[ ${#sides[@]} -gt 0 ]] || sides=(2 3 4 5)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
secs() { local t0 t1; t0=$(date +%s.%N); "$@" > /dev/null 2>&1 || { echo fail; return; }; t1=$(date +%s.%N); awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }'; }
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) { print "-"; exit } print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
volume() { "$wedge" run <(echo "local s = import('$1') print(string.format('%.4f %d', s:volume(), s:triangles()))") 2>/dev/null || echo "- -"; }
echo "runs $runs, OpenSCAD limit ${limit}s, $(nproc) cores, $(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| model | bosses | wedge s | OpenSCAD s | OpenSCAD / wedge | wedge STL volume, triangles | OpenSCAD STL volume, triangles |"
echo "|---|---|---|---|---|---|---|"
cases=()
for k in "${sides[@]}"; do cases+=("plate $k"); done
cases+=("gear 0")
for c in "${cases[@]}"; do
  read -r model k <<< "$c"
  : > "$tmp/w"; : > "$tmp/o"
  for ((r = 0; r < runs; ++r)); do
    secs "$wedge" run "$here/tree.lua" "n=$k" "model=$model" "out=$tmp/w.stl" >> "$tmp/w"
    secs timeout "$limit" openscad -o "$tmp/o.stl" -D "n=$k" -D "model=\"$model\"" "$here/tree.scad" >> "$tmp/o"
  done
  w=$(grep -v fail "$tmp/w" | median); o=$(grep -v fail "$tmp/o" | median)
  ratio=$(awk -v w="$w" -v o="$o" 'BEGIN { if (w + 0 > 0 && o + 0 > 0) printf "%.0f", o / w; else print "-" }')
  bosses=$([[ $model == plate ]] && echo $((k * k)) || echo "-")
  echo "| $model | $bosses | $w | $o | $ratio | $(volume "$tmp/w.stl") | $(volume "$tmp/o.stl") |"
  [[ $model == plate ]] && echo "$((k * k)) $w $o" >> "$tmp/fit"
done
# t = c * bosses^p: p by least squares on the logs.
awk '{ x = log($1); n++; sx += x; sxx += x * x; yw = log($2); syw += yw; sxyw += x * yw; yo = log($3); syo += yo; sxyo += x * yo }
  END { if (n < 2) exit; d = n * sxx - sx * sx
        printf "growth with the bosses: wedge t ~ bosses^%.2f, OpenSCAD t ~ bosses^%.2f\n", (n * sxyw - sx * syw) / d, (n * sxyo - sx * syo) / d }' "$tmp/fit"
