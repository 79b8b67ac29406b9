// Lua bindings of the surfaces of surfaces/: bezier_surface, nurbs_surface, revolved_surface,
// extruded_surface, swept_surface, lofted_surface, teapot, and the Surface methods. Surface
// parameters are normalised: (u, v) in [0, 1] x [0, 1] for every kind of surface.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "csg/brep_leaf.h"
#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_curve.h"
#include "lua/wrap_solid.h"
#include "tessellate/surface_mesh.h"

namespace wedge::lua {

namespace {
constexpr const char* kKey = "wedge.Surface";
}  // namespace

void push_surface(lua_State* L, LuaSurface s) { push_object(L, kKey, std::move(s)); }

namespace {

// Depth of nesting of tables at the top of the stack along t[1][1]...: 1 for {1, 2}, 2 for a list
// of points, 3 for a grid of points.
int nesting(lua_State* L) {
  int depth = 0, pushed = 0;
  while (lua_type(L, -1) == LUA_TTABLE) {
    ++depth;
    lua_rawgeti(L, -1, 1);
    ++pushed;
  }
  lua_pop(L, pushed);
  return depth;
}

// A grid at the top of the stack: grid[i][j] = {x, y, z}.
std::vector<std::vector<Point3>> read_grid_top(lua_State* L, int arg, const std::string& what) {
  if (lua_type(L, -1) != LUA_TTABLE) throw ArgError{arg, "field '" + what + "' must be a grid of points, got " + type_name(L, -1)};
  std::vector<std::vector<Point3>> grid;
  lua_Integer rows = lua_Integer(lua_rawlen(L, -1));
  for (lua_Integer i = 1; i <= rows; ++i) {
    lua_rawgeti(L, -1, i);
    std::string err;
    std::vector<Point3> row;
    if (lua_type(L, -1) != LUA_TTABLE)
      err = "field '" + what + "[" + std::to_string(i) + "]' must be a list of points (a row), got " + type_name(L, -1);
    else {
      lua_Integer cols = lua_Integer(lua_rawlen(L, -1));
      for (lua_Integer j = 1; j <= cols && err.empty(); ++j) {
        lua_rawgeti(L, -1, j);
        std::string name = "field '" + what + "[" + std::to_string(i) + "][" + std::to_string(j) + "]'";
        if (lua_type(L, -1) != LUA_TTABLE) err = name + " must be a point {x, y, z}, got " + type_name(L, -1);
        else {
          try {
            row.push_back(to_vec3(L, -1, arg, name, true));
          } catch (const ArgError& e) {
            err = e.message;
          }
        }
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
    if (!err.empty()) throw ArgError{arg, err};
    grid.push_back(std::move(row));
  }
  return grid;
}

std::vector<std::vector<double>> read_number_grid(lua_State* L, Options& o, const char* key) {
  o.push(key);
  std::vector<std::vector<double>> out;
  std::string err;
  if (lua_type(L, -1) != LUA_TTABLE) err = std::string("field '") + key + "' must be a grid of numbers, got " + type_name(L, -1);
  else
    for (lua_Integer i = 1; i <= lua_Integer(lua_rawlen(L, -1)) && err.empty(); ++i) {
      lua_rawgeti(L, -1, i);
      std::vector<double> row;
      if (lua_type(L, -1) != LUA_TTABLE)
        err = std::string("field '") + key + "[" + std::to_string(i) + "]' must be a list of numbers (a row), got " + type_name(L, -1);
      else
        for (lua_Integer j = 1; j <= lua_Integer(lua_rawlen(L, -1)) && err.empty(); ++j) {
          int t = lua_rawgeti(L, -1, j);
          double x = lua_tonumber(L, -1);
          const std::string name = std::string("field '") + key + "[" + std::to_string(i) + "][" + std::to_string(j) + "]'";
          if (t != LUA_TNUMBER) err = name + " must be a number, got " + type_name(L, -1);
          else if (!std::isfinite(x)) err = name + " must be finite, got " + number_text(x);
          row.push_back(x);
          lua_pop(L, 1);
        }
      lua_pop(L, 1);
      out.push_back(std::move(row));
    }
  lua_pop(L, 1);
  if (!err.empty()) throw ArgError{o.arg(), err};
  return out;
}

std::vector<double> read_number_list(lua_State* L, Options& o, const char* key) {
  o.push(key);
  std::vector<double> out;
  std::string err;
  if (lua_type(L, -1) != LUA_TTABLE) err = std::string("field '") + key + "' must be a list of numbers, got " + type_name(L, -1);
  else
    for (lua_Integer i = 1; i <= lua_Integer(lua_rawlen(L, -1)) && err.empty(); ++i) {
      int t = lua_rawgeti(L, -1, i);
      double x = lua_tonumber(L, -1);
      const std::string name = std::string("field '") + key + "[" + std::to_string(i) + "]'";
      if (t != LUA_TNUMBER) err = name + " must be a number, got " + type_name(L, -1);
      else if (!std::isfinite(x)) err = name + " must be finite, got " + number_text(x);
      out.push_back(x);
      lua_pop(L, 1);
    }
  lua_pop(L, 1);
  if (!err.empty()) throw ArgError{o.arg(), err};
  return out;
}

// bezier_surface{grid} | bezier_surface{grid=...} | bezier_surface{{p11, p12, ...}, ...}
int bezier_surface_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    std::vector<std::vector<Point3>> grid;
    if (o.has("grid")) {
      o.push("grid");
      grid = read_grid_top(L, 1, "grid");
      lua_pop(L, 1);
    } else {
      o.allow_positional();
      lua_pushvalue(L, 1);
      if (nesting(L) >= 4) {
        lua_rawgeti(L, -1, 1);
        grid = read_grid_top(L, 1, "grid");
        lua_pop(L, 1);
      } else {
        grid = read_grid_top(L, 1, "grid");
      }
      lua_pop(L, 1);
    }
    o.finish();
    for (std::size_t i = 1; i < grid.size(); ++i)
      if (grid[i].size() != grid[0].size())
        throw ArgError{1, "grid must be rectangular: row " + std::to_string(i + 1) + " has " + std::to_string(grid[i].size()) +
                              " points, row 1 has " + std::to_string(grid[0].size())};
    push_surface(L, {{as_arg(1, [&] { return std::make_shared<const NurbsSurface>(bezier_surface(grid)); })}});
    return 1;
  });
}

// nurbs_surface{points=grid, weights=, uknots=, vknots=, udegree=3, vdegree=3}
int nurbs_surface_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    if (!o.has("points")) throw ArgError{1, "field 'points' (a grid of points) is required"};
    o.push("points");
    auto grid = read_grid_top(L, 1, "points");
    lua_pop(L, 1);
    int p = o.integer("udegree", 3), q = o.integer("vdegree", 3);
    std::vector<std::vector<double>> w;
    if (o.has("weights")) w = read_number_grid(L, o, "weights");
    std::vector<double> U, V;
    if (o.has("uknots")) U = read_number_list(L, o, "uknots");
    if (o.has("vknots")) V = read_number_list(L, o, "vknots");
    o.finish();
    auto s = as_arg(1, [&] {
      if (grid.empty()) fail("points: the control grid is empty");
      // open_uniform_knots speaks of a curve ("a curve of degree 3 needs at least 4 control
      // points, got 2" for a 2 x 2 grid): name the surface's own degree and direction.
      if (p >= 1 && grid.size() < std::size_t(p) + 1)
        fail("udegree ", p, " needs at least ", p + 1, " rows of control points, got ", grid.size(), " (give a lower udegree=)");
      if (q >= 1 && grid[0].size() < std::size_t(q) + 1)
        fail("vdegree ", q, " needs at least ", q + 1, " control points in each row, got ", grid[0].size(), " (give a lower vdegree=)");
      if (U.empty()) U = open_uniform_knots(p, grid.size());
      if (V.empty()) V = open_uniform_knots(q, grid[0].size());
      return std::make_shared<const NurbsSurface>(p, q, grid, U, V, w);
    });
    push_surface(L, {{s}});
    return 1;
  });
}

