// Mesh file writers: OBJ, STL (ASCII and binary), PLY (ASCII and binary little-endian) and OFF.
// Each writes through an AtomicFile (kernel/file_io.h): the old file stays until a complete,
// synced new one replaces it, and every write error is reported with the system's reason.
// Text numbers are the shortest decimal that reads back as the same double (std::to_chars).
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "kernel/error.h"
#include "kernel/file_io.h"
#include "kernel/kernel.h"
#include "kernel/predicates.h"
#include "tessellate/mesh_io.h"
#include "tessellate/progress.h"

namespace wedge {

namespace {

// Each block of 64 KiB asks the thread's poll (tessellate/progress.h) whether to stop: a cancel
// (Ctrl-C in `wedge run`) throws from it, and the unfinished AtomicFile leaves the old file.
void poll() {
  if (const TessellatePoll* p = tessellate_poll()) (*p)();
}

// A text line builder over the file: numbers in their shortest exact form.
class TextOut {
 public:
  explicit TextOut(AtomicFile& file) : file_(file) { buf_.reserve(kFlush + 256); }
  TextOut& operator<<(std::string_view s) {
    buf_.append(s);
    return maybe_flush();
  }
  TextOut& operator<<(char c) {
    buf_.push_back(c);
    return maybe_flush();
  }
  TextOut& operator<<(double x) {
    char tmp[32];
    auto r = std::to_chars(tmp, tmp + sizeof tmp, x);
    buf_.append(tmp, r.ptr);
    return maybe_flush();
  }
  TextOut& operator<<(float x) {  // the shortest decimal that reads back as the same float
    char tmp[32];
    auto r = std::to_chars(tmp, tmp + sizeof tmp, x);
    buf_.append(tmp, r.ptr);
    return maybe_flush();
  }
  TextOut& operator<<(std::uint64_t x) {
    char tmp[24];
    auto r = std::to_chars(tmp, tmp + sizeof tmp, x);
    buf_.append(tmp, r.ptr);
    return maybe_flush();
  }
  TextOut& operator<<(std::uint32_t x) { return *this << static_cast<std::uint64_t>(x); }
  void flush() {
    poll();
    file_.write(buf_);
    buf_.clear();
  }

 private:
  static constexpr std::size_t kFlush = 1 << 16;
  TextOut& maybe_flush() {
    if (buf_.size() >= kFlush) flush();
    return *this;
  }
  AtomicFile& file_;
  std::string buf_;
};

void put_u32le(std::string& out, std::uint32_t x) {
  if constexpr (std::endian::native == std::endian::big) x = __builtin_bswap32(x);
  char b[4];
  std::memcpy(b, &x, 4);
  out.append(b, 4);
}
void put_f32le(std::string& out, float x) { put_u32le(out, std::bit_cast<std::uint32_t>(x)); }
void put_f64le(std::string& out, double x) {
  std::uint64_t u = std::bit_cast<std::uint64_t>(x);
  if constexpr (std::endian::native == std::endian::big) u = __builtin_bswap64(u);
  char b[8];
  std::memcpy(b, &u, 8);
  out.append(b, 8);
}

// A file must hold every triangle as a valid surface: each directed edge at most once, no
// triangle repeating a vertex. Counts the triangles that break it.
std::size_t non_manifold_triangles(const Mesh& mesh) {
  std::vector<std::uint64_t> edges;
  edges.reserve(mesh.triangles.size() * 3);
  std::size_t bad = 0;
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) ++bad;
    for (int k = 0; k < 3; ++k) edges.push_back(std::uint64_t(t[k]) << 32 | t[(k + 1) % 3]);
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 1; i < edges.size(); ++i)
    if (edges[i] == edges[i - 1]) ++bad;
  return bad;
}

