// The B-Rep tessellator's sampling (private to tessellate/, brep_sampling.cpp): where an edge
// needs its points, whether a surface is straight along one parameter, and the estimate of a
// tessellation's triangle count that is checked against the budget before any work is done.
#pragma once
#include <array>
#include <functional>
#include <unordered_map>
#include <vector>

#include "brep/brep.h"

namespace wedge::brep_sampling {

// The angle between two vectors (0 if either is zero), radians.
double angle_between(const Vec3& a, const Vec3& b);

// The parameter (0: u, 1: v) along which the surface is a straight line everywhere (its second
// derivative along it and the twist term vanish in the normal direction), or -1.
int straight_axis(const Surface& S);

// straight_axis() of each surface, found once per tessellation (it samples the surface 49 times).
class StraightAxes {
 public:
  int operator()(const Surface& S) {
    auto [it, added] = known_.try_emplace(&S, -1);
    if (added) it->second = straight_axis(S);
    return it->second;
  }

 private:
  std::unordered_map<const Surface*, int> known_;
};

// The triangles a tessellation at `tol` needs, about: each face sampled on a grid of cells (each
// cell's area and largest normal curvature give the equilateral triangles it needs), each curved
// edge by its length over the spacing its curvature needs (a boundary point costs a triangle).
double estimate_triangles(const Model& m, const Tolerance& tol, StraightAxes& straight_axis);
// The triangles of the faces that are not parametric (planes) at any tolerance, about: each face
// sides - 2 + 2 per ring for its straight sides (the points of its curved edges are counted by
// estimate_triangles); exact for a polyhedron (a box: 12).
double planar_triangles(const Model& m);

// The tangent of the tilt a triangle may take against the surface it stands for: the angular
// tolerance's, at most 45 degrees (past 90 it is turned over).
double tilt_tangent(const Tolerance& tol);

// |d2| across d1: for a line with derivatives d1, d2, its curvature (in the surface or out of
// it) times |d1|^2. A chord of parameter length h bows off the line by about this times h^2 / 8.
double bend_across(const Vec3& d1, const Vec3& d2);

// Chords per unit parameter that the tolerances need along u and along v, from a jet J (S, Su,
// Sv, Suu, Suv, Svv) and its unit normal n: where the normal curvature term along u is k
// (|Suu.n|, or the twist term |Suv.n| where larger) and the speed |Su|, the chord's deviation
// k d^2 / 8 and its turn |Suu.n| d / |Su|. The twist term M = Suv.n turns the normal along u by |M| |Su| / |Su x Sv| per unit u
// (Weingarten's equations where Suu.n = 0), not |M| / |Su|: a twisted extrusion's side 0.03
// wide was given rows of points 0.004 apart across it, whose slivers the border's chords then
// turned over, and its refinement ran to the point budget. (Where M = 0, as before.)
std::array<double, 2> chords_needed(const Vec3* J, const Vec3& n, const Tolerance& tol);

// The width the tolerances give a face's triangles across the direction d (in (u, v)) at uv, from
// the surface's normal curvature across d; infinite where it does not bend across (or d is 0).
double width_across(const Surface& S, const Vec2& uv, const Vec2& d, const Tolerance& tol);

// As curve_parameters (brep_mesh.h), and a stretch [a, b] is also split while `turns(a, b)` (the
// normals of the faces along the edge turn by more than the angular tolerance between a and b).
std::vector<double> edge_parameters(const Curve& c, const Tolerance& tol, const std::function<bool(double, double)>& turns);

}  // namespace wedge::brep_sampling