// A planar profile (x = radius, y = height) stood up in the XZ plane, OpenSCAD's revolve convention.
class StoodUp : public Curve {
 public:
  explicit StoodUp(CurvePtr c) : c_(std::move(c)) {}
  std::pair<double, double> domain() const override { return c_->domain(); }
  Point3 eval(double t) const override { return up(c_->eval(t)); }
  Vec3 derivative(double t, int k) const override { return up(c_->derivative(t, k)); }
  std::vector<double> breaks() const override { return c_->breaks(); }

 private:
  static Vec3 up(const Vec3& p) { return Vec3(p.x(), 0, p.y()); }
  CurvePtr c_;
};

// revolved_surface(curve [, {angle=360}]): a 2D curve follows OpenSCAD (x is the radius, y becomes
// z); a 3D curve is revolved about the Z axis as it stands.
int revolved_surface_fn(lua_State* L) {
  return table_call(L, 2, [&] {
    const LuaCurve& c = check_curve(L, 1);
    double angle = 360;
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      angle = o.number("angle", 360);
      o.finish();
    }
    if (!(angle > 0 && angle <= 360)) throw ArgError{2, "field 'angle' must be in (0, 360], got " + number_text(angle)};
    CurvePtr curve = c.planar ? CurvePtr(std::make_shared<StoodUp>(c.curve)) : c.curve;
    push_surface(L, {{as_arg(1, [&] { return std::make_shared<const RevolvedSurface>(curve, Point3::Zero(), Vec3::UnitZ(), radians(angle)); })}});
    return 1;
  });
}

