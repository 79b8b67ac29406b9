// Lua bindings of csg/solid.h: the Solid userdata, its transforms and queries, tolerance().
#include "lua/wrap_solid.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_curve.h"
#include "lua/wrap_matrix.h"
#include "lua/wrap_render.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Solid";
constexpr const char* kToleranceKey = "wedge.tolerance";
constexpr const char* kAngleKey = "wedge.tolerance.angle";
constexpr const char* kMaxTrianglesKey = "wedge.tolerance.max_triangles";
constexpr const char* kMaxCrossingsKey = "wedge.tolerance.max_crossings";
constexpr const char* kConvertersKey = "wedge.mesh_converters";
constexpr const char* kMaterialsKey = "wedge.face_materials";

const Solid& self(lua_State* L) { return check_solid(L, 1); }

// Pushes s transformed by m, keeping the material of the Solid at index 1.
int push_transformed(lua_State* L, const Mat4& m) {
  push_solid(L, self(L).transformed(m), 1);
  return 1;
}

int translate_m(lua_State* L) {
  return guarded(L, [&] {
    Vec3 d = lua_type(L, 2) == LUA_TTABLE ? check_vec3(L, 2, true)
                                           : Vec3{check_number(L, 2), check_number(L, 3), opt_number(L, 4, 0)};
    check_no_more_method(L, lua_type(L, 2) == LUA_TTABLE ? 2 : 4);
    return push_transformed(L, translate(d));
  });
}

int rotate_m(lua_State* L) {
  return guarded(L, [&] {
    double a = check_number(L, 2);
    Vec3 axis = lua_isnoneornil(L, 3) ? Vec3::UnitZ() : check_axis(L, 3);
    Mat4 m = lua_isnoneornil(L, 4) ? rotate(a, axis) : rotate(a, axis, check_vec3(L, 4, true));
    check_no_more_method(L, 4);
    return push_transformed(L, m);
  });
}

template <Mat4 (*F)(double)>
int rotate_axis_m(lua_State* L) {
  return guarded(L, [&] {
    const double a = check_number(L, 2);
    check_no_more_method(L, 2);
    return push_transformed(L, F(a));
  });
}

int scale_m(lua_State* L) {
  return guarded(L, [&] {
    double kx = check_number(L, 2);
    Vec3 k = lua_isnoneornil(L, 3) ? Vec3(kx, kx, kx) : Vec3{kx, check_number(L, 3), check_number(L, 4)};
    check_no_more_method(L, 4);
    if (k.x() == 0 || k.y() == 0 || k.z() == 0)
      throw ArgError{2, "scale factors must be non-zero (a zero factor flattens the solid)"};
    return push_transformed(L, scale(k));
  });
}

int mirror_m(lua_State* L) {
  return guarded(L, [&] {
    Vec3 p = lua_isnoneornil(L, 3) ? Vec3::Zero() : check_vec3(L, 3, true);
    const Vec3 n = check_axis(L, 2);
    check_no_more_method(L, 3);
    return push_transformed(L, reflect(n, p));
  });
}

int shear_m(lua_State* L) {
  return table_call(L, 2, [&] {
    return push_transformed(L, shear(check_shear(L, 2)));
  });
}

int transform_m(lua_State* L) {
  return guarded(L, [&] {
    const Mat4 m = check_matrix(L, 2);
    check_no_more_method(L, 2);
    return push_transformed(L, m);
  });
}

int volume_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    lua_pushnumber(L, self(L).mass_properties(current_tolerance(L)).volume);
    return 1;
  });
}

int area_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    lua_pushnumber(L, self(L).mass_properties(current_tolerance(L)).area);
    return 1;
  });
}

int centroid_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    const Solid& s = self(L);
    // As bounds(): an empty solid's centroid was {0, 0, 0}, a point it does not hold.
    if (s.bounds().empty()) throw Error("the solid is empty: it has no centroid");
    push_vec3(L, s.mass_properties(current_tolerance(L)).centroid);
    return 1;
  });
}

