// wedge::brep — the winged-edge boundary representation (Baumgart 1975, "A polyhedron
// representation for computer vision"), with the Euler operators of Mäntylä ("An Introduction to
// Solid Modeling", 1988, ch. 9–12) as the only way to change its topology.
//
// Notation. A Model holds shells → faces → loops (one outer loop, any number of inner loops =
// rings) → edges → vertices, each in an arena addressed by a typed id. Every edge has two vertices
// v[0], v[1] and two sides: side 0 runs v[0]→v[1], side 1 runs v[1]→v[0]. Each side lies in one
// loop and has the four wings of Baumgart's edge: the predecessor and successor edge on that side.
// A wing is stored as an EdgeSide (edge id + side bit) rather than a bare edge id, so that an edge
// with the same loop on both sides (a "strut", which mev makes) is never ambiguous. A loop with no
// edge holds a lone vertex (the state mvfs makes). Geometry, all of it from surfaces/, is attached by
// id in IdMaps that follow the arenas: a point per vertex, a curve per edge (none: straight), a
// surface per face, and a curve in the face's (u, v) domain per side of a parametric face.
//
// Counts: V, E, F, S are the live vertices, edges, faces, shells; R = loops − faces (the rings);
// H, the through-holes (genus), is counted by the operators (kfmrh/mfkrh) and checked by
// validate() against the genus of each shell found by traversal.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "kernel/kernel.h"
#include "surfaces/surfaces.h"

namespace wedge {

using VertexId = Id<struct VertexTag>;
using EdgeId = Id<struct EdgeTag>;
using LoopId = Id<struct LoopTag>;
using FaceId = Id<struct FaceTag>;
using ShellId = Id<struct ShellTag>;

// One side of an edge: the edge traversed v[0]→v[1] (side 0) or v[1]→v[0] (side 1).
struct EdgeSide {
  EdgeId edge;
  int side = 0;
  bool valid() const { return edge.valid(); }
  EdgeSide mate() const { return {edge, 1 - side}; }
  bool operator==(const EdgeSide&) const = default;
};

// --- geometry -----------------------------------------------------------------------------
// Every curve and surface is one of surfaces/. An edge carries a CurvePtr running from the point
// of v[0] to that of v[1] over its domain, or nullptr for the straight segment between them (its
// vertices are then its whole geometry, so moving a vertex moves it). The planar builders' arcs
// are CircularArcs; the curved builders attach any curve.
//
// A face carries a FaceSurface: its surface, which side the solid is on, and how the face bounds
// it. A planar face's surface is a Plane whose unit_normal() points out of the solid; a side wall
// of the planar sweep of an arc is a Cylinder (solid outside it unless `reversed`); both are
// bounded by the face's loops in space. A `parametric` face is bounded in the surface's (u, v)
// domain by the PCurves of its sides (curved builders' faces cover a whole parameter rectangle,
// with seams and poles on its border). No surface: the plane fitted to the outer loop.
struct FaceSurface {
  SurfacePtr surface;
  // The outward normal is -(Su x Sv) (planes are always stored with Su x Sv outward).
  bool reversed = false;
  bool parametric = false;
  // What the surface is, in the words of s:faces(): "sphere", "cylinder", "cone", "torus",
  // "revolved", "extruded", "swept", "lofted", "nurbs" (set by the builder that made the face).
  std::string kind;