// STL's corners are 32-bit floats: the mesh is written as file_mesh(mesh, true) makes it, so that
// every reader (which welds corners by position) gets a valid surface back.
void write_stl(const Mesh& double_mesh, AtomicFile& file, bool ascii) {
  // STL holds 32-bit floats: a coordinate beyond their range would be written as infinity, and a
  // mesh whose every coordinate is below their normal range (a part 1e-40 wide) as zeros or a
  // few digits. (One tiny coordinate in a mesh of size 1 is rounding noise: 0 is fine for it.)
  double reach = 0;
  for (std::size_t i = 0; i < double_mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      if (std::fabs(double_mesh.positions[i][k]) > std::numeric_limits<float>::max())
        fail("cannot write '", file.path(), "': vertex ", i, " coordinate ", double_mesh.positions[i][k],
             " is beyond the range of STL's 32-bit floats");
      reach = std::max(reach, std::fabs(double_mesh.positions[i][k]));
    }
  constexpr double kLeast = std::numeric_limits<float>::min() * 0x1p23;  // 24 bits of the largest coordinate
  if (reach > 0 && reach < kLeast)
    fail("cannot write '", file.path(), "': the mesh's largest coordinate ", reach, " is below ", kLeast,
         ", where STL's 32-bit floats lose their digits (scale the part up, or write .ply or .obj)");
  const FileMesh rounded = file_mesh(double_mesh, true);
  const Mesh& mesh = rounded.mesh;
  if (std::size_t bad = non_manifold_triangles(mesh))
    fail("cannot write '", file.path(), "': rounded to STL's 32-bit floats, ", bad, " of ", mesh.triangles.size(),
         " triangles make non-manifold edges (vertices closer than a float's precision; write .ply or .obj, which keep doubles)");
  if (mesh.triangles.empty())
    fail("cannot write '", file.path(), "': every triangle collapses when rounded to STL's 32-bit floats");
  if (rounded.flat != 0)
    fail("cannot write '", file.path(), "': rounded to STL's 32-bit floats, ", rounded.flat, " of ", mesh.triangles.size(),
         " triangles have three collinear corners that cannot be mended (write .ply or .obj, which keep doubles)");
  if (ascii) {
    TextOut out(file);
    out << "solid wedge\n";
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Vec3 n = mesh.triangle_normal(t);
      out << "  facet normal " << float(n.x()) << ' ' << float(n.y()) << ' ' << float(n.z()) << "\n    outer loop\n";
      for (auto v : mesh.triangles[t]) {
        const Point3& p = mesh.positions[v];
        // Each coordinate is a float held in a double: its shortest decimal as a double reads back
        // as that float in readers of either precision, so ASCII and binary give one mesh.
        out << "      vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      }
      out << "    endloop\n  endfacet\n";
    }
    out << "endsolid wedge\n";
    out.flush();
    return;
  }
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    fail("cannot write '", file.path(), "': ", mesh.triangles.size(), " triangles are more than binary STL can count");
  std::string out;
  out.reserve(1 << 16);
  std::string header = std::string("binary STL written by wedge ") + version();
  header.resize(80, ' ');
  out += header;
  put_u32le(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = mesh.triangle_normal(t);
    for (int k = 0; k < 3; ++k) put_f32le(out, static_cast<float>(n[k]));
    for (auto v : mesh.triangles[t])
      for (int k = 0; k < 3; ++k) put_f32le(out, static_cast<float>(mesh.positions[v][k]));
    out.append(2, '\0');  // attribute byte count
    if (out.size() >= (1 << 16)) {
      poll();
      file.write(out);
      out.clear();
    }
  }
  file.write(out);
}

// A colour component in 0..1 as a byte (rounded, clamped).
std::uint8_t colour_byte(double c) { return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255)); }

// The distinct colours in order of first use, and each triangle's index among them.
std::vector<Vec3> palette(const std::vector<Vec3>& colours, std::vector<std::size_t>& index) {
  std::vector<Vec3> out;
  index.resize(colours.size());
  for (std::size_t t = 0; t < colours.size(); ++t) {
    auto it = std::find(out.begin(), out.end(), colours[t]);
    index[t] = static_cast<std::size_t>(it - out.begin());
    if (it == out.end()) out.push_back(colours[t]);
  }
  return out;
}