int inertia_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    const Solid& s = self(L);
    // About the centroid, which an empty solid has not (centroid() is an error there too; this
    // was a zero matrix).
    if (s.bounds().empty()) throw Error("the solid is empty: it has no centroid to take the inertia about");
    const MassProperties mp = s.mass_properties(current_tolerance(L));
    const Mat3& I = mp.inertia;
    // About volume x size^2: beyond doubles for a solid some 1e60 wide (its volume is not).
    if (!I.allFinite())
      fail("the inertia tensor overflows: the solid's volume ", number_text(mp.volume),
           " times its size squared is beyond the range of doubles (measure a scaled-down copy)");
    if (mp.volume > 0 && !(I.trace() >= std::numeric_limits<double>::min()))
      fail("the inertia tensor underflows: the solid's volume ", number_text(mp.volume),
           " times its size squared is below the range of doubles (measure a scaled-up copy)");
    lua_createtable(L, 3, 0);
    for (int r = 0; r < 3; ++r) {
      push_vec3(L, I.row(r).transpose());
      lua_rawseti(L, -2, r + 1);
    }
    return 1;
  });
}

int bounds_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    Box3 b = self(L).bounds();
    // An empty solid (box(1,1,1) - box(1,1,1)) has no extent: an error, as a scene of empty parts
    // gives (it was {0,0,0}-{0,0,0}, a point the solid does not hold).
    if (b.empty()) throw Error("the solid is empty: it has no bounds");
    lua_createtable(L, 0, 2);
    push_vec3(L, b.min);
    lua_setfield(L, -2, "min");
    push_vec3(L, b.max);
    lua_setfield(L, -2, "max");
    return 1;
  });
}

int euler_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    EulerCounts c = self(L).euler(current_tolerance(L));
    lua_createtable(L, 0, 6);
    const std::pair<const char*, long> fields[] = {{"V", c.V}, {"E", c.E}, {"F", c.F}, {"R", c.R}, {"H", c.H}, {"S", c.S}};
    for (const auto& [name, value] : fields) {
      lua_pushinteger(L, value);
      lua_setfield(L, -2, name);
    }
    return 1;
  });
}

// s:is_valid() -> true, or false and the broken rule in words.
int is_valid_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    const Solid& s = self(L);
    std::string why = s.validate(current_tolerance(L));
    if (why.empty()) {
      EulerCounts c = s.euler(current_tolerance(L));
      if (c.characteristic() != 0) {
        std::ostringstream out;
        out << "Euler-Poincare fails: V - E + F - R + 2H - 2S = " << c.characteristic();
        why = out.str();
      }
    }
    lua_pushboolean(L, why.empty());
    if (why.empty()) return 1;
    lua_pushlstring(L, why.data(), why.size());
    return 2;
  });
}

// s:contains({x,y,z}) -> "inside" | "outside" | "boundary"
int contains_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 2);
    Vec3 p = check_vec3(L, 2);
    lua_pushstring(L, membership_name(self(L).contains(p, current_tolerance(L))));
    return 1;
  });
}