  // The face's plane or cylinder when it is bounded in space (not parametric), else nullptr.
  const Plane* plane() const;
  const Cylinder* cylinder() const;
};
// The three kinds of face, made.
FaceSurface plane_face(const Point3& point, const Vec3& unit_outward_normal);
FaceSurface cylinder_face(const Point3& origin, const Vec3& unit_axis, double radius, bool solid_outside);
FaceSurface parametric_face(SurfacePtr surface, bool reversed = false, std::string kind = {});

// A face's surface moved by the affine map m, as Model::transform moves it (a mirror reverses a
// parametric face). A cylinder stays one under a similarity; under any other map it becomes the
// exact elliptic cylinder, a parametric face over the part of it inside `extent` (a box that
// holds the face before the map; surface_patch's extruded circle).
FaceSurface transformed_surface(const FaceSurface& s, const Mat4& m, const Box3& extent = Box3());
// The same surface with the solid on its other side (a plane's normal negated, a cylinder's or a
// parametric face's `reversed` toggled): a subtracted operand's face in a difference.
FaceSurface flipped_surface(const FaceSurface& s);
// The face's surface as a bounded surface of surfaces/ covering the part of it inside `extent` (a
// box that holds the face): a Plane for a plane, the circle extruded along the axis for a cylinder,
// a parametric face's own surface. `reversed` is set when the solid's outward normal is -(Su x Sv).
// nullptr when there is no surface (no plane until fitted to a loop) or an empty extent for a
// plane or cylinder.
SurfacePtr surface_patch(const FaceSurface& s, const Box3& extent, bool& reversed);

// The image of an edge in the (u, v) domain of the face on one of its sides: the straight segment
// from `start` (at the curve's t0, the point of v[0]) to `end` (at t1), linear in t. A seam edge
// has two (one per side, on the two borders of the domain); a pole is where consecutive sides'
// images do not meet (the segment between them maps to one point).
struct PCurve {
  Vec2 start, end;
  Vec2 at(double s) const { return start + s * (end - start); }  // s in [0, 1]
};

// --- topology records ---------------------------------------------------------------------
struct BrepVertex {
  EdgeSide out;  // some side starting here; invalid for a lone vertex
};
struct BrepSide {
  LoopId loop;
  EdgeSide next, prev;  // successor and predecessor in the loop (the wings of this side)
};
struct BrepEdge {
  VertexId v[2];
  BrepSide side[2];
};
struct BrepLoop {
  FaceId face;
  EdgeSide first;   // invalid when the loop holds only `lone`
  VertexId lone;
};
struct BrepFace {
  ShellId shell;
  LoopId outer;
  std::vector<LoopId> rings;
};
struct BrepShell {
  int faces = 0;
};

// The verdict of validate(): ok, or the first rule that broke, where, in words.
struct Validation {
  bool ok = true;
  std::string message;
  explicit operator bool() const { return ok; }
};

// A corner of a loop at vertex v: the side `out` leaving v in that loop (invalid when v is the
// loop's lone vertex). Corners say where an operator inserts when a vertex occurs more than once.
struct Corner {
  LoopId loop;
  EdgeSide out;
  VertexId v;
};

class Model {
 public:
  // ---------------------------------------------------------------------------------------
  // The Euler operators. Each checks its precondition first and throws wedge::Error naming the
  // precondition that failed, leaving the model exactly as it was. Effects are on (V,E,F,R,H,S).
  // ---------------------------------------------------------------------------------------

  struct Mvfs { VertexId v; FaceId f; ShellId s; };
  // Make vertex, face, shell: a new shell of one face whose loop holds the lone vertex at p.
  // Precondition: p finite. Effect V+1 F+1 S+1. Inverse: kvfs(v).
  Mvfs mvfs(const Point3& p);
  // Kill vertex, face, shell. Precondition: v is the lone vertex of a one-face shell.
  // Effect V−1 F−1 S−1. Inverse: mvfs(p).
  void kvfs(VertexId v);

  struct Mev { EdgeId e; VertexId v; };
  // Make edge and vertex: a new edge from v (e.v[0] = v) to a new vertex at p, inside face f.
  // Precondition: v lies on a loop of f. The edge is inserted at v's first corner in that loop
  // (see mev_at for a chosen corner). Effect V+1 E+1. Inverse: kev(e, new v).
  Mev mev(FaceId f, VertexId v, const Point3& p, CurvePtr curve = nullptr);
  // As mev, at a chosen corner: the new edge goes in just before side c.out.
  Mev mev_at(Corner c, const Point3& p, CurvePtr curve = nullptr);
  // Kill edge and vertex. Precondition: v is an end of e and e is the only edge at v.
  // Effect V−1 E−1. Inverse: mev(f, other end, point of v).
  void kev(EdgeId e, VertexId v);

