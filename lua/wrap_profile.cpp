// Lua bindings of 2D profiles and the planar extrude: polygon{}, rect(), extrude().
// A profile is a polygon with holes in the XY plane (brep/brep.h's Profile). A closed Curve (such
// as circle(r)) is also accepted as a profile: it is replaced by its polyline at the current
// chordal tolerance, so the extruded solid is faceted (planar faces within the tolerance of the
// curve), which the B-Rep's planar extrude can build exactly through Euler operators.
#include <algorithm>
#include <cmath>

#include "csg/brep_leaf.h"
#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_curve.h"
#include "lua/wrap_solid.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Profile";

double signed_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& u = p[i];
    const Vec2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return a / 2;
}

// A list of {x, y} points at stack index idx (argument `arg`), at least three, not all collinear.
std::vector<Vec2> read_ring(lua_State* L, int idx, int arg, const std::string& what) {
  idx = lua_absindex(L, idx);
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{arg, what + " must be a list of points {x, y}, got " + type_name(L, idx)};
  std::vector<Vec2> ring;
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    std::string err;
    try {
      ring.push_back(to_vec2(L, -1, arg, what + " point " + std::to_string(i)));
    } catch (const ArgError& e) {
      err = e.message;
    }
    lua_pop(L, 1);
    if (!err.empty()) throw ArgError{arg, err};
  }
  // A closing point equal to the first is allowed and dropped.
  if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
  if (ring.size() < 3) throw ArgError{arg, what + " needs at least 3 points, got " + std::to_string(ring.size())};
  if (std::abs(signed_area(ring)) == 0) throw ArgError{arg, what + " has zero area (its points are collinear)"};
  return ring;
}

Profile& push_profile(lua_State* L, Profile p) {
  as_arg(1, [&] { validate_profile(p); });  // the error points at the line that made the profile
  if (signed_area(p.outer) < 0) std::reverse(p.outer.begin(), p.outer.end());
  for (auto& h : p.holes)
    if (signed_area(h) > 0) std::reverse(h.begin(), h.end());
  return push_object(L, kKey, std::move(p));
}

// polygon{{x,y}, ...} | polygon{outer={...}, holes={{...}, ...}}
int polygon_fn(lua_State* L) {
  return guarded(L, [&] {
    check_table(L, 1);
    Profile p;
    lua_pushstring(L, "outer");
    bool has_outer = lua_rawget(L, 1) != LUA_TNIL;
    lua_pop(L, 1);
    if (!has_outer) {
      p.outer = read_ring(L, 1, 1, "polygon");
    } else {
      Options o(L, 1);
      o.push("outer");
      std::string err;
      try {
        p.outer = read_ring(L, -1, 1, "field 'outer'");
      } catch (const ArgError& e) {
        err = e.message;
      }
      lua_pop(L, 1);
      if (!err.empty()) throw ArgError{1, err};
      if (o.push("holes") != LUA_TNIL) {
        int holes = lua_gettop(L);
        try {
          if (lua_type(L, holes) != LUA_TTABLE) throw ArgError{1, "field 'holes' must be a list of polygons"};
          lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, holes));
          for (lua_Integer i = 1; i <= n; ++i) {
            lua_rawgeti(L, holes, i);
            p.holes.push_back(read_ring(L, -1, 1, "hole " + std::to_string(i)));
            lua_pop(L, 1);
          }
        } catch (const ArgError& e) {
          err = e.message;
        }
        lua_settop(L, holes);
      }
      lua_pop(L, 1);
      if (!err.empty()) throw ArgError{1, err};
      o.finish();
    }
    push_profile(L, std::move(p));
    return 1;
  });
}

