// Lua bindings of brep/: the low-level B-Rep (`brep()` and its Euler operators) and the
// primitives built through them (box, cube, polyhedron), which return Solids whose leaf is the
// B-Rep (csg/brep_leaf.h).
//
// Ids. Vertices, edges, loops and faces are returned to Lua as plain integers: the id's index in
// its arena (0-based, never reused within one model). An integer is only meaningful for the model
// and element kind it came from; a wrong one is caught by the operator's precondition check
// ("mev: 7 is not a face of this model").
//
// Methods of a Brep (b = brep()):
//   v, f = b:mvfs{x,y,z}          e, v2 = b:mev(f, v, {x,y,z})     e, f2 = b:mef(f, v1, v2)
//   ring = b:kemr(e)              e = b:mekr(v1, v2)               ring = b:kfmrh(f_hole, f)
//   f2 = b:mfkrh(f, ring)         b:kev(e, v)  b:kef(e, f)  b:kvfs(v)
//   e2, v = b:semv(e, {x,y,z})    b:jekv(e2, v)                    (split / join an edge)
//   b:counts() -> {V=,E=,F=,R=,H=,S=}     b:validate([geometry=true]) -> true | false, message
//   b:point(v) -> {x,y,z}         b:vertices(f) -> outer loop's vertex ids
//   b:solid() -> a Solid (a copy of the model; it must validate)
#include <cmath>
#include <string>

#include "csg/brep_leaf.h"
#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_solid.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Brep";

Model& self(lua_State* L) { return check_object<Model>(L, 1, kKey, "Brep"); }

// An id of one of this model's elements (`what`: "a face"), blamed on the argument that gave it:
// the operator's own check named the operator alone ("mev: -1 is not a face of this model").
template <class IdT, class Elements>
IdT check_id(lua_State* L, int idx, const Elements& elements, const char* what) {
  const IdT id(check_integer(L, idx));
  if (!elements.contains(id)) throw ArgError{idx, std::to_string(id.value) + " is not " + what + " of this model"};
  return id;
}
template <class IdT>
IdT check_id(lua_State* L, int idx) {
  return IdT(check_integer(L, idx));
}
// A vertex position: finite (check_vec3) and within +-kMaxCoordinate, as every builder keeps
// its solids (brep.h); blamed on the argument that gave it.
Point3 check_point(lua_State* L, int idx) {
  Point3 p = check_vec3(L, idx);  // {x, y, z}: mvfs{5, 5} was taken as (5, 5, 0)
  for (int k = 0; k < 3; ++k)
    if (std::abs(p[k]) > kMaxCoordinate)
      throw ArgError{idx, "point coordinate " + std::to_string(k + 1) + " is " + number_text(p[k]) + ", beyond +-" +
                              number_text(kMaxCoordinate) + " (volumes and normals would overflow)"};
  return p;
}

template <class IdT>
void push_id(lua_State* L, IdT id) {
  lua_pushinteger(L, id.value);
}

// Runs an operator. When Lua knows the running function's name, the Lua error puts it in front
// of the message (lua_util's raise_pending; under pcall(b.kemr, b, e) the API's name
// "Brep:kemr"), so the message's own "op: " prefix is dropped.
template <class F>
auto op(lua_State* L, const char* name, F&& f) {
  try {
    return f();
  } catch (const Error& e) {
    std::string m = e.what(), prefix = std::string(name) + ": ";
    bool named = !running_function_name(L).empty();
    if (named && m.rfind(prefix, 0) == 0) m = m.substr(prefix.size());
    throw Error(m);
  }
}

// A solid's leaf must bound a solid: its faces may not cross one another, nor its shells overlap.
void require_bounds_solid(const Solid& s) {
  if (std::string d = s.validate(Tolerance{}); !d.empty()) fail("not a solid: ", d);
}

int brep_fn(lua_State* L) {
  return guarded(L, [&] {
    push_object(L, kKey, Model());
    return 1;
  });
}

int mvfs_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 2);
    Point3 p = check_point(L, 2);
    auto r = op(L, "mvfs", [&] { return m.mvfs(p); });
    push_id(L, r.v);
    push_id(L, r.f);
    return 2;
  });
}

