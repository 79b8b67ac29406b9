// Mesh file readers: OBJ, STL (ASCII and binary), PLY (ASCII, binary little- and big-endian) and
// OFF, each parsed here from the file's bytes. Writers are in mesh_write.cpp.
//
// The rules every reader follows, because the file may be hostile:
//  - A count in a header is checked against the bytes that follow before anything is allocated:
//    each element has a least size (a binary record's fixed part, or one character and one
//    separator per number of a text one), and a count that cannot fit is an error, so a 51-byte
//    file declaring 2e9 faces is refused at once and memory stays proportional to the file.
//  - Every index is checked against the vertex count, every coordinate for being finite.
//  - An error names the file, the place (line, byte offset, or element number) and what is wrong.
// We parse the formats ourselves rather than through OpenMesh because its readers allocate what a
// header asks for, report every problem as one boolean, and its half-edge kernel drops the faces
// that would make an edge non-manifold.
#include "tessellate/mesh_io.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

#include "kernel/error.h"
#include "kernel/file_io.h"
#include "kernel/scaled.h"
#include "tessellate/planar.h"

namespace wedge {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string quoted(std::string_view tok) {
  constexpr std::size_t kMax = 40;  // a token in a message; a hostile one may be megabytes long
  std::string s(tok.substr(0, kMax));
  for (char& c : s)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return "'" + s + (tok.size() > kMax ? "...'" : "'");
}

// "cannot read 'name': <what>"
template <class... Parts>
[[noreturn]] void bad(const std::string& name, const Parts&... parts) {
  fail("cannot read '", name, "': ", parts...);
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Parses a whole token as a number. Returns an empty string, or what is wrong with it.
std::string parse_double(std::string_view tok, double& out) {
  std::string_view t = tok;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), out);
  if (ec == std::errc::result_out_of_range && ptr == t.data() + t.size()) return quoted(tok) + " is out of range";
  if (ec != std::errc() || ptr != t.data() + t.size() || t.empty()) return quoted(tok) + " is not a number";
  if (!std::isfinite(out)) return "non-finite number " + quoted(tok);
  return {};
}

std::string parse_integer(std::string_view tok, long long& out) {
  std::string_view t = tok;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), out);
  if (ec == std::errc::result_out_of_range && ptr == t.data() + t.size()) return quoted(tok) + " is out of range";
  if (ec != std::errc() || ptr != t.data() + t.size() || t.empty()) return quoted(tok) + " is not an integer";
  return {};
}

// Text split into lines and whitespace-separated tokens, with line numbers for messages.
class Text {
 public:
  explicit Text(std::string_view s, char comment = 0) : s_(s), comment_(comment) {}

  // The next token, across lines; empty at the end. line() is then the token's line.
  std::string_view token() {
    for (;;) {
      while (pos_ < s_.size() && is_blank(s_[pos_])) ++pos_;
      if (pos_ >= s_.size()) return {};
      if (s_[pos_] == '\n') {
        ++pos_, ++line_;
        continue;
      }
      if (comment_ && s_[pos_] == comment_) {
        while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
        continue;
      }
      std::size_t start = pos_;
      while (pos_ < s_.size() && !is_blank(s_[pos_]) && s_[pos_] != '\n' && s_[pos_] != comment_) ++pos_;
      return s_.substr(start, pos_ - start);
    }
  }

  // The tokens of the next line that has any (comments removed); false at the end.
  bool line_tokens(std::vector<std::string_view>& out) {
    out.clear();
    while (pos_ < s_.size()) {
      std::size_t end = s_.find('\n', pos_);
      if (end == std::string_view::npos) end = s_.size();
      std::string_view line = s_.substr(pos_, end - pos_);
      const std::size_t this_line = line_;
      pos_ = end < s_.size() ? end + 1 : end;
      ++line_;
      if (comment_)
        if (auto c = line.find(comment_); c != std::string_view::npos) line = line.substr(0, c);
      split(line, out);
      if (!out.empty()) {
        token_line_ = this_line;
        return true;
      }
    }
    return false;
  }

  // The rest of the current line (for names after "solid"); moves to the next line.
  void skip_line() {
    while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
  }

  static void split(std::string_view line, std::vector<std::string_view>& out) {
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && (is_blank(line[i]) || line[i] == '\n')) ++i;
      std::size_t j = i;
      while (j < line.size() && !is_blank(line[j]) && line[j] != '\n') ++j;
      if (j > i) out.push_back(line.substr(i, j - i));
      i = j;
    }
  }

  std::size_t line() const { return line_; }              // of the last token()
  std::size_t last_line() const { return token_line_; }   // of the last line_tokens()
  std::size_t remaining() const { return s_.size() - pos_; }
  std::size_t position() const { return pos_; }

 private:
  std::string_view s_;
  char comment_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t token_line_ = 0;
};

// Polygons as a flat list of corners: face f is corners[start[f] .. start[f + 1]).
struct Polygons {
  std::vector<std::uint32_t> corners;
  std::vector<std::size_t> start{0};
  std::size_t count() const { return start.size() - 1; }
};