// extruded_surface(curve, vector)
int extruded_surface_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    Vec3 d = check_vec3(L, 2, true);
    if (d == Vec3::Zero()) throw ArgError{2, "extrusion vector must be non-zero"};
    // As the builders: the surface's points stay within +-1e100 (a vector of 1e308 was accepted).
    if (d.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw ArgError{2, "extrusion vector component " + number_text(d.cwiseAbs().maxCoeff()) + " is beyond +-1e+100"};
    push_surface(L, {{std::make_shared<const ExtrudedSurface>(c.curve, d)}});
    return 1;
  });
}

// swept_surface(profile, path): the profile's x, y in the normal plane of the path.
int swept_surface_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& profile = check_curve(L, 1);
    const LuaCurve& path = check_curve(L, 2);
    push_surface(L, {{as_arg(2, [&] { return std::make_shared<const SweptSurface>(profile.curve, path.curve); })}});
    return 1;
  });
}

// lofted_surface{c1, c2, ...}: through the section curves in order.
int lofted_surface_fn(lua_State* L) {
  return guarded(L, [&] {
    check_table(L, 1);
    std::vector<CurvePtr> sections;
    lua_Integer n = lua_Integer(lua_rawlen(L, 1));
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, 1, i);
      const LuaCurve* c = test_curve(L, -1);
      lua_pop(L, 1);
      if (!c) throw ArgError{1, "section " + std::to_string(i) + " must be a Curve"};
      sections.push_back(c->curve);
    }
    push_surface(L, {{as_arg(1, [&] { return std::make_shared<const LoftedSurface>(sections); })}});
    return 1;
  });
}

int teapot_fn(lua_State* L) {
  return guarded(L, [&] {
    check_no_more(L, 0);
    LuaSurface s;
    for (NurbsSurface& p : teapot()) s.patches.push_back(std::make_shared<const NurbsSurface>(std::move(p)));
    push_surface(L, std::move(s));
    return 1;
  });
}

// patch_solid(S1, S2, ...) or patch_solid{S1, S2, ...}: every patch of the surfaces, joined where
// they share boundary curves and capped where a loop of their boundary is left open and planar.
int patch_solid_fn(lua_State* L) {
  return guarded(L, [&] {
    std::vector<SurfacePtr> patches;
    int n = lua_gettop(L);
    auto take = [&](int idx, int arg) {
      const LuaSurface* s = test_surface(L, idx);
      if (!s) throw ArgError{arg, "expected a Surface, got " + type_name(L, idx)};
      patches.insert(patches.end(), s->patches.begin(), s->patches.end());
    };
    if (n == 1 && lua_type(L, 1) == LUA_TTABLE) {
      for (lua_Integer i = 1, m = static_cast<lua_Integer>(lua_rawlen(L, 1)); i <= m; ++i) {
        lua_rawgeti(L, 1, i);
        take(lua_gettop(L), 1);
        lua_pop(L, 1);
      }
    } else {
      for (int i = 1; i <= n; ++i) take(i, i);
    }
    if (patches.empty()) throw ArgError{1, "expected surfaces with at least one patch"};
    push_solid(L, brep_solid(as_arg(1, [&] { return patch_solid(patches, "nurbs"); })));
    return 1;
  });
}

