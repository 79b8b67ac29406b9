// The plain triangle mesh that every module passes around: shared vertex positions, optional
// per-vertex normals and texture coordinates, and for each triangle the id of the source face it
// came from (a B-Rep face, a surface patch, an input triangle of a boolean), or -1.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernel/bbox.h"
#include "kernel/types.h"

namespace wedge {

// Volume, area, centroid and inertia tensor (about the centroid, density 1) of a solid: what
// mass_properties(Mesh) measures on triangles and the B-Rep computes from its exact geometry.
struct MassProperties {
  double volume = 0;
  double area = 0;
  Point3 centroid = Point3::Zero();
  Mat3 inertia = Mat3::Zero();
};

// The element counts of a solid, as the Euler–Poincaré formula uses them:
// V - E + F - R + 2H - 2S = 0, with R the inner loops (rings) and H the through-holes (genus).
struct EulerCounts {
  long V = 0, E = 0, F = 0, R = 0, H = 0, S = 0;
  long characteristic() const { return V - E + F - R + 2 * H - 2 * S; }
  bool operator==(const EulerCounts&) const = default;
  EulerCounts operator-(const EulerCounts& o) const {
    return {V - o.V, E - o.E, F - o.F, R - o.R, H - o.H, S - o.S};
  }
};

struct Mesh {
  using Triangle = std::array<std::uint32_t, 3>;  // counter-clockwise seen from outside

  std::vector<Point3> positions;
  std::vector<Vec3> normals;        // empty, or one per position
  std::vector<Vec2> uvs;            // empty, or one per position
  std::vector<Triangle> triangles;
  std::vector<std::int32_t> face_ids;  // empty, or one per triangle

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }

  // Adds a vertex / triangle and returns its index.
  std::uint32_t add_vertex(const Point3& p);
  std::uint32_t add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::int32_t face_id = -1);

  // The same triangles (and face ids) on vertices at exactly equal positions merged into one;
  // normals and uvs dropped. Rebuilds the shared vertices of an STL file, and gives the surface
  // topology of a render mesh that splits vertices at uv seams or creases.
  Mesh welded() const;

  // Appends `other`, offsetting its indices. Attributes present in only one of the two are
  // dropped (normals, uvs) or filled with -1 (face ids).
  void append(const Mesh& other);

  Box3 bounds() const;
  double area() const;
  // Signed volume by the divergence theorem; positive for a closed mesh oriented outward.
  double volume() const;

  // Area-weighted vertex normals (each triangle adds its unnormalised cross product to its three
  // vertices), replacing any existing normals.
  void compute_vertex_normals();
  Vec3 triangle_normal(std::size_t t) const;  // unit, or zero for a degenerate triangle

  // A copy for shading: each vertex is split per source face (face_ids) and given the
  // area-weighted normal of that face's triangles around it, so shading is smooth within a face
  // and sharp across face boundaries (a box's faces stay flat, a cylinder's wall stays round).
  // Without face ids this is compute_vertex_normals() on a copy. Existing normals are kept.
  Mesh with_face_normals() const;

  // Applies a transform to positions and normals; a mirror also reverses triangle order so the
  // mesh stays outward-oriented.
  Mesh transformed(const Mat4& m) const;

  // Throws wedge::Error naming the first inconsistency: attribute array sizes, an index out of
  // range, a non-finite coordinate.
  void check() const;
};

// Newell's method (Newell, Newell & Sancha 1972; Sutherland et al.): the normal of a closed polygon,
// possibly non-convex and slightly non-planar, as the sum over its edges (a, b) of
// ((ay - by)(az + bz), (az - bz)(ax + bx), (ax - bx)(ay + by)). Its length is twice the polygon's
// area; it points to where the polygon runs counter-clockwise. The one Newell normal of the project.
Vec3 newell_normal(const std::vector<Point3>& loop);

// Mass properties of a closed, outward-oriented triangle mesh by the divergence theorem over
// signed tetrahedra from the origin (exact for the polyhedron the mesh describes).
MassProperties mass_properties(const Mesh& mesh);
// V, E, F (triangles), S (connected components) of a closed triangle mesh, R = 0 and H from
// Euler–Poincaré per component. Throws if an edge is not shared by exactly two triangles, or a
// vertex joins separate fans of triangles.
EulerCounts euler_counts(const Mesh& mesh);
// `welded` (original.welded()) with each vertex whose triangles make several fans, from separate
// vertices of `original` (parts that touch at one point, as a boolean returns them), split into
// one vertex per fan again, the first fan keeping the index. A vertex of `original` itself in
// two fans (a bowtie), or whose triangles do not close into fans, is left as it is, for
// euler_counts to report.
Mesh split_fans(const Mesh& welded, const Mesh& original);
// `welded` with its parts apart where they touch: around an edge of more than two triangles
// (two solids sharing an edge, welded as an STL is read), each triangle is paired with its
// neighbour on its solid's side (by exact orientation), and each vertex gets one copy per set of
// corners joined across paired edges (its fans, as split_fans). Throws where the triangles around
// an edge cannot be so paired (overlapping solids, two coplanar on one side). `edges`, if given,
// says whether any edge had more than two triangles.
Mesh split_touching(const Mesh& welded, bool* edges = nullptr);

}  // namespace wedge
