// Mesh files: OBJ, STL (ASCII and binary), PLY (ASCII and binary) and OFF, read and written here.
//
// Writing is atomic (kernel/file_io.h): the mesh goes to a temporary file beside the target, which
// replaces it only once complete and synced, so a failed export never leaves a half-written file
// and reports the system's reason (a full disk, a read-only folder).
//
// Reading trusts nothing in a file: a count in a header is checked against the file's size before
// anything is allocated, so memory stays proportional to the file; every malformed file is an
// error naming the file, the place (line, byte offset, or element number) and what is wrong.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "kernel/mesh.h"

namespace wedge {

struct MeshWriteOptions {
  bool ascii = false;  // STL and PLY: ASCII instead of binary (OBJ and OFF are always ASCII)
  // Empty, or one RGB colour (components in 0..1) per triangle. PLY: the face element gets the
  // properties `uchar red, green, blue` (MeshLab's and Blender's names). OBJ: a material library
  // beside the file (same name, .mtl) with one material per colour (its Kd), named by `mtllib`,
  // and `usemtl` before each run of triangles of one colour. STL and OFF: ignored.
  std::vector<Vec3> triangle_colors;
};

// The format from the file name's extension (case-insensitive): .obj .stl .ply .off. Throws
// wedge::Error naming the extension and the supported ones otherwise.
std::string mesh_format(const std::string& path);

// Reads a triangle mesh. Polygons are fanned into triangles from their first corner. For OBJ,
// the file's own triangles, normals and texture coordinates are kept: corners are keyed by
// (position, uv, normal), so a vertex used with different uvs or normals in different corners is
// split and each corner keeps its own (a faceted cube with one `vn` per face gives 24 vertices).
// Corners without a normal in a file that has some, or whose vertex was split, get the
// area-weighted average of the face normals around their file vertex; a file without normals or
// splits gives a mesh without normals (the renderer computes the same area-weighted ones).
// PLY and OFF keep per-vertex normals and texture coordinates. STL's separate corners are welded
// by exact position. The mesh may so hold several vertices at one position: a Solid checks
// closedness on the vertices welded by position (csg/solid.h). Throws wedge::Error naming the
// path, the place and the reason.
Mesh read_mesh(const std::string& path);

// The same from a file's bytes, for `format` "obj", "stl", "ply" or "off"; `name` is the file's
// name in messages. The entry point of the fuzz targets (fuzz/).
Mesh parse_mesh(std::string_view bytes, const std::string& format, const std::string& name);

// The mesh as a file holds it, which is how write_mesh writes it. Each position is rounded to the
// file's numbers (`floats`: STL's 32-bit floats; otherwise doubles, kept as they are); the ends
// of an edge that round to one point are merged (a transform far from the origin rounds the ends
// of a boolean result's tiny edges together, a narrowing to floats many more); with `floats`,
// all vertices at one float point whose doubles differ are merged too (an STL reader welds them).
// Vertices at one double position that share no edge stay apart: the copies a non-manifold
// boolean result keeps. Then triangles with two corners at one vertex are dropped, and of the
// triangles on one set of three vertices, pairs of opposite orientation (the fin of no volume a
// collapse leaves where a thin sliver was). Last, a triangle whose three distinct corners are exactly
// collinear (zero area, as rounding can make a thin one) is mended: it goes, and its neighbour
// across the long edge is split at the middle corner into two triangles on the same points
// (repeated while a split leaves a flat half; on an open border it just goes). A closed mesh stays closed. Normals and uvs follow their vertex (dropped
// with `floats`). `source` holds, for each triangle of the result, the index in `mesh` of the
// triangle it came from (the halves of a split share it); `merged` counts the vertices merged
// away, `dropped` the triangles removed before mending, `mended` the flat triangles mended, and
// `flat` the flat triangles left (a mend that would repeat an edge: write_mesh refuses to write
// such a mesh as STL, and writes it as it is in the other formats).
struct FileMesh {
  Mesh mesh;
  std::vector<std::size_t> source;
  std::size_t merged = 0, dropped = 0, mended = 0, flat = 0;
};
FileMesh file_mesh(const Mesh& mesh, bool floats);

// Writes a mesh (positions, and for OBJ/PLY/OFF the normals and uvs it has). Throws wedge::Error
// naming the path and the reason; on error the target file is left as it was.
void write_mesh(const Mesh& mesh, const std::string& path, const MeshWriteOptions& options = {});

}  // namespace wedge
