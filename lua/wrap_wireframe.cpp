// Wireframe models (API.md "Scenes": a solid's edges as curves, no faces): wireframe(s) keeps the
// edges of a solid (or of anything with a mesh) as polylines, which export as OBJ polylines
// ("l" records) and render as lines; beside it, render{s, wireframe=true} is the wireframe
// display of a solid's triangles.
#include "lua/wrap_wireframe.h"

#include <cstdio>
#include <sstream>

#include "kernel/file_io.h"
#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_solid.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Wireframe";

Wireframe& self(lua_State* L) { return check_object<Wireframe>(L, 1, kKey, "Wireframe"); }

double length(const Wireframe& w) {
  double total = 0;
  for (const auto& line : w.lines)
    for (std::size_t i = 1; i < line.size(); ++i) total += (line[i] - line[i - 1]).norm();
  return total;
}

// wireframe(x [, {crease=30, color={r,g,b}}]): the edges of x's mesh between different faces (or,
// for a mesh without faces, meeting at more than `crease` degrees), and its boundary.
int wireframe_fn(lua_State* L) {
  return table_call(L, 2, [&] {
    double crease = 30;
    Wireframe w;
    w.color = render::Vec4f(0.1f, 0.1f, 0.1f, 1);
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      crease = o.number("crease", 30);
      if (!(crease > 0 && crease < 180)) throw ArgError{2, "field 'crease' must be within 0..180 degrees, got " + number_text(crease)};
      if (auto c = o.vec3("color")) {
        for (int k = 0; k < 3; ++k)
          if (!((*c)[k] >= 0 && (*c)[k] <= 1))
            throw ArgError{2, "field 'color[" + std::to_string(k + 1) + "]' must be within 0..1, got " + number_text((*c)[k])};
        w.color = render::Vec4f(float(c->x()), float(c->y()), float(c->z()), 1);
      }
      o.finish();
    }
    if (lua_isnoneornil(L, 1)) throw ArgError{1, "Solid or mesh expected, got " + std::string(lua_isnone(L, 1) ? "no value" : "nil")};
    const Mesh mesh = to_mesh(L, 1, 1, current_tolerance(L));
    w.lines = render::polylines(render::feature_edges(mesh, crease));
    if (w.lines.empty()) throw ArgError{1, "this " + type_name(L, 1) + " has no edges to draw"};
    push_object(L, kKey, std::move(w));
    return 1;
  });
}

int length_m(lua_State* L) {
  return guarded(L, [&] {
    lua_pushnumber(L, length(self(L)));
    return 1;
  });
}

// w:polylines(): {{{x,y,z}, ...}, ...}
int polylines_m(lua_State* L) {
  return guarded(L, [&] {
    const Wireframe& w = self(L);
    lua_createtable(L, int(w.lines.size()), 0);
    for (std::size_t i = 0; i < w.lines.size(); ++i) {
      lua_createtable(L, int(w.lines[i].size()), 0);
      for (std::size_t k = 0; k < w.lines[i].size(); ++k) {
        push_vec3(L, w.lines[i][k]);
        lua_rawseti(L, -2, lua_Integer(k + 1));
      }
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  });
}

// w:segments(): the number of straight pieces.
int segments_m(lua_State* L) {
  return guarded(L, [&] {
    std::size_t n = 0;
    for (const auto& line : self(L).lines) n += line.size() - 1;
    lua_pushinteger(L, lua_Integer(n));
    return 1;
  });
}

int len_m(lua_State* L) {
  return guarded(L, [&] {
    lua_pushinteger(L, lua_Integer(self(L).lines.size()));
    return 1;
  });
}

int tostring_m(lua_State* L) {
  return guarded(L, [&] {
    std::ostringstream out;
    out << "Wireframe(" << self(L).lines.size() << " polylines, length " << length(self(L)) << ")";
    const std::string s = out.str();
    lua_pushlstring(L, s.data(), s.size());
    return 1;
  });
}

const luaL_Reg kMethods[] = {{"length", length_m}, {"polylines", polylines_m}, {"segments", segments_m}, {nullptr, nullptr}};
const luaL_Reg kMeta[] = {{"__len", len_m}, {"__tostring", tostring_m}, {nullptr, nullptr}};
const luaL_Reg kFunctions[] = {{"wireframe", wireframe_fn}, {nullptr, nullptr}};

}  // namespace

const Wireframe* test_wireframe(lua_State* L, int idx) { return test_object<Wireframe>(L, idx, kKey); }

void write_wireframe_obj(const Wireframe& w, const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || path.substr(dot) != ".obj")
    fail("cannot write '", path, "': a wireframe has no faces; export it as .obj (polylines)");
  AtomicFile file(path);  // whole or not at all (kernel/file_io.h)
  char line[96];
  std::snprintf(line, sizeof line, "# wedge wireframe: %zu polylines\n", w.lines.size());
  file.write(line);
  for (const auto& l : w.lines)
    for (const auto& p : l) {
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
      file.write(line);
    }
  std::size_t base = 1;
  for (const auto& l : w.lines) {
    std::string record = "l";
    for (std::size_t k = 0; k < l.size(); ++k) record += " " + std::to_string(base + k);
    file.write(record + "\n");
    base += l.size();
  }
  file.commit();
}

void register_wireframe(lua_State* L) {
  register_class(L, kKey, "Wireframe", kMethods, kMeta, gc_object<Wireframe>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
