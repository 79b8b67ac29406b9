// Lua bindings of 2D profiles and the solids built from them: polygon{}, rect(), extrude(),
// revolve(), sweep(), loft{}, and the curved primitives sphere, cylinder, cone, torus, tube.
// A profile is a polygon with holes in the XY plane (brep/brep.h's Profile), or a closed Curve
// (such as circle(r)), which is used exactly: its solid's side faces lie on the exact swept
// surface (brep/curved.cpp). A polygon extruded straight (no twist, no scale) stays the planar
// prism of brep/build.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

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
// `what` names the ring in messages about the whole ring ("field 'outer'", "the outer ring"); its
// points are named by path when `what` is a field ("field 'outer[2]'"), else "point 2".
std::vector<Vec2> read_ring(lua_State* L, int idx, int arg, const std::string& what) {
  idx = lua_absindex(L, idx);
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{arg, what + " must be a list of points {x, y}, got " + type_name(L, idx)};
  const bool field = what.rfind("field '", 0) == 0;
  std::vector<Vec2> ring;
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    std::string err;
    try {
      ring.push_back(to_vec2(L, -1, arg, field ? element_name(what, i, "point") : "point " + std::to_string(i)));
    } catch (const ArgError& e) {
      err = e.message;
    }
    lua_pop(L, 1);
    if (!err.empty()) throw ArgError{arg, err};
  }
  // A closing point equal to the first is allowed and dropped.
  if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
  if (ring.size() < 3) throw ArgError{arg, what + " needs at least 3 points, got " + std::to_string(ring.size())};
  // Zero area: collinear points, or a ring that crosses itself so that its parts cancel (a bow
  // tie), which the profile's own checks then name with the edges that cross.
  if (std::abs(signed_area(ring)) == 0) {
    std::size_t b = 1;
    while (b < ring.size() && ring[b] == ring[0]) ++b;
    bool collinear = true;
    for (std::size_t i = b + 1; i < ring.size() && collinear; ++i)
      collinear = (ring[b] - ring[0]).x() * (ring[i] - ring[0]).y() == (ring[b] - ring[0]).y() * (ring[i] - ring[0]).x();
    if (collinear) throw ArgError{arg, what + " has zero area (its points are collinear)"};
  }
  return ring;
}

// A profile as Lua holds it: polygons, and holes that are closed curves (circle(r), a closed
// spline), kept exact for the curved builders. `polygon.holes` ends with each curve hole's polyline
// (at the tolerance current when the profile was made), for the planar paths and for checks.
struct LuaProfile {
  Profile polygon;
  std::vector<CurvePtr> curve_holes;
  std::size_t polygon_holes() const { return polygon.holes.size() - curve_holes.size(); }
};

LuaProfile& push_profile(lua_State* L, Profile p, std::vector<CurvePtr> curve_holes = {}) {
  as_arg(1, [&] { validate_profile(p); });  // the error points at the line that made the profile
  if (signed_area(p.outer) < 0) std::reverse(p.outer.begin(), p.outer.end());
  for (auto& h : p.holes)
    if (signed_area(h) > 0) std::reverse(h.begin(), h.end());
  return push_object(L, kKey, LuaProfile{std::move(p), std::move(curve_holes)});
}

// A closed planar curve at stack index idx as a polyline ring (argument `arg`, named `what`).
std::vector<Vec2> curve_ring(lua_State* L, const Curve& c, int arg, const std::string& what) {
  if (!c.closed()) throw ArgError{arg, what + " is an open curve: a hole must be closed"};
  std::vector<Vec2> ring;
  for (const auto& q : c.points(current_tolerance(L).chordal)) {
    if (std::abs(q.z()) > 1e-12) throw ArgError{arg, what + " leaves the XY plane: a profile must be planar"};
    ring.emplace_back(q.x(), q.y());
  }
  if (ring.size() > 1 && (ring.front() - ring.back()).norm() < 1e-12) ring.pop_back();
  if (ring.size() < 3) throw ArgError{arg, what + " is too small for the tolerance"};
  return ring;
}