  struct Mef { EdgeId e; FaceId f; };
  // Make edge and face: split face f by a new edge v1→v2 (e.v[0] = v1). Precondition: v1 ≠ v2
  // lie on the same loop of f. The new face gets the part of the loop from v1 to v2 closed by the
  // new edge back to v1; f keeps the rest and its rings. Effect E+1 F+1. Inverse: kef(e, new f).
  Mef mef(FaceId f, VertexId v1, VertexId v2, CurvePtr curve = nullptr);
  // As mef, at chosen corners: c1 and c2 are sides of one loop starting at v1 and v2.
  Mef mef_at(EdgeSide c1, EdgeSide c2, CurvePtr curve = nullptr);
  // Kill edge and face: remove e and merge face f into the face g on e's other side (f's rings
  // move to g). Precondition: e's sides lie in two different faces, one of them f, on f's outer
  // loop. Effect E−1 F−1. Inverse: mef(g, ...).
  void kef(EdgeId e, FaceId f);

  // Kill edge, make ring: e has its loop on both sides; removing it splits the loop in two. The
  // part at e.v[0] stays (as outer loop if it was), the part at e.v[1] becomes a new ring of the
  // same face (a lone-vertex loop when e.v[1] hung only on e). Precondition: both sides of e in
  // one loop. Effect E−1 R+1. Inverse: mekr(e.v[0], e.v[1]). Returns the new ring.
  LoopId kemr(EdgeId e);
  // Make edge, kill ring: a new edge v1→v2 joining two loops of one face; the loop of v2 is
  // killed if it is a ring, else the loop of v1. Precondition: v1, v2 on two different loops of
  // one face, at least one of them a ring. Effect E+1 R−1. Inverse: kemr(e).
  EdgeId mekr(VertexId v1, VertexId v2, CurvePtr curve = nullptr);
  EdgeId mekr_at(Corner c1, Corner c2, CurvePtr curve = nullptr);

  // Kill face, make ring and hole: the single loop of face `hole` becomes a ring of face f.
  // Precondition: hole ≠ f, hole has no rings. Effect F−1 R+1 and H+1 when both faces are in
  // one shell, else S−1 (the shells merge). Inverse: mfkrh(f, ring). Returns the ring.
  LoopId kfmrh(FaceId hole, FaceId f);
  // Make face, kill ring and hole: ring (a ring of f) becomes the outer loop of a new face.
  // Effect F+1 R−1 and H−1, or S+1 when the new face is no longer connected to f (it then
  // gets a new shell). Precondition: ring is a ring of f; H > 0 when no shell splits.
  // Inverse: kfmrh(new f, f).
  FaceId mfkrh(FaceId f, LoopId ring);

  // Split edge, make vertex: e (v0→v1) becomes v0→new v and a new edge new v→v1.
  // Effect V+1 E+1. Inverse: jekv(new e).
  Mev semv(EdgeId e, const Point3& p);
  // Join edges, kill vertex: kills vertex v and its edge e2, extending v's other edge e to e2's
  // far end (e may be flipped to run into v). Precondition: v is an end of e2 and has exactly
  // two edges. Effect V−1 E−1. Inverse: semv(e, point of v).
  void jekv(EdgeId e2, VertexId v);

  // Reverses edge e: swaps v[0] and v[1] and its two sides (an arc's axis flips). Not a
  // topological change: every loop passes the same edges in the same order.
  void reverse_edge(EdgeId e);

  // ---------------------------------------------------------------------------------------
  // Queries.
  EulerCounts counts() const;
  // The structural rules (wings, closed loops, 2-manifold edges, shells by traversal, rings,
  // genus vs H) and, with geometry, the geometric ones (planar faces, simple loops, outer
  // loops counter-clockwise seen from outside and rings clockwise, positive volume).
  Validation validate(bool geometry = true) const;

  const Arena<BrepVertex, VertexId>& vertices() const { return vertices_; }
  const Arena<BrepEdge, EdgeId>& edges() const { return edges_; }
  const Arena<BrepLoop, LoopId>& loops() const { return loops_; }
  const Arena<BrepFace, FaceId>& faces() const { return faces_; }
  const Arena<BrepShell, ShellId>& shells() const { return shells_; }
  long holes() const { return holes_; }

