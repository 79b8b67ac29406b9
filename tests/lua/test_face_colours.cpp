// Per-face colour in PLY and OBJ (+ .mtl) exports of a boolean of coloured solids, read back by a
// small reader written here (not wedge's): each triangle that lies in one of the cube's cut planes
// (x = 0, y = 0 or z = 0) must carry the cube's colour, every other one the sphere's.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "lua/wedge_lua.h"

namespace fs = std::filesystem;

namespace {
using P = std::array<double, 3>;
using C = std::array<int, 3>;  // 0..255
struct Tri {
  std::array<P, 3> v;
  C colour;
};

// True when the triangle lies on one of the cube's faces: in one of the planes x = 0, y = 0,
// z = 0, on the side where the other two coordinates are >= 0 (the sphere's seam lies in the plane
// y = 0 too, and a triangle from a pole to two seam points is a sphere triangle in that plane).
// "In the plane" to 1e-12: the sphere's poles lie on the cube's edge x = y = 0 (exactly, since
// cos_sin; at x = cos(pi / 2) = 6e-17 before), and a cut face may end there.
bool on_cut(const Tri& t) {
  constexpr double eps = 1e-12;
  for (int a = 0; a < 3; ++a)
    if (std::abs(t.v[0][a]) <= eps && std::abs(t.v[1][a]) <= eps && std::abs(t.v[2][a]) <= eps) {
      bool inside = true;
      for (int b = 0; b < 3; ++b)
        if (b != a)
          for (int k = 0; k < 3; ++k) inside = inside && t.v[k][b] >= -eps;
      if (inside) return true;
    }
  return false;
}

// An ASCII or binary little-endian PLY with double x y z (maybe more vertex properties, all
// double) and faces "list uchar uint vertex_indices" + uchar red green blue.
std::vector<Tri> read_ply(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, format;
  std::size_t nv = 0, nf = 0, vprops = 0;
  std::vector<std::string> face_props;
  std::string element;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format") ls >> format;
    else if (w == "element") {
      ls >> element;
      (element == "vertex" ? nv : nf) = [&] { std::size_t n; ls >> n; return n; }();
    } else if (w == "property") {
      std::string type, name, last;
      while (ls >> name) last = name;
      if (element == "vertex") ++vprops;
      else face_props.push_back(last);
    }
  }
  REQUIRE(face_props == std::vector<std::string>{"vertex_indices", "red", "green", "blue"});
  std::vector<P> pts(nv);
  std::vector<Tri> tris(nf);
  if (format == "ascii") {
    for (auto& p : pts) {
      for (double& x : p) in >> x;
      for (std::size_t k = 3; k < vprops; ++k) {
        double skip;
        in >> skip;
      }
    }
    for (auto& t : tris) {
      int n;
      std::array<std::size_t, 3> ix;
      in >> n >> ix[0] >> ix[1] >> ix[2] >> t.colour[0] >> t.colour[1] >> t.colour[2];
      REQUIRE(n == 3);
      for (int k = 0; k < 3; ++k) t.v[k] = pts.at(ix[k]);
    }
  } else {
    REQUIRE(format == "binary_little_endian");
    auto get = [&](void* dst, std::size_t n) { in.read(static_cast<char*>(dst), std::streamsize(n)); };
    for (auto& p : pts) {
      get(p.data(), 24);
      for (std::size_t k = 3; k < vprops; ++k) {
        double skip;
        get(&skip, 8);
      }
    }
    for (auto& t : tris) {
      std::uint8_t n;
      std::uint32_t ix[3];
      std::uint8_t c[3];
      get(&n, 1);
      get(ix, 12);
      get(c, 3);
      REQUIRE(n == 3);
      for (int k = 0; k < 3; ++k) {
        t.v[k] = pts.at(ix[k]);
        t.colour[k] = c[k];
      }
    }
  }
  REQUIRE(in.good());
  return tris;
}

