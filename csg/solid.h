// wedge::Solid — the value type users hold (in C++ and in Lua). Like Manifold's public type it is
// immutable and cheap to copy: a shared pointer to a node of the CSG tree. Operations return new
// Solids; evaluation happens on demand, when a query (volume, mesh, export, render) asks for it.
//
// A leaf of the tree is any SolidLeaf: a B-Rep model (csg/brep_leaf.h, planar faces tessellated by
// tessellate/), an imported closed mesh (MeshLeaf below), later free-form solids. A leaf answers
// exactly what it can (a B-Rep knows its Euler counts and exact volume); everything else falls back
// to the leaf's triangle mesh.
#pragma once
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "brep/brep.h"
#include "csg/boolean.h"
#include "csg/membership.h"
#include "csg/rebuild.h"
#include "csg/shading.h"
#include "kernel/kernel.h"

namespace wedge {

class SolidLeaf {
 public:
  virtual ~SolidLeaf() = default;
  virtual std::string kind() const = 0;                   // "brep", "mesh", ...
  // A closed, outward-oriented triangle mesh within `tol` of the exact boundary.
  virtual Mesh mesh(const Tolerance& tol) const = 0;
  // As mesh(tol), and for each triangle the (u, v) of its corners on its parametric face's surface
  // (csg/shading.h); a leaf without parametrised faces leaves `corner_uv` empty.
  virtual Mesh parametrised_mesh(const Tolerance& tol, CornerUvs& corner_uv) const {
    corner_uv.clear();
    return mesh(tol);
  }
  virtual Box3 bounds() const = 0;
  // Exact answers where the leaf has them; nullopt means "ask the mesh".
  virtual std::optional<MassProperties> mass_properties() const { return std::nullopt; }
  virtual std::optional<EulerCounts> euler() const { return std::nullopt; }
  // "" when valid, otherwise the broken rule in words.
  virtual std::string validate() const = 0;
  // For a leaf whose surface comes from outside (a file, a polyhedron's faces, Euler operators): ""
  // when its mesh bounds a solid, decided exactly (no two triangles meet beyond what they share,
  // no shell inside another that faces the same way), otherwise what is wrong. A closed,
  // consistently oriented surface can still cross itself: its signed volume and its inside are
  // then not a solid's, and volume(), contains() and cells() refuse it. Leaves built to be
  // solids (the curved primitives) return "". Found once per leaf.
  virtual std::string solid_defect() const { return ""; }
  // An exactly transformed copy, or nullptr if this leaf cannot transform itself (the Solid then
  // keeps a transform node and transforms the mesh).
  virtual std::shared_ptr<const SolidLeaf> transformed(const Mat4& /*m*/) const { return nullptr; }
  // True when mesh() is the solid exactly (planar faces, straight edges), at any tolerance.
  virtual bool polyhedral() const { return false; }
  // True when the leaf knows its symmetry (csg/brep_leaf.h): a mirrored or turned copy of it may
  // be placed as its source's very mesh (canonical()).
  virtual bool symmetric() const { return false; }
  // The same solid placed by its symmetry, for a boolean's operands (Node::operands), or nullptr
  // where it is placed so already (or has no symmetry).
  virtual std::shared_ptr<const SolidLeaf> canonical() const { return nullptr; }
  // The surface kind (as s:faces() names it) of each face id that mesh() puts on its triangles,
  // indexed by the id; empty when the mesh carries no face ids of its own (its coplanar regions
  // are then its faces).
  virtual std::vector<std::string> face_kinds() const { return {}; }
  // The surface of each face id that mesh() puts on its triangles, indexed like face_kinds()
  // (a planar face without a surface given its Plane); empty when face_kinds() is.
  virtual std::vector<FaceSurface> face_surfaces() const { return {}; }
};

// A face of a solid as s:faces() lists it.
struct SolidFace {
  std::string surface;  // "plane", "cylinder", "cone", "sphere", "torus", "nurbs", "revolved", ...
  double area = 0;      // of its triangles at the tolerance asked
  int loops = 0;        // 1 + its rings
  // The surface itself, in the solid's coordinates: for a boolean result, the surface of the
  // source face its triangles came from (a sphere's face of `sphere(1) - cube(1)` is the sphere).
  FaceSurface geometry;
  Box3 bounds;  // of the face's triangles (surface_patch's extent for planes and cylinders)
};

// Progress and cancel for the evaluation of CSG trees. `progress` is called after each boolean
// node with the nodes done and the nodes the evaluation needs; `cancelled` is polled between
// nodes and between the stages of each boolean, and when it returns true the evaluation throws
// Cancelled and keeps no partial result. `stats`, if set, accumulates the time per stage.
struct EvalStats {
  double tessellate = 0, check = 0, broad = 0, arrange = 0, classify = 0, output = 0, rebuild = 0;  // ms
  long booleans = 0, pruned = 0, cached = 0;
  long remade = 0;  // moved boolean results that rounding spoiled, made again from moved operands
  long widest = 0;  // the most operands one engine pass took (see EvalOptions::union_fan_in)
};
struct EvalControl {
  std::function<void(std::size_t done, std::size_t total)> progress;
  CancelCheck cancelled;
  EvalStats* stats = nullptr;
};
// Installs `control` for the evaluations of this process until set_eval_control(nullptr); the
// caller keeps it alive. For the runner and tests.
void set_eval_control(const EvalControl* control);
// The evaluator's optimisations, on by default; off only to measure what they save (bench/).
struct EvalOptions {
  bool cache = true;     // shared subtrees once, results kept per tolerance
  bool prune = true;     // bounding-box pruning and disjoint unions without the engine
  bool parallel = true;  // independent operands evaluated in parallel
  // The most operands one engine pass takes that can lie on one another (whose boxes can share a
  // point; more operands whose boxes are sparse, a plate and its bosses, go in one pass): a larger
  // group of overlapping operands is evaluated as a balanced tree of unions (or intersections) of
  // at most this many, and a difference with more such subtrahends subtracts their union
  // (csg/solid.cpp). 0: all in one pass. (Named for the union, where it came first; it bounds the
  // intersection and the difference the same way.)
  std::size_t union_fan_in = 32;
  // The fan-in where more than this many operands' boxes hold one point (spokes through one hub,
  // copies of a shape shifted or turned a little): one pass over operands piled on one another
  // grows far faster than their number (24 cylinders through one point: 1.6 s in one pass, 0.2 s
  // as a tree of passes of 4), and 32 boxes shifted by 1/1024 crossed past the engine's work
  // budget in one pass. Used where it is below union_fan_in; below 2, no separate bound.
  std::size_t stack_fan_in = 4;
};
void set_eval_options(const EvalOptions& options);

// A closed 2-manifold triangle mesh as a leaf (what import() returns). The mesh is kept as given,
// attributes and all (a vertex split for its uvs or normals stays split, so it renders as the file
// has it); closedness, 2-manifoldness and the Euler counts are those of its vertices welded by
// exactly equal position. A surface that crosses itself or holds shells that overlap (a file of
// two overlapping cubes, a model written far from the origin and rounded) bounds no solid as it
// is: the leaf is then the region it winds around at least once, resolved exactly and rounded
// (resolve_self; its triangles keep their face ids, not the file's uvs or normals), decided on
// the first query that needs the mesh. Where that cannot be done, the queries that need a solid
// refuse the leaf (solid_defect) and validate() says why.
class MeshLeaf final : public SolidLeaf {
 public:
  // Throws wedge::Error if the mesh is not closed, not 2-manifold or inside out; `what` names the
  // mesh in the message (e.g. the file it came from).
  explicit MeshLeaf(Mesh mesh, const std::string& what = "mesh");
  std::string kind() const override { return "mesh"; }
  Mesh mesh(const Tolerance&) const override { return solid().resolved ? solid().mesh : mesh_; }
  Box3 bounds() const override { return mesh_.bounds(); }
  std::optional<EulerCounts> euler() const override { return solid().resolved ? solid().counts : counts_; }
  std::string validate() const override { return solid_defect(); }
  std::string solid_defect() const override;
  std::shared_ptr<const SolidLeaf> transformed(const Mat4& m) const override;
  bool polyhedral() const override { return true; }
  const Mesh& triangles() const { return mesh_; }

