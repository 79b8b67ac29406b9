// Mesh file I/O over OpenMesh's readers and writers (the only translation unit that includes
// OpenMesh), except reading OBJ, which is parsed here (see read_obj). Per-corner texture
// coordinates and normals become split vertices.
#include "tessellate/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string_view>
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

// --- OBJ ---
// OBJ is read here rather than through OpenMesh: OpenMesh's importer keeps one normal per vertex
// (its halfedge normals are keyed by vertex and set only when a face is added whole, which a
// TriMesh never does for a quad or polygon), and its half-edge kernel drops or duplicates the
// faces that would make an edge non-manifold. A mesh file's triangles, normals and texture
// coordinates are kept here exactly as the file gives them.

struct ObjCorner {
  long v = 0, vt = 0, vn = 0;  // 1-based after resolution; 0 = absent (vt, vn)
};

[[noreturn]] void obj_fail(const std::string& path, std::size_t line, const std::string& what) {
  fail("cannot read '", path, "': line ", line, ": ", what);
}

bool parse_double(std::string_view tok, double& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && ptr == tok.data() + tok.size();
}

bool parse_long(std::string_view tok, long& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && ptr == tok.data() + tok.size();
}

Mesh read_obj(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot read '", path, "': ", std::strerror(errno));
  std::vector<Point3> v;
  std::vector<Vec2> vt;
  std::vector<Vec3> vn;
  std::vector<std::vector<ObjCorner>> faces;
  std::vector<std::size_t> face_line;
  std::string line, joined;
  std::size_t lineno = 0, first_line = 0;
  std::vector<std::string_view> tok;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (joined.empty()) first_line = lineno;
    if (!line.empty() && line.back() == '\\') {  // continuation
      line.pop_back();
      joined += line + " ";
      continue;
    }
    joined += line;
    std::string_view rest(joined);
    if (auto hash = rest.find('#'); hash != std::string_view::npos) rest = rest.substr(0, hash);
    tok.clear();
    for (std::size_t i = 0; i < rest.size();) {
      while (i < rest.size() && std::isspace(static_cast<unsigned char>(rest[i]))) ++i;
      std::size_t j = i;
      while (j < rest.size() && !std::isspace(static_cast<unsigned char>(rest[j]))) ++j;
      if (j > i) tok.push_back(rest.substr(i, j - i));
      i = j;
    }
    const std::size_t at = first_line;
    if (!tok.empty()) {
      auto numbers = [&](std::size_t min, std::size_t max, double* out) {
        if (tok.size() - 1 < min) obj_fail(path, at, "'" + std::string(tok[0]) + "' needs " + std::to_string(min) + " numbers");
        for (std::size_t k = 1; k < tok.size() && k <= max; ++k)
          if (!parse_double(tok[k], out[k - 1])) obj_fail(path, at, "'" + std::string(tok[k]) + "' is not a number");
      };
      if (tok[0] == "v") {
        double x[3] = {0, 0, 0};
        numbers(3, 3, x);  // a w or a vertex colour after x y z is ignored
        v.emplace_back(x[0], x[1], x[2]);
      } else if (tok[0] == "vt") {
        double x[2] = {0, 0};
        numbers(1, 2, x);
        vt.emplace_back(x[0], x[1]);
      } else if (tok[0] == "vn") {
        double x[3] = {0, 0, 0};
        numbers(3, 3, x);
        vn.emplace_back(x[0], x[1], x[2]);
      } else if (tok[0] == "f" || tok[0] == "fo") {
        if (tok.size() < 4) obj_fail(path, at, "a face needs at least 3 corners");
        std::vector<ObjCorner> f;
        for (std::size_t k = 1; k < tok.size(); ++k) {
          // v, v/vt, v//vn or v/vt/vn; negative indices count back from the latest element.
          std::string_view c = tok[k];
          long idx[3] = {0, 0, 0};
          const std::size_t sizes[3] = {v.size(), vt.size(), vn.size()};
          for (int part = 0; part < 3; ++part) {
            std::size_t slash = c.find('/');
            std::string_view field = c.substr(0, slash);
            if (!field.empty() || part == 0) {
              if (!parse_long(field, idx[part]) || idx[part] == 0)
                obj_fail(path, at, "bad face corner '" + std::string(tok[k]) + "'");
              if (idx[part] < 0) {
                idx[part] += static_cast<long>(sizes[part]) + 1;
                if (idx[part] < 1) obj_fail(path, at, "face corner '" + std::string(tok[k]) + "' refers before the first element");
              }
            }
            if (slash == std::string_view::npos) break;
            c.remove_prefix(slash + 1);
            if (part == 2) obj_fail(path, at, "bad face corner '" + std::string(tok[k]) + "'");
          }
          f.push_back({idx[0], idx[1], idx[2]});
        }
        faces.push_back(std::move(f));
        face_line.push_back(at);
      }
      // Anything else (o, g, s, usemtl, mtllib, l, p, curves) carries no triangles: ignored.
    }
    joined.clear();
  }
  if (faces.empty()) fail("'", path, "' holds no triangles");
  // Resolve and check the indices (positive ones may refer to elements given later).
  bool any_vt = false, any_vn = false;
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (const auto& c : faces[i]) {
      if (c.v > static_cast<long>(v.size()))
        obj_fail(path, face_line[i], "face refers to vertex " + std::to_string(c.v) + " of " + std::to_string(v.size()));
      if (c.vt > static_cast<long>(vt.size()))
        obj_fail(path, face_line[i], "face refers to texture coordinate " + std::to_string(c.vt) + " of " + std::to_string(vt.size()));
      if (c.vn > static_cast<long>(vn.size()))
        obj_fail(path, face_line[i], "face refers to normal " + std::to_string(c.vn) + " of " + std::to_string(vn.size()));
      any_vt = any_vt || c.vt, any_vn = any_vn || c.vn;
    }

  // Corners become vertices keyed by (position, uv, normal): a file vertex used with different
  // texture coordinates or normals in different corners is split, so every corner keeps its own.
  // Polygons are fanned from their first corner.
  Mesh m;
  using Key = std::tuple<long, double, double, double, double, double, long>;
  std::map<Key, std::uint32_t> corner_index;
  std::vector<long> source;  // the file vertex of each mesh vertex
  std::vector<bool> own_normal;
  std::vector<Vec3> normals;
  auto corner = [&](const ObjCorner& c) {
    Vec2 uv = c.vt ? vt[c.vt - 1] : Vec2(0, 0);
    Vec3 n = c.vn ? vn[c.vn - 1] : Vec3(0, 0, 0);
    Key key{c.v, uv.x(), uv.y(), n.x(), n.y(), n.z(), c.vn ? 1 : 0};
    auto [it, inserted] = corner_index.emplace(key, static_cast<std::uint32_t>(m.positions.size()));
    if (inserted) {
      m.add_vertex(v[c.v - 1]);
      if (any_vt) m.uvs.push_back(uv);
      normals.push_back(n);
      own_normal.push_back(c.vn != 0);
      source.push_back(c.v);
    }
    return it->second;
  };
  for (const auto& f : faces) {
    const std::uint32_t a = corner(f[0]);
    std::uint32_t b = corner(f[1]);
    for (std::size_t k = 2; k < f.size(); ++k) {
      const std::uint32_t c = corner(f[k]);
      m.add_triangle(a, b, c);
      b = c;
    }
  }
  // Smooth normals only where the file has none: area-weighted over the triangles around the
  // file's vertex (not the split mesh vertex, so a uv seam does not crease the shading). With no
  // normals in the file and no vertex split, the mesh is left without normals and the renderer
  // computes the same ones.
  const bool split = m.positions.size() > std::set<long>(source.begin(), source.end()).size();
  if (any_vn || split) {
    std::vector<Vec3> smooth(v.size(), Vec3::Zero());
    for (const auto& t : m.triangles) {
      Vec3 w = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
      for (int k = 0; k < 3; ++k) smooth[source[t[k]] - 1] += w;
    }
    for (std::size_t i = 0; i < normals.size(); ++i)
      if (!own_normal[i]) {
        const Vec3& s = smooth[source[i] - 1];
        normals[i] = s.norm() > 0 ? Vec3(s.normalized()) : Vec3::Zero();
      }
    m.normals = std::move(normals);
  }
  return m;
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
  if (format == "obj") {
    Mesh m = read_obj(path);
    try {
      m.check();
    } catch (const Error& e) {
      fail("'", path, "': ", e.what());
    }
    return m;
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
  // STL stores each triangle's corners separately; corners written from the same vertex have
  // identical coordinates, so merging exactly equal positions rebuilds the shared vertices.
  if (format == "stl") m = m.welded();
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
