// Mesh file I/O over OpenMesh's readers and writers (the only translation unit that includes
// OpenMesh). Conversion: OpenMesh TriMesh <-> wedge::Mesh, with per-corner texture coordinates and
// normals turned into split vertices.
#include "tessellate/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>

#include <unistd.h>

#include "kernel/error.h"

namespace wedge {

namespace {

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using TexCoord2D = OpenMesh::Vec2d;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void quiet_openmesh() {
  // OpenMesh reports problems on std::cerr; we report them as errors instead.
  static bool done = [] {
    omerr().disable();
    omout().disable();
    omlog().disable();
    return true;
  }();
  (void)done;
}

// STL stores each triangle's corners separately; corners written from the same vertex have
// identical coordinates, so merging exactly equal positions rebuilds the shared vertices.
void weld_identical_vertices(Mesh& m) {
  std::map<std::tuple<double, double, double>, std::uint32_t> index;
  std::vector<std::uint32_t> remap(m.positions.size());
  std::vector<Point3> positions;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const auto& p = m.positions[i];
    auto [it, inserted] = index.emplace(std::make_tuple(p.x(), p.y(), p.z()), static_cast<std::uint32_t>(positions.size()));
    if (inserted) positions.push_back(p);
    remap[i] = it->second;
  }
  m.positions = std::move(positions);
  m.normals.clear();
  m.uvs.clear();
  for (auto& t : m.triangles)
    for (auto& v : t) v = remap[v];
}

}  // namespace

std::string mesh_format(const std::string& path) {
  std::string ext = lower_extension(path);
  if (ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".off") return ext.substr(1);
  fail("'", path, "': unknown mesh format '", ext.empty() ? std::string("(no extension)") : ext,
       "' (supported: .obj .stl .ply .off)");
}

Mesh read_mesh(const std::string& path) {
  std::string format = mesh_format(path);
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) fail("cannot read '", path, "': ", std::strerror(errno));
    if (probe.peek() == std::ifstream::traits_type::eof()) fail("cannot read '", path, "': the file is empty");
  }
  quiet_openmesh();
  OMesh om;
  om.request_vertex_normals();
  om.request_vertex_texcoords2D();
  om.request_halfedge_texcoords2D();
  om.request_halfedge_normals();
  OpenMesh::IO::Options opt;
  opt += OpenMesh::IO::Options::VertexNormal;
  opt += OpenMesh::IO::Options::VertexTexCoord;
  opt += OpenMesh::IO::Options::FaceTexCoord;
  if (!OpenMesh::IO::read_mesh(om, path, opt))
    fail("cannot read '", path, "': not a valid ", format, " file");
  if (om.n_faces() == 0) fail("'", path, "' holds no triangles");

  const bool corner_uv = opt.check(OpenMesh::IO::Options::FaceTexCoord);
  const bool vertex_uv = !corner_uv && opt.check(OpenMesh::IO::Options::VertexTexCoord);
  const bool has_normals = opt.check(OpenMesh::IO::Options::VertexNormal);

  Mesh m;
  // A corner's key: its vertex and, where the file gives them per corner, its uv.
  std::map<std::tuple<int, double, double>, std::uint32_t> corner_index;
  for (auto fh : om.faces()) {
    std::array<std::uint32_t, 3> tri{};
    int k = 0;
    for (auto heh : om.fh_range(fh)) {
      if (k >= 3) break;
      auto vh = om.to_vertex_handle(heh);
      OpenMesh::Vec2d uv(0, 0);
      if (corner_uv) uv = om.texcoord2D(heh);
      else if (vertex_uv) uv = om.texcoord2D(vh);
      auto key = std::make_tuple(vh.idx(), corner_uv ? uv[0] : 0.0, corner_uv ? uv[1] : 0.0);
      auto it = corner_index.find(key);
      if (it == corner_index.end()) {
        const auto& p = om.point(vh);
        std::uint32_t idx = m.add_vertex(Point3(p[0], p[1], p[2]));
        if (has_normals) {
          const auto& n = om.normal(vh);
          m.normals.emplace_back(n[0], n[1], n[2]);
        }
        if (corner_uv || vertex_uv) m.uvs.emplace_back(uv[0], uv[1]);
        it = corner_index.emplace(key, idx).first;
      }
      tri[k++] = it->second;
    }
    // No face ids: a file's triangles carry no B-Rep faces, so a renderer smooths the normals
    // over the whole mesh where the file gives none.
    if (k == 3) m.add_triangle(tri[0], tri[1], tri[2]);
  }
  if (format == "stl") weld_identical_vertices(m);
  if (has_normals) {
    bool all_zero = std::all_of(m.normals.begin(), m.normals.end(), [](const Vec3& n) { return n.squaredNorm() == 0; });
    if (all_zero) m.normals.clear();
  }
  try {
    m.check();
  } catch (const Error& e) {
    fail("'", path, "': ", e.what());
  }
  return m;
}

void write_mesh(const Mesh& mesh, const std::string& path, const MeshWriteOptions& options) {
  std::string format = mesh_format(path);
  mesh.check();
  if (mesh.triangles.empty()) fail("cannot write '", path, "': the mesh has no triangles");
  namespace fs = std::filesystem;
  fs::path target(path);
  fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) fail("cannot write '", path, "': directory '", dir.string(), "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) fail("cannot write '", path, "': ", std::strerror(errno));

  quiet_openmesh();
  OMesh om;
  const bool normals = mesh.normals.size() == mesh.positions.size() && format != "stl";
  const bool uvs = mesh.uvs.size() == mesh.positions.size() && format != "stl";
  if (normals) om.request_vertex_normals();
  if (uvs) om.request_vertex_texcoords2D();
  om.request_face_normals();
  std::vector<OMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    auto vh = om.add_vertex(OMesh::Point(p.x(), p.y(), p.z()));
    if (normals) om.set_normal(vh, OMesh::Normal(mesh.normals[i].x(), mesh.normals[i].y(), mesh.normals[i].z()));
    if (uvs) om.set_texcoord2D(vh, OMesh::TexCoord2D(mesh.uvs[i].x(), mesh.uvs[i].y()));
    handles.push_back(vh);
  }
  // OpenMesh's half-edge kernel refuses faces that would make an edge non-manifold; a mesh file
  // must hold every triangle, so count refusals and report them rather than write a partial mesh.
  std::size_t refused = 0;
  for (const auto& t : mesh.triangles) {
    auto fh = om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
    if (!fh.is_valid()) ++refused;
  }
  if (refused)
    fail("cannot write '", path, "': ", refused, " of ", mesh.triangles.size(),
         " triangles make non-manifold edges or repeat a vertex (the mesh is not a valid surface)");
  om.update_face_normals();

  OpenMesh::IO::Options opt;
  if (!options.ascii && (format == "stl" || format == "ply")) opt += OpenMesh::IO::Options::Binary;
  if (normals) opt += OpenMesh::IO::Options::VertexNormal;
  if (uvs) opt += OpenMesh::IO::Options::VertexTexCoord;

  fs::path tmp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + "." + format);
  bool ok = OpenMesh::IO::write_mesh(om, tmp.string(), opt, 17);
  if (!ok) {
    fs::remove(tmp, ec);
    fail("cannot write '", path, "': the ", format, " writer failed");
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    fail("cannot write '", path, "': ", ec.message());
  }
}

}  // namespace wedge