 private:
  MeshLeaf() = default;
  Mesh mesh_;
  EulerCounts counts_;
  std::string what_ = "mesh";
  // The solid the surface bounds: `resolved` where it is not the mesh as given; `defect` where
  // none could be made.
  struct Solidified {
    bool resolved = false;
    Mesh mesh;
    EulerCounts counts;
    std::string defect;
  };
  const Solidified& solid() const;
  mutable std::once_flag solid_once_;
  mutable Solidified solid_;
};

// The checks Solid::transformed(m) makes, for a solid lying in `box` (an empty box: only those of
// the matrix itself), with `what` naming m in the message ("the transform"). Throws wedge::Error
// when m is not finite; flattens (singular: the determinant of its columns made unit length is
// below 1e-12); shrinks volumes below 1e-300 otherwise (tiny factors, as scale(1e-101): volumes and
// normals would underflow); is projective; puts the box beyond +-kMaxCoordinate; or moves it so far
// from the origin that doubles there cannot hold its shape. Scenes place their parts by the same rule.
void check_transform(const Mat4& m, const Box3& box, const std::string& what = "the transform");

class Solid {
 public:
  Solid();  // the empty solid
  explicit Solid(std::shared_ptr<const SolidLeaf> leaf);
  static Solid from_mesh(Mesh mesh, const std::string& what = "mesh");