// --- methods ---

// S:patch(i) -> the surface of patch i alone (1-based).
int patch_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaSurface& s = check_surface(L, 1);
    check_no_more_method(L, 2);
    const lua_Integer i = check_integer(L, 2);  // not luaL_checkinteger: no longjmp out of guarded()
    if (i < 1 || i > lua_Integer(s.patches.size()))
      throw ArgError{2, "patch index must be in 1.." + std::to_string(s.patches.size()) + ", got " + std::to_string(i)};
    LuaSurface one;
    one.patches.push_back(s.patches[static_cast<std::size_t>(i - 1)]);
    push_surface(L, std::move(one));
    return 1;
  });
}

// (u, v [, patch]) at idx, idx+1, idx+2 -> the patch and its own parameters.
const Surface& locate(lua_State* L, const LuaSurface& s, int idx, double& u, double& v) {
  double nu = check_number(L, idx), nv = check_number(L, idx + 1);
  if (nu < -1e-12 || nu > 1 + 1e-12) throw ArgError{idx, "parameter u must be in [0, 1], got " + number_text(nu)};
  if (nv < -1e-12 || nv > 1 + 1e-12) throw ArgError{idx + 1, "parameter v must be in [0, 1], got " + number_text(nv)};
  int patch = lua_isnoneornil(L, idx + 2) ? 1 : check_integer(L, idx + 2);
  if (patch < 1 || patch > int(s.patches.size()))
    throw ArgError{idx + 2, "patch must be 1.." + std::to_string(s.patches.size()) + ", got " + std::to_string(patch)};
  const Surface& S = *s.patches[patch - 1];
  auto [u0, u1] = S.u_domain();
  auto [v0, v1] = S.v_domain();
  u = u0 + std::clamp(nu, 0.0, 1.0) * (u1 - u0);
  v = v0 + std::clamp(nv, 0.0, 1.0) * (v1 - v0);
  return S;
}

int eval_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaSurface& s = check_surface(L, 1);
    check_no_more_method(L, 4);
    double u, v;
    const Surface& S = locate(L, s, 2, u, v);
    push_vec3(L, S.eval(u, v));
    return 1;
  });
}

int normal_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaSurface& s = check_surface(L, 1);
    check_no_more_method(L, 4);
    double u, v;
    const Surface& S = locate(L, s, 2, u, v);
    const Vec3 n = S.normal(u, v);
    // A surface whose control points coincide there has no normal: {0, 0, 0} is no direction.
    if (n == Vec3::Zero() || !n.allFinite()) fail("the surface has no normal at (", number_text(lua_tonumber(L, 2)), ", ", number_text(lua_tonumber(L, 3)), "): it does not span an area there");
    push_vec3(L, n);
    return 1;
  });
}

int patches_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaSurface& s = check_surface(L, 1);
    check_no_more_method(L, 1);
    lua_pushinteger(L, lua_Integer(s.patches.size()));
    return 1;
  });
}

void push_points(lua_State* L, const std::vector<Vec3>& pts) {
  lua_createtable(L, int(pts.size()), 0);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    push_vec3(L, pts[i]);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
}