// The triangles of the polygon c[0 .. n) (indices into `positions`), appended to `out`: a fan from
// its first corner where the polygon is convex (every corner turns the same way about its Newell
// normal, and the turns add up to one turn), else a constrained Delaunay triangulation in its plane
// (tessellate/planar.h): fanned, a concave face (the L-shaped end of a prism, one polygon as CAD
// exporters write it) had triangles outside itself, and the solid crossed itself. "" or, for a
// polygon whose edges cross, what is wrong.
std::string polygon_triangles(const std::vector<Point3>& positions, const std::uint32_t* c, std::size_t n,
                              std::vector<Mesh::Triangle>& out) {
  auto fan = [&] {
    for (std::size_t k = 2; k < n; ++k) out.push_back({c[0], c[k - 1], c[k]});
  };
  if (n <= 3) {
    fan();
    return "";
  }
  std::vector<Point3> loop(n);
  for (std::size_t k = 0; k < n; ++k) loop[k] = positions[c[k]];
  const Vec3 normal = newell_normal(loop);
  const double len = normal.norm();
  if (!(len > 0) || !std::isfinite(len)) {  // no area: left to the checks of zero-area triangles
    fan();
    return "";
  }
  const Vec3 axis = normal / len;
  double turning = 0;
  bool convex = true;
  for (std::size_t k = 0; k < n && convex; ++k) {
    const Vec3 a = loop[k] - loop[(k + n - 1) % n], b = loop[(k + 1) % n] - loop[k];
    const double s = a.cross(b).dot(axis);
    convex = s >= 0;
    turning += std::atan2(s, a.dot(b));
  }
  if (convex && std::abs(turning - 2 * M_PI) < 1e-6) {
    fan();
    return "";
  }
  try {
    const std::vector<std::vector<std::uint32_t>> loops{std::vector<std::uint32_t>(c, c + n)};
    for (const Triangle& t : triangulate_face(positions, loops, normal)) out.push_back({t[0], t[1], t[2]});
  } catch (const Error&) {
    return "its edges cross each other (a polygon face must be simple)";
  }
  return "";
}

// A mesh of the vertices and the polygons (polygon_triangles); `where(f)` names face f in errors.
template <class Where>
Mesh fan(std::vector<Point3> positions, const Polygons& polys, const std::string& name, Where&& where) {
  Mesh m;
  m.positions = std::move(positions);
  std::size_t tris = 0;
  for (std::size_t f = 0; f < polys.count(); ++f) tris += polys.start[f + 1] - polys.start[f] - 2;
  m.triangles.reserve(tris);
  for (std::size_t f = 0; f < polys.count(); ++f) {
    const std::uint32_t* c = polys.corners.data() + polys.start[f];
    const std::size_t n = polys.start[f + 1] - polys.start[f];
    if (std::string why = polygon_triangles(m.positions, c, n, m.triangles); !why.empty()) bad(name, where(f), ": ", why);
  }
  return m;
}

// --- OBJ ---
// OBJ's triangles, normals and texture coordinates are kept exactly as the file gives them; a
// corner is keyed by (position, uv, normal).

struct ObjCorner {
  long long v = 0, vt = 0, vn = 0;  // 1-based after resolution; 0 = absent (vt, vn)
};