  bool empty() const;
  // Whether the solid has nothing in it at `tol`: the empty solid, or a boolean whose result is
  // empty (box(1,1,1) - box(1,1,1), which empty() cannot see without evaluating it). A leaf, moved
  // or not, never is; anything else is evaluated (the result is kept, as for mesh(tol)).
  bool evaluates_empty(const Tolerance& tol) const;
  // Checked by check_transform(m, loose_bounds()).
  Solid transformed(const Mat4& m) const;
  // The box the solid lies in, found without evaluating anything (a difference: its first
  // operand's), so it may be larger than bounds().
  Box3 loose_bounds() const;

  // A lazy boolean node (csg/boolean.h): union and intersection of all operands, difference of
  // the first minus the rest. Nothing is computed until a query asks for the mesh; the result is
  // then kept per tolerance.
  // `where` (a script's "model.lua:12") names the node in the errors of its evaluation.
  static Solid boolean(BooleanOp op, std::vector<Solid> operands, std::string where = {});

  // Queries. `tol` is the chordal tolerance used where the mesh is needed.
  Mesh mesh(const Tolerance& tol) const;
  Box3 bounds() const;
  // The bounds of the solid moved by m (affine), as tight as bounds() (a boolean's from its
  // evaluated mesh moved, not from its box moved: the box of a turned sphere is too big), without
  // making the moved solid: for a scene's parts, each placed by its own world matrix.
  Box3 bounds(const Mat4& m) const;
  MassProperties mass_properties(const Tolerance& tol) const;
  EulerCounts euler(const Tolerance& tol) const;
  std::string validate(const Tolerance& tol) const;  // "" when valid
  // The faces: of a B-Rep leaf, its own; of anything else, those of the winged-edge solid rebuilt
  // from its mesh (one face per connected region of one source face).
  std::vector<SolidFace> faces(const Tolerance& tol) const;
  // The evaluated mesh rebuilt as a winged-edge solid through Euler operators (csg/rebuild.h).
  std::shared_ptr<const RebuiltSolid> rebuilt(const Tolerance& tol) const;
  // The mesh with face ids that index face_kinds(tol) (a boolean's faces numbered across its operands).
  Mesh tagged_mesh(const Tolerance& tol) const;
  std::vector<std::string> face_kinds(const Tolerance& tol) const;
  // The surface of each face id of tagged_mesh(tol), in the solid's coordinates.
  std::vector<FaceSurface> face_surfaces(const Tolerance& tol) const;
  // The mesh for rendering and export (csg/shading.h): vertices split per face, each vertex's
  // normal the outward normal of its face's surface there (for a boolean result, the source
  // surface: never averaged from triangles) and its uv that surface's parameters; face ids as in
  // tagged_mesh(tol). An imported mesh that has its own normals is given as it is.
  Mesh shaded_mesh(const Tolerance& tol) const;
  // A copy whose faces carry `tag` (a material, a colour: the caller's number) wherever no tag
  // from further down the tree is on them; booleans keep each face's tag, so every face of a
  // result keeps the tag of the solid it came from. face_tags(tol)[id] is the tag of face id of
  // tagged_mesh(tol), -1 where none.
  Solid tagged(int tag) const;
  std::vector<int> face_tags(const Tolerance& tol) const;

  // True when every leaf is polyhedral: the mesh is then the solid itself, at any tolerance.
  bool polyhedral() const;

  // Point membership (csg/membership.h): exact for a polyhedral solid; for a curved one, a point
  // within tol.chordal of its mesh is "boundary" and the rest is decided on the mesh.
  Membership contains(const Point3& p, const Tolerance& tol) const;
  // The octree cell decomposition down to cells of longest side <= size; for a curved solid the
  // cells within tol.chordal of its mesh count as boundary, so the bounds bracket the exact volume.
  CellDecomposition cells(double size, const Tolerance& tol) const;

  struct Node;  // the CSG node (csg/solid.cpp)
 private:
  explicit Solid(std::shared_ptr<const Node> node);
  std::shared_ptr<const Node> node_;
};

}  // namespace wedge
