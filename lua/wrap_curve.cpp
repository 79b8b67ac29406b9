// Lua bindings of the curves of surfaces/: bezier, bspline, nurbs, interpolate, catmull_rom,
// natural_spline, hermite, polynomial, circle, and the Curve methods. Curve parameters are normalised: t runs over
// [0, 1] for every kind of curve, whatever its own domain.
#include <cmath>
#include <sstream>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_curve.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Curve";


// Reads the list of points at the top of the stack (value of argument `arg`). `what` is the field
// ("field 'points'"), whose elements are named by path ("field 'points[2]'"), or empty for the
// bare list, whose elements are "point 2".
std::vector<Point3> read_points_top(lua_State* L, int arg, const std::string& what, bool& planar,
                                    const std::string& item = "point") {
  if (lua_type(L, -1) != LUA_TTABLE)
    throw ArgError{arg, (what.empty() ? "the list of " + item + "s" : what) + " must be a list of " + item + "s, got " + type_name(L, -1)};
  std::vector<Point3> pts;
  lua_Integer n = lua_Integer(lua_rawlen(L, -1));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    std::string err;
    Point3 p;
    const std::string name = what.empty() ? item + " " + std::to_string(i) : element_name(what, i, item.c_str());
    if (lua_type(L, -1) != LUA_TTABLE) err = name + " must be {x, y} or {x, y, z}, got " + type_name(L, -1);
    else {
      if (lua_Integer(lua_rawlen(L, -1)) >= 3) planar = false;
      try {
        p = to_vec3(L, -1, arg, name, true);
      } catch (const ArgError& e) {
        err = e.message;
      }
    }
    lua_pop(L, 1);
    if (!err.empty()) throw ArgError{arg, err};
    pts.push_back(p);
  }
  return pts;
}

// The points of a curve constructor's table: points=..., or t[1] as the list, or the array part
// itself (the bare-list shorthand bezier{{0,0},{1,2},{3,0}}).
std::vector<Point3> read_points(lua_State* L, Options& o, bool& planar) {
  planar = true;
  if (o.has("points")) {
    o.push("points");
    auto pts = read_points_top(L, o.arg(), "field 'points'", planar);
    lua_pop(L, 1);
    return pts;
  }
  o.allow_positional();
  int idx = lua_absindex(L, o.arg());
  lua_rawgeti(L, idx, 1);
  bool nested = false;
  if (lua_type(L, -1) == LUA_TTABLE) {
    lua_rawgeti(L, -1, 1);
    nested = lua_type(L, -1) == LUA_TTABLE;
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  if (nested) {
    lua_rawgeti(L, idx, 1);
    auto pts = read_points_top(L, o.arg(), "", planar);
    lua_pop(L, 1);
    return pts;
  }
  lua_pushvalue(L, idx);
  auto pts = read_points_top(L, o.arg(), "", planar);
  lua_pop(L, 1);
  return pts;
}

std::vector<double> read_numbers(lua_State* L, Options& o, const char* key) {
  std::vector<double> out;
  int t = o.push(key);
  std::string err;
  const std::string name = "field '" + o.field(key) + "'";
  if (t != LUA_TTABLE) err = name + " must be a list of numbers, got " + type_name(L, -1);
  else {
    lua_Integer n = lua_Integer(lua_rawlen(L, -1));
    for (lua_Integer i = 1; i <= n && err.empty(); ++i) {
      int ti = lua_rawgeti(L, -1, i);
      double x = lua_tonumber(L, -1);
      const std::string entry = element_name(name, i, "entry");
      if (ti != LUA_TNUMBER) err = entry + " must be a number, got " + type_name(L, -1);
      else if (!std::isfinite(x)) err = entry + " must be finite, got " + number_text(x);
      lua_pop(L, 1);
      out.push_back(x);
    }
  }
  lua_pop(L, 1);
  if (!err.empty()) throw ArgError{o.arg(), err};
  return out;
}

void push_point(lua_State* L, const Point3& p, bool planar) {
  if (planar) push_vec2(L, p.head<2>());
  else push_vec3(L, p);
}

// t in [0, 1] -> the curve's own parameter.
double curve_param(lua_State* L, const Curve& c, int idx) {
  double t = check_number(L, idx);
  if (t < -1e-12 || t > 1 + 1e-12) throw ArgError{idx, "parameter t must be in [0, 1], got " + number_text(t)};
  auto [a, b] = c.domain();
  return a + std::clamp(t, 0.0, 1.0) * (b - a);
}

int bezier_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    o.finish();
    push_curve(L, {as_arg(1, [&] { return std::make_shared<const BezierCurve>(pts); }), planar});
    return 1;
  });
}