Mesh parse_obj(std::string_view bytes, const std::string& name) {
  std::vector<Point3> v;
  std::vector<Vec2> vt;
  std::vector<Vec3> vn;
  std::vector<ObjCorner> corners;
  std::vector<std::size_t> face_start{0};
  std::vector<std::size_t> face_line;
  std::string joined;
  std::vector<std::string_view> tok;
  std::size_t lineno = 0, first_line = 0, pos = 0;
  while (pos < bytes.size()) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view line = bytes.substr(pos, end - pos);
    pos = end + 1;
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (joined.empty()) first_line = lineno;
    if (!line.empty() && line.back() == '\\') {  // continuation
      joined.append(line.substr(0, line.size() - 1));
      joined += ' ';
      continue;
    }
    std::string_view rest = line;
    if (!joined.empty()) {
      joined.append(line);
      rest = joined;
    }
    if (auto hash = rest.find('#'); hash != std::string_view::npos) rest = rest.substr(0, hash);
    tok.clear();
    Text::split(rest, tok);
    const std::size_t at = first_line;
    auto obj_fail = [&](const std::string& what) { bad(name, "line ", at, ": ", what); };
    if (!tok.empty()) {
      // `what` names the element as the file numbers it ("vertex 3", counting from 1).
      auto numbers = [&](std::size_t min, std::size_t max, double* out, const std::string& what) {
        if (tok.size() - 1 < min) obj_fail(quoted(tok[0]) + " needs " + std::to_string(min) + " numbers");
        for (std::size_t k = 1; k < tok.size() && k <= max; ++k)
          if (std::string why = parse_double(tok[k], out[k - 1]); !why.empty()) obj_fail(what + ": " + why);
      };
      if (tok[0] == "v") {
        double x[3] = {0, 0, 0};
        numbers(3, 3, x, "vertex " + std::to_string(v.size() + 1));  // a w or a vertex colour after x y z is ignored
        v.emplace_back(x[0], x[1], x[2]);
      } else if (tok[0] == "vt") {
        double x[2] = {0, 0};
        numbers(1, 2, x, "texture coordinate " + std::to_string(vt.size() + 1));
        vt.emplace_back(x[0], x[1]);
      } else if (tok[0] == "vn") {
        double x[3] = {0, 0, 0};
        numbers(3, 3, x, "normal " + std::to_string(vn.size() + 1));
        vn.emplace_back(x[0], x[1], x[2]);
      } else if (tok[0] == "f" || tok[0] == "fo") {
        if (tok.size() < 4) obj_fail("a face needs at least 3 corners, got " + std::to_string(tok.size() - 1));
        for (std::size_t k = 1; k < tok.size(); ++k) {
          // v, v/vt, v//vn or v/vt/vn; negative indices count back from the latest element.
          std::string_view c = tok[k];
          long long idx[3] = {0, 0, 0};
          const std::size_t sizes[3] = {v.size(), vt.size(), vn.size()};
          static const char* const kind[3] = {"vertex", "texture coordinate", "normal"};
          // Faces and corners numbered from 1, as the file numbers its elements: "face 0 corner 0"
          // was the first corner of the first face of a file whose first vertex is 1. (OFF and PLY
          // number from 0, and their messages do too.)
          const std::string corner = "face " + std::to_string(face_line.size() + 1) + " corner " + std::to_string(k) + " " + quoted(tok[k]);
          for (int part = 0; part < 3; ++part) {
            std::size_t slash = c.find('/');
            std::string_view field = c.substr(0, slash);
            if (!field.empty() || part == 0) {
              if (std::string why = parse_integer(field, idx[part]); !why.empty())
                obj_fail(corner + ": " + kind[part] + " index " + (field.empty() ? "missing" : why));
              if (idx[part] == 0)
                obj_fail(corner + ": " + kind[part] + " index 0 (OBJ numbers from 1; negative numbers count back from the last)");
              if (idx[part] < 0) {
                const long long given = idx[part];
                idx[part] += static_cast<long long>(sizes[part]) + 1;
                if (idx[part] < 1)
                  obj_fail(corner + ": " + kind[part] + " index " + std::to_string(given) + " counts back before the first " +
                           kind[part] + " (" + std::to_string(sizes[part]) + " so far)");
              }
            }
            if (slash == std::string_view::npos) break;
            c.remove_prefix(slash + 1);
            if (part == 2) obj_fail(corner + ": more than 3 parts (v, v/vt, v//vn or v/vt/vn)");
          }
          corners.push_back({idx[0], idx[1], idx[2]});
        }
        face_start.push_back(corners.size());
        face_line.push_back(at);
      }
      // Anything else (o, g, s, usemtl, mtllib, l, p, curves) carries no triangles: ignored.
    }
    joined.clear();
  }
  if (face_line.empty()) fail("'", name, "' holds no triangles (no 'f' lines)");
  // Resolve and check the indices (positive ones may refer to elements given later).
  bool any_vt = false, any_vn = false;
  for (std::size_t f = 0; f + 1 < face_start.size(); ++f)
    for (std::size_t k = face_start[f]; k < face_start[f + 1]; ++k) {
      const ObjCorner& c = corners[k];
      auto check = [&](long long i, std::size_t n, const char* what, const char* plural) {
        if (i > static_cast<long long>(n))
          bad(name, "line ", face_line[f], ": face ", f + 1, " corner ", k - face_start[f] + 1, ": ", what, " index ", i,
              " is out of range (", n, " ", plural, " in the file, numbered from 1)");
      };
      check(c.v, v.size(), "vertex", "vertices");
      check(c.vt, vt.size(), "texture coordinate", "texture coordinates");
      check(c.vn, vn.size(), "normal", "normals");
      any_vt = any_vt || c.vt, any_vn = any_vn || c.vn;
    }

  // Corners become vertices keyed by (position, uv, normal): a file vertex used with different
  // texture coordinates or normals in different corners is split, so every corner keeps its own.
  // Polygons are fanned from their first corner.
  Mesh m;
  using Key = std::tuple<long long, double, double, double, double, double, long long>;
  std::map<Key, std::uint32_t> corner_index;
  std::vector<long long> source;  // the file vertex of each mesh vertex
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
  std::vector<std::uint32_t> idx;
  std::vector<Mesh::Triangle> tris;
  for (std::size_t f = 0; f + 1 < face_start.size(); ++f) {
    const ObjCorner* c = corners.data() + face_start[f];
    const std::size_t n = face_start[f + 1] - face_start[f];
    idx.clear();
    for (std::size_t k = 0; k < n; ++k) idx.push_back(corner(c[k]));
    tris.clear();
    if (std::string why = polygon_triangles(m.positions, idx.data(), n, tris); !why.empty())
      bad(name, "line ", face_line[f], ": face ", f + 1, ": ", why);
    for (const auto& t : tris) m.add_triangle(t[0], t[1], t[2]);
  }
  // Smooth normals only where the file has none: area-weighted over the triangles around the
  // file's vertex (not the split mesh vertex, so a uv seam does not crease the shading). With no
  // normals in the file and no vertex split, the mesh is left without normals and the renderer
  // computes the same ones.
  const bool split = m.positions.size() > std::set<long long>(source.begin(), source.end()).size();
  if (any_vn || split) {
    std::vector<Vec3> smooth(v.size(), Vec3::Zero());
    for (const auto& t : m.triangles) {
      Vec3 w = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
      for (int k = 0; k < 3; ++k) smooth[source[t[k]] - 1] += w;
    }
    for (std::size_t i = 0; i < normals.size(); ++i)
      if (!own_normal[i]) {
        const Vec3& s = smooth[source[i] - 1];
        normals[i] = unit_vector(s);
      }
    m.normals = std::move(normals);
  }
  return m;
}

// --- STL ---

std::uint32_t load_u32le(const char* p) {
  std::uint32_t x;
  std::memcpy(&x, p, 4);
  if constexpr (std::endian::native == std::endian::big) x = __builtin_bswap32(x);
  return x;
}

float load_f32le(const char* p) { return std::bit_cast<float>(load_u32le(p)); }

Mesh parse_stl_binary(std::string_view bytes, const std::string& name) {
  if (bytes.size() < 84)
    bad(name, "not an ASCII STL (no 'solid' at the start) and too short for a binary one (", bytes.size(),
        " bytes; a binary STL has an 84-byte header)");
  const std::uint64_t n = load_u32le(bytes.data() + 80);
  const std::uint64_t expected = 84 + 50 * n;
  if (bytes.size() < expected)
    bad(name, "binary STL declares ", n, " triangles (", expected, " bytes) but the file has ", bytes.size(),
        " bytes: truncated after triangle ", (bytes.size() - 84) / 50, " or a wrong count");
  if (bytes.size() > expected)
    bad(name, "binary STL declares ", n, " triangles (", expected, " bytes) but the file has ", bytes.size(),
        " bytes: ", bytes.size() - expected, " bytes after the last triangle (a wrong count?)");
  if (n == 0) fail("'", name, "' holds no triangles (its binary STL header says 0)");
  Mesh m;
  m.positions.reserve(3 * n);
  m.triangles.reserve(n);
  for (std::uint64_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + 50 * t;
    for (int k = 0; k < 3; ++k) {
      const char* p = rec + 12 + 12 * k;
      const double x = load_f32le(p), y = load_f32le(p + 4), z = load_f32le(p + 8);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        bad(name, "triangle ", t + 1, " (byte ", p - bytes.data(), "): corner ", k + 1, " has a non-finite coordinate");
      m.positions.emplace_back(x, y, z);
    }
    const auto i = static_cast<std::uint32_t>(3 * t);
    m.triangles.push_back({i, i + 1, i + 2});
  }
  return m;
}