void write_obj(const Mesh& mesh, AtomicFile& file, bool normals, bool uvs, const std::vector<Vec3>& colours,
               const std::string& mtl_name) {
  TextOut out(file);
  out << "# written by wedge " << version() << '\n';
  std::vector<std::size_t> index;
  if (!colours.empty()) {
    palette(colours, index);
    out << "mtllib " << mtl_name << '\n';
  }
  for (const auto& p : mesh.positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  if (uvs)
    for (const auto& t : mesh.uvs) out << "vt " << t.x() << ' ' << t.y() << '\n';
  if (normals)
    for (const auto& n : mesh.normals) out << "vn " << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
  std::size_t current = SIZE_MAX;
  for (std::size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
    const auto& t = mesh.triangles[ti];
    if (!index.empty() && index[ti] != current) {
      current = index[ti];
      out << "usemtl wedge_" << std::uint64_t(current) << '\n';
    }
    out << 'f';
    for (auto v : t) {
      const std::uint64_t i = std::uint64_t(v) + 1;
      out << ' ' << i;
      if (uvs || normals) {
        out << '/';
        if (uvs) out << i;
        if (normals) out << '/' << i;
      }
    }
    out << '\n';
  }
  out.flush();
}

void write_off(const Mesh& mesh, AtomicFile& file, bool normals, bool uvs) {
  TextOut out(file);
  out << (uvs ? "ST" : "") << (normals ? "N" : "") << "OFF\n";
  out << std::uint64_t(mesh.positions.size()) << ' ' << std::uint64_t(mesh.triangles.size()) << " 0\n";
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Point3& p = mesh.positions[i];
    out << p.x() << ' ' << p.y() << ' ' << p.z();
    if (normals) out << ' ' << mesh.normals[i].x() << ' ' << mesh.normals[i].y() << ' ' << mesh.normals[i].z();
    if (uvs) out << ' ' << mesh.uvs[i].x() << ' ' << mesh.uvs[i].y();
    out << '\n';
  }
  for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  out.flush();
}

// The .mtl of write_obj: material wedge_k has the k-th distinct colour as its diffuse colour.
void write_mtl(const std::vector<Vec3>& colours, AtomicFile& file) {
  TextOut out(file);
  out << "# written by wedge " << version() << '\n';
  std::vector<std::size_t> index;
  const std::vector<Vec3> p = palette(colours, index);
  for (std::size_t k = 0; k < p.size(); ++k)
    out << "newmtl wedge_" << std::uint64_t(k) << "\nKd " << p[k].x() << ' ' << p[k].y() << ' ' << p[k].z() << '\n';
  out.flush();
}

void write_ply(const Mesh& mesh, AtomicFile& file, bool ascii, bool normals, bool uvs, const std::vector<Vec3>& colours) {
  const bool coloured = !colours.empty();
  TextOut head(file);
  head << "ply\nformat " << (ascii ? "ascii" : "binary_little_endian") << " 1.0\ncomment written by wedge "
       << version() << "\nelement vertex " << std::uint64_t(mesh.positions.size())
       << "\nproperty double x\nproperty double y\nproperty double z\n";
  if (normals) head << "property double nx\nproperty double ny\nproperty double nz\n";
  if (uvs) head << "property double u\nproperty double v\n";
  head << "element face " << std::uint64_t(mesh.triangles.size()) << "\nproperty list uchar uint vertex_indices\n";
  if (coloured) head << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  head << "end_header\n";
  if (ascii) {
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const Point3& p = mesh.positions[i];
      head << p.x() << ' ' << p.y() << ' ' << p.z();
      if (normals) head << ' ' << mesh.normals[i].x() << ' ' << mesh.normals[i].y() << ' ' << mesh.normals[i].z();
      if (uvs) head << ' ' << mesh.uvs[i].x() << ' ' << mesh.uvs[i].y();
      head << '\n';
    }
    for (std::size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
      const auto& t = mesh.triangles[ti];
      head << "3 " << t[0] << ' ' << t[1] << ' ' << t[2];
      if (coloured)
        for (int k = 0; k < 3; ++k) head << ' ' << std::uint32_t(colour_byte(colours[ti][k]));
      head << '\n';
    }
    head.flush();
    return;
  }
  head.flush();
  std::string out;
  out.reserve(1 << 16);
  auto spill = [&] {
    if (out.size() >= (1 << 16)) {
      poll();
      file.write(out);
      out.clear();
    }
  };
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) put_f64le(out, mesh.positions[i][k]);
    if (normals)
      for (int k = 0; k < 3; ++k) put_f64le(out, mesh.normals[i][k]);
    if (uvs)
      for (int k = 0; k < 2; ++k) put_f64le(out, mesh.uvs[i][k]);
    spill();
  }
  for (std::size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
    out.push_back(3);
    for (auto v : mesh.triangles[ti]) put_u32le(out, v);
    if (coloured)
      for (int k = 0; k < 3; ++k) out.push_back(static_cast<char>(colour_byte(colours[ti][k])));
    spill();
  }
  file.write(out);
}