int mev_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 4);
    auto f = check_id<FaceId>(L, 2, m.faces(), "a face");
    auto v = check_id<VertexId>(L, 3, m.vertices(), "a vertex");
    Point3 p = check_point(L, 4);
    auto r = op(L, "mev", [&] { return m.mev(f, v, p); });
    push_id(L, r.e);
    push_id(L, r.v);
    return 2;
  });
}

int mef_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 4);
    auto f = check_id<FaceId>(L, 2, m.faces(), "a face");
    auto v1 = check_id<VertexId>(L, 3, m.vertices(), "a vertex");
    auto v2 = check_id<VertexId>(L, 4, m.vertices(), "a vertex");
    auto r = op(L, "mef", [&] { return m.mef(f, v1, v2); });
    push_id(L, r.e);
    push_id(L, r.f);
    return 2;
  });
}

int kemr_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 2);
    auto e = check_id<EdgeId>(L, 2, m.edges(), "an edge");
    push_id(L, op(L, "kemr", [&] { return m.kemr(e); }));
    return 1;
  });
}

int mekr_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto v1 = check_id<VertexId>(L, 2, m.vertices(), "a vertex");
    auto v2 = check_id<VertexId>(L, 3, m.vertices(), "a vertex");
    push_id(L, op(L, "mekr", [&] { return m.mekr(v1, v2); }));
    return 1;
  });
}

int kfmrh_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto h = check_id<FaceId>(L, 2, m.faces(), "a face");
    auto f = check_id<FaceId>(L, 3, m.faces(), "a face");
    push_id(L, op(L, "kfmrh", [&] { return m.kfmrh(h, f); }));
    return 1;
  });
}

int mfkrh_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto f = check_id<FaceId>(L, 2, m.faces(), "a face");
    auto l = check_id<LoopId>(L, 3, m.loops(), "a loop");
    push_id(L, op(L, "mfkrh", [&] { return m.mfkrh(f, l); }));
    return 1;
  });
}

int kev_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto e = check_id<EdgeId>(L, 2, m.edges(), "an edge");
    auto v = check_id<VertexId>(L, 3, m.vertices(), "a vertex");
    op(L, "kev", [&] { m.kev(e, v); });
    return 0;
  });
}

int kef_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto e = check_id<EdgeId>(L, 2, m.edges(), "an edge");
    auto f = check_id<FaceId>(L, 3, m.faces(), "a face");
    op(L, "kef", [&] { m.kef(e, f); });
    return 0;
  });
}

int kvfs_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 2);
    auto v = check_id<VertexId>(L, 2, m.vertices(), "a vertex");
    op(L, "kvfs", [&] { m.kvfs(v); });
    return 0;
  });
}

int semv_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto e = check_id<EdgeId>(L, 2, m.edges(), "an edge");
    Point3 p = check_point(L, 3);
    auto r = op(L, "semv", [&] { return m.semv(e, p); });
    push_id(L, r.e);
    push_id(L, r.v);
    return 2;
  });
}

int jekv_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 3);
    auto e = check_id<EdgeId>(L, 2, m.edges(), "an edge");
    auto v = check_id<VertexId>(L, 3, m.vertices(), "a vertex");
    op(L, "jekv", [&] { m.jekv(e, v); });
    return 0;
  });
}

void push_counts(lua_State* L, const EulerCounts& c) {
  lua_createtable(L, 0, 6);
  const std::pair<const char*, long> f[] = {{"V", c.V}, {"E", c.E}, {"F", c.F}, {"R", c.R}, {"H", c.H}, {"S", c.S}};
  for (auto [k, v] : f) {
    lua_pushinteger(L, v);
    lua_setfield(L, -2, k);
  }
}

int counts_m(lua_State* L) {
  return guarded(L, [&] {
    push_counts(L, self(L).counts());
    return 1;
  });
}

// b:validate([geometry=true]): true, or false and the broken rule in words.
int validate_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 2);
    bool geometry = lua_isnoneornil(L, 2) ? true : check_boolean(L, 2);
    Validation v = m.validate(geometry);
    lua_pushboolean(L, v.ok);
    if (v.ok) return 1;
    lua_pushstring(L, v.message.c_str());
    return 2;
  });
}