// The closed planar curve c as a polyline ring at tolerance `tol` (no check of the plane).
std::vector<Vec2> curve_polyline(const Curve& c, double tol) {
  std::vector<Vec2> ring;
  for (const auto& q : c.points(tol)) ring.emplace_back(q.x(), q.y());
  if (ring.size() > 1 && (ring.front() - ring.back()).norm() < 1e-12) ring.pop_back();
  return ring;
}

double segment_distance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto point_segment = [](const Vec2& p, const Vec2& u, const Vec2& v) {
    const Vec2 e = v - u;
    const double l = e.squaredNorm(), t = l > 0 ? std::clamp((p - u).dot(e) / l, 0.0, 1.0) : 0.0;
    return (p - (u + t * e)).norm();
  };
  return std::min({point_segment(a, c, d), point_segment(b, c, d), point_segment(c, a, b), point_segment(d, a, b)});
}

// validate_profile() for a profile some of whose rings are closed curves (rings[i] for each
// curves[i], 0 the outer ring), judged by the exact curves rather than by their polylines. A
// polyline at tolerance t is within t of its curve, so a curve's polyline at a distance d > t
// (2t from another curve's) from the other rings proves the exact curve clear of them; nearer,
// the curves are sampled again at a quarter of that distance, until a crossing shows in the
// polylines or the distance falls to a rounding of the profile's size (touching). Checked on the
// polylines at the current tolerance alone, a circle hole whose polyline fitted inside a ring of
// 1.001 times its radius was accepted although the circle crosses every edge of the ring by up to
// 0.009, and the solid built from the exact circle then failed to tessellate.
void validate_curve_profile(Profile p, const std::vector<std::pair<std::size_t, CurvePtr>>& curves, double tol) {
  validate_profile(p);
  double size = 0;
  for (const Vec2& q : p.outer) size = std::max(size, q.cwiseAbs().maxCoeff());
  auto ring = [&](std::size_t r) -> std::vector<Vec2>& { return r == 0 ? p.outer : p.holes[r - 1]; };
  auto is_curve = [&](std::size_t r) {
    for (const auto& c : curves)
      if (c.first == r) return true;
    return false;
  };
  for (int round = 0; round < 64; ++round) {
    double worst = std::numeric_limits<double>::infinity();  // the least distance over the margin
    std::size_t near_a = 0, near_b = 0;
    for (const auto& [r, curve] : curves)
      for (std::size_t k = 0; k <= p.holes.size(); ++k) {
        if (k == r || (is_curve(k) && k < r)) continue;
        const double margin = is_curve(k) ? 2 * tol : tol;
        const auto &x = ring(r), &y = ring(k);
        for (std::size_t i = 0; i < x.size(); ++i) {
          const Vec2 &a = x[i], &b = x[(i + 1) % x.size()];
          const Vec2 lo = a.cwiseMin(b).array() - margin, hi = a.cwiseMax(b).array() + margin;
          for (std::size_t j = 0; j < y.size(); ++j) {
            const Vec2 &c = y[j], &d = y[(j + 1) % y.size()];
            if (std::max(c.x(), d.x()) < lo.x() || std::min(c.x(), d.x()) > hi.x() || std::max(c.y(), d.y()) < lo.y() ||
                std::min(c.y(), d.y()) > hi.y())
              continue;
            const double dist = segment_distance(a, b, c, d);
            if (dist <= margin && dist / margin < worst) worst = dist / margin, near_a = std::min(r, k), near_b = std::max(r, k);
          }
        }
      }
    if (worst == std::numeric_limits<double>::infinity()) return;
    if (tol <= 1e-12 * size) {
      if (near_a == 0) fail("hole ", near_b, " touches or crosses the outer ring (a hole must lie strictly inside it)");
      fail("holes ", near_a, " and ", near_b, " touch or cross each other");
    }
    tol = std::max(tol * std::max(worst, 1e-3) / 4, 1e-12 * size);
    for (const auto& [r, curve] : curves) ring(r) = curve_polyline(*curve, tol);
    validate_profile(p);
  }
}