// An OBJ with "mtllib", "usemtl", "v", "vn" and "f a/b/c"; colours from the library's Kd.
std::vector<Tri> read_obj(const fs::path& path, std::vector<std::pair<P, P>>* vertex_normals = nullptr) {
  std::ifstream in(path);
  std::string line, lib;
  std::vector<P> v, vn;
  std::vector<std::array<std::size_t, 6>> faces;  // 3 positions, 3 normals
  std::vector<std::string> face_mtl;
  std::string current;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "mtllib") ls >> lib;
    else if (w == "usemtl") ls >> current;
    else if (w == "v" || w == "vn") {
      P p;
      ls >> p[0] >> p[1] >> p[2];
      (w == "v" ? v : vn).push_back(p);
    } else if (w == "f") {
      std::array<std::size_t, 6> f{};
      for (int k = 0; k < 3; ++k) {
        std::string c;
        ls >> c;
        f[k] = std::stoul(c.substr(0, c.find('/'))) - 1;
        f[k + 3] = std::stoul(c.substr(c.rfind('/') + 1)) - 1;
      }
      faces.push_back(f);
      face_mtl.push_back(current);
    }
  }
  REQUIRE(!lib.empty());
  std::map<std::string, C> kd;
  std::ifstream m(path.parent_path() / lib);
  REQUIRE(m.good());
  std::string name;
  while (std::getline(m, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "newmtl") ls >> name;
    else if (w == "Kd") {
      double r, g, b;
      ls >> r >> g >> b;
      kd[name] = {int(std::lround(r * 255)), int(std::lround(g * 255)), int(std::lround(b * 255))};
    }
  }
  std::vector<Tri> tris;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    Tri t;
    for (int k = 0; k < 3; ++k) t.v[k] = v.at(faces[i][k]);
    REQUIRE(kd.count(face_mtl[i]));
    t.colour = kd[face_mtl[i]];
    tris.push_back(t);
    if (vertex_normals)
      for (int k = 0; k < 3; ++k) vertex_normals->push_back({v.at(faces[i][k]), vn.at(faces[i][k + 3])});
  }
  return tris;
}

void check_colours(const std::vector<Tri>& tris) {
  const C red{255, 0, 0}, blue{0, 0, 255};
  int cube = 0, sphere = 0, wrong = 0;
  for (const auto& t : tris) {
    // A triangle of no area (the boolean's output keeps a few) shows no colour and has no plane.
    double e1[3], e2[3];
    for (int a = 0; a < 3; ++a) e1[a] = t.v[1][a] - t.v[0][a], e2[a] = t.v[2][a] - t.v[0][a];
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    if (cx * cx + cy * cy + cz * cz < 1e-24) continue;
    const bool cut = on_cut(t);
    cube += cut;
    sphere += !cut;
    wrong += t.colour != (cut ? blue : red);
  }
  CHECK(cube > 10);
  CHECK(sphere > 100);
  CHECK(wrong == 0);
}
}  // namespace

TEST_CASE("PLY and OBJ exports carry each face's colour from the solid it came from", "[lua][io][colour]") {
  const fs::path dir = fs::temp_directory_path() / ("wedge-face-colours-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ostringstream err;
  const int status = wedge::lua::run_string("local dir = '" + dir.string() + R"('
    tolerance(0.01)
    local red = sphere(1):material{diffuse = {1, 0, 0}}
    local blue = cube(2):material{diffuse = {0, 0, 1}}
    local d = red - blue
    export(d, dir .. "/d_ascii.ply", {ascii = true})
    export(d, dir .. "/d_binary.ply")
    export(d, dir .. "/d.obj")
    export(box(1, 1, 1), dir .. "/plain.ply", {ascii = true})
  )", "@colours.lua", err);
  INFO(err.str());
  REQUIRE(status == 0);
  SECTION("ASCII PLY") { check_colours(read_ply(dir / "d_ascii.ply")); }
  SECTION("binary PLY") { check_colours(read_ply(dir / "d_binary.ply")); }
  SECTION("OBJ and its material library") {
    std::vector<std::pair<P, P>> vn;
    check_colours(read_obj(dir / "d.obj", &vn));
    CHECK(fs::exists(dir / "d.mtl"));
    // The normals written are the sphere's (the radial direction) wherever the vertex is off the
    // cut planes.
    double worst = 0;
    for (const auto& [p, n] : vn) {
      if (p[0] == 0 || p[1] == 0 || p[2] == 0) continue;
      const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(n[k] - p[k] / r));
    }
    CHECK(worst < 1e-9);
  }
  SECTION("a solid without a material exports no colours") {
    std::ifstream in(dir / "plain.ply");
    std::stringstream s;
    s << in.rdbuf();
    CHECK(s.str().find("property uchar red") == std::string::npos);
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}