int point_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 2);
    auto v = check_id<VertexId>(L, 2);
    push_vec3(L, op(L, "point", [&] { return m.point(v); }));
    return 1;
  });
}

// b:vertices(f): the vertex ids of face f's outer loop, in order.
int vertices_m(lua_State* L) {
  return guarded(L, [&] {
    Model& m = self(L);
    check_no_more_method(L, 2);
    auto f = check_id<FaceId>(L, 2);
    if (!m.faces().contains(f)) throw ArgError{2, "no face " + std::to_string(f.value) + " in this model"};
    auto vs = m.loop_vertices(m.faces()[f].outer);
    lua_createtable(L, static_cast<int>(vs.size()), 0);
    for (std::size_t i = 0; i < vs.size(); ++i) {
      lua_pushinteger(L, vs[i].value);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    return 1;
  });
}

int solid_m(lua_State* L) {
  return guarded(L, [&] {
    Model copy = self(L);
    Solid s = brep_solid(std::move(copy));
    // validate() holds the structure; a model whose faces cross (a hole's face lying on the face
    // it will be cut from, before kfmrh) is sound as a graph but bounds no solid.
    op(L, "solid", [&] { require_bounds_solid(s); });
    push_solid(L, s);
    return 1;
  });
}

int tostring_m(lua_State* L) {
  return guarded(L, [&] {
    EulerCounts c = self(L).counts();
    std::string s = "Brep{V=" + std::to_string(c.V) + ", E=" + std::to_string(c.E) + ", F=" + std::to_string(c.F) +
                    ", R=" + std::to_string(c.R) + ", H=" + std::to_string(c.H) + ", S=" + std::to_string(c.S) + "}";
    lua_pushstring(L, s.c_str());
    return 1;
  });
}

// --- primitives ---------------------------------------------------------------------------------

// Sizes given as three positional arguments are blamed on their own argument number; a size
// given in a table (or one number for all three) on that argument, naming the component.
Vec3 positive_size(const Vec3& s, int arg, bool positional = false) {
  static const char* axis[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (!(s[i] > 0)) {
      const std::string got = ", got " + number_text(s[i]);
      if (positional) throw ArgError{arg + i, "size must be positive" + got};
      if (s[0] == s[1] && s[1] == s[2]) throw ArgError{arg, "size must be positive" + got};
      throw ArgError{arg, std::string("size ") + axis[i] + " must be positive" + got};
    }
  return s;
}

// box(x, y, z) | box{size={x,y,z}, center=false}
int box_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Vec3 size;
    bool center = false;
    if (lua_type(L, 1) == LUA_TTABLE) {
      Options o(L, 1);
      if (o.push("size") == LUA_TNUMBER) {
        double s = lua_tonumber(L, -1);
        size = Vec3(s, s, s);
      } else {
        size = o.vec3("size", Vec3(1, 1, 1));
      }
      lua_pop(L, 1);
      center = o.boolean("center", false);
      o.finish();
      size = positive_size(size, 1);
    } else {
      size = positive_size(Vec3{check_number(L, 1), check_number(L, 2), check_number(L, 3)}, 1, true);  // {}: checked in order
      check_no_more(L, 3, "box{size={x, y, z}, center=true}");
    }
    push_solid(L, brep_solid(box(size, center ? Point3(-0.5 * size) : Point3::Zero())));
    return 1;
  });
}

// cube(s) | cube{size=s, center=false}
int cube_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    double s;
    bool center = false;
    if (lua_type(L, 1) == LUA_TTABLE) {
      Options o(L, 1);
      s = o.number("size", 1);
      center = o.boolean("center", false);
      o.finish();
    } else {
      s = check_number(L, 1);
      check_no_more(L, 1, "cube{size=s, center=true}");
    }
    Vec3 size = positive_size(Vec3(s, s, s), 1);
    push_solid(L, brep_solid(box(size, center ? Point3(-0.5 * size) : Point3::Zero())));
    return 1;
  });
}

