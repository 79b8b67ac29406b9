// The tessellate tests' check of a mesh read back from a file, independent of euler_counts.
#pragma once
#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "kernel/mesh.h"

namespace wedge {

// Each undirected edge of the welded mesh (vertices merged by exact position) and how often it
// is used in each direction; closed and consistently oriented iff every edge has one of each (and
// no triangle has two corners at one point). `vertices` and `edges` (if given) receive the counts.
inline bool closed_and_oriented(const Mesh& mesh, std::size_t* vertices = nullptr, std::size_t* edges = nullptr) {
  std::map<std::array<double, 3>, std::size_t> weld;
  std::vector<std::size_t> id(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Point3& p = mesh.positions[i];
    id[i] = weld.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, weld.size()).first->second;
  }
  std::map<std::pair<std::size_t, std::size_t>, std::array<int, 2>> uses;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      std::size_t a = id[t[k]], b = id[t[(k + 1) % 3]];
      if (a == b) return false;
      uses[{std::min(a, b), std::max(a, b)}][a < b ? 0 : 1]++;
    }
  if (vertices) *vertices = weld.size();
  if (edges) *edges = uses.size();
  for (const auto& [e, n] : uses)
    if (n[0] != 1 || n[1] != 1) return false;
  return !uses.empty();
}

}  // namespace wedge
