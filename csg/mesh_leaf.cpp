// A closed triangle mesh as a leaf of the CSG tree (csg/mesh_leaf.h).
#include "csg/mesh_leaf.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "kernel/error.h"
#include "kernel/predicates.h"

namespace wedge {

namespace {

// `apart` (split_touching of `original`'s welded copy: the same triangles, vertices by part) with
// `original`'s normals and uvs back: one vertex per (part's vertex, original vertex) pair met at
// a corner, so that both the parts and the file's seams stay apart. (The welded copy has no
// normals or uvs: an OBJ of parts touching along an edge lost its texture and its facets'
// normals when read.)
Mesh with_attributes(Mesh apart, const Mesh& original) {
  const bool normals = original.normals.size() == original.positions.size() && !original.normals.empty();
  const bool uvs = original.uvs.size() == original.positions.size() && !original.uvs.empty();
  if (!normals && !uvs) return apart;
  std::unordered_map<std::uint64_t, std::uint32_t> made;
  Mesh out;
  out.face_ids = apart.face_ids;
  out.triangles.resize(apart.triangles.size());
  for (std::size_t t = 0; t < apart.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = apart.triangles[t][k], o = original.triangles[t][k];
      auto [it, inserted] = made.emplace(std::uint64_t(v) << 32 | o, static_cast<std::uint32_t>(out.positions.size()));
      if (inserted) {
        out.positions.push_back(original.positions[o]);
        if (normals) out.normals.push_back(original.normals[o]);
        if (uvs) out.uvs.push_back(original.uvs[o]);
      }
      out.triangles[t][k] = it->second;
    }
  return out;
}

}  // namespace

MeshLeaf::MeshLeaf(Mesh mesh, const std::string& what) : mesh_(std::move(mesh)), what_(what) {
  mesh_.check();
  if (mesh_.triangles.empty()) fail(what, " has no triangles");
  // The range the builders keep to (brep.h): a file's coordinate of 1e300 gave "signed volume nan",
  // one of 5e-324 "flat".
  for (std::size_t i = 0; i < mesh_.positions.size(); ++i) {
    const Point3& p = mesh_.positions[i];
    if (!(p.cwiseAbs().maxCoeff() <= kMaxCoordinate))
      fail(what, ": a vertex at (", p.x(), ", ", p.y(), ", ", p.z(), ") is beyond +-", kMaxCoordinate,
           " (volumes and normals would overflow)");
  }
  if (const double size = mesh_.bounds().size().maxCoeff(); size < 1 / kMaxCoordinate)
    fail(what, " is ", size, " wide, below 1e-100 (its volume would underflow to zero)");
  try {
    // As indexed first: a boolean's result whose parts touch along an edge keeps a vertex per
    // part at each shared point, and written to OFF or PLY and read back it is closed and
    // 2-manifold as it is; welded, four triangles met at the edge and the file was refused.
    counts_ = euler_counts(mesh_);
  } catch (const Error&) {
    const Mesh welded = mesh_.welded();
    try {
      // A render mesh splits a vertex wherever its corners differ in uv or normal (a textured
      // cube's seams, a faceted cube's per-face normals); the surface it describes is still
      // closed, and it is the welded copy the closed / 2-manifold / Euler checks must see. Parts
      // that touch at a point with a vertex each (a boolean's result, exported and read back) are
      // welded there too: each of their fans is its own vertex again.
      counts_ = euler_counts(split_fans(welded, mesh_));
    } catch (const Error& e) {
      // Parts that touch along an edge, welded as an STL is read (or an OBJ's per-face
      // vertices, welded to close it): four triangles at the edge. Each paired with its
      // neighbour on its solid's side, the parts are apart again, and that mesh is the leaf's.
      // (Only where an edge has more than two triangles: parts that touch at a point alone, by
      // one vertex of the file's own, stay refused, as split_fans leaves them.)
      try {
        bool edges = false;
        Mesh apart = split_touching(welded, &edges);
        if (!edges) throw Error("no edge of more than two triangles");
        counts_ = euler_counts(apart);
        mesh_ = with_attributes(std::move(apart), mesh_);
      } catch (const Error&) {
        fail(what, ": ", e.what());
      }
    }
  }
  // The sign exactly: a sliver a few ulps thick (a boolean's result between nearly flush faces)
  // can sum to a volume of 0 or less in doubles.
  if (volume_sign(mesh_.positions, mesh_.triangles) <= 0)
    fail(what, " is inside out or flat (signed volume ", mesh_.volume(),
         "): triangles must be counter-clockwise seen from outside");
}

std::shared_ptr<const SolidLeaf> MeshLeaf::transformed(const Mat4& m) const {
  auto leaf = std::shared_ptr<MeshLeaf>(new MeshLeaf());
  leaf->mesh_ = mesh_.transformed(m);
  leaf->counts_ = counts_;
  leaf->what_ = what_;
  return leaf;
}

const MeshLeaf::Solidified& MeshLeaf::solid() const {
  std::call_once(solid_once_, [&] {
    const std::string defect = mesh_solid_defect(mesh_, what_);
    if (defect.empty()) return;
    try {
      BooleanResult r = resolve_self(mesh_);
      if (r.mesh.triangles.empty()) {
        solid_.defect = defect + " (and the region it winds around is empty)";
        return;
      }
      // (As indexed: the region's parts may touch along an edge, each with its own vertices.)
      solid_.counts = euler_counts(r.mesh);
      solid_.mesh = std::move(r.mesh);
      solid_.resolved = true;
    } catch (const Cancelled&) {
      throw;
    } catch (const Error&) {
      solid_.defect = defect + " (and it could not be resolved into the region it winds around)";
    }
  });
  return solid_;
}

std::string MeshLeaf::solid_defect() const { return solid().defect; }

// Regions grown across edges from each unvisited triangle, in triangle order.
std::size_t planar_regions(Mesh& mesh, std::vector<FaceSurface>& planes) {
  Mesh w = mesh.welded();
  const std::size_t n = w.triangles.size();
  std::unordered_map<std::uint64_t, std::uint32_t> edge_tri;  // directed edge -> triangle
  edge_tri.reserve(n * 3);
  for (std::uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) edge_tri[std::uint64_t(w.triangles[t][k]) << 32 | w.triangles[t][(k + 1) % 3]] = t;
  std::vector<std::int32_t> region(n, -1);
  std::int32_t count = 0;
  for (std::uint32_t seed = 0; seed < n; ++seed) {
    if (region[seed] >= 0) continue;
    std::vector<std::uint32_t> stack{seed};
    region[seed] = count;
    const auto& S = w.triangles[seed];
    const Point3 &a = w.positions[S[0]], &b = w.positions[S[1]], &c = w.positions[S[2]];
    const Vec3 ns = (b - a).cross(c - a);
    planes.push_back(ns.norm() > 0 ? plane_face(a, ns.normalized()) : FaceSurface{});
    while (!stack.empty()) {
      std::uint32_t t = stack.back();
      stack.pop_back();
      const auto& T = w.triangles[t];
      for (int k = 0; k < 3; ++k) {
        auto it = edge_tri.find(std::uint64_t(T[(k + 1) % 3]) << 32 | T[k]);
        if (it == edge_tri.end() || region[it->second] >= 0) continue;
        const auto& U = w.triangles[it->second];
        bool flat = true;
        for (int j = 0; j < 3 && flat; ++j) flat = orient3d(a, b, c, w.positions[U[j]]) == 0;
        const Vec3 nu = (w.positions[U[1]] - w.positions[U[0]]).cross(w.positions[U[2]] - w.positions[U[0]]);
        if (!flat || ns.dot(nu) <= 0) continue;
        region[it->second] = count;
        stack.push_back(it->second);
      }
    }
    ++count;
  }
  mesh.face_ids.assign(region.begin(), region.end());
  return static_cast<std::size_t>(count);
}

void check_triangle_budget(std::size_t triangles, const Tolerance& tol) {
  if (triangles > tol.max_triangles)
    fail("the mesh has ", triangles, " triangles, more than the budget of ", tol.max_triangles,
         ": raise the budget with tolerance{max_triangles=N}");
}

void check_boolean_budget(BooleanOp op, const std::vector<const Mesh*>& operands, std::size_t max_triangles) {
  double triangles = 0;
  for (const Mesh* m : operands) triangles += double(m->triangles.size());
  if (triangles > double(max_triangles))
    fail("boolean: the ", boolean_op_name(op), " of ", operands.size(), " operands would make about ", std::llround(triangles),
         " triangles (its operands' together), more than the budget of ", max_triangles,
         ": raise the budget with tolerance{max_triangles=N}");
}

}  // namespace wedge