// An STL keyword in any case: some exporters write SOLID, FACET NORMAL, VERTEX, and such a file
// was read as binary ("binary STL declares 824203333 triangles").
bool keyword(std::string_view tok, std::string_view want) {
  if (tok.size() != want.size()) return false;
  for (std::size_t i = 0; i < tok.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(tok[i])) != want[i]) return false;
  return true;
}

Mesh parse_stl_ascii(std::string_view bytes, const std::string& name) {
  Text text(bytes);
  Mesh m;
  auto expect = [&](std::string_view want) {
    std::string_view tok = text.token();
    if (tok.empty()) bad(name, "line ", text.line(), ": the file ends where ", quoted(want), " was expected (truncated)");
    if (!keyword(tok, want)) bad(name, "line ", text.line(), ": expected ", quoted(want), ", got ", quoted(tok));
  };
  auto number = [&](const char* what) {
    std::string_view tok = text.token();
    if (tok.empty()) bad(name, "line ", text.line(), ": the file ends inside a ", what, " (truncated)");
    double x = 0;
    if (std::string why = parse_double(tok, x); !why.empty()) bad(name, "line ", text.line(), ": ", what, ": ", why);
    return x;
  };
  std::size_t solids = 0;
  for (std::string_view tok = text.token(); !tok.empty(); tok = text.token()) {
    if (!keyword(tok, "solid")) bad(name, "line ", text.line(), ": expected 'solid', got ", quoted(tok));
    ++solids;
    text.skip_line();  // the solid's name
    for (;;) {
      tok = text.token();
      if (tok.empty()) bad(name, "line ", text.line(), ": the file ends before 'endsolid' (truncated)");
      if (keyword(tok, "endsolid")) {
        text.skip_line();
        break;
      }
      if (!keyword(tok, "facet")) bad(name, "line ", text.line(), ": expected 'facet' or 'endsolid', got ", quoted(tok));
      expect("normal");
      for (int k = 0; k < 3; ++k) number("facet normal");  // recomputed from the corners
      expect("outer");
      expect("loop");
      const auto first = static_cast<std::uint32_t>(m.positions.size());
      for (int k = 0; k < 3; ++k) {
        tok = text.token();
        if (keyword(tok, "endloop"))
          bad(name, "line ", text.line(), ": a facet with ", k, " vertices (STL facets are triangles)");
        if (tok.empty()) bad(name, "line ", text.line(), ": the file ends inside a facet (truncated)");
        if (!keyword(tok, "vertex")) bad(name, "line ", text.line(), ": expected 'vertex', got ", quoted(tok));
        double x = number("vertex"), y = number("vertex"), z = number("vertex");
        m.positions.emplace_back(x, y, z);
      }
      tok = text.token();
      if (keyword(tok, "vertex")) bad(name, "line ", text.line(), ": a facet with more than 3 vertices (STL facets are triangles)");
      if (tok.empty()) bad(name, "line ", text.line(), ": the file ends inside a facet (truncated)");
      if (!keyword(tok, "endloop")) bad(name, "line ", text.line(), ": expected 'endloop', got ", quoted(tok));
      expect("endfacet");
      m.triangles.push_back({first, first + 1, first + 2});
    }
  }
  if (solids == 0) bad(name, "the file holds only white space");
  if (m.triangles.empty()) fail("'", name, "' holds no triangles (its solid has no facets)");
  return m;
}

// ASCII if it starts with "solid" (in any case) and its second line starts a facet or ends the
// solid; binary otherwise (some binary files also start their header with "solid").
bool stl_is_ascii(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  if (!keyword(bytes.substr(i, 5), "solid")) return false;
  if (bytes.size() >= 84 && bytes.size() == 84 + 50 * std::uint64_t(load_u32le(bytes.data() + 80))) {
    std::size_t eol = bytes.find('\n', i);
    if (eol == std::string_view::npos) return false;
    Text rest(bytes.substr(eol + 1));
    std::string_view tok = rest.token();
    return keyword(tok, "facet") || keyword(tok, "endsolid");
  }
  return true;
}

Mesh parse_stl(std::string_view bytes, const std::string& name) {
  Mesh m = stl_is_ascii(bytes) ? parse_stl_ascii(bytes, name) : parse_stl_binary(bytes, name);
  // STL stores each triangle's corners separately; corners written from the same vertex have
  // identical coordinates, so merging exactly equal positions rebuilds the shared vertices. Where
  // that joins separate closed fans at one point (parts that touch at a corner, as a boolean
  // returns them and export writes them), each fan gets its vertex back: the file said nothing
  // of one vertex there, and welded the solid was refused as not 2-manifold.
  return split_fans(m.welded(), m);
}

// --- OFF ---
// [ST][C][N][4][n]OFF, then "nv nf ne", nv vertex lines (x y z [nx ny nz] [colour] [s t]) and nf
// face lines (n i1 .. in [colour]). '#' starts a comment.

