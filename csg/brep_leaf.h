// A winged-edge B-Rep model as a leaf of the CSG tree: Euler counts, validation and (for planar
// faces) mass properties come exactly from the model; the mesh is its faces tessellated.
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "brep/brep.h"
#include "csg/solid.h"

namespace wedge {

// The motions that map a builder's solid onto itself, as far as the builder knows them: every
// rotation and mirror about a point (a sphere), or about an axis (a solid of revolution: every turn
// about it and every mirror through a plane that holds it; with `flip`, also the mirror across the
// plane through `centre` normal to it: a cylinder, a torus).
struct Symmetry {
  enum class Kind { None, Point, Axis } kind = Kind::None;
  Point3 centre = Point3::Zero();
  Vec3 axis = Vec3::UnitZ();  // unit
  bool flip = false;
};

class BrepLeaf final : public SolidLeaf, public std::enable_shared_from_this<BrepLeaf> {
 public:
  // Throws wedge::Error with validate()'s message when the model is not a valid solid.
  explicit BrepLeaf(Model model, const Symmetry& symmetry = {});
  std::string kind() const override { return "brep"; }
  // tessellate/brep_mesh.h: each edge sampled once for both faces, faces triangulated in their
  // plane or parameter domain and refined to the tolerance. A copy moved by a rotation,
  // translation, mirror or uniform scale (transformed()) gives its source's mesh moved: the source
  // tessellates once for all its copies (400 placed drills: one tessellation, not 400).
  Mesh mesh(const Tolerance& tol) const override;
  Mesh parametrised_mesh(const Tolerance& tol, CornerUvs& corner_uv) const override;
  // Found once (Model::bounds samples every curved edge and face): asked again for each transformed
  // copy of the leaf, each prune and each check of a transform.
  Box3 bounds() const override;
  std::optional<MassProperties> mass_properties() const override;
  std::optional<EulerCounts> euler() const override { return model_->counts(); }
  std::string validate() const override;
  // Planar models only (a polyhedron's faces, Euler operators': their mesh is the solid); a
  // similarity copy asks its source.
  std::string solid_defect() const override;
  std::shared_ptr<const SolidLeaf> transformed(const Mat4& m) const override;
  // A similarity copy of a leaf with a known symmetry, placed by the move of its symmetry class
  // that depends only on where the copy lies (canonical_move): as a boolean's operand,
  // sphere(5):mirror{1, 0, 0}, cylinder(1, 2):rotate_z(7) and torus:rotate_z(180) are their
  // sources' very meshes, so that s - s:mirror{1, 0, 0} is empty and a symmetric part united with
  // its mirror image is itself (moved as asked, the mesh lay a rounding or a chord's sag off, and
  // left hundreds of slivers). Alone the copy keeps the move asked (a textured sphere turned
  // shows its texture turned). Made once.
  std::shared_ptr<const SolidLeaf> canonical() const override;
  std::vector<std::string> face_kinds() const override;
  std::vector<FaceSurface> face_surfaces() const override;
  bool symmetric() const override { return symmetry_.kind != Symmetry::Kind::None; }
  bool polyhedral() const override { return model_->all_planar() && !model_->has_param_faces(); }
  const Model& model() const { return *model_; }

 private:
  struct Trusted {};
  BrepLeaf(Model model, std::shared_ptr<const BrepLeaf> source, const Mat4& matrix)
      : model_(std::make_shared<const Model>(std::move(model))), source_(std::move(source)), matrix_(matrix) {}
  // The source's tessellation at tol, made once and kept (for its copies).
  std::shared_ptr<const std::pair<Mesh, CornerUvs>> shared_mesh(const Tolerance& tol) const;
  std::shared_ptr<const Model> model_;
  // A similarity copy: the leaf it was moved from (itself no copy) and the move.
  std::shared_ptr<const BrepLeaf> source_;
  Mat4 matrix_ = Mat4::Identity();
  Symmetry symmetry_;  // of the source (a copy's is its source's)
  bool placed_ = false;  // a canonical twin itself
  mutable std::once_flag canonical_once_;
  mutable std::shared_ptr<const SolidLeaf> canonical_;
  mutable std::mutex meshes_mutex_;
  mutable std::map<std::pair<double, double>, std::shared_ptr<const std::pair<Mesh, CornerUvs>>> meshes_;
  mutable std::once_flag bounds_once_;
  mutable Box3 bounds_;
  mutable std::once_flag defect_once_;
  mutable std::string defect_;
};

// The kind of a face's surface as s:faces() names it: "plane", "cylinder", or a curved builder's
// name ("sphere", "torus", "revolved", ...); "nurbs" for an unnamed NURBS patch.
std::string surface_kind(const FaceSurface& surface);

// The face's surface, a face without one given its plane (through the outer loop's first vertex,
// normal from face_normal).
FaceSurface face_surface(const Model& m, FaceId f);

// The similarity m' = m g, g a symmetry of `sym` (so m' moves the solid where m does), that depends
// only on the copy: for a point symmetry, no turn (s I plus the move of the centre); for an axis,
// the turn F(d) F(a)^T between canonical frames of the axis a and its image d (d's sign chosen
// where `flip`), with d and the scale s taken to 2^-40 so that moves a rounding apart agree.
// Proper (no mirror). m itself where it is no similarity or the symmetry is None.
Mat4 canonical_move(const Mat4& m, const Symmetry& sym);

// A Solid whose leaf is the model (validated), with its builder's symmetry.
Solid brep_solid(Model model, const Symmetry& symmetry = {});
// The planar extrude as a Solid: the profile (outer counter-clockwise, any holes) at z = 0 swept
// to z = height through Euler operators (brep/build.cpp's prism), for binding to extrude().
inline Solid prism_solid(const Profile& profile, double height) { return brep_solid(prism(profile, height)); }

}  // namespace wedge