int bspline_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    int degree = o.integer("degree", 3);
    std::vector<double> knots;
    if (o.has("knots")) knots = read_numbers(L, o, "knots");
    std::vector<double> weights;
    if (o.has("weights")) weights = read_numbers(L, o, "weights");
    o.finish();
    auto c = as_arg(1, [&] {
      if (knots.empty()) knots = open_uniform_knots(degree, pts.size());
      return std::make_shared<const NurbsCurve>(degree, pts, knots, weights);
    });
    push_curve(L, {c, planar});
    return 1;
  });
}

int interpolate_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    int degree = o.integer("degree", 3);
    o.finish();
    push_curve(L, {as_arg(1, [&] { return std::make_shared<const NurbsCurve>(interpolate_nurbs(pts, degree)); }), planar});
    return 1;
  });
}

int catmull_rom_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    bool closed = o.boolean("closed", false);
    double t = o.number("tension", 0), b = o.number("bias", 0), c = o.number("continuity", 0);
    o.finish();
    push_curve(L, {as_arg(1, [&] { return std::make_shared<const HermiteSpline>(kochanek_bartels(pts, t, b, c, closed)); }), planar});
    return 1;
  });
}

int natural_spline_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    o.finish();
    push_curve(L, {as_arg(1, [&] { return std::make_shared<const HermiteSpline>(natural_spline(pts)); }), planar});
    return 1;
  });
}

// hermite{points=, tangents=[, params=]}: the cubic Hermite spline through the points with the
// given derivatives (at parameters 0, 1, ..., n-1 unless params= gives increasing ones).
int hermite_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    if (!o.has("tangents")) throw ArgError{o.arg(), "field 'tangents' is required: one tangent per point"};
    o.push("tangents");
    bool tangents_planar = true;
    auto tangents = read_points_top(L, o.arg(), "field 'tangents'", tangents_planar, "tangent");
    lua_pop(L, 1);
    std::vector<double> params;
    if (o.has("params")) params = read_numbers(L, o, "params");
    o.finish();
    if (pts.size() < 2) throw ArgError{o.arg(), "a Hermite spline needs at least 2 points, got " + std::to_string(pts.size())};
    if (tangents.size() != pts.size())
      throw ArgError{o.arg(), "field 'tangents' needs one per point (" + std::to_string(pts.size()) + " points), got " + std::to_string(tangents.size())};
    if (!params.empty() && params.size() != pts.size())
      throw ArgError{o.arg(), "field 'params' needs one per point (" + std::to_string(pts.size()) + " points), got " + std::to_string(params.size())};
    if (params.empty())
      for (std::size_t i = 0; i < pts.size(); ++i) params.push_back(double(i));
    std::vector<Vec3> d(tangents.begin(), tangents.end());
    push_curve(L, {as_arg(1, [&] { return std::make_shared<const HermiteSpline>(params, pts, d); }), planar && tangents_planar});
    return 1;
  });
}

// polynomial{points}: the interpolating polynomial of degree n-1 (Neville), to show Runge's wiggles.
int polynomial_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    bool planar;
    auto pts = read_points(L, o, planar);
    o.finish();
    push_curve(L, {as_arg(1, [&] { return std::make_shared<const PolynomialInterpolant>(pts); }), planar});
    return 1;
  });
}

// circle(r) | circle{r=1, center={0,0}}: the exact rational circle in the XY plane.
int circle_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    double r;
    Vec3 center = Vec3::Zero();
    bool planar = true;
    if (lua_type(L, 1) == LUA_TTABLE) {
      Options o(L, 1);
      r = o.positive("r", 1);
      if (auto c = o.vec3("center", true)) {
        center = *c;
        planar = center.z() == 0;
      }
      o.finish();
    } else {
      r = check_number(L, 1);
      check_no_more(L, 1);
    }
    if (!(r > 0)) throw ArgError{1, "radius must be positive, got " + number_text(r)};
    // As rect(): a disc whose area would underflow to zero is no profile.
    if (r < 1 / 1e100) throw ArgError{1, "radius " + number_text(r) + " is below 1e-100 (the area would underflow to zero)"};
    push_curve(L, {std::make_shared<const NurbsCurve>(nurbs_circle(center, r)), planar});
    return 1;
  });
}