// polygon{{x,y}, ...} | polygon{points={...}} | polygon{outer={...}, holes={{...}, ...}}; the bare
// list may have holes= too. A bad field is named by its path: "polygon: holes[1][2][2] must be a
// number, got boolean".
int polygon_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    check_table(L, 1);
    Profile p;
    std::vector<CurvePtr> curves;
    Options o(L, 1);
    // points= is the long form of the bare list (API.md: "a bare list of points is the shorthand
    // for points="), and may have holes as outer= does.
    const bool has_outer = o.has("outer"), has_points = o.has("points");
    if (has_outer && has_points) throw ArgError{1, "give the outer ring as points= or as outer=, not both"};
    std::string err;
    if (!has_outer && !has_points) {
      o.allow_positional();
      p.outer = read_ring(L, 1, 1, "the outer ring");
    } else {
      const char* outer_key = has_points ? "points" : "outer";
      if (lua_rawlen(L, 1) > 0) throw ArgError{1, std::string("give the outer ring as a bare list or as ") + outer_key + "=, not both"};
      o.push(outer_key);
      try {
        p.outer = read_ring(L, -1, 1, std::string("field '") + outer_key + "'");
      } catch (const ArgError& e) {
        err = e.message;
      }
      lua_pop(L, 1);
      if (!err.empty()) throw ArgError{1, err};
    }
    if (o.push("holes") != LUA_TNIL) {
      int holes = lua_gettop(L);
      try {
        if (lua_type(L, holes) != LUA_TTABLE)
          throw ArgError{1, "field 'holes' must be a list of polygons or closed curves, got " + type_name(L, holes)};
        lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, holes));
        std::vector<std::vector<Vec2>> curve_rings;
        for (lua_Integer i = 1; i <= n; ++i) {
          lua_rawgeti(L, holes, i);
          const std::string name = "field 'holes[" + std::to_string(i) + "]'";
          if (const LuaCurve* c = test_curve(L, -1)) {
            curve_rings.push_back(curve_ring(L, *c->curve, 1, name));
            curves.push_back(c->curve);
          } else {
            p.holes.push_back(read_ring(L, -1, 1, name));
          }
          lua_pop(L, 1);
        }
        p.holes.insert(p.holes.end(), curve_rings.begin(), curve_rings.end());
      } catch (const ArgError& e) {
        err = e.message;
      }
      lua_settop(L, holes);
    }
    lua_pop(L, 1);
    if (!err.empty()) throw ArgError{1, err};
    o.finish();
    if (!curves.empty()) {
      std::vector<std::pair<std::size_t, CurvePtr>> exact;
      for (std::size_t i = 0; i < curves.size(); ++i) exact.emplace_back(p.holes.size() - curves.size() + i + 1, curves[i]);
      as_arg(1, [&] { validate_curve_profile(p, exact, current_tolerance(L).chordal); });
    }
    push_profile(L, std::move(p), std::move(curves));
    return 1;
  });
}

// rect(w, h [, center])
int rect_fn(lua_State* L) {
  return guarded(L, [&] {
    double w = check_number(L, 1), h = check_number(L, 2);
    if (!(w > 0)) throw ArgError{1, "width must be positive, got " + number_text(w)};
    if (!(h > 0)) throw ArgError{2, "height must be positive, got " + number_text(h)};
    // As box(): within 1e-100..1e100, so that the area neither underflows nor overflows.
    if (w < 1 / kMaxCoordinate) throw ArgError{1, "width " + number_text(w) + " is below 1e-100 (the area would underflow to zero)"};
    if (h < 1 / kMaxCoordinate) throw ArgError{2, "height " + number_text(h) + " is below 1e-100 (the area would underflow to zero)"};
    bool center = lua_isnoneornil(L, 3) ? false : check_boolean(L, 3);
    check_no_more(L, 3);
    Vec2 o = center ? Vec2(-w / 2, -h / 2) : Vec2(0, 0);
    push_profile(L, Profile{{o, o + Vec2(w, 0), o + Vec2(w, h), o + Vec2(0, h)}, {}});
    return 1;
  });
}

