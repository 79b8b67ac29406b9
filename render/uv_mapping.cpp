// Two-step texture mapping (E. Bier and K. Sloan, "Two-Part Texture Mappings", IEEE CG&A 1986):
// S-mapping onto an intermediate cylinder, sphere or box, then O-mapping from the object to it
// by the ray from the centre (cylinder, sphere) or along the dominant normal axis (box).
#include <cmath>

#include "render/render.h"

namespace wedge::render {

Mesh with_uv_mapping(const Mesh& mesh, UvMapping mapping, const Vec3& axis_in) {
  mesh.check();
  if (!(axis_in.norm() > 0)) fail("uv mapping axis must be non-zero");
  Mesh out = mesh;
  const Box3 b = mesh.bounds();
  const Point3 c = b.empty() ? Point3::Zero() : Point3(b.center());
  const Vec3 size = b.size();
  // An orthonormal frame (e1, e2, axis).
  const Vec3 axis = axis_in.normalized();
  Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  double lo = 1e300, hi = -1e300;
  for (const auto& p : mesh.positions) lo = std::min(lo, (p - c).dot(axis)), hi = std::max(hi, (p - c).dot(axis));
  const double h = hi > lo ? hi - lo : 1;
  if (mapping == UvMapping::Box && mesh.normals.empty()) out.compute_vertex_normals();
  out.uvs.resize(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3 d = mesh.positions[i] - c;
    const double x = d.dot(e1), y = d.dot(e2), z = d.dot(axis);
    double u = 0, v = 0;
    switch (mapping) {
      case UvMapping::Cylinder:
        u = (std::atan2(y, x) + kPi) / (2 * kPi);
        v = (z - lo) / h;
        break;
      case UvMapping::Sphere: {
        const double r = d.norm();
        u = (std::atan2(y, x) + kPi) / (2 * kPi);
        v = r > 0 ? std::acos(std::clamp(z / r, -1.0, 1.0)) / kPi : 0.5;
        v = 1 - v;
        break;
      }
      case UvMapping::Box: {
        // Project onto the box face the normal points at most.
        const Vec3& n = out.normals[i];
        int k = 0;
        for (int j = 1; j < 3; ++j)
          if (std::abs(n[j]) > std::abs(n[k])) k = j;
        const int a = (k + 1) % 3, bb = (k + 2) % 3;
        const double sa = size[a] > 0 ? size[a] : 1, sb = size[bb] > 0 ? size[bb] : 1;
        u = (d[a] + 0.5 * sa) / sa;
        v = (d[bb] + 0.5 * sb) / sb;
        break;
      }
    }
    out.uvs[i] = Vec2(u, v);
  }
  return out;
}

}  // namespace wedge::render
