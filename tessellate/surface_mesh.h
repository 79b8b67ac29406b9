// Surface -> Mesh: the tessellation of a parametric surface of surfaces/ on a parameter grid, for
// rendering, export and closed single-surface solids (B-Rep faces go through tessellate(Model) in
// tessellate/brep_mesh.h instead).
#pragma once
#include <cstdint>
#include <vector>

#include "kernel/mesh.h"
#include "surfaces/surfaces.h"

namespace wedge {

// A triangle mesh whose chordal error (distance between a triangle and the surface at the same
// parameters) stays below `tolerance`: a grid refined until midpoint samples of every cell agree.
// This is the render mesh: vertices along a closed seam or a pole are not merged, so each keeps
// its own uv (a texture wraps without a jump). Trims keep the cells whose centroid is inside.
// Throws if the tolerance would need more than 4M vertices, or more than max_triangles triangles
// (checked on each refined grid before it is evaluated). Positions, normals and uvs (the surface
// parameters) are filled; face_ids = face_id.
Mesh tessellate(const Surface& s, double tolerance, int face_id = -1, std::size_t max_triangles = SIZE_MAX);
// The same grid welded for solids and export: where the first and last rows in u (or v) coincide
// (within 1e-9 of the surface's size, found by evaluation) they become one row, and a row that
// maps to one point (a pole) becomes one vertex that its triangles fan into (no degenerate
// triangles). A closed surface (sphere, torus, full revolution of a closed profile) gives a closed
// 2-manifold. A seam vertex keeps the uv of the first row (uvs jump across the seam: use
// tessellate() for texturing); a pole vertex has the middle of the collapsed row's parameter range
// and the pole's limit normal (the mean of the normals taken just inside the pole from each grid
// point). A closed result is oriented outward (triangles and normals reversed if Su x Sv points in).
Mesh tessellate_welded(const Surface& s, double tolerance, int face_id = -1, std::size_t max_triangles = SIZE_MAX);
// The mesh of the grid us x vs (parameters increasing; trims applied as in tessellate()). Patches
// that share an edge and are meshed with the same parameters along it get the same edge points,
// which is how multi-patch surfaces are tessellated without cracks. `points`, if given, holds the
// already evaluated grid (row-major, us outer).
Mesh tessellate_grid(const Surface& s, const std::vector<double>& us, const std::vector<double>& vs,
                     int face_id = -1, const std::vector<Point3>* points = nullptr);
// tessellate_welded() of the grid us x vs.
Mesh tessellate_grid_welded(const Surface& s, const std::vector<double>& us, const std::vector<double>& vs,
                            int face_id = -1, const std::vector<Point3>* points = nullptr);
// Several patches (the teapot) as one mesh, triangles carrying their patch's index as face id.
// Untrimmed patches all get one uniform grid, as fine as the most demanding patch needs, so edges
// that patches share get the same points (no T-junctions); trimmed patches are meshed one by one.
// max_triangles bounds the whole mesh, checked before the shared grid is made.
Mesh tessellate_patches(const std::vector<SurfacePtr>& patches, double tolerance, std::size_t max_triangles = SIZE_MAX);

}  // namespace wedge