Mesh parse_off(std::string_view bytes, const std::string& name) {
  Text text(bytes, '#');
  std::vector<std::string_view> tok;
  if (!text.line_tokens(tok)) bad(name, "the file holds only comments or white space");
  std::string_view key = tok[0];
  const bool has_st = key.substr(0, 2) == "ST";
  if (has_st) key.remove_prefix(2);
  const bool has_c = !key.empty() && key.front() == 'C';
  if (has_c) key.remove_prefix(1);
  const bool has_n = !key.empty() && key.front() == 'N';
  if (has_n) key.remove_prefix(1);
  if (!key.empty() && (key.front() == '4' || key.front() == 'n'))
    bad(name, "line ", text.last_line(), ": ", quoted(tok[0]), " is a higher-dimensional OFF; only 3D is supported");
  if (key != "OFF") bad(name, "line ", text.last_line(), ": not an OFF file (expected 'OFF', got ", quoted(tok[0]), ")");
  std::vector<std::string_view> counts(tok.begin() + 1, tok.end());
  if (!counts.empty() && counts[0] == "BINARY") bad(name, "line ", text.last_line(), ": binary OFF is not supported");
  if (counts.empty()) {
    if (!text.line_tokens(tok)) bad(name, "the file ends before the counts line (vertices faces edges)");
    counts = tok;
  }
  const std::size_t counts_line = text.last_line();
  if (counts.size() < 2 || counts.size() > 3)
    bad(name, "line ", counts_line, ": expected the counts 'vertices faces edges', got ", counts.size(), " numbers");
  long long nv = 0, nf = 0, ne = 0;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    long long& c = k == 0 ? nv : k == 1 ? nf : ne;
    if (std::string why = parse_integer(counts[k], c); !why.empty()) bad(name, "line ", counts_line, ": count ", why);
    if (c < 0) bad(name, "line ", counts_line, ": negative count ", c);
  }
  // Each vertex line holds at least 3 numbers (6 with normals, 5 with texture coordinates, plus a
  // colour), each face line at least 4 (n and three indices); a number takes a character and a
  // separator. A header that asks for more than the file can hold is refused before allocating.
  const long long per_vertex = 3 + (has_n ? 3 : 0) + (has_c ? 3 : 0) + (has_st ? 2 : 0);
  const long long capacity = static_cast<long long>(text.remaining() / 2 + 1);
  if (nv > capacity / per_vertex || nf > capacity / 4 || nv * per_vertex + nf * 4 > capacity)
    bad(name, "line ", counts_line, ": the header declares ", nv, " vertices and ", nf, " faces, but the ",
        text.remaining(), " bytes after it can hold at most ", capacity, " numbers (truncated file or wrong counts)");
  if (nf == 0) fail("'", name, "' holds no triangles (its header declares 0 faces)");
  if (nv > std::numeric_limits<std::uint32_t>::max()) bad(name, "line ", counts_line, ": more than 2^32 vertices");

  std::vector<Point3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;
  positions.reserve(static_cast<std::size_t>(nv));
  for (long long i = 0; i < nv; ++i) {
    if (!text.line_tokens(tok))
      bad(name, "the file ends after ", i, " of the header's ", nv, " vertices (truncated file or wrong count)");
    const std::size_t at = text.last_line();
    if (static_cast<long long>(tok.size()) < per_vertex)
      bad(name, "line ", at, ": vertex ", i, " has ", tok.size(), " numbers, needs ", per_vertex);
    double x[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    auto read = [&](std::size_t from, int n, double* out, const char* what) {
      for (int k = 0; k < n; ++k)
        if (std::string why = parse_double(tok[from + k], out[k]); !why.empty())
          bad(name, "line ", at, ": vertex ", i, " ", what, ": ", why);
    };
    read(0, 3, x, "coordinate");
    positions.emplace_back(x[0], x[1], x[2]);
    if (has_n) {
      read(3, 3, x + 3, "normal");
      normals.emplace_back(x[3], x[4], x[5]);
    }
    if (has_st) {
      read(tok.size() - 2, 2, x + 6, "texture coordinate");
      uvs.emplace_back(x[6], x[7]);
    }
  }
  Polygons polys;
  std::vector<std::size_t> face_line;
  for (long long f = 0; f < nf; ++f) {
    if (!text.line_tokens(tok))
      bad(name, "the file ends after ", f, " of the header's ", nf, " faces (truncated file or wrong count)");
    const std::size_t at = text.last_line();
    face_line.push_back(at);
    long long n = 0;
    if (std::string why = parse_integer(tok[0], n); !why.empty()) bad(name, "line ", at, ": face ", f, ": corner count ", why);
    if (n < 3) bad(name, "line ", at, ": face ", f, " has ", n, " corners, needs at least 3");
    if (n > static_cast<long long>(tok.size()) - 1)
      bad(name, "line ", at, ": face ", f, " declares ", n, " corners but the line holds ", tok.size() - 1, " indices");
    for (long long k = 1; k <= n; ++k) {
      long long idx = 0;
      if (std::string why = parse_integer(tok[k], idx); !why.empty()) bad(name, "line ", at, ": face ", f, ": index ", why);
      if (idx < 0 || idx >= nv)
        bad(name, "line ", at, ": face ", f, ": index ", idx, " is out of range (", nv, " vertices, numbered from 0)");
      polys.corners.push_back(static_cast<std::uint32_t>(idx));
    }
    polys.start.push_back(polys.corners.size());
  }
  if (text.line_tokens(tok))
    bad(name, "line ", text.last_line(), ": more data after the header's ", nf, " faces (wrong count?)");
  Mesh m = fan(std::move(positions), polys, name, [&](std::size_t f) { return "line " + std::to_string(face_line[f]) + ": face " + std::to_string(f); });
  if (has_n) m.normals = std::move(normals);
  if (has_st) m.uvs = std::move(uvs);
  return m;
}

// --- PLY ---
// A header of elements and their properties, then the data as text or binary of either byte
// order. Vertex properties x y z, nx ny nz and u v (or s t, texture_u texture_v) are read; the
// face list vertex_indices (or vertex_index) gives the polygons; everything else is skipped.

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

bool ply_type(std::string_view s, PlyType& t) {
  static const std::pair<std::string_view, PlyType> names[] = {
      {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},    {"uint8", PlyType::u8},
      {"short", PlyType::i16},  {"int16", PlyType::i16},   {"ushort", PlyType::u16},  {"uint16", PlyType::u16},
      {"int", PlyType::i32},    {"int32", PlyType::i32},   {"uint", PlyType::u32},    {"uint32", PlyType::u32},
      {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64},  {"float64", PlyType::f64}};
  for (const auto& [n, ty] : names)
    if (s == n) return t = ty, true;
  return false;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
  }
  return 1;
}