// polyhedron{points={{x,y,z},...}, faces={{1,2,3,...},...}}: 1-based, counter-clockwise from outside.
int polyhedron_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    std::vector<Point3> pts;
    std::vector<std::vector<int>> faces;
    if (o.push("points") != LUA_TTABLE) throw ArgError{1, "field 'points' must be a list of {x, y, z}"};
    int pt = lua_gettop(L);
    for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, pt)); i <= n; ++i) {
      lua_rawgeti(L, pt, i);
      pts.push_back(to_vec3(L, -1, 1, "points[" + std::to_string(i) + "]"));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    if (o.push("faces") != LUA_TTABLE) throw ArgError{1, "field 'faces' must be a list of lists of point numbers"};
    int ft = lua_gettop(L);
    for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, ft)); i <= n; ++i) {
      lua_rawgeti(L, ft, i);
      if (lua_type(L, -1) != LUA_TTABLE) throw ArgError{1, "faces[" + std::to_string(i) + "] must be a list of point numbers"};
      std::vector<int> f;
      for (lua_Integer k = 1, m = static_cast<lua_Integer>(lua_rawlen(L, -1)); k <= m; ++k) {
        lua_rawgeti(L, -1, k);
        int isnum = 0;
        lua_Integer idx = lua_tointegerx(L, -1, &isnum);
        lua_pop(L, 1);
        if (!isnum) throw ArgError{1, "faces[" + std::to_string(i) + "][" + std::to_string(k) + "] must be an integer"};
        // Checked here, in 64 bits: 4294967297 must not wrap to point 1 on the way to int.
        if (idx < 1 || idx > static_cast<lua_Integer>(pts.size()))
          throw ArgError{1, "faces[" + std::to_string(i) + "][" + std::to_string(k) + "] is point " + std::to_string(idx) +
                                ", but there are " + std::to_string(pts.size()) + " points (numbered from 1)"};
        f.push_back(static_cast<int>(idx) - 1);
      }
      faces.push_back(std::move(f));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    o.finish();
    Solid s = brep_solid(op(L, "polyhedron", [&] { return polyhedron(pts, faces); }));
    // Faces that cross or shells that overlap bound no solid: refused here, at the script's line,
    // not at the first query that needs the volume (or never, where a boolean took its mesh).
    op(L, "polyhedron", [&] { require_bounds_solid(s); });
    push_solid(L, s);
    return 1;
  });
}

// worked_example() -> solid, rows: the seed's block with a protrusion, a sharp-cornered and a
// round-cornered depression and a round through hole, built by Euler operators; rows lists each
// feature's own counts ({name=, V=, E=, F=, R=, H=, S=}) in the order they were built.
int worked_example_fn(lua_State* L) {
  return guarded(L, [&] {
    std::vector<FeatureRow> rows;
    Model m = op(L, "worked_example", [&] { return worked_example(&rows); });
    push_solid(L, brep_solid(std::move(m)));
    lua_createtable(L, static_cast<int>(rows.size()), 0);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      push_counts(L, rows[i].counts);
      lua_pushstring(L, rows[i].name.c_str());
      lua_setfield(L, -2, "name");
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    return 2;
  });
}

const luaL_Reg kMethods[] = {
    {"mvfs", mvfs_m},   {"mev", mev_m},     {"mef", mef_m},     {"kemr", kemr_m},         {"mekr", mekr_m},
    {"kfmrh", kfmrh_m}, {"mfkrh", mfkrh_m}, {"kev", kev_m},     {"kef", kef_m},           {"kvfs", kvfs_m},
    {"semv", semv_m},   {"jekv", jekv_m},   {"counts", counts_m}, {"validate", validate_m}, {"point", point_m},
    {"vertices", vertices_m}, {"solid", solid_m}, {nullptr, nullptr}};
const luaL_Reg kMeta[] = {{"__tostring", tostring_m}, {nullptr, nullptr}};
const luaL_Reg kFunctions[] = {
    {"brep", brep_fn}, {"box", box_fn}, {"cube", cube_fn}, {"polyhedron", polyhedron_fn},
    {"worked_example", worked_example_fn}, {nullptr, nullptr}};

}  // namespace

void register_brep(lua_State* L) {
  register_class(L, kKey, "Brep", kMethods, kMeta, gc_object<Model>);
  set_functions(L, kFunctions);
}

}  // namespace wedge::lua