// Refuses a closed curve profile that crosses itself (a closed Catmull-Rom figure eight), as
// polygon{} refuses a bow tie. The planar caps of extrude, loft, sweep and a partial revolve
// happened to refuse it ("loop intersects itself"); a full revolve has no caps, and gave a "valid"
// solid whose volume was the signed sum of the lobes' (39.80 = 64.52 - 24.73). The crossing of two
// stretches of the curve is a crossing of its polyline at the current tolerance.
void require_simple_curve(lua_State* L, const Curve& c, int arg) {
  try {
    validate_profile(Profile{curve_polyline(c, current_tolerance(L).chordal), {}});
  } catch (const Error&) {
    throw ArgError{arg, "the curve intersects itself: a profile must be a simple closed curve"};
  }
}

// The profile at argument `arg`: a Profile, or a closed planar Curve as its polyline.
Profile check_profile(lua_State* L, int arg) {
  if (const LuaProfile* p = test_object<LuaProfile>(L, arg, kKey)) return p->polygon;
  if (const LuaCurve* c = test_curve(L, arg)) {
    if (!c->curve->closed()) throw ArgError{arg, "the curve is open: a profile must be a closed curve"};
    std::vector<Point3> pts = c->curve->points(current_tolerance(L).chordal);
    Profile p;
    for (const auto& q : pts) {
      if (std::abs(q.z()) > 1e-12) throw ArgError{arg, "the curve leaves the XY plane: a profile must be planar"};
      p.outer.emplace_back(q.x(), q.y());
    }
    if (p.outer.size() > 1 && (p.outer.front() - p.outer.back()).norm() < 1e-12) p.outer.pop_back();
    require_simple_curve(L, *c->curve, arg);
    if (signed_area(p.outer) < 0) std::reverse(p.outer.begin(), p.outer.end());
    return p;
  }
  throw ArgError{arg, "profile (polygon, rect or closed curve) expected, got " + type_name(L, arg)};
}

// The exact section of a profile argument: a Profile's polygons, or a closed curve split in two.
Section check_section(lua_State* L, int arg) {
  if (const LuaProfile* p = test_object<LuaProfile>(L, arg, kKey)) {
    Profile polygons = p->polygon;
    polygons.holes.resize(p->polygon_holes());
    Section s = section_of(polygons);
    for (const auto& c : p->curve_holes) s.holes.push_back(loop_of_curve(c));
    return s;
  }
  if (const LuaCurve* c = test_curve(L, arg)) {
    if (!c->curve->closed()) throw ArgError{arg, "the curve is open: a profile must be a closed curve"};
    auto [a, b] = c->curve->domain();
    for (int i = 0; i <= 16; ++i)
      if (std::abs(c->curve->eval(a + (b - a) * i / 16).z()) > 1e-12)
        throw ArgError{arg, "the curve leaves the XY plane: a profile must be planar"};
    require_simple_curve(L, *c->curve, arg);
    return Section{loop_of_curve(c->curve), {}};
  }
  throw ArgError{arg, "profile (polygon, rect or closed curve) expected, got " + type_name(L, arg)};
}

// Runs a kernel builder, turning its wedge::Error into an error of argument `arg`.
template <class F>
Model build(int arg, F&& f) {
  return as_arg(arg, std::forward<F>(f));
}