bool ply_integral(PlyType t) { return t != PlyType::f32 && t != PlyType::f64; }

// The range of an integer type, and its name for messages ("char (-128..127)").
std::string ply_range_error(PlyType t, long long x) {
  long long lo = 0, hi = 0;
  const char* name = "";
  switch (t) {
    case PlyType::i8: lo = -128, hi = 127, name = "char"; break;
    case PlyType::u8: lo = 0, hi = 255, name = "uchar"; break;
    case PlyType::i16: lo = -32768, hi = 32767, name = "short"; break;
    case PlyType::u16: lo = 0, hi = 65535, name = "ushort"; break;
    case PlyType::i32: lo = -2147483648LL, hi = 2147483647LL, name = "int"; break;
    case PlyType::u32: lo = 0, hi = 4294967295LL, name = "uint"; break;
    default: return "";
  }
  if (x >= lo && x <= hi) return "";
  return std::to_string(x) + " is out of range for type " + name + " (" + std::to_string(lo) + ".." + std::to_string(hi) + ")";
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::f32;
  bool list = false;
  PlyType count_type = PlyType::u8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;
  std::vector<PlyProperty> props;
};

// Reads values of a PLY body, text or binary, with the place of the last value for messages.
class PlyBody {
 public:
  enum class Format { ascii, little, big };
  PlyBody(std::string_view body, std::size_t offset, std::size_t first_line, Format format, const std::string& name)
      : body_(body), offset_(offset), text_(body), format_(format), name_(name) {
    line_offset_ = first_line - 1;
  }

  // The value as a double; `what` names it in messages ("vertex 3 property 'x'").
  template <class What>
  double value(PlyType t, const What& what) {
    if (format_ == Format::ascii) {
      std::string_view tok = text_.token();
      if (tok.empty()) bad(name_, "the file ends at ", what(), " (truncated or a wrong count in the header)");
      if (ply_integral(t)) {
        long long x = 0;
        if (std::string why = parse_integer(tok, x); !why.empty()) bad(name_, "line ", line(), ": ", what(), ": ", why);
        // As a binary file of the header's types could hold it: a char of 300 is no char.
        if (std::string why = ply_range_error(t, x); !why.empty()) bad(name_, "line ", line(), ": ", what(), ": ", why);
        return static_cast<double>(x);
      }
      double x = 0;
      if (std::string why = parse_double(tok, x); !why.empty()) bad(name_, "line ", line(), ": ", what(), ": ", why);
      return x;
    }
    const std::size_t n = ply_size(t);
    if (pos_ + n > body_.size())
      bad(name_, "byte ", offset_ + pos_, ": the file ends at ", what(), " (truncated or a wrong count in the header)");
    unsigned char b[8];
    std::memcpy(b, body_.data() + pos_, n);
    pos_ += n;
    const bool swap = (format_ == Format::big) != (std::endian::native == std::endian::big);
    if (swap) std::reverse(b, b + n);
    switch (t) {
      case PlyType::i8: return static_cast<std::int8_t>(b[0]);
      case PlyType::u8: return b[0];
      case PlyType::i16: { std::int16_t x; std::memcpy(&x, b, 2); return x; }
      case PlyType::u16: { std::uint16_t x; std::memcpy(&x, b, 2); return x; }
      case PlyType::i32: { std::int32_t x; std::memcpy(&x, b, 4); return x; }
      case PlyType::u32: { std::uint32_t x; std::memcpy(&x, b, 4); return x; }
      case PlyType::f32: { float x; std::memcpy(&x, b, 4); return x; }
      case PlyType::f64: { double x; std::memcpy(&x, b, 8); return x; }
    }
    return 0;
  }

  // Skips a list's items, checking first that they fit in the file.
  template <class What>
  void skip(PlyType t, std::uint64_t n, const What& what) {
    if (format_ == Format::ascii) {
      for (std::uint64_t k = 0; k < n; ++k) value(t, what);
      return;
    }
    if (n > (body_.size() - pos_) / ply_size(t))
      bad(name_, "byte ", offset_ + pos_, ": ", what(), " holds ", n, " items, more than the rest of the file (truncated or corrupt)");
    pos_ += n * ply_size(t);
  }

  // What is left after the last element: white space for text, nothing for binary.
  bool at_end() {
    if (format_ == Format::ascii) return text_.token().empty();
    return pos_ == body_.size();
  }
  std::size_t line() const { return line_offset_ + text_.line(); }
  std::string place() const {
    return format_ == Format::ascii ? "line " + std::to_string(line()) : "byte " + std::to_string(offset_ + pos_);
  }
  bool ascii() const { return format_ == Format::ascii; }
  std::size_t left() const { return format_ == Format::ascii ? text_.remaining() : body_.size() - pos_; }

 private:
  std::string_view body_;
  std::size_t offset_;
  std::size_t pos_ = 0;
  Text text_;
  Format format_;
  const std::string& name_;
  std::size_t line_offset_ = 0;
};

