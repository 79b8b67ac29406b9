#include "csg/solid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>

namespace wedge {

// --- mesh measurements ---

MassProperties mass_properties(const Mesh& mesh) {
  // For each triangle (a, b, c) the signed tetrahedron (0, a, b, c) contributes its volume
  // det/6, its first moment vol*(a+b+c)/4 and its second moments
  // vol/20 * (sum_i x_i x_i^T + (sum_i x_i)(sum_i x_i)^T) (Tonon 2004, covariance of a tetrahedron
  // with one vertex at the origin).
  MassProperties mp;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();  // integral of x x^T over the solid
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3& b = mesh.positions[t[1]];
    const Vec3& c = mesh.positions[t[2]];
    double v = a.dot(b.cross(c)) / 6.0;
    mp.volume += v;
    mp.area += 0.5 * (b - a).cross(c - a).norm();
    Vec3 s = a + b + c;
    first += v * s / 4.0;
    second += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  if (mp.volume != 0) mp.centroid = first / mp.volume;
  // Second moment about the centroid, then the inertia tensor I = trace(C) Id - C.
  Mat3 c = second - mp.volume * mp.centroid * mp.centroid.transpose();
  mp.inertia = c.trace() * Mat3::Identity() - c;
  return mp;
}

EulerCounts euler_counts(const Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    for (int k = 0; k < 3; ++k) {
      auto key = std::make_pair(t[k], t[(k + 1) % 3]);
      if (++directed[key] > 1)
        fail("mesh is not 2-manifold: edge ", key.first, "-", key.second, " is used twice in the same direction");
    }
  }
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first}))
      fail("mesh is not closed: edge ", e.first, "-", e.second, " has only one triangle");
  // Every vertex must be one fan of triangles: around v, each triangle (v, u, w) links u to w, and
  // the links must close into a single cycle. Two parts that touch at one point give two cycles
  // (the mesh is closed but not a 2-manifold there; its Euler counts would say nothing true).
  {
    std::vector<std::array<std::uint32_t, 3>> corners;  // (v, u, w)
    corners.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) corners.push_back({t[k], t[(k + 1) % 3], t[(k + 2) % 3]});
    std::sort(corners.begin(), corners.end());
    for (std::size_t i = 0; i < corners.size();) {
      std::size_t j = i;
      while (j < corners.size() && corners[j][0] == corners[i][0]) ++j;
      // corners[i..j) are sorted by u: follow u -> w from the first until the cycle closes.
      auto next = [&](std::uint32_t u) {
        auto it = std::lower_bound(corners.begin() + long(i), corners.begin() + long(j), u,
                                   [](const std::array<std::uint32_t, 3>& c, std::uint32_t x) { return c[1] < x; });
        return (*it)[2];
      };
      std::size_t steps = 1;
      for (std::uint32_t u = next(corners[i][1]); u != corners[i][1]; u = next(u)) ++steps;
      if (steps != j - i) {
        const Point3& p = mesh.positions[corners[i][0]];
        fail("mesh is not 2-manifold: vertex ", corners[i][0], " at (", p.x(), ", ", p.y(), ", ", p.z(),
             ") joins separate fans of triangles (parts that touch at one point)");
      }
      i = j;
    }
  }
  // Components by union-find over vertices used by triangles.
  std::vector<std::uint32_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<bool> used(mesh.positions.size(), false);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      used[t[k]] = true;
      parent[find(t[k])] = find(t[(k + 1) % 3]);
    }
  EulerCounts c;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      ++c.V;
      if (find(static_cast<std::uint32_t>(v)) == v) ++c.S;
    }
  c.E = static_cast<long>(directed.size() / 2);
  c.F = static_cast<long>(mesh.triangles.size());
  long chi = c.V - c.E + c.F;  // = 2S - 2H
  c.H = (2 * c.S - chi) / 2;
  return c;
}

// --- MeshLeaf ---