// extrude(profile, h [, {twist=0, scale=1}])
int extrude_fn(lua_State* L) {
  return table_call(L, 3, [&] {
    Profile p = check_profile(L, 1);
    double h = check_number(L, 2);
    if (!(h > 0)) throw ArgError{2, "height must be positive, got " + number_text(h)};
    double twist = 0, k = 1;
    if (!lua_isnoneornil(L, 3)) {
      Options o(L, 3);
      twist = o.number("twist", 0);
      k = o.number("scale", 1);
      o.finish();
    }
    if (!(k >= 0)) throw ArgError{3, "field 'scale' must be zero or positive, got " + number_text(k)};
    if (!(std::abs(twist) <= 36000))
      throw ArgError{3, "field 'twist' must be within -36000..36000 degrees (100 turns), got " + number_text(twist)};
    // A polygon (no curve holes) extruded straight stays the planar prism or frustum.
    const LuaProfile* lp = test_object<LuaProfile>(L, 1, kKey);
    bool polygon = lp != nullptr && lp->curve_holes.empty();
    if (!polygon || twist != 0) {
      Section s = check_section(L, 1);
      push_solid(L, brep_solid(build(1, [&] { return extrude(s, h, radians(twist), k); })));
    } else if (k == 1) {
      push_solid(L, prism_solid(p, h));
    } else if (p.holes.empty()) {
      // (A scale so small that the top face has no area in doubles, 1e-300, was reported as
      // "polyhedron: face 2 has zero area", naming no argument.)
      try {
        push_solid(L, brep_solid(frustum(p.outer, h, k, Vec2::Zero())));
      } catch (const Error& e) {
        throw ArgError{3, "field 'scale' = " + number_text(k) + ": " + e.what()};
      }
    } else {
      // Holes scale with the outer ring: the exact sweep (planar sides on the scaled extrusion).
      Section s = check_section(L, 1);
      push_solid(L, brep_solid(build(1, [&] { return extrude(s, h, 0, k); })));
    }
    return 1;
  });
}

int area_m(lua_State* L) {
  return guarded(L, [&] {
    const Profile& p = check_object<LuaProfile>(L, 1, kKey, "Profile").polygon;
    double a = std::abs(signed_area(p.outer));
    for (const auto& h : p.holes) a -= std::abs(signed_area(h));
    lua_pushnumber(L, a);
    return 1;
  });
}

int tostring_m(lua_State* L) {
  return guarded(L, [&] {
    const LuaProfile& lp = check_object<LuaProfile>(L, 1, kKey, "Profile");
    std::string s = "Profile(" + std::to_string(lp.polygon.outer.size()) + " points, " + std::to_string(lp.polygon.holes.size()) + " holes";
    if (!lp.curve_holes.empty()) s += ", " + std::to_string(lp.curve_holes.size()) + " of them curves";
    s += ")";
    lua_pushstring(L, s.c_str());
    return 1;
  });
}

// revolve(profile [, {angle=360}]): OpenSCAD's rotate_extrude (x the radius, y becomes z).
int revolve_fn(lua_State* L) {
  return table_call(L, 2, [&] {
    Section s = check_section(L, 1);
    double angle = 360;
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      angle = o.number("angle", 360);
      o.finish();
    }
    if (!(angle > 0 && angle <= 360)) throw ArgError{2, "field 'angle' must be in (0, 360] degrees, got " + number_text(angle)};
    // A whole turn is symmetric about the z axis.
    Symmetry sym;
    if (angle == 360) sym.kind = Symmetry::Kind::Axis;
    push_solid(L, brep_solid(build(1, [&] { return revolve(s, radians(angle)); }), sym));
    return 1;
  });
}

// sweep(profile, path): the profile along a 3D curve with rotation-minimising frames.
int sweep_fn(lua_State* L) {
  return guarded(L, [&] {
    Section s = check_section(L, 1);
    const LuaCurve& path = check_curve(L, 2);
    check_no_more(L, 2);
    // A corner is the path's fault, whatever the profile.
    as_arg(2, [&] { require_smooth_path(*path.curve); });
    push_solid(L, brep_solid(build(1, [&] { return sweep_along(s, path.curve); })));
    return 1;
  });
}