Mesh parse_ply(std::string_view bytes, const std::string& name) {
  // The header: lines up to "end_header".
  if (bytes.substr(0, 4) != "ply\n" && bytes.substr(0, 5) != "ply\r\n")
    bad(name, "not a PLY file (it does not start with the line 'ply')");
  std::size_t pos = 0, line = 0;
  PlyBody::Format format = PlyBody::Format::ascii;
  bool have_format = false, ended = false;
  std::vector<PlyElement> elements;
  std::vector<std::string_view> tok;
  while (pos < bytes.size()) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view l = bytes.substr(pos, end - pos);
    pos = std::min(end + 1, bytes.size());
    ++line;
    tok.clear();
    Text::split(l, tok);
    if (tok.empty() || line == 1) continue;
    auto header_fail = [&](const std::string& what) { bad(name, "header line ", line, ": ", what); };
    if (tok[0] == "end_header") {
      ended = true;
      break;
    } else if (tok[0] == "comment" || tok[0] == "obj_info") {
      continue;
    } else if (tok[0] == "format") {
      if (tok.size() != 3) header_fail("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      if (tok[1] == "ascii") format = PlyBody::Format::ascii;
      else if (tok[1] == "binary_little_endian") format = PlyBody::Format::little;
      else if (tok[1] == "binary_big_endian") format = PlyBody::Format::big;
      else header_fail("unknown format " + quoted(tok[1]));
      if (tok[2] != "1.0") header_fail("unsupported version " + quoted(tok[2]));
      have_format = true;
    } else if (tok[0] == "element") {
      if (tok.size() != 3) header_fail("expected 'element <name> <count>'");
      long long n = 0;
      if (std::string why = parse_integer(tok[2], n); !why.empty()) header_fail("element count " + why);
      if (n < 0) header_fail("negative element count " + std::to_string(n));
      elements.push_back({std::string(tok[1].substr(0, 64)), static_cast<std::uint64_t>(n), line, {}});
    } else if (tok[0] == "property") {
      if (elements.empty()) header_fail("a property before any element");
      PlyProperty p;
      if (tok.size() == 5 && tok[1] == "list") {
        p.list = true;
        if (!ply_type(tok[2], p.count_type)) header_fail("unknown type " + quoted(tok[2]));
        if (!ply_integral(p.count_type)) header_fail("a list count must be an integer type, not " + quoted(tok[2]));
        if (!ply_type(tok[3], p.type)) header_fail("unknown type " + quoted(tok[3]));
        p.name = tok[4];
      } else if (tok.size() == 3) {
        if (!ply_type(tok[1], p.type)) header_fail("unknown type " + quoted(tok[1]));
        p.name = tok[2];
      } else {
        header_fail("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      for (const PlyProperty& q : elements.back().props)
        if (q.name == p.name) header_fail("a second property " + quoted(std::string_view(p.name)) + " in element " + quoted(std::string_view(elements.back().name)));
      elements.back().props.push_back(std::move(p));
    } else {
      header_fail("unknown keyword " + quoted(tok[0]));
    }
  }
  if (!ended) bad(name, "the header has no 'end_header' line (truncated, or not a PLY file)");
  if (!have_format) bad(name, "the header has no 'format' line");

  // Counts against the size of the body: each element has a least size (its fixed properties
  // and list counts in binary; one number per property in text, a character and a separator
  // each), so a count that cannot fit is refused before anything is allocated.
  const std::size_t body = bytes.size() - pos;
  const std::size_t budget = format == PlyBody::Format::ascii ? body / 2 + 1 : body;
  std::size_t need = 0;
  for (const auto& e : elements) {
    std::size_t least = 0;
    for (const auto& p : e.props) least += format == PlyBody::Format::ascii ? 1 : ply_size(p.list ? p.count_type : p.type);
    if (e.count > 0 && least == 0) bad(name, "header line ", e.line, ": element '", e.name, "' has no properties");
    if (e.count > 0 && (e.count > (budget - std::min(need, budget)) / least))
      bad(name, "header line ", e.line, ": element '", e.name, "' declares ", e.count, " items of at least ", least,
          format == PlyBody::Format::ascii ? " numbers" : " bytes", ", but the ", body,
          " bytes after the header cannot hold them (truncated file or wrong count)");
    need += e.count * least;
  }

  PlyBody in(bytes.substr(pos), pos, line + 1, format, name);
  std::vector<Point3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;
  Polygons polys;
  bool have_vertices = false, have_faces = false, have_normals = false, have_uvs = false;
  std::uint64_t nv = 0;
  std::vector<std::size_t> face_place;  // for messages about indices, checked at the end
  for (const auto& e : elements) {
    // Which property is what, for the two elements we read.
    std::vector<int> role(e.props.size(), -1);  // vertex: 0..2 x y z, 3..5 normal, 6..7 uv; face: 8 indices
    if (e.name == "vertex") {
      if (have_vertices) bad(name, "header line ", e.line, ": a second 'vertex' element");
      const char* names[8][3] = {{"x", nullptr, nullptr},       {"y", nullptr, nullptr},       {"z", nullptr, nullptr},
                                 {"nx", nullptr, nullptr},      {"ny", nullptr, nullptr},      {"nz", nullptr, nullptr},
                                 {"u", "s", "texture_u"},       {"v", "t", "texture_v"}};
      for (std::size_t k = 0; k < e.props.size(); ++k)
        for (int r = 0; r < 8; ++r)
          for (const char* n : names[r])
            if (n && e.props[k].name == n && !e.props[k].list) role[k] = r;
      auto has = [&](int r) { return std::find(role.begin(), role.end(), r) != role.end(); };
      if (!has(0) || !has(1) || !has(2)) bad(name, "header line ", e.line, ": the 'vertex' element has no x, y and z");
      have_vertices = true;
      have_normals = has(3) && has(4) && has(5);
      have_uvs = has(6) && has(7);
      nv = e.count;
      if (nv > std::numeric_limits<std::uint32_t>::max()) bad(name, "header line ", e.line, ": more than 2^32 vertices");
      positions.reserve(e.count);
      if (have_normals) normals.reserve(e.count);
      if (have_uvs) uvs.reserve(e.count);
    } else if (e.name == "face") {
      if (have_faces) bad(name, "header line ", e.line, ": a second 'face' element");
      for (std::size_t k = 0; k < e.props.size(); ++k)
        if (e.props[k].list && (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index")) role[k] = 8;
      if (std::find(role.begin(), role.end(), 8) == role.end())
        bad(name, "header line ", e.line, ": the 'face' element has no list 'vertex_indices'");
      have_faces = true;
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double x[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        auto what = [&] { return e.name + " " + std::to_string(i) + " property '" + p.name + "'"; };
        if (!p.list) {
          double val = in.value(p.type, what);
          if (role[k] >= 0 && role[k] < 8) {
            if (!std::isfinite(val)) bad(name, in.place(), ": ", what(), " is not finite");
            x[role[k]] = val;
          }
          continue;
        }
        const double count = in.value(p.count_type, what);
        if (count < 0) bad(name, in.place(), ": ", what(), " has a negative count ", count);
        const auto n = static_cast<std::uint64_t>(count);
        if (role[k] != 8) {
          in.skip(p.type, n, what);
          continue;
        }
        if (n < 3) bad(name, in.place(), ": face ", i, " has ", n, " corners, needs at least 3");
        if (!in.ascii() && n > in.left() / ply_size(p.type))
          bad(name, in.place(), ": face ", i, " declares ", n, " corners, more than the rest of the file holds (truncated or corrupt)");
        for (std::uint64_t c = 0; c < n; ++c) {
          const double idx = in.value(p.type, what);
          if (!(idx >= 0) || idx != std::floor(idx) || idx > std::numeric_limits<std::uint32_t>::max())
            bad(name, in.place(), ": face ", i, " corner ", c, ": index ", idx, " is not a vertex number");
          polys.corners.push_back(static_cast<std::uint32_t>(idx));
        }
        polys.start.push_back(polys.corners.size());
        face_place.push_back(i);
      }
      if (e.name == "vertex") {
        positions.emplace_back(x[0], x[1], x[2]);
        if (have_normals) normals.emplace_back(x[3], x[4], x[5]);
        if (have_uvs) uvs.emplace_back(x[6], x[7]);
      }
    }
  }
  if (!in.at_end())
    bad(name, in.place(), ": more data after the last element the header declares (a wrong count?)");
  if (!have_vertices) bad(name, "the header declares no 'vertex' element");
  if (polys.count() == 0) fail("'", name, "' holds no triangles (no faces)");
  for (std::size_t f = 0; f < polys.count(); ++f)
    for (std::size_t k = polys.start[f]; k < polys.start[f + 1]; ++k)
      if (polys.corners[k] >= nv)
        bad(name, "face ", face_place[f], " corner ", k - polys.start[f], ": index ", polys.corners[k],
            " is out of range (", nv, " vertices, numbered from 0)");
  Mesh m = fan(std::move(positions), polys, name, [&](std::size_t f) { return "face " + std::to_string(face_place[f]); });
  if (have_normals) m.normals = std::move(normals);
  if (have_uvs) m.uvs = std::move(uvs);
  return m;
}

}  // namespace

std::string mesh_format(const std::string& path) {
  std::string ext = lower_extension(path);
  if (ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".off") return ext.substr(1);
  fail("'", path, "': unknown mesh format '", ext.empty() ? std::string("(no extension)") : ext,
       "' (supported: .obj .stl .ply .off)");
}

Mesh parse_mesh(std::string_view bytes, const std::string& format, const std::string& name) {
  if (bytes.empty()) bad(name, "the file is empty");
  // Text as editors save it: a UTF-8 byte order mark is skipped (it made the first line unknown and
  // an OBJ's vertex 1 vanish), lines ended by CR alone (classic Mac OS) are read as lines, and
  // UTF-16 is named (it read as one line of junk, "holds no triangles"). A binary STL's 80-byte
  // header may hold any bytes: only a BOM before "solid" is text.
  // (substr(pos) throws past the end: a 1-byte file is 1 byte.)
  const auto at = [&](std::size_t pos, std::string_view what) { return bytes.size() >= pos + what.size() && bytes.substr(pos, what.size()) == what; };
  const bool text = format != "stl" || (bytes.size() >= 8 && keyword(bytes.substr(3, 5), "solid")) || at(2, std::string_view("s\0o\0l\0i\0d\0", 10)) || at(2, std::string_view("\0s\0o\0l\0i\0d", 10));
  if (text && at(0, "\xEF\xBB\xBF")) {
    bytes.remove_prefix(3);
    if (bytes.empty()) bad(name, "the file holds only a UTF-8 byte order mark");
  }
  else if (text && (at(0, "\xFF\xFE") || at(0, "\xFE\xFF")))
    bad(name, "the file is UTF-16 text (it starts with a UTF-16 byte order mark): save it as UTF-8 or ASCII");
  std::string unix_lines;
  const bool ascii = format == "stl" ? stl_is_ascii(bytes) : format != "ply" || bytes.substr(0, 64).find("format ascii") != std::string_view::npos;
  if (ascii)
    if (bytes.find('\r') != std::string_view::npos && bytes.find('\n') == std::string_view::npos) {
      unix_lines.assign(bytes);
      std::replace(unix_lines.begin(), unix_lines.end(), '\r', '\n');
      bytes = unix_lines;
    }
  Mesh m;
  if (format == "obj") m = parse_obj(bytes, name);
  else if (format == "stl") m = parse_stl(bytes, name);
  else if (format == "ply") m = parse_ply(bytes, name);
  else if (format == "off") m = parse_off(bytes, name);
  else fail("'", name, "': unknown mesh format '", format, "' (supported: obj stl ply off)");
  // A file without normals gives none; all-zero normals (some writers' placeholder) count as none.
  if (!m.normals.empty() &&
      std::all_of(m.normals.begin(), m.normals.end(), [](const Vec3& n) { return n.squaredNorm() == 0; }))
    m.normals.clear();
  try {
    m.check();
  } catch (const Error& e) {
    fail("'", name, "': ", e.what());
  }
  return m;
}

Mesh read_mesh(const std::string& path) {
  std::string format = mesh_format(path);
  return parse_mesh(read_file(path), format, path);
}

}  // namespace wedge