// A triangle of file_mesh's on its merged vertices, and the input triangle it comes from.
struct FlatTri {
  std::array<std::uint32_t, 3> v;
  std::size_t source;
};

// Rounding can bring a triangle's three distinct corners onto one line (zero area: a reader, and
// our own boolean's operand check, sees a degenerate triangle). Such a flat triangle x, y, m, with
// m strictly inside segment x-y (decided exactly on the file's numbers), is removed and its
// neighbour y, x, d across the long edge split into y, m, d and m, x, d: the same points, the
// same surface in as many triangles. When that neighbour was flat too, its halves are, and they
// are mended in turn. Neighbours are found by position, as a reader welds them (a uv seam's
// copies of a vertex are one point); the halves keep the neighbour's own copies of y, x and d. A
// flat triangle whose long edge has no neighbour (an open mesh's border) is removed: the border
// runs through m instead; so is one whose neighbour is itself reversed (a fin on copies of its
// points, which a far transform can round together), with that neighbour. A flat triangle stays when its long edge has more than one neighbour,
// when its mend would repeat an edge (d already joined to m, other than by a half's reverse, with
// which that half cancels) or when the steps run out;
// `out.flat` counts those. `kept` is updated in place, in the order of the sources.
void mend_flat(std::vector<FlatTri>& kept, const std::vector<std::array<double, 3>>& f, FileMesh& out) {
  using u32 = std::uint32_t;
  auto point = [&](u32 v) { return Point3(f[v][0], f[v][1], f[v][2]); };
  auto flat = [&](const FlatTri& t) { return collinear(point(t.v[0]), point(t.v[1]), point(t.v[2])); };
  std::vector<std::size_t> queue;
  for (std::size_t t = 0; t < kept.size(); ++t)
    if (flat(kept[t])) queue.push_back(t);
  if (queue.empty()) return;
  std::map<std::array<double, 3>, u32> weld;  // position -> its number
  auto at = [&](u32 v) { return weld.emplace(f[v], static_cast<u32>(weld.size())).first->second; };
  auto key = [&](u32 a, u32 b) { return std::uint64_t(at(a)) << 32 | at(b); };
  constexpr std::size_t kMany = std::numeric_limits<std::size_t>::max();
  std::unordered_map<std::uint64_t, std::size_t> edge;  // directed edge -> the triangle using it, or kMany
  edge.reserve(kept.size() * 3);
  auto enter = [&](std::size_t t) {
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = edge.emplace(key(kept[t].v[k], kept[t].v[(k + 1) % 3]), t);
      if (!fresh) it->second = kMany;
    }
  };
  for (std::size_t t = 0; t < kept.size(); ++t) enter(t);
  auto triangle_of = [&](u32 a, u32 b) {
    const auto it = edge.find(key(a, b));
    return it == edge.end() ? kMany : it->second;
  };
  std::vector<char> alive(kept.size(), 1);
  auto remove = [&](std::size_t t) {
    alive[t] = 0;
    for (int k = 0; k < 3; ++k) {
      auto it = edge.find(key(kept[t].v[k], kept[t].v[(k + 1) % 3]));
      if (it != edge.end() && it->second == t) edge.erase(it);
    }
  };
  auto add = [&](std::array<u32, 3> v, std::size_t source) {
    kept.push_back({v, source});
    alive.push_back(1);
    enter(kept.size() - 1);
    queue.push_back(kept.size() - 1);
  };
  // A mend makes new flat triangles only on the line of the old one, inside its long edge or
  // sharing the neighbour's; the bound guards the loop against whatever a broken input does.
  std::size_t steps = 4 * kept.size() + 64;
  while (!queue.empty() && steps > 0) {
    const std::size_t t = queue.back();
    queue.pop_back();
    if (!alive[t] || !flat(kept[t])) continue;
    --steps;
    // Along the axis on which the corners spread most, the collinear corners' order is the line's.
    const std::array<u32, 3> c = kept[t].v;
    auto spread = [&](int k) { return std::fabs(f[c[0]][k] - f[c[1]][k]) + std::fabs(f[c[0]][k] - f[c[2]][k]); };
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (spread(k) > spread(axis)) axis = k;
    int mid = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = f[c[(k + 1) % 3]][axis], b = f[c[(k + 2) % 3]][axis], m = f[c[k]][axis];
      if ((a < m && m < b) || (b < m && m < a)) mid = k;
    }
    const u32 m = c[mid], x = c[(mid + 1) % 3], y = c[(mid + 2) % 3];  // the triangle is x, y, m
    const auto across = edge.find(key(y, x));
    if (across == edge.end()) {
      remove(t);
      ++out.mended;
      continue;
    }
    const std::size_t nb = across->second;
    if (nb == kMany || triangle_of(x, y) != t) continue;  // an edge of more than two triangles
    // The neighbour's corners from y on: y', x', d (its own copies of y and x).
    std::array<u32, 3> nv = kept[nb].v;
    while (at(nv[0]) != at(y)) std::rotate(nv.begin(), nv.begin() + 1, nv.end());
    const u32 d = nv[2];
    if (at(d) == at(m)) {  // the neighbour is the flat triangle reversed, on copies of its points: a fin
      remove(t);
      remove(nb);
      out.mended += 2;
      continue;
    }
    // A half whose reverse is there already (a triangle on m, d and y', or on m, d and x') cancels
    // with it instead of being added, as file_mesh's fins do; otherwise the edge m-d must be new.
    auto third_at = [&](std::size_t r, u32 a, u32 b, u32 want) {
      if (r == kMany) return false;
      for (u32 v : kept[r].v)
        if (at(v) != at(a) && at(v) != at(b)) return at(v) == at(want);
      return false;
    };
    const std::size_t r = triangle_of(d, m), s = triangle_of(m, d);
    const bool cancel_a = third_at(r, d, m, y), cancel_b = third_at(s, m, d, x);
    if ((r != kMany || s != kMany) && !cancel_a && !cancel_b) continue;  // m-d is another edge already
    const std::size_t source = kept[nb].source;
    remove(t);
    remove(nb);
    if (cancel_a) remove(r);
    else add({nv[0], m, d}, source);
    if (cancel_b) remove(s);
    else add({m, nv[1], d}, source);
    ++out.mended;
  }
  std::vector<FlatTri> live;
  live.reserve(kept.size());
  for (std::size_t t = 0; t < kept.size(); ++t)
    if (alive[t]) {
      live.push_back(kept[t]);
      out.flat += flat(kept[t]);
    }
  std::stable_sort(live.begin(), live.end(), [](const FlatTri& a, const FlatTri& b) { return a.source < b.source; });
  kept = std::move(live);
}

}  // namespace