// loft{profiles={p1, p2, ...}, heights={z1, z2, ...}}
int loft_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    std::vector<Section> sections;
    std::vector<double> heights;
    if (o.push("profiles") != LUA_TTABLE)
      throw ArgError{1, "field 'profiles' must be a list of profiles (polygon, rect or closed curve), got " + type_name(L, -1)};
    int t = lua_gettop(L);
    for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, t)); i <= n; ++i) {
      lua_rawgeti(L, t, i);
      try {
        sections.push_back(check_section(L, lua_gettop(L)));
      } catch (const ArgError& e) {
        // check_section names the stack slot; the profile is element i of field 'profiles'.
        std::string m = e.message;
        if (m.rfind("profile (", 0) == 0) m = "must be a profile (polygon, rect or closed curve), got " + type_name(L, -1);
        else if (m.rfind("the curve ", 0) == 0) m = m.substr(4);
        throw ArgError{1, "field 'profiles[" + std::to_string(i) + "]' " + m};
      }
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    if (o.push("heights") != LUA_TTABLE) throw ArgError{1, "field 'heights' must be a list of numbers, got " + type_name(L, -1)};
    t = lua_gettop(L);
    for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, t)); i <= n; ++i) {
      const std::string name = "field 'heights[" + std::to_string(i) + "]'";
      if (lua_rawgeti(L, t, i) != LUA_TNUMBER) throw ArgError{1, name + " must be a number, got " + type_name(L, -1)};
      const double z = lua_tonumber(L, -1);
      if (!std::isfinite(z)) throw ArgError{1, name + " must be finite, got " + number_text(z)};
      if (std::abs(z) > kMaxCoordinate)
        throw ArgError{1, name + " is " + number_text(z) + ", beyond +-" + number_text(kMaxCoordinate)};
      heights.push_back(z);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    o.finish();
    push_solid(L, brep_solid(build(1, [&] { return loft(sections, heights); })));
    return 1;
  });
}

// A size argument: a finite number > 0.
double positive_arg(double x, int arg, const char* what) {
  if (!(x > 0) || !std::isfinite(x)) throw ArgError{arg, std::string(what) + " must be positive, got " + number_text(x)};
  return x;
}

// The curved primitives take numbers or one table. In the table form a bad field is named by its
// key ("sphere: r must be positive, got -1", "torus: r must be less than R (1), got 2"); in the
// positional form by its argument number and what it is ("bad argument #1 to 'sphere' (radius r
// must be positive, got -1)").
struct Sizes {
  lua_State* L;
  std::optional<Options> o;
  explicit Sizes(lua_State* L) : L(L) {
    if (lua_type(L, 1) == LUA_TTABLE) o.emplace(L, 1);
  }
  bool table() const { return o.has_value(); }
  // Field `key` (table form) or argument `arg` (positional; absent when arg is 0), > 0.
  double positive(const char* key, int arg, double fallback, const char* what) {
    if (o) return o->positive(key, fallback);
    return positive_arg(arg ? check_number(L, arg) : fallback, arg ? arg : 1, what);
  }
  double non_negative(const char* key, int arg, double fallback, const char* what) {
    const double x = o ? o->number(key, fallback) : check_number(L, arg);
    if (!(x >= 0))
      throw ArgError{o ? 1 : arg, (o ? "field '" + std::string(key) + "'" : std::string(what)) + " must be >= 0, got " + number_text(x)};
    return x;
  }
  // "r" or "minor radius r", as the message names it.
  std::string name(const char* key, const char* what) const { return o ? key : what; }
  // The table's unknown fields, or (positional) an argument past the `positional` it takes.
  void finish(int positional, const char* table_form) {
    if (o) o->finish();
    check_no_more(L, o ? 1 : positional, table_form);
  }
};

// sphere(r) | sphere{r=1, center={0,0,0}}
int sphere_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Sizes z(L);
    const double r = z.positive("r", 1, 1, "radius r");
    const Vec3 c = z.table() ? z.o->vec3("center", Vec3::Zero(), true) : Vec3::Zero();
    z.finish(1, "sphere{r=r, center={x, y, z}}");
    push_solid(L, brep_solid(build(1, [&] { return sphere(r, c); }), Symmetry{Symmetry::Kind::Point, Point3(c), Vec3::UnitZ(), false}));
    return 1;
  });
}

// cylinder(r, h) | cylinder{r=1, h=1, center=false}: axis +Z, base at z = 0 unless center.
int cylinder_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Sizes z(L);
    const double r = z.positive("r", 1, 1, "radius r");
    const double h = z.positive("h", 2, 1, "height h");
    const bool center = z.table() && z.o->boolean("center", false);
    z.finish(2, "cylinder{r=r, h=h, center=true}");
    push_solid(L, brep_solid(build(1, [&] { return cylinder(r, h, Point3(0, 0, center ? -h / 2 : 0)); }),
                             Symmetry{Symmetry::Kind::Axis, Point3(0, 0, center ? 0 : h / 2), Vec3::UnitZ(), true}));
    return 1;
  });
}

