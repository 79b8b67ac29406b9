#include "csg/brep_leaf.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "tessellate/brep_mesh.h"

namespace wedge {

BrepLeaf::BrepLeaf(Model model) {
  Validation v = model.validate();
  if (!v) fail("not a valid solid: ", v.message);
  model_ = std::make_shared<const Model>(std::move(model));
}

Solid brep_solid(Model model) { return Solid(std::make_shared<const BrepLeaf>(std::move(model))); }

std::optional<MassProperties> BrepLeaf::mass_properties() const {
  // Exact for planar models and for models of parametric faces; the planar builders' cylinder
  // patches are left to the mesh.
  bool cylinders = false;
  model_->faces().for_each([&](FaceId f, const BrepFace&) {
    cylinders = cylinders || model_->surface(f).cylinder();
  });
  if (cylinders) return std::nullopt;
  return model_->mass_properties();
}

std::shared_ptr<const SolidLeaf> BrepLeaf::transformed(const Mat4& m) const {
  Model copy = *model_;
  try {
    copy.transform(m);
  } catch (const Error&) {
    return nullptr;  // e.g. a non-uniform scale of arcs: the Solid transforms the mesh instead
  }
  return std::make_shared<const BrepLeaf>(std::move(copy));
}

Mesh BrepLeaf::mesh(const Tolerance& tol) const { return tessellate(*model_, tol); }

Mesh BrepLeaf::parametrised_mesh(const Tolerance& tol, CornerUvs& corner_uv) const {
  return tessellate(*model_, tol, &corner_uv);
}

// The surface kind of a B-Rep face, as s:faces() names it.
std::string surface_kind(const FaceSurface& fs) {
  if (fs.cylinder()) return "cylinder";
  if (const FaceSurface* ps = &fs; ps->parametric) {
    if (!ps->kind.empty()) return ps->kind;
    if (dynamic_cast<const NurbsSurface*>(ps->surface.get())) return "nurbs";
    if (dynamic_cast<const Plane*>(ps->surface.get())) return "plane";
    return "swept";
  }
  return "plane";
}

std::vector<std::string> BrepLeaf::face_kinds() const {
  std::vector<std::string> kinds(model_->faces().capacity(), "plane");
  model_->faces().for_each([&](FaceId f, const BrepFace&) { kinds[static_cast<std::size_t>(f.value)] = surface_kind(model_->surface(f)); });
  return kinds;
}

FaceSurface face_surface(const Model& m, FaceId f) {
  const FaceSurface& s = m.surface(f);
  if (s.surface) return s;
  const auto vs = m.loop_vertices(m.faces()[f].outer);
  const Vec3 n = m.face_normal(f);
  if (!(n.norm() > 0)) return s;  // no area, no plane
  return plane_face(vs.empty() ? Point3::Zero() : m.point(vs.front()), n);
}

std::vector<FaceSurface> BrepLeaf::face_surfaces() const {
  std::vector<FaceSurface> out(model_->faces().capacity());
  model_->faces().for_each([&](FaceId f, const BrepFace&) { out[static_cast<std::size_t>(f.value)] = face_surface(*model_, f); });
  return out;
}

}  // namespace wedge
