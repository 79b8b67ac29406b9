// bench_brep: time to build and to validate a 10,000-face polyhedron (a torus of 100 x 100
// quads, genus 1) with wedge's winged edge, and OpenMesh's PolyMesh building and checking the
// same faces in the same run. Prints the median of several repetitions.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "brep/brep.h"

#ifdef WEDGE_BENCH_OPENMESH
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#endif

using namespace wedge;
using Clock = std::chrono::steady_clock;

namespace {
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

int main() {
  const int n = 100, k = 100, reps = 7;
  std::vector<Point3> pts;
  std::vector<std::vector<int>> faces;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      double u = 2 * kPi * i / n, v = 2 * kPi * j / k;
      pts.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
      faces.push_back({i * k + j, ((i + 1) % n) * k + j, ((i + 1) % n) * k + (j + 1) % k, i * k + (j + 1) % k});
    }
  // Quads of a torus of revolution are planar (each is a trapezoid between two meridians).
  std::vector<double> build, validate, both;
  EulerCounts counts;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    Model m = polyhedron(pts, faces);  // includes one validate()
    build.push_back(ms_since(t0));
    auto t1 = Clock::now();
    Validation v = m.validate();
    validate.push_back(ms_since(t1));
    if (!v) {
      std::printf("invalid: %s\n", v.message.c_str());
      return 1;
    }
    counts = m.counts();
  }
  std::printf("wedge polyhedron %zu faces: V=%ld E=%ld F=%ld R=%ld H=%ld S=%ld\n", faces.size(), counts.V, counts.E, counts.F,
              counts.R, counts.H, counts.S);
  std::printf("wedge build (Euler operators + validate): %.2f ms\n", median(build));
  std::printf("wedge validate alone:                     %.2f ms\n", median(validate));
#ifdef WEDGE_BENCH_OPENMESH
  std::vector<double> om;
  long om_chi = 0;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    OpenMesh::PolyMesh_ArrayKernelT<> mesh;
    std::vector<OpenMesh::VertexHandle> vh;
    vh.reserve(pts.size());
    for (const Point3& p : pts) vh.push_back(mesh.add_vertex({p.x(), p.y(), p.z()}));
    std::vector<OpenMesh::VertexHandle> fv;
    for (const auto& f : faces) {
      fv.clear();
      for (int i : f) fv.push_back(vh[static_cast<std::size_t>(i)]);
      if (!mesh.add_face(fv).is_valid()) {
        std::printf("OpenMesh rejected a face\n");
        return 1;
      }
    }
    bool ok = true;
    for (auto e : mesh.edges()) ok = ok && !mesh.is_boundary(e);
    for (auto v : mesh.vertices()) ok = ok && mesh.is_manifold(v);
    om_chi = static_cast<long>(mesh.n_vertices()) - static_cast<long>(mesh.n_edges()) + static_cast<long>(mesh.n_faces());
    om.push_back(ms_since(t0));
    if (!ok) {
      std::printf("OpenMesh: not closed/manifold\n");
      return 1;
    }
  }
  std::printf("OpenMesh PolyMesh build + check:          %.2f ms (V-E+F = %ld)\n", median(om), om_chi);
  std::printf("ratio wedge build / OpenMesh:             %.2f\n", median(build) / median(om));
#endif
  return 0;
}