// cone{r1=1, r2=0, h=1, center=false} | cone(r1, r2, h)
int cone_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Sizes z(L);
    const double r1 = z.non_negative("r1", 1, 1, "radius r1");
    const double r2 = z.non_negative("r2", 2, 0, "radius r2");
    const double h = z.positive("h", 3, 1, "height h");
    const bool center = z.table() && z.o->boolean("center", false);
    z.finish(3, "cone{r1=r1, r2=r2, h=h, center=true}");
    if (r1 == 0 && r2 == 0) throw ArgError{1, "radii r1 and r2 must not both be 0"};
    push_solid(L, brep_solid(build(1, [&] { return cone(r1, r2, h, Point3(0, 0, center ? -h / 2 : 0)); }),
                             Symmetry{Symmetry::Kind::Axis, Point3(0, 0, center ? 0 : h / 2), Vec3::UnitZ(), r1 == r2}));
    return 1;
  });
}

// torus{R=2, r=0.5, center={0,0,0}} | torus(R, r): in the XY plane.
int torus_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Sizes z(L);
    const double R = z.positive("R", 1, 2, "major radius R");
    const double r = z.positive("r", 2, 0.5, "minor radius r");
    const Vec3 c = z.table() ? z.o->vec3("center", Vec3::Zero(), true) : Vec3::Zero();
    z.finish(2, "torus{R=R, r=r, center={x, y, z}}");
    if (!(r < R))
      throw ArgError{z.table() ? 1 : 2, z.name("r", "minor radius r") + " must be less than " + z.name("R", "major radius R") + " (" +
                                            number_text(R) + "), got " + number_text(r)};
    push_solid(L, brep_solid(build(1, [&] { return torus(R, r, c); }), Symmetry{Symmetry::Kind::Axis, Point3(c), Vec3::UnitZ(), true}));
    return 1;
  });
}

// tube{r_outer=2, r_inner=1, h=1, center=false} | tube(r_outer, r_inner, h)
int tube_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Sizes z(L);
    const double ro = z.positive("r_outer", 1, 2, "outer radius r_outer");
    const double ri = z.positive("r_inner", 2, 1, "inner radius r_inner");
    const double h = z.positive("h", 3, 1, "height h");
    const bool center = z.table() && z.o->boolean("center", false);
    z.finish(3, "tube{r_outer=ro, r_inner=ri, h=h, center=true}");
    if (!(ri < ro))
      throw ArgError{z.table() ? 1 : 2, z.name("r_inner", "inner radius r_inner") + " must be less than " +
                                            z.name("r_outer", "outer radius r_outer") + " (" + number_text(ro) + "), got " +
                                            number_text(ri)};
    push_solid(L, brep_solid(build(1, [&] { return tube(ro, ri, h, Point3(0, 0, center ? -h / 2 : 0)); }),
                             Symmetry{Symmetry::Kind::Axis, Point3(0, 0, center ? 0 : h / 2), Vec3::UnitZ(), true}));
    return 1;
  });
}

const luaL_Reg kFunctions[] = {{"polygon", polygon_fn},   {"rect", rect_fn},         {"extrude", extrude_fn},
                               {"revolve", revolve_fn},   {"sweep", sweep_fn},       {"loft", loft_fn},
                               {"sphere", sphere_fn},     {"cylinder", cylinder_fn}, {"cone", cone_fn},
                               {"torus", torus_fn},       {"tube", tube_fn},         {nullptr, nullptr}};
const luaL_Reg kMethods[] = {{"area", area_m}, {nullptr, nullptr}};
const luaL_Reg kMeta[] = {{"__tostring", tostring_m}, {nullptr, nullptr}};

}  // namespace

void register_profiles(lua_State* L) {
  register_class(L, kKey, "Profile", kMethods, kMeta, gc_object<LuaProfile>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