// rect(w, h [, center])
int rect_fn(lua_State* L) {
  return guarded(L, [&] {
    double w = check_number(L, 1), h = check_number(L, 2);
    if (!(w > 0)) throw ArgError{1, "width must be positive, got " + std::to_string(w)};
    if (!(h > 0)) throw ArgError{2, "height must be positive, got " + std::to_string(h)};
    bool center = lua_isnoneornil(L, 3) ? false : check_boolean(L, 3);
    Vec2 o = center ? Vec2(-w / 2, -h / 2) : Vec2(0, 0);
    push_profile(L, Profile{{o, o + Vec2(w, 0), o + Vec2(w, h), o + Vec2(0, h)}, {}});
    return 1;
  });
}

// The profile at argument `arg`: a Profile, or a closed planar Curve as its polyline.
Profile check_profile(lua_State* L, int arg) {
  if (const Profile* p = test_object<Profile>(L, arg, kKey)) return *p;
  if (const LuaCurve* c = test_curve(L, arg)) {
    if (!c->curve->closed()) throw ArgError{arg, "the curve is open: a profile must be a closed curve"};
    std::vector<Point3> pts = c->curve->points(current_tolerance(L).chordal);
    Profile p;
    for (const auto& q : pts) {
      if (std::abs(q.z()) > 1e-12) throw ArgError{arg, "the curve leaves the XY plane: a profile must be planar"};
      p.outer.emplace_back(q.x(), q.y());
    }
    if (p.outer.size() > 1 && (p.outer.front() - p.outer.back()).norm() < 1e-12) p.outer.pop_back();
    if (signed_area(p.outer) < 0) std::reverse(p.outer.begin(), p.outer.end());
    return p;
  }
  throw ArgError{arg, "profile (polygon, rect or closed curve) expected, got " + type_name(L, arg)};
}

// extrude(profile, h [, {twist=0, scale=1}])
int extrude_fn(lua_State* L) {
  return guarded(L, [&] {
    Profile p = check_profile(L, 1);
    double h = check_number(L, 2);
    if (!(h > 0)) throw ArgError{2, "height must be positive, got " + std::to_string(h)};
    double twist = 0, k = 1;
    if (!lua_isnoneornil(L, 3)) {
      Options o(L, 3);
      twist = o.number("twist", 0);
      k = o.number("scale", 1);
      o.finish();
    }
    if (twist != 0)
      throw ArgError{3, "twist is not supported yet: a twisted extrude has non-planar side faces, and the B-Rep "
                        "builds planar extrudes only (use swept_surface for twisted shapes)"};
    if (!(k >= 0)) throw ArgError{3, "field 'scale' must be zero or positive, got " + std::to_string(k)};
    if (k == 1) {
      push_solid(L, prism_solid(p, h));
    } else {
      if (!p.holes.empty()) throw ArgError{3, "a scaled extrude of a profile with holes is not supported yet"};
      push_solid(L, brep_solid(frustum(p.outer, h, k, Vec2::Zero())));
    }
    return 1;
  });
}

int area_m(lua_State* L) {
  return guarded(L, [&] {
    const Profile& p = check_object<Profile>(L, 1, kKey, "Profile");
    double a = std::abs(signed_area(p.outer));
    for (const auto& h : p.holes) a -= std::abs(signed_area(h));
    lua_pushnumber(L, a);
    return 1;
  });
}

int tostring_m(lua_State* L) {
  return guarded(L, [&] {
    const Profile& p = check_object<Profile>(L, 1, kKey, "Profile");
    std::string s = "Profile(" + std::to_string(p.outer.size()) + " points, " + std::to_string(p.holes.size()) + " holes)";
    lua_pushstring(L, s.c_str());
    return 1;
  });
}

const luaL_Reg kFunctions[] = {{"polygon", polygon_fn}, {"rect", rect_fn}, {"extrude", extrude_fn}, {nullptr, nullptr}};
const luaL_Reg kMethods[] = {{"area", area_m}, {nullptr, nullptr}};
const luaL_Reg kMeta[] = {{"__tostring", tostring_m}, {nullptr, nullptr}};

}  // namespace

void register_profiles(lua_State* L) {
  register_class(L, kKey, "Profile", kMethods, kMeta, gc_object<Profile>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
