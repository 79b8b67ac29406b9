#include "csg/brep_leaf.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "tessellate/brep_mesh.h"

namespace wedge {

BrepLeaf::BrepLeaf(Model model, const Symmetry& symmetry) : symmetry_(symmetry) {
  Validation v = model.validate();
  if (!v) fail("not a valid solid: ", v.message);
  model_ = std::make_shared<const Model>(std::move(model));
}

namespace {

// x to a multiple of 2^-40 of its binade (exact where it is one already: 1, 2, 0.5, 0.25...).
double to_grid(double x) {
  if (x == 0 || !std::isfinite(x)) return x;
  int e = 0;
  std::frexp(x, &e);
  return std::ldexp(std::nearbyint(std::ldexp(x, 40 - e)), e - 40);
}

// A right-handed orthonormal frame whose third column is the unit vector d, a function of d alone:
// the first column is the world axis least along d (the first of equals) made normal to d, so the
// frame of +z is exactly the identity.
Mat3 axis_frame(const Vec3& d) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(d[i]) < std::abs(d[k])) k = i;
  Vec3 x = Vec3::Unit(k) - d[k] * d;
  x.normalize();
  Mat3 f;
  f.col(0) = x;
  f.col(1) = d.cross(x);
  f.col(2) = d;
  return f;
}

// |A|^2 / 3 (the square of its scale) where the linear part A is a similarity (A^T A a multiple of
// the identity, to 1e-12), else 0.
double similarity_scale2(const Mat3& a) {
  const Mat3 ata = a.transpose() * a;
  const double s2 = ata.trace() / 3;
  return s2 > 0 && (ata - s2 * Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-12 * s2 ? s2 : 0.0;
}

}  // namespace

Mat4 canonical_move(const Mat4& m, const Symmetry& sym) {
  if (sym.kind == Symmetry::Kind::None) return m;
  const Mat3 exact = m.block<3, 3>(0, 0);
  const double s2 = similarity_scale2(exact);
  if (!(s2 > 0)) return m;
  const double s = to_grid(std::sqrt(s2));
  // The linear part to 2^-40 of the scale: a turn and its inverse, composed, are the identity
  // again (their product was a rounding off it, and the copy's mesh with it).
  const double q = std::ldexp(1.0, std::ilogb(s) - 40);
  const Mat3 a = exact.unaryExpr([&](double x) { return std::nearbyint(x / q) * q; });
  Mat3 turn = Mat3::Identity();
  if (sym.kind == Symmetry::Kind::Axis) {
    Vec3 d = (a * sym.axis).normalized();
    for (int i = 0; i < 3; ++i) d[i] = to_grid(d[i]);
    d.normalize();
    if (sym.flip) {
      int k = 0;
      while (k < 2 && d[k] == 0) ++k;
      if (d[k] < 0) d = -d;
    }
    turn = axis_frame(d) * axis_frame(sym.axis).transpose();
  }
  const Mat3 linear = s * turn;
  // m' x = linear x + t', the centre going where m takes it: t' = t + (A - linear) c.
  Mat4 out = m;
  out.block<3, 3>(0, 0) = linear;
  if (linear != a) out.block<3, 1>(0, 3) = m.block<3, 1>(0, 3) + (a * sym.centre - linear * sym.centre);
  return out;
}

Box3 BrepLeaf::bounds() const {
  std::call_once(bounds_once_, [&] { bounds_ = model_->bounds(); });
  return bounds_;
}

std::string BrepLeaf::validate() const {
  const std::string structure = model_->validate().message;
  return structure.empty() ? solid_defect() : structure;
}

std::string BrepLeaf::solid_defect() const {
  if (source_) return source_->solid_defect();
  std::call_once(defect_once_, [&] {
    if (polyhedral()) defect_ = mesh_solid_defect(mesh(Tolerance{}), "the solid");
  });
  return defect_;
}

Solid brep_solid(Model model, const Symmetry& symmetry) { return Solid(std::make_shared<const BrepLeaf>(std::move(model), symmetry)); }

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

std::shared_ptr<const SolidLeaf> BrepLeaf::canonical() const {
  std::call_once(canonical_once_, [&] {
    if (!source_ || placed_ || symmetry_.kind == Symmetry::Kind::None) return;
    const Mat4 m = canonical_move(matrix_, symmetry_);
    if (m == matrix_) return;
    Model copy = *source_->model_;
    try {
      copy.transform(m);
    } catch (const Error&) {
      return;
    }
    auto out = std::shared_ptr<BrepLeaf>(new BrepLeaf(std::move(copy), source_, m));
    out->symmetry_ = symmetry_;
    out->placed_ = true;
    canonical_ = std::move(out);
  });
  return canonical_;
}

std::shared_ptr<const SolidLeaf> BrepLeaf::transformed(const Mat4& m) const {
  Model copy = *model_;
  try {
    copy.transform(m);
  } catch (const Error&) {
    return nullptr;  // e.g. a non-uniform scale of arcs: the Solid transforms the mesh instead
  }
  // A rotation, translation, mirror or uniform scale keeps a valid model valid (every check of
  // validate() is invariant under them): the copy is not validated again. That validation (for a
  // curved model, its exact volume by quadrature) cost 1.7 ms per translated cylinder: 0.68 s of
  // building bench_tree's plate of 400 drilled bosses, and as much of a script that places parts.
  if (similarity_scale2(m.block<3, 3>(0, 0)) > 0) {
    std::shared_ptr<BrepLeaf> out;
    if (source_) out.reset(new BrepLeaf(std::move(copy), source_, m * matrix_));
    else out.reset(new BrepLeaf(std::move(copy), shared_from_this(), m));
    out->symmetry_ = symmetry_;
    return out;
  }
  return std::make_shared<const BrepLeaf>(std::move(copy));
}

std::shared_ptr<const std::pair<Mesh, CornerUvs>> BrepLeaf::shared_mesh(const Tolerance& tol) const {
  std::lock_guard<std::mutex> lock(meshes_mutex_);  // held while tessellating: a second copy waits
  auto& slot = meshes_[{tol.chordal, tol.angular}];
  if (!slot) {
    auto made = std::make_shared<std::pair<Mesh, CornerUvs>>();
    made->first = tessellate(*model_, tol, &made->second);
    slot = std::move(made);
  }
  return slot;
}

Mesh BrepLeaf::mesh(const Tolerance& tol) const {
  CornerUvs uv;
  return source_ ? parametrised_mesh(tol, uv) : tessellate(*model_, tol);
}

Mesh BrepLeaf::parametrised_mesh(const Tolerance& tol, CornerUvs& corner_uv) const {
  if (!source_) return tessellate(*model_, tol, &corner_uv);
  // The source at the tolerance that keeps this copy's: finer by the scale where it enlarges.
  Tolerance t = tol;
  const double scale = std::sqrt((matrix_.block<3, 3>(0, 0).transpose() * matrix_.block<3, 3>(0, 0)).trace() / 3);
  if (std::abs(scale - 1) > 1e-9) t.chordal = tol.chordal / std::max(1.0, scale);
  const auto made = source_->shared_mesh(t);
  corner_uv = made->second;
  if (reverses_orientation(matrix_))  // Mesh::transformed swaps corners 1 and 2
    for (auto& uv : corner_uv) std::swap(uv[1], uv[2]);
  return made->first.transformed(matrix_);
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