MeshLeaf::MeshLeaf(Mesh mesh, const std::string& what) : mesh_(std::move(mesh)) {
  mesh_.check();
  if (mesh_.triangles.empty()) fail(what, " has no triangles");
  try {
    // A render mesh splits a vertex wherever its corners differ in uv or normal (a textured
    // cube's seams, a faceted cube's per-face normals); the surface it describes is still
    // closed, and it is the welded copy the closed / 2-manifold / Euler checks must see.
    counts_ = euler_counts(mesh_.welded());
  } catch (const Error& e) {
    fail(what, ": ", e.what());
  }
  double v = mesh_.volume();
  if (!(v > 0)) fail(what, " is inside out or flat (signed volume ", v, "): triangles must be counter-clockwise seen from outside");
}

std::shared_ptr<const SolidLeaf> MeshLeaf::transformed(const Mat4& m) const {
  auto leaf = std::shared_ptr<MeshLeaf>(new MeshLeaf());
  leaf->mesh_ = mesh_.transformed(m);
  leaf->counts_ = counts_;
  return leaf;
}

// --- the CSG tree ---

namespace {
// The largest stretch a transform applies to any direction (its spectral norm, bounded above by
// the Frobenius norm of the linear part, which is cheap and safe for choosing tolerances).
double m_norm(const Mat4& m) { return m.block<3, 3>(0, 0).norm(); }
}  // namespace

struct Solid::Node {
  enum class Kind { Empty, Leaf, Transform, Boolean } kind = Kind::Empty;
  std::shared_ptr<const SolidLeaf> leaf;
  Mat4 matrix = Mat4::Identity();
  std::shared_ptr<const Node> child;
  // Boolean: the operation, its operands, and the evaluated meshes by chordal tolerance.
  BooleanOp op = BooleanOp::Union;
  std::vector<std::shared_ptr<const Node>> operands;
  mutable std::mutex cache_mutex;
  mutable std::map<std::pair<double, double>, std::shared_ptr<const Mesh>> cache;

  Node() = default;
  Node(const Node& o) : kind(o.kind), leaf(o.leaf), matrix(o.matrix), child(o.child), op(o.op), operands(o.operands) {}
};

Solid Solid::boolean(BooleanOp op, std::vector<Solid> operands) {
  if (operands.empty()) fail("boolean: no operands");
  auto n = std::make_shared<Node>();
  n->kind = Node::Kind::Boolean;
  n->op = op;
  for (auto& s : operands) n->operands.push_back(s.node_);
  return Solid(std::shared_ptr<const Node>(n));
}

Solid::Solid() : node_(std::make_shared<Node>()) {}

Solid::Solid(std::shared_ptr<const SolidLeaf> leaf) {
  if (!leaf) fail("Solid: null leaf");
  auto n = std::make_shared<Node>();
  n->kind = Node::Kind::Leaf;
  n->leaf = std::move(leaf);
  node_ = n;
}

Solid::Solid(std::shared_ptr<const Node> node) : node_(std::move(node)) {}

Solid Solid::from_mesh(Mesh mesh, const std::string& what) {
  return Solid(std::make_shared<MeshLeaf>(std::move(mesh), what));
}

bool Solid::empty() const { return node_->kind == Node::Kind::Empty; }

Solid Solid::transformed(const Mat4& m) const {
  if (!m.allFinite()) fail("transform has non-finite entries");
  if (std::abs(m.block<3, 3>(0, 0).determinant()) < 1e-300) fail("transform is singular: it would flatten the solid");
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() != 0)
    fail("transform is projective (last row not 0 0 0 1): solids take affine transforms only");
  // A result beyond the coordinates a solid may have is an error here, not a nan volume later.
  if (const Box3 b = bounds(); !b.empty()) {
    double reach = 0;
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner((i & 1) ? b.max.x() : b.min.x(), (i & 2) ? b.max.y() : b.min.y(), (i & 4) ? b.max.z() : b.min.z());
      reach = std::max(reach, apply_point(m, corner).cwiseAbs().maxCoeff());
    }
    if (!(reach <= kMaxCoordinate))
      fail("the transform overflows: the solid would reach coordinate ", reach, ", beyond +-", kMaxCoordinate,
           " (its volume and normals would not be finite numbers)");
  }
  switch (node_->kind) {
    case Node::Kind::Empty: return *this;
    case Node::Kind::Leaf:
      if (auto t = node_->leaf->transformed(m)) return Solid(std::move(t));
      break;
    case Node::Kind::Transform: {
      // Fold consecutive transforms into one node.
      auto n = std::make_shared<Node>(*node_);
      n->matrix = m * node_->matrix;
      return Solid(std::shared_ptr<const Node>(n));
    }
    case Node::Kind::Boolean: break;
  }
  auto n = std::make_shared<Node>();
  n->kind = Node::Kind::Transform;
  n->matrix = m;
  n->child = node_;
  return Solid(std::shared_ptr<const Node>(n));
}