FileMesh file_mesh(const Mesh& mesh, bool floats) {
  using u32 = std::uint32_t;
  using F3 = std::array<double, 3>;
  const std::size_t n = mesh.positions.size();
  std::vector<F3> f(n);  // each vertex's position as the file holds it
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) f[i][k] = floats ? double(static_cast<float>(mesh.positions[i][k])) : mesh.positions[i][k];
  std::vector<u32> rep(n);
  std::iota(rep.begin(), rep.end(), 0u);
  auto find = [&](u32 x) {
    while (rep[x] != x) x = rep[x] = rep[rep[x]];
    return x;
  };
  FileMesh out;
  auto join = [&](u32 a, u32 b) {
    a = find(a), b = find(b);
    if (a == b) return;
    rep[std::max(a, b)] = std::min(a, b);
    ++out.merged;
  };
  // An edge whose ends are at one point collapses.
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] != t[(k + 1) % 3] && f[t[k]] == f[t[(k + 1) % 3]]) join(t[k], t[(k + 1) % 3]);
  if (floats) {
    // A reader of an STL welds corners by position: vertices at one float point whose doubles
    // differ are one vertex. (Copies at one double position, a non-manifold result's shells kept
    // apart, stay apart in the index; no STL reader can tell them apart anyway.)
    auto exact = [&](u32 i) { return F3{mesh.positions[i].x(), mesh.positions[i].y(), mesh.positions[i].z()}; };
    std::vector<u32> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](u32 a, u32 b) { return f[a] != f[b] ? f[a] < f[b] : exact(a) < exact(b); });
    for (std::size_t i = 0; i < n;) {
      std::size_t j = i + 1;
      bool distinct = false;
      for (; j < n && f[order[j]] == f[order[i]]; ++j) distinct |= exact(order[j]) != exact(order[i]);
      if (distinct)
        for (std::size_t k = i + 1; k < j; ++k) join(order[i], order[k]);
      i = j;
    }
  }
  // Triangles on the merged vertices, less those with two corners at one vertex; then, of the
  // triangles on one set of three vertices, opposite pairs cancel (a fin of no volume).
  struct Tri {
    std::array<u32, 3> key;  // sorted vertices
    bool odd;                // orientation against the sorted order
    std::size_t t;
  };
  std::vector<Tri> tris;
  tris.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::array<u32, 3> v{find(mesh.triangles[t][0]), find(mesh.triangles[t][1]), find(mesh.triangles[t][2])};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    const std::size_t m = static_cast<std::size_t>(std::min_element(v.begin(), v.end()) - v.begin());
    const u32 b = v[(m + 1) % 3], c = v[(m + 2) % 3];
    tris.push_back({{v[m], std::min(b, c), std::max(b, c)}, b > c, t});
  }
  std::stable_sort(tris.begin(), tris.end(), [](const Tri& a, const Tri& b) { return a.key < b.key; });
  for (std::size_t i = 0; i < tris.size();) {
    std::size_t j = i;
    long balance = 0;
    for (; j < tris.size() && tris[j].key == tris[i].key; ++j) balance += tris[j].odd ? -1 : 1;
    for (std::size_t k = i; k < j && balance != 0; ++k)
      if ((tris[k].odd ? -1 : 1) * balance > 0) {
        out.source.push_back(tris[k].t);
        balance += tris[k].odd ? 1 : -1;
      }
    i = j;
  }
  std::sort(out.source.begin(), out.source.end());
  out.dropped = mesh.triangles.size() - out.source.size();
  std::vector<FlatTri> kept;
  kept.reserve(out.source.size());
  for (std::size_t t : out.source)
    kept.push_back({{find(mesh.triangles[t][0]), find(mesh.triangles[t][1]), find(mesh.triangles[t][2])}, t});
  mend_flat(kept, f, out);
  if (out.merged == 0 && out.dropped == 0 && out.mended == 0 && !floats) {
    out.mesh = mesh;
    return out;
  }
  // The kept triangles on their used vertices, numbered in order of first use; a merged vertex
  // keeps its representative's normal and uv (STL has neither).
  const bool ids = mesh.face_ids.size() == mesh.triangles.size();
  const bool normals = !floats && !mesh.normals.empty() && mesh.normals.size() == n;
  const bool uvs = !floats && !mesh.uvs.empty() && mesh.uvs.size() == n;
  std::vector<u32> index(n, std::numeric_limits<u32>::max());
  out.source.clear();
  for (const FlatTri& k : kept) {
    Mesh::Triangle tri;
    for (int c = 0; c < 3; ++c) {
      const u32 v = k.v[c];
      if (index[v] == std::numeric_limits<u32>::max()) {
        index[v] = static_cast<u32>(out.mesh.positions.size());
        out.mesh.positions.emplace_back(f[v][0], f[v][1], f[v][2]);
        if (normals) out.mesh.normals.push_back(mesh.normals[v]);
        if (uvs) out.mesh.uvs.push_back(mesh.uvs[v]);
      }
      tri[c] = index[v];
    }
    out.mesh.triangles.push_back(tri);
    out.source.push_back(k.source);
    if (ids) out.mesh.face_ids.push_back(mesh.face_ids[k.source]);
  }
  return out;
}