// s:cells{size=, boxes=false} | s:cells(size) -> {inside=, boundary=, outside=, volume_min=,
// volume_max=} (counts of octree leaf cells; with boxes=true also boxes={{min=, max=, state=}, ...})
int cells_m(lua_State* L) {
  return table_call(L, 2, [&] {
    check_no_more_method(L, 2);
    double size = 0;
    bool boxes = false;
    if (lua_type(L, 2) == LUA_TNUMBER) {
      size = check_number(L, 2);
      if (!(size > 0)) throw ArgError{2, "size must be positive, got " + number_text(size)};
    } else {
      Options o(L, 2);
      const bool given = o.has("size");
      size = o.positive("size", 1);
      boxes = o.boolean("boxes", false);
      o.finish();  // first: cells{sz=0.1} is a misspelt field, not a missing one
      if (!given) throw ArgError{2, "field 'size' is required (the longest side of the smallest cells)"};
    }
    CellDecomposition d = self(L).cells(size, current_tolerance(L));
    lua_createtable(L, 0, 6);
    const std::pair<const char*, long> counts[] = {{"inside", d.inside}, {"boundary", d.boundary}, {"outside", d.outside}};
    for (const auto& [name, value] : counts) {
      lua_pushinteger(L, value);
      lua_setfield(L, -2, name);
    }
    lua_pushnumber(L, d.volume_min);
    lua_setfield(L, -2, "volume_min");
    lua_pushnumber(L, d.volume_max);
    lua_setfield(L, -2, "volume_max");
    if (boxes) {
      lua_createtable(L, static_cast<int>(d.cells.size()), 0);
      for (std::size_t i = 0; i < d.cells.size(); ++i) {
        lua_createtable(L, 0, 3);
        push_vec3(L, d.cells[i].box.min);
        lua_setfield(L, -2, "min");
        push_vec3(L, d.cells[i].box.max);
        lua_setfield(L, -2, "max");
        lua_pushstring(L, membership_name(d.cells[i].state));
        lua_setfield(L, -2, "state");
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
      lua_setfield(L, -2, "boxes");
    }
    return 1;
  });
}

// s:faces() -> { {surface=, area=, loops=, geometry=, reversed=}, ... }: geometry is the face's
// surface as a Surface (S:eval, S:normal over (u, v) in [0, 1]^2; a plane or cylinder bounded to
// the face's box), reversed true when the outward normal is -S:normal.
int faces_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    std::vector<SolidFace> faces = self(L).faces(current_tolerance(L));
    lua_createtable(L, static_cast<int>(faces.size()), 0);
    for (std::size_t i = 0; i < faces.size(); ++i) {
      lua_createtable(L, 0, 3);
      lua_pushlstring(L, faces[i].surface.data(), faces[i].surface.size());
      lua_setfield(L, -2, "surface");
      lua_pushnumber(L, faces[i].area);
      lua_setfield(L, -2, "area");
      lua_pushinteger(L, faces[i].loops);
      lua_setfield(L, -2, "loops");
      bool reversed = false;
      if (SurfacePtr patch = surface_patch(faces[i].geometry, faces[i].bounds, reversed)) {
        push_surface(L, LuaSurface{{patch}});
        lua_setfield(L, -2, "geometry");
        lua_pushboolean(L, reversed);
        lua_setfield(L, -2, "reversed");
      }
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    return 1;
  });
}

// s:triangles{tolerance=} -> the triangle count after tessellation
int triangles_m(lua_State* L) {
  return table_call(L, 2, [&] {
    check_no_more_method(L, 2);
    Tolerance tol = current_tolerance(L);
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      tol.chordal = o.positive("tolerance", tol.chordal);
      if (auto n = o.number("max_triangles")) tol.max_triangles = std::size_t(check_max_triangles(*n, 2));
      if (auto n = o.number("max_crossings")) tol.max_crossings = std::size_t(check_budget("max_crossings", *n, 2));
      o.finish();
    }
    lua_pushinteger(L, static_cast<lua_Integer>(self(L).mesh(tol).triangle_count()));
    return 1;
  });
}

// s:material{ambient=, diffuse=, specular=, shininess=, emission=, texture=} -> a copy carrying it.
int material_m(lua_State* L) {
  return table_call(L, 2, [&] {
    const Solid& s = self(L);
    // Read as render{} will read it, so that a bad value is reported on the line that made it.
    std::shared_ptr<const render::Texture> texture;
    read_material(L, 2, 2, texture);
    // The material also goes on the solid's faces as a tag (its place in the registry's list of
    // materials), so that a boolean keeps it on the faces that came from this solid.
    if (lua_getfield(L, LUA_REGISTRYINDEX, kMaterialsKey) != LUA_TTABLE) {
      lua_pop(L, 1);
      lua_newtable(L);
      lua_pushvalue(L, -1);
      lua_setfield(L, LUA_REGISTRYINDEX, kMaterialsKey);
    }
    const lua_Integer tag = static_cast<lua_Integer>(lua_rawlen(L, -1));
    lua_pushvalue(L, 2);
    lua_rawseti(L, -2, tag + 1);
    lua_pop(L, 1);
    push_solid(L, s.tagged(static_cast<int>(tag)));
    lua_pushvalue(L, 2);
    lua_setiuservalue(L, -2, 1);
    return 1;
  });
}