  const Point3& point(VertexId v) const;
  // The edge's curve (nullptr: straight), running from v[0] to v[1].
  const CurvePtr& curve(EdgeId e) const;
  const FaceSurface& surface(FaceId f) const;
  void set_point(VertexId v, const Point3& p);
  void set_curve(EdgeId e, CurvePtr c);
  void set_surface(FaceId f, FaceSurface s);
  // The pcurve of one side of an edge on its face, or nullptr (planar faces need none).
  const PCurve* pcurve(EdgeSide s) const;
  void set_pcurve(EdgeSide s, const PCurve& p);
  // The point of edge e at fraction s in [0, 1] of its parameter range (any curve kind).
  Point3 edge_point(EdgeId e, double s) const;
  // The edge's curve, a LineSegment for a straight edge: a Curve running v[0] -> v[1].
  CurvePtr edge_curve(EdgeId e) const;
  // True when some face is parametric (the model has free-form or quadric faces).
  bool has_param_faces() const;

  // The first corner of v in loop l (throws if v is not on l).
  Corner corner(LoopId l, VertexId v) const;
  const BrepSide& side(EdgeSide s) const { return edges_[s.edge].side[s.side]; }
  VertexId origin(EdgeSide s) const { return edges_[s.edge].v[s.side]; }
  VertexId dest(EdgeSide s) const { return edges_[s.edge].v[1 - s.side]; }
  // The sides of a loop in order (empty for a lone-vertex loop), and its vertices.
  std::vector<EdgeSide> loop_sides(LoopId l) const;
  std::vector<VertexId> loop_vertices(LoopId l) const;
  // The loop's boundary as points: each side's start, arcs sampled with `arc_segments` pieces.
  std::vector<Point3> loop_polyline(LoopId l, int arc_segments = 16) const;
  // One side as points from its start to its end inclusive (arcs sampled).
  std::vector<Point3> side_polyline(EdgeSide s, int arc_segments = 16) const;
  // The outward unit normal of a face at its loop (plane normal; fitted to the outer loop when the face has no surface).
  Vec3 face_normal(FaceId f) const;
  Box3 bounds() const;
  bool all_planar() const;  // every face a plane (or none) and every edge a line

  // Mass properties of a closed solid from its exact geometry (brep/mass.cpp): with planar faces
  // and straight edges, the divergence theorem over the faces' fan triangles (exact); otherwise
  // Gauss-Legendre quadrature of the divergence-theorem integrands over each parametric face's
  // parameter rectangle and, on planar faces, of Green's theorem along their (curved) edges.
  // Throws for a cylinder face of the planar builders or a trimmed parametric face.
  MassProperties mass_properties() const;
  // The signed volume enclosed by the boundary polylines (arcs sampled), for any faces; with
  // parametric faces a coarse quadrature of them (for the sign: validate(), the builders).
  double approximate_volume() const;

  // Applies m to the geometry. A mirror (negative determinant) reverses every loop so that outer
  // loops stay counter-clockwise seen from outside. Arcs become ellipses (TransformedCurves) under
  // a non-similarity; throws for one when the model has cylinder faces of the planar builders.
  void transform(const Mat4& m);


 private:
  // validate()'s tests break a model on purpose (tests/brep/test_euler.cpp defines this friend,
  // writing the arenas directly); nothing else changes topology except through the Euler operators.
  friend struct ModelCorruptor;

  BrepSide& side_mut(EdgeSide s) { return edges_[s.edge].side[s.side]; }
  // link(a, b): next(a) = b, prev(b) = a
  void link(EdgeSide a, EdgeSide b);
  void relabel(EdgeSide start, LoopId l);
  void append_arc_interior(EdgeSide s, int arc_segments, std::vector<Point3>& out) const;  // set the loop of every side in start's cycle
  bool find_corner(FaceId f, VertexId v, Corner* c) const;
  bool ring_stays_connected(FaceId f, LoopId ring, std::vector<FaceId>* component) const;
  void require_vertex(VertexId v, const char* op, const char* what) const;
  void require_edge(EdgeId e, const char* op) const;
  void require_face(FaceId f, const char* op) const;
  EdgeId new_edge(VertexId a, VertexId b, CurvePtr c);
  VertexId new_vertex(const Point3& p);
  FaceId new_face(ShellId s);
  void kill_face(FaceId f);

