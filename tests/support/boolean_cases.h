// Operands for the boolean engine's tests and benchmark: closed, outward triangle meshes made from
// plain doubles, and named configurations with the volumes their results must have.
//
// Every generator returns a closed, 2-manifold, outward-oriented wedge::Mesh with face ids set
// (boxes: one id per side, base..base+5; spheres: base; cylinders: wall base, caps base+1 and
// base+2). Where a result's volume has a closed form it is given; for curved operands the closed
// form is the polyhedron's own volume (polyhedron_volume), not that of the smooth solid, since
// the engine combines the polyhedra.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "csg/csg.h"
#include "kernel/mesh.h"
#include "kernel/types.h"

namespace wedge::testing {

// The box [lo, lo + size] (12 triangles), then `m` applied to it (a rotation, a placement).
Mesh box_mesh(const Point3& lo, const Vec3& size, const Mat4& m = Mat4::Identity(), int face_id = 0);
// A UV sphere: `rings` bands of latitude and 2 * rings slices (4 * rings * (rings - 1)
// triangles), rings chosen so the count is nearest `triangles`. Poles on the z axis.
Mesh uv_sphere(const Point3& center, double radius, int triangles, int face_id = 0);
// An icosahedron subdivided k times (20 * 4^k triangles), k chosen so the count is nearest
// `triangles` in ratio, its vertices pushed out to the sphere.
Mesh icosphere(const Point3& center, double radius, int triangles, int face_id = 0);
// A prism of `sides` sides around the z axis between z0 and z1, radius to its vertices, caps
// fanned from their centres (4 * sides triangles), then `m` applied.
Mesh cylinder_mesh(double radius, double z0, double z1, int sides, const Mat4& m = Mat4::Identity(),
              int face_id = 0);

// The signed volume of a closed mesh (divergence theorem about its first vertex, summed in long
// double): the volume of the polyhedron as its doubles describe it, to about 1e-16 relative.
double polyhedron_volume(const Mesh& m);

// A named configuration of operands with the volumes of its three results where a closed form
// exists: the union and the intersection of all operands, and the first minus the rest.
struct BooleanCase {
  std::string name;
  std::vector<Mesh> operands;
  std::optional<double> union_volume, intersection_volume, difference_volume;
  // True where the regularised union is non-manifold (shells that touch along an edge or at a
  // vertex): CGAL's corefinement refuses it, the closed form is the reference.
  bool nonmanifold_union = false;

  std::optional<double> expected(BooleanOp op) const;
};

// Issue 11's degenerate configurations, one case each (two operands): identical operands, A - A,
// coplanar overlapping faces of the same and of opposite orientation, an edge lying on a face, a
// vertex on a face, cubes sharing a face, an edge, a vertex, a flush pocket, nested, disjoint,
// T-junctions between operands, nearly parallel faces (slivers), 1e-6 and 1e6 coordinates together.
std::vector<BooleanCase> degenerate_cases();
BooleanCase degenerate_case(const std::string& name);  // throws wedge::Error for an unknown name

// Two spheres of radius 1 with centres 0.6 apart along (1, 1, 1) / |.| (UV spheres of about
// `triangles` triangles each, the second turned so their grids do not line up).
std::vector<Mesh> overlapping_spheres(int triangles);

// The classic CSG figure: operands cube (side 2 at the origin), sphere (radius 1.35, about
// `sphere_triangles`), and three cylinders (radius 0.7, along x, y, z, `sides` sides). The figure
// is (cube n sphere) - cylinder_x - cylinder_y - cylinder_z.
std::vector<Mesh> classic_figure_operands(int sphere_triangles = 4096, int sides = 64);

// n x n x n spheres of radius 1 on a lattice of spacing 1.5 (each overlaps its neighbours),
// about `triangles` triangles each. Their union is the benchmark's lattice case.
std::vector<Mesh> sphere_lattice(int n = 8, int triangles = 1280);

// A plate [0, n] x [0, n] x [0, 1] followed by n x n cylinders (radius 0.3, `sides` sides,
// z from -0.5 to 1.5) at the cell centres: the plate minus the rest has the volume
// plate_with_holes_volume.
std::vector<Mesh> plate_and_cylinders(int n = 20, int sides = 32);
double plate_with_holes_volume(const std::vector<Mesh>& plate_and_cylinders);

// An octet truss: on the nodes of an (n + 1)^3 grid of spacing 1, struts (cylinders of radius r,
// `sides` sides, from node to node, caps centred on the nodes) along the cell edges and the
// faces' diagonals, each once, and a ball (an icosphere of radius 1.5 r, about `ball_triangles`)
// on every node: up to 18 struts and a ball meet at a node. Its union is a lattice part of the
// kind printed in 3D.
std::vector<Mesh> octet_truss(int n = 2, double r = 0.08, int sides = 32, int ball_triangles = 320);

// The Menger sponge of `level` as cube minus bars: the cube [0, 3^level]^3 followed by the square
// bars (running past the cube by 1 at both ends) whose removal leaves the sponge, 3 * (1 + 9 + ...)
// of them. Integer coordinates, so every coplanarity is exact. The sponge's volume is 20^level.
std::vector<Mesh> menger_operands(int level = 3);
double menger_volume(int level);

// The box [lo, hi] with each side cut into n x n squares of two triangles, welded into one closed
// mesh (a coarse operand crossing it meets many of its triangles).
Mesh grid_box(const Vec3& lo, const Vec3& hi, int n);
// The volume of a union (or of the first box minus the others) of axis-parallel boxes (lo, hi),
// exactly as their doubles say: per cell of the grid of all their coordinates, its centre in or
// out.
double boxes_volume(BooleanOp op, const std::vector<std::array<Vec3, 2>>& boxes);

}  // namespace wedge::testing