int tostring_m(lua_State* L) {
  return guarded(L, [&] {
    const Solid& s = self(L);
    std::ostringstream out;
    if (s.empty() || s.bounds().empty()) out << "Solid(empty)";
    else {
      Box3 b = s.bounds();
      out << "Solid(bounds " << b.min.x() << " " << b.min.y() << " " << b.min.z() << " .. " << b.max.x() << " "
          << b.max.y() << " " << b.max.z() << ")";
    }
    std::string str = out.str();
    lua_pushlstring(L, str.data(), str.size());
    return 1;
  });
}

// tolerance() -> current; tolerance(t) sets the chordal tolerance for this state.
// tolerance(chordal) | tolerance{chordal=, angle=, max_triangles=, max_crossings=}: the global
// tessellation tolerances (chordal in model units, angular in degrees), the triangle budget of one
// tessellation (default 10 million) and the work budget of one boolean (default 50,000 points where
// three operands' surfaces cross: csg/boolean.h); returns the chordal and the angular tolerance
// and the two budgets now in force.
int tolerance_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    check_no_more(L, 1);
    if (lua_type(L, 1) == LUA_TTABLE) {
      Options o(L, 1);
      auto chordal = o.number("chordal");
      auto angle = o.number("angle");
      auto budget = o.number("max_triangles");
      auto crossings = o.number("max_crossings");
      o.finish();
      // Every field is checked before any is set: {max_triangles=1000, chordal=-1} raised its
      // error about chordal but had already set max_triangles to 1000.
      const double checked_budget = budget ? check_max_triangles(*budget, 1) : 0;
      const double checked_crossings = crossings ? check_budget("max_crossings", *crossings, 1) : 0;
      if (chordal && !(*chordal > 0)) throw ArgError{1, "field 'chordal' must be positive, got " + number_text(*chordal)};
      if (angle && !(*angle > 0 && *angle <= 90)) throw ArgError{1, "field 'angle' must be within 0..90 degrees (above 0), got " + number_text(*angle)};
      if (budget) lua_pushnumber(L, checked_budget), lua_setfield(L, LUA_REGISTRYINDEX, kMaxTrianglesKey);
      if (crossings) lua_pushnumber(L, checked_crossings), lua_setfield(L, LUA_REGISTRYINDEX, kMaxCrossingsKey);
      if (chordal) lua_pushnumber(L, *chordal), lua_setfield(L, LUA_REGISTRYINDEX, kToleranceKey);
      if (angle) lua_pushnumber(L, *angle), lua_setfield(L, LUA_REGISTRYINDEX, kAngleKey);
    } else if (!lua_isnoneornil(L, 1)) {
      double t = check_number(L, 1);
      if (!(t > 0)) throw ArgError{1, "tolerance must be positive, got " + number_text(t)};
      lua_pushnumber(L, t);
      lua_setfield(L, LUA_REGISTRYINDEX, kToleranceKey);
    }
    const Tolerance t = current_tolerance(L);
    lua_pushnumber(L, t.chordal);
    lua_pushnumber(L, t.angular);
    lua_pushinteger(L, lua_Integer(t.max_triangles));
    lua_pushinteger(L, lua_Integer(t.max_crossings));
    return 4;
  });
}

const luaL_Reg kMethods[] = {
    {"translate", translate_m},
    {"rotate", rotate_m},
    {"rotate_x", rotate_axis_m<rotate_x>},
    {"rotate_y", rotate_axis_m<rotate_y>},
    {"rotate_z", rotate_axis_m<rotate_z>},
    {"scale", scale_m},
    {"mirror", mirror_m},
    {"shear", shear_m},
    {"transform", transform_m},
    {"volume", volume_m},
    {"area", area_m},
    {"centroid", centroid_m},
    {"inertia", inertia_m},
    {"bounds", bounds_m},
    {"euler", euler_m},
    {"is_valid", is_valid_m},
    {"triangles", triangles_m},
    {"contains", contains_m},
    {"faces", faces_m},
    {"cells", cells_m},
    {"material", material_m},
    {nullptr, nullptr}};

const luaL_Reg kMeta[] = {{"__tostring", tostring_m}, {nullptr, nullptr}};

const luaL_Reg kFunctions[] = {{"tolerance", tolerance_fn}, {nullptr, nullptr}};

}  // namespace

