#!/usr/bin/env bash
# MeshLab judges wedge's mesh files: every primitive and builder (tests/meshlab/shapes.lua) is
# exported as STL, PLY and OFF, and meshlabserver's "Compute Topological Measures" must find in
# each 0 boundary edges, a two-manifold mesh, and the number of connected components and the genus
# worked out by hand. One X server (xvfb-run) for all the files.
# Usage: judge.sh <wedge executable> <work dir>
set -uo pipefail
wedge=$1
work=$2
here=$(cd "$(dirname "$0")" && pwd)
for tool in meshlabserver xvfb-run xauth; do
  command -v "$tool" >/dev/null || { echo "judge: $tool not found: run scripts/install-deps (meshlab, xvfb, xauth)" >&2; exit 1; }
done
rm -rf "$work" && mkdir -p "$work" || exit 1
"$wedge" run "$here/shapes.lua" "$work" >"$work/manifest" || { echo "judge: shapes.lua failed" >&2; exit 1; }
[ -s "$work/manifest" ] || { echo "judge: shapes.lua listed no files" >&2; exit 1; }
# meshlabserver writes its report to stdout; each file's report goes to <file>.topo.
xvfb-run -a bash -c '
  while read -r path components genus; do
    meshlabserver -i "$path" -s "$0" >"$path.topo" 2>&1
  done <"$1/manifest"' "$here/topo.mlx" "$work"
failures=0
files=0
while read -r path components genus; do
  files=$((files + 1))
  report="$path.topo"
  problem=""
  grep -q "^Boundary Edges 0$" "$report" || problem+=" boundary edges: $(grep -m1 '^Boundary Edges' "$report" || echo none reported);"
  grep -q "^Mesh is two-manifold" "$report" || problem+=" not two-manifold;"
  grep -q "^Mesh is composed by $components connected component(s)$" "$report" ||
    problem+=" expected $components component(s), got: $(grep -m1 '^Mesh is composed by' "$report" || echo none reported);"
  grep -q "^Genus is $genus$" "$report" || problem+=" expected genus $genus, got: $(grep -m1 '^Genus is' "$report" || echo none reported);"
  if [ -n "$problem" ]; then
    echo "FAIL $(basename "$path"):$problem"
    failures=$((failures + 1))
  else
    echo "ok   $(basename "$path"): 0 boundary edges, two-manifold, $components component(s), genus $genus"
  fi
done <"$work/manifest"
echo "judge: $files files, $failures failed"
[ "$failures" -eq 0 ]