// S:mesh{tolerance=0.01} -> {vertices={{x,y,z},...}, normals=..., uvs={{u,v},...},
// triangles={{i,j,k},...} (1-based, counter-clockwise seen from the normal side), patches={p,...}}.
// welded=true: closed seams merged and poles collapsed (a closed surface gives a closed mesh, oriented
// outward; uvs jump across the seam).
int mesh_fn(lua_State* L) {
  return table_call(L, 2, [&] {
    const LuaSurface& s = check_surface(L, 1);
    check_no_more_method(L, 2);
    double tol = 0.01;
    bool welded = false;
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      tol = o.positive("tolerance", 0.01);
      welded = o.boolean("welded", false);
      o.finish();
    }
    const std::size_t budget = current_tolerance(L).max_triangles;
    Mesh m = as_arg(2, [&] { return surface_mesh(s, tol, welded, budget); });
    lua_createtable(L, 0, 5);
    push_points(L, m.positions);
    lua_setfield(L, -2, "vertices");
    push_points(L, m.normals);
    lua_setfield(L, -2, "normals");
    // The mesh's uvs are each patch's own parameters (radians on a revolved surface, 0..2 on a
    // Catmull-Rom extrusion of 3 points); S:eval takes them normalised to [0, 1] per patch, and
    // a vertex's uv passed to it raised "parameter u must be in [0, 1]" or gave a point up to 2
    // units away on a unit sphere. A vertex's patch is that of its triangles.
    std::vector<int> patch_of(m.uvs.size(), 0);
    for (std::size_t i = 0; i < m.triangles.size() && i < m.face_ids.size(); ++i)
      for (int k = 0; k < 3; ++k) patch_of[static_cast<std::size_t>(m.triangles[i][k])] = std::max(m.face_ids[i], 0);
    lua_createtable(L, int(m.uvs.size()), 0);
    for (std::size_t i = 0; i < m.uvs.size(); ++i) {
      const Surface& S = *s.patches[std::min(static_cast<std::size_t>(patch_of[i]), s.patches.size() - 1)];
      auto [u0, u1] = S.u_domain();
      auto [v0, v1] = S.v_domain();
      push_vec2(L, Vec2(u1 > u0 ? (m.uvs[i].x() - u0) / (u1 - u0) : 0, v1 > v0 ? (m.uvs[i].y() - v0) / (v1 - v0) : 0));
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    lua_setfield(L, -2, "uvs");
    lua_createtable(L, int(m.triangles.size()), 0);
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      lua_createtable(L, 3, 0);
      for (int k = 0; k < 3; ++k) {
        lua_pushinteger(L, lua_Integer(m.triangles[i][k]) + 1);
        lua_rawseti(L, -2, k + 1);
      }
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    lua_setfield(L, -2, "triangles");
    lua_createtable(L, int(m.face_ids.size()), 0);
    for (std::size_t i = 0; i < m.face_ids.size(); ++i) {
      lua_pushinteger(L, m.face_ids[i] + 1);
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    lua_setfield(L, -2, "patches");
    return 1;
  });
}

int tostring_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaSurface& s = check_surface(L, 1);
    std::string text = s.patches.size() == 1 ? "Surface" : "Surface(" + std::to_string(s.patches.size()) + " patches)";
    lua_pushstring(L, text.c_str());
    return 1;
  });
}

const luaL_Reg kFunctions[] = {
    {"bezier_surface", bezier_surface_fn},
    {"nurbs_surface", nurbs_surface_fn},
    {"revolved_surface", revolved_surface_fn},
    {"extruded_surface", extruded_surface_fn},
    {"swept_surface", swept_surface_fn},
    {"lofted_surface", lofted_surface_fn},
    {"teapot", teapot_fn},
    {"patch_solid", patch_solid_fn},
    {nullptr, nullptr}};

const luaL_Reg kMethods[] = {
    {"eval", eval_fn}, {"normal", normal_fn}, {"mesh", mesh_fn}, {"patches", patches_fn}, {"patch", patch_fn}, {nullptr, nullptr}};

const luaL_Reg kMeta[] = {{"__tostring", tostring_fn}, {nullptr, nullptr}};

}  // namespace

const LuaSurface* test_surface(lua_State* L, int idx) { return test_object<LuaSurface>(L, idx, kKey); }
const LuaSurface& check_surface(lua_State* L, int idx) { return check_object<LuaSurface>(L, idx, kKey, "Surface"); }

Mesh surface_mesh(const LuaSurface& s, double tolerance, bool welded, std::size_t max_triangles) {
  if (s.patches.empty()) return Mesh();
  if (welded) {
    if (s.patches.size() != 1)
      fail("welded=true needs a single-patch surface (this one has ", s.patches.size(), " patches)");
    return tessellate_welded(*s.patches[0], tolerance, 0, max_triangles);
  }
  return tessellate_patches(s.patches, tolerance, max_triangles);
}

void register_surfaces(lua_State* L) {
  register_class(L, kKey, "Surface", kMethods, kMeta, gc_object<LuaSurface>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