  Arena<BrepVertex, VertexId> vertices_;
  Arena<BrepEdge, EdgeId> edges_;
  Arena<BrepLoop, LoopId> loops_;
  Arena<BrepFace, FaceId> faces_;
  Arena<BrepShell, ShellId> shells_;
  long holes_ = 0;
  MassProperties exact_mass(bool rough = false) const;  // brep/mass.cpp
  // Geometry, attached by id.
  IdMap<VertexId, Point3> points_;
  IdMap<EdgeId, CurvePtr> curves_;
  IdMap<FaceId, FaceSurface> surfaces_;
  IdMap<EdgeId, std::array<std::optional<PCurve>, 2>> pcurves_;
};

// ---------------------------------------------------------------------------------------------
// Solids built only through the Euler operators (brep/build.cpp). Outward orientation: outer
// loops counter-clockwise seen from outside.

// An axis-aligned box with its minimum corner at `corner`. Sizes must be positive.
Model box(const Vec3& size, const Point3& corner = Point3::Zero());

// A 2D profile: the outer polygon counter-clockwise, holes clockwise or counter-clockwise (they
// are reoriented), in the xy-plane.
struct Profile {
  std::vector<Vec2> outer;
  std::vector<std::vector<Vec2>> holes;
};
// Coordinates of a solid stay within +-kMaxCoordinate: the products that give normals (two
// factors) and volumes (three) then stay finite. Builders and transforms refuse more, by name.
constexpr double kMaxCoordinate = 1e100;

// Throws wedge::Error naming the fault: a ring with fewer than 3 points, a point that is not
// finite or beyond kMaxCoordinate, a point repeated, a ring that crosses or touches itself, a hole
// that touches, crosses or lies outside the outer ring (a hole equal to it included), holes that
// touch or overlap. polygon{} calls it where the profile is made; prism() again.
void validate_profile(const Profile& profile);

// The planar extrude: the profile at z = 0 swept to z = height (a through-hole per profile hole).
Model prism(const Profile& profile, double height);
// A frustum of a pyramid: the polygon `base` at z = 0, the same polygon scaled by `top_scale`
// about `apex_xy` at z = height; top_scale = 0 gives a pyramid with apex (apex_xy, height).
Model frustum(const std::vector<Vec2>& base, double height, double top_scale, const Vec2& apex_xy);

// A closed 2-manifold polyhedron from points and faces (0-based indices, each face
// counter-clockwise seen from outside). Rejects open or non-manifold input, inconsistent
// orientation, repeated or unused indices, with a message naming the edge, vertex or face.
// Any genus; each connected component becomes a shell. face_of, if given, receives the model face
// of each input face.
Model polyhedron(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces,
                 std::vector<FaceId>* face_of = nullptr);

// Sweeps face f of m by d (Mäntylä's translational sweep, through mev and mef only): every
// loop of f gets a side wall; f ends up moved by d. Side faces of arcs get cylinders.
void sweep(Model& m, FaceId f, const Vec3& d);

// --- Curved solids (brep/curved.cpp) ------------------------------------------------------------
//
// A section is a closed loop of curve pieces in the XY plane, each piece running from its start to
// the next piece's start (a full circle is two half circles: no edge starts and ends at one vertex).
// The outer loop runs counter-clockwise, holes clockwise.
using SectionLoop = std::vector<CurvePtr>;
struct Section {
  SectionLoop outer;
  std::vector<SectionLoop> holes;
};
// The section of a polygon profile (line pieces), and a closed curve as a loop of two halves.
Section section_of(const Profile& p);
SectionLoop loop_of_curve(const CurvePtr& closed_curve);
SectionLoop circle_loop(const Vec2& center, double r);  // counter-clockwise, two half arcs

// The generalised sweep that every curved builder reduces to: sides[k][j] is the surface swept by
// piece j of loop k (u along the piece, v along the sweep over one common interval); neighbouring
// pieces meet (S_j(u1, v) = S_{j+1}(u0, v)). Capped: planar end faces at v0 and v1 (a section that
// collapses to a point at v1 is an apex); closed: S(u, v1) = S(u, v0), a ring with no caps. A
// piece end that does not move along v is a pole (one vertex, no edge); a piece that does not move
// at all (a profile edge on a revolve's axis) gives no face. Built only through Euler operators
// (build_from_loops); throws if the result is not a valid solid.
//
// Counts, one convention for every builder: per profile vertex off the axis, one vertex at each
// end of the sweep and one edge between them (closed sweeps: two edges, split at the half-way
// parameter, so that no edge is a loop); per profile piece one side face, one edge at each end
// (closed: one seam edge); the caps carry the profile's holes as rings.
Model sweep_sides(const std::vector<std::vector<SurfacePtr>>& sides, bool closed);

// The solids of the Lua API. Angles in radians. Each returns a validated model.
//   sphere:   V 2 (the poles), E 1 (the seam), F 1
//   cylinder: V 4, E 6, F 4 (two half-cylinder faces, two discs); cone frustum the same
//   cone with an apex: V 3, E 4, F 3
//   torus:    V 4, E 6, F 2, H 1 (two half-tube faces)
//   tube:     V 8, E 12, F 6, R 2, H 1
Model sphere(double r, const Point3& center = Point3::Zero());
Model cylinder(double r, double h, const Point3& base = Point3::Zero());
// A cone frustum along +z from radius r1 at z = 0 to r2 at z = h (either may be 0: an apex).
Model cone(double r1, double r2, double h, const Point3& base = Point3::Zero());
Model torus(double R, double r, const Point3& center = Point3::Zero());
Model tube(double r_outer, double r_inner, double h, const Point3& base = Point3::Zero());
// OpenSCAD's linear_extrude: height h, twist (radians, counter-clockwise at the top), scale of
// the top section (0: an apex at the origin's axis).
Model extrude(const Section& s, double h, double twist = 0, double scale = 1);
// OpenSCAD's rotate_extrude: x is the radius, y becomes z; angle in (0, 2 pi]. Every x >= 0.
Model revolve(const Section& s, double angle);
// The section swept along a 3D path with rotation-minimising frames (section x along the frame's
// r, y along s). A closed path gives a ring (the frames' twist at the joint is spread along it).
Model sweep_along(const Section& s, const CurvePtr& path);
// Lofted through sections at heights (ruled for two, a natural cubic spline across for more).
// Every section needs the same number of loops and pieces.
Model loft(const std::vector<Section>& sections, const std::vector<double>& heights);

// A closed set of surface patches as a solid (Newell's teapot body or lid, or a user's patches):
// patches that share a boundary curve (same points at the same fractions of their parameter
// ranges, run in opposite directions) are joined along it, sides that collapse to a point are
// poles, and every loop of the boundary left open must be planar and is closed by a planar cap.
// Each patch is one face over its whole parameter rectangle, of surface kind `kind`; all patches
// must be oriented alike (the solid is turned outward if they all point in). V, E, F: the distinct
// patch corners, the joined sides (a closed side counts twice: it is split in two), the patches
// plus one cap per open loop. Throws, naming the patch or the place, when the boundary does not
// close, branches, is not planar where open, or the result is not a valid solid.
Model patch_solid(const std::vector<SurfacePtr>& patches, const std::string& kind = "nurbs");

// The seed's worked example: a block with a protrusion, a sharp-cornered depression, a round-
// cornered depression and a round through-hole. `rows` receives each feature's own counts
// (block, protrusion, sharp depression, round depression, hole), in that order.
struct FeatureRow {
  std::string name;
  EulerCounts counts;
};
Model worked_example(std::vector<FeatureRow>* rows = nullptr);

}  // namespace wedge