void push_solid(lua_State* L, Solid s, int material_from) {
  if (material_from) material_from = lua_absindex(L, material_from);
  auto** slot = static_cast<Solid**>(lua_newuserdatauv(L, sizeof(Solid*), 1));
  *slot = nullptr;
  luaL_setmetatable(L, kKey);
  *slot = new Solid(std::move(s));
  if (material_from && test_solid(L, material_from)) {
    lua_getiuservalue(L, material_from, 1);
    lua_setiuservalue(L, -2, 1);
  }
}

const Solid* test_solid(lua_State* L, int idx) { return test_object<Solid>(L, idx, kKey); }

const Solid& check_solid(lua_State* L, int idx) { return check_object<Solid>(L, idx, kKey, "Solid"); }

int push_material(lua_State* L, int idx) {
  if (!test_solid(L, idx)) {
    lua_pushnil(L);
    return LUA_TNIL;
  }
  return lua_getiuservalue(L, idx, 1);
}

int push_tag_material(lua_State* L, int tag) {
  if (tag < 0 || lua_getfield(L, LUA_REGISTRYINDEX, kMaterialsKey) != LUA_TTABLE) {
    if (tag >= 0) lua_pop(L, 1);
    lua_pushnil(L);
    return LUA_TNIL;
  }
  int type = lua_rawgeti(L, -1, tag + 1);
  lua_remove(L, -2);
  return type;
}

double check_budget(const char* field, double n, int arg) {
  if (!(n >= 1 && n <= 1e12 && n == std::floor(n))) {
    // All the digits of a fraction: 1e12 + 0.5 printed as "1e+12" looked within range.
    char digits[32];
    std::snprintf(digits, sizeof digits, "%.17g", n);
    throw ArgError{arg, std::string("field '") + field + "' must be a whole number in 1..1e12, got " +
                            (n == std::floor(n) || !std::isfinite(n) ? number_text(n) : std::string(digits))};
  }
  return n;
}

double check_max_triangles(double n, int arg) { return check_budget("max_triangles", n, arg); }

Tolerance current_tolerance(lua_State* L) {
  Tolerance t;
  if (lua_getfield(L, LUA_REGISTRYINDEX, kToleranceKey) == LUA_TNUMBER) t.chordal = lua_tonumber(L, -1);
  lua_pop(L, 1);
  if (lua_getfield(L, LUA_REGISTRYINDEX, kAngleKey) == LUA_TNUMBER) t.angular = lua_tonumber(L, -1);
  lua_pop(L, 1);
  if (lua_getfield(L, LUA_REGISTRYINDEX, kMaxTrianglesKey) == LUA_TNUMBER) t.max_triangles = std::size_t(lua_tonumber(L, -1));
  lua_pop(L, 1);
  if (lua_getfield(L, LUA_REGISTRYINDEX, kMaxCrossingsKey) == LUA_TNUMBER) t.max_crossings = std::size_t(lua_tonumber(L, -1));
  lua_pop(L, 1);
  return t;
}

void add_mesh_converter(lua_State* L, MeshConverter converter) {
  if (lua_getfield(L, LUA_REGISTRYINDEX, kConvertersKey) != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setfield(L, LUA_REGISTRYINDEX, kConvertersKey);
  }
  lua_pushlightuserdata(L, reinterpret_cast<void*>(converter));
  lua_rawseti(L, -2, static_cast<lua_Integer>(lua_rawlen(L, -2) + 1));
  lua_pop(L, 1);
}

Mesh to_mesh(lua_State* L, int idx, int arg, const Tolerance& tol) {
  idx = lua_absindex(L, idx);
  if (const Solid* s = test_solid(L, idx)) return s->mesh(tol);
  std::vector<MeshConverter> converters;
  if (lua_getfield(L, LUA_REGISTRYINDEX, kConvertersKey) == LUA_TTABLE) {
    lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, -1, i);
      converters.push_back(reinterpret_cast<MeshConverter>(lua_touserdata(L, -1)));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  for (MeshConverter c : converters)
    if (auto m = c(L, idx, tol)) return std::move(*m);
  throw ArgError{arg, "Solid or mesh expected, got " + type_name(L, idx)};
}

void register_solid(lua_State* L) {
  register_class(L, kKey, "Solid", kMethods, kMeta, gc_object<Solid>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
