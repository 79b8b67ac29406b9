// A winged-edge B-Rep model as a leaf of the CSG tree: Euler counts, validation and (for planar
// faces) mass properties come exactly from the model; the mesh is its faces tessellated.
#pragma once
#include <memory>

#include "brep/brep.h"
#include "csg/solid.h"

namespace wedge {

class BrepLeaf final : public SolidLeaf {
 public:
  // Throws wedge::Error with validate()'s message when the model is not a valid solid.
  explicit BrepLeaf(Model model);
  std::string kind() const override { return "brep"; }
  // tessellate/brep_mesh.h: each edge sampled once for both faces, faces triangulated in their
  // plane or parameter domain and refined to the tolerance.
  Mesh mesh(const Tolerance& tol) const override;
  Mesh parametrised_mesh(const Tolerance& tol, CornerUvs& corner_uv) const override;
  Box3 bounds() const override { return model_->bounds(); }
  std::optional<MassProperties> mass_properties() const override;
  std::optional<EulerCounts> euler() const override { return model_->counts(); }
  std::string validate() const override { return model_->validate().message; }
  std::shared_ptr<const SolidLeaf> transformed(const Mat4& m) const override;
  std::vector<std::string> face_kinds() const override;
  std::vector<FaceSurface> face_surfaces() const override;
  bool polyhedral() const override { return model_->all_planar() && !model_->has_param_faces(); }
  const Model& model() const { return *model_; }

 private:
  std::shared_ptr<const Model> model_;
};

// The kind of a face's surface as s:faces() names it: "plane", "cylinder", or a curved builder's
// name ("sphere", "torus", "revolved", ...); "nurbs" for an unnamed NURBS patch.
std::string surface_kind(const FaceSurface& surface);

// The face's surface, a face without one given its plane (through the outer loop's first vertex,
// normal from face_normal).
FaceSurface face_surface(const Model& m, FaceId f);

// A Solid whose leaf is the model (validated).
Solid brep_solid(Model model);
// The planar extrude as a Solid: the profile (outer counter-clockwise, any holes) at z = 0 swept
// to z = height through Euler operators (brep/build.cpp's prism), for binding to extrude().
inline Solid prism_solid(const Profile& profile, double height) { return brep_solid(prism(profile, height)); }

}  // namespace wedge
