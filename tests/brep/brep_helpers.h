// Helpers shared by the brep tests: a structural signature that two models with the same
// topology and geometry share whatever their ids (loops as cyclic point sequences, faces as
// their outer loop plus sorted rings, shells as sorted face lists).
#pragma once
#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "brep/brep.h"

namespace wedge::test {

inline std::string point_key(const Point3& p) {
  std::ostringstream o;
  o.precision(12);
  o << "(" << p.x() << "," << p.y() << "," << p.z() << ")";
  return o.str();
}

inline std::string loop_key(const Model& m, LoopId l) {
  std::vector<std::string> pts;
  for (VertexId v : m.loop_vertices(l)) pts.push_back(point_key(m.point(v)));
  // Rotate to the smallest starting point so the cycle has one spelling.
  auto it = std::min_element(pts.begin(), pts.end());
  std::rotate(pts.begin(), it, pts.end());
  std::string s;
  for (auto& p : pts) s += p;
  return s;
}

inline std::string signature(const Model& m) {
  std::map<std::int32_t, std::vector<std::string>> shells;
  m.faces().for_each([&](FaceId, const BrepFace& f) {
    std::vector<std::string> rings;
    for (LoopId r : f.rings) rings.push_back(loop_key(m, r));
    std::sort(rings.begin(), rings.end());
    std::string s = "[" + loop_key(m, f.outer);
    for (auto& r : rings) s += "|" + r;
    shells[f.shell.value].push_back(s + "]");
  });
  std::vector<std::string> all;
  for (auto& [id, faces] : shells) {
    std::sort(faces.begin(), faces.end());
    std::string s = "{";
    for (auto& f : faces) s += f;
    all.push_back(s + "}");
  }
  std::sort(all.begin(), all.end());
  std::string out;
  for (auto& s : all) out += s;
  return out;
}

// A vertex of face f (the first of its outer loop).
inline VertexId first_vertex(const Model& m, FaceId f) { return m.loop_vertices(m.faces()[f].outer)[0]; }

inline FaceId face_facing(const Model& m, const Vec3& n) {
  FaceId out;
  m.faces().for_each([&](FaceId f, const BrepFace&) {
    if (m.face_normal(f).dot(n) > 0.999) out = f;
  });
  return out;
}

}  // namespace wedge::test