void write_mesh(const Mesh& mesh, const std::string& path, const MeshWriteOptions& options) {
  std::string format = mesh_format(path);
  try {
    mesh.check();
  } catch (const Error& e) {
    fail("cannot write '", path, "': ", e.what());
  }
  if (mesh.triangles.empty()) fail("cannot write '", path, "': the mesh has no triangles");
  if (std::size_t bad = non_manifold_triangles(mesh))
    fail("cannot write '", path, "': ", bad, " of ", mesh.triangles.size(),
         " triangles make non-manifold edges or repeat a vertex (the mesh is not a valid surface)");
  const bool normals = mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty();
  const bool uvs = mesh.uvs.size() == mesh.positions.size() && !mesh.uvs.empty();
  auto finite = [](const auto& values) {
    return std::all_of(values.begin(), values.end(), [](const auto& v) { return v.allFinite(); });
  };
  if ((normals && !finite(mesh.normals)) || (uvs && !finite(mesh.uvs)))
    fail("cannot write '", path, "': the mesh has a non-finite normal or texture coordinate");

  const auto& colours = options.triangle_colors;
  if (!colours.empty() && colours.size() != mesh.triangles.size())
    fail("cannot write '", path, "': ", colours.size(), " triangle colours for ", mesh.triangles.size(), " triangles");
  if (!finite(colours)) fail("cannot write '", path, "': a triangle colour is not a finite number");

  // Ends of an edge that the mesh's own rounding brought to one point (a boolean result moved far
  // from the origin) collapse here, or every reader would see a degenerate triangle. (STL's
  // rounding to floats is write_stl's.)
  FileMesh collapsed;
  if (format != "stl") {
    collapsed = file_mesh(mesh, false);
    if (collapsed.dropped != 0 || collapsed.mended != 0) {
      if (!colours.empty()) {
        std::vector<Vec3> kept;
        for (std::size_t t : collapsed.source) kept.push_back(colours[t]);
        MeshWriteOptions o = options;
        o.triangle_colors = std::move(kept);
        return write_mesh(collapsed.mesh, path, o);
      }
      return write_mesh(collapsed.mesh, path, options);
    }
  }
  // OBJ's colours go to a material library beside it, written (and committed) first, so that the
  // OBJ never names a library that is not there.
  const bool mtl = format == "obj" && !colours.empty();
  std::string mtl_path, mtl_name;
  if (mtl) {
    const std::size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    mtl_path = path.substr(0, dot) + ".mtl";
    mtl_name = mtl_path.substr(slash == std::string::npos ? 0 : slash + 1);
    AtomicFile lib(mtl_path);
    write_mtl(colours, lib);
    lib.commit();
  }
  AtomicFile file(path);
  if (format == "stl") write_stl(mesh, file, options.ascii);
  else if (format == "obj") write_obj(mesh, file, normals, uvs, colours, mtl_name);
  else if (format == "off") write_off(mesh, file, normals, uvs);
  else write_ply(mesh, file, options.ascii, normals, uvs, colours);
  file.commit();
}

}  // namespace wedge