Mesh Solid::mesh(const Tolerance& tol) const {
  switch (node_->kind) {
    case Node::Kind::Empty: return Mesh();
    case Node::Kind::Leaf: return node_->leaf->mesh(tol);
    case Node::Kind::Transform: {
      // Tessellate the child finely enough that scaling up keeps the chordal error within tol.
      Tolerance t = tol;
      double stretch = m_norm(node_->matrix);
      if (stretch > 0) t.chordal = tol.chordal / std::max(1.0, stretch);
      return Solid(node_->child).mesh(t).transformed(node_->matrix);
    }
    case Node::Kind::Boolean: {
      std::pair<double, double> key(tol.chordal, tol.angular);
      {
        std::lock_guard<std::mutex> lock(node_->cache_mutex);
        auto it = node_->cache.find(key);
        if (it != node_->cache.end()) return *it->second;
      }
      std::vector<Mesh> meshes;
      for (const auto& o : node_->operands) meshes.push_back(Solid(o).mesh(tol));
      std::vector<const Mesh*> ptrs;
      for (const auto& m : meshes) ptrs.push_back(&m);
      auto result = std::make_shared<const Mesh>(wedge::boolean(node_->op, ptrs).mesh);
      std::lock_guard<std::mutex> lock(node_->cache_mutex);
      node_->cache[key] = result;
      return *result;
    }
  }
  return Mesh();
}

Box3 Solid::bounds() const {
  switch (node_->kind) {
    case Node::Kind::Empty: return Box3();
    case Node::Kind::Leaf: return node_->leaf->bounds();
    case Node::Kind::Transform: {
      Box3 b = Solid(node_->child).bounds(), out;
      if (b.empty()) return out;
      for (int i = 0; i < 8; ++i) {
        Vec3 corner((i & 1) ? b.max.x() : b.min.x(), (i & 2) ? b.max.y() : b.min.y(), (i & 4) ? b.max.z() : b.min.z());
        out.extend(apply_point(node_->matrix, corner));
      }
      return out;
    }
    case Node::Kind::Boolean: {
      // Bounds of the operands that can contribute (exact bounds need the evaluated mesh).
      Box3 out;
      if (node_->op == BooleanOp::Union) {
        for (const auto& o : node_->operands) {
          Box3 b = Solid(o).bounds();
          if (!b.empty()) {
            out.extend(b.min);
            out.extend(b.max);
          }
        }
        return out;
      }
      return mesh(Tolerance{}).bounds();
    }
  }
  return Box3();
}

MassProperties Solid::mass_properties(const Tolerance& tol) const {
  if (node_->kind == Node::Kind::Leaf)
    if (auto mp = node_->leaf->mass_properties()) return *mp;
  return wedge::mass_properties(mesh(tol));
}

EulerCounts Solid::euler(const Tolerance& tol) const {
  if (node_->kind == Node::Kind::Empty) return EulerCounts();
  if (node_->kind == Node::Kind::Leaf)
    if (auto c = node_->leaf->euler()) return *c;
  if (node_->kind == Node::Kind::Transform) return Solid(node_->child).euler(tol);
  return euler_counts(mesh(tol));
}

std::string Solid::validate(const Tolerance& tol) const {
  switch (node_->kind) {
    case Node::Kind::Empty: return "";
    case Node::Kind::Leaf: return node_->leaf->validate();
    case Node::Kind::Transform: return Solid(node_->child).validate(tol);
    case Node::Kind::Boolean: return mesh_solid_defect(mesh(tol), "boolean result");
  }
  return "";
}

}  // namespace wedge