// --- methods ---

int eval_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    check_no_more_method(L, 2);
    push_point(L, c.curve->eval(curve_param(L, *c.curve, 2)), c.planar);
    return 1;
  });
}

int tangent_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    check_no_more_method(L, 2);
    const Vec3 t = c.curve->tangent(curve_param(L, *c.curve, 2));
    // A curve whose points coincide there does not move: {0, 0, 0} is no direction.
    if (t == Vec3::Zero() || !t.allFinite()) fail("the curve has no tangent at t = ", number_text(lua_tonumber(L, 2)), ": it does not move there (its points coincide)");
    push_point(L, t, c.planar);
    return 1;
  });
}

// c:derivative(t, k): d^k C / dt^k for the normalised t.
int derivative_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    check_no_more_method(L, 3);
    double t = curve_param(L, *c.curve, 2);
    int k = lua_isnoneornil(L, 3) ? 1 : check_integer(L, 3);
    if (k < 0) throw ArgError{3, "derivative order must be >= 0, got " + std::to_string(k)};
    auto [a, b] = c.curve->domain();
    push_point(L, c.curve->derivative(t, k) * std::pow(b - a, k), c.planar);
    return 1;
  });
}

int length_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    check_no_more_method(L, 1);
    lua_pushnumber(L, c.curve->length());
    return 1;
  });
}

int closed_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    check_no_more_method(L, 1);
    lua_pushboolean(L, c.curve->closed());
    return 1;
  });
}

// c:points{tolerance=0.01}: a polyline within the chordal tolerance (a closed curve repeats its
// first point last).
int points_fn(lua_State* L) {
  return table_call(L, 2, [&] {
    const LuaCurve& c = check_curve(L, 1);
    check_no_more_method(L, 2);
    double tol = 0.01;
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      tol = o.positive("tolerance", 0.01);
      o.finish();
    }
    std::vector<Point3> pts = c.curve->points(tol);
    lua_createtable(L, int(pts.size()), 0);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      push_point(L, pts[i], c.planar);
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  });
}

int tostring_fn(lua_State* L) {
  return guarded(L, [&] {
    const LuaCurve& c = check_curve(L, 1);
    std::string kind = "Curve";
    if (dynamic_cast<const NurbsCurve*>(c.curve.get())) kind = "Curve(nurbs)";
    else if (dynamic_cast<const BezierCurve*>(c.curve.get())) kind = "Curve(bezier)";
    else if (dynamic_cast<const HermiteSpline*>(c.curve.get())) kind = "Curve(spline)";
    else if (dynamic_cast<const PolynomialInterpolant*>(c.curve.get())) kind = "Curve(polynomial)";
    lua_pushstring(L, kind.c_str());
    return 1;
  });
}

const luaL_Reg kFunctions[] = {
    {"bezier", bezier_fn},
    {"bspline", bspline_fn},
    {"nurbs", bspline_fn},
    {"interpolate", interpolate_fn},
    {"catmull_rom", catmull_rom_fn},
    {"natural_spline", natural_spline_fn},
    {"hermite", hermite_fn},
    {"polynomial", polynomial_fn},
    {"circle", circle_fn},
    {nullptr, nullptr}};

const luaL_Reg kMethods[] = {
    {"eval", eval_fn},
    {"tangent", tangent_fn},
    {"derivative", derivative_fn},
    {"length", length_fn},
    {"closed", closed_fn},
    {"points", points_fn},
    {nullptr, nullptr}};

const luaL_Reg kMeta[] = {{"__tostring", tostring_fn}, {nullptr, nullptr}};

}  // namespace

const LuaCurve* test_curve(lua_State* L, int idx) { return test_object<LuaCurve>(L, idx, kKey); }
const LuaCurve& check_curve(lua_State* L, int idx) { return check_object<LuaCurve>(L, idx, kKey, "Curve"); }
void push_curve(lua_State* L, LuaCurve c) { push_object(L, kKey, std::move(c)); }

void register_curves(lua_State* L) {
  register_class(L, kKey, "Curve", kMethods, kMeta, gc_object<LuaCurve>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
