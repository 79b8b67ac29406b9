// Lua bindings of kernel/transform.h: the `matrix` table and the Matrix userdata.
#include <cmath>
#include <sstream>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_matrix.h"
#include "render/render.h"

namespace wedge::lua {

Shear check_shear(lua_State* L, int arg) {
  Options o(L, arg);
  Shear s;
  s.xy = o.number("xy", 0); s.xz = o.number("xz", 0);
  s.yx = o.number("yx", 0); s.yz = o.number("yz", 0);
  s.zx = o.number("zx", 0); s.zy = o.number("zy", 0);
  o.finish();
  return s;
}

namespace {

constexpr const char* kKey = "wedge.Matrix";

Mat4& push_matrix(lua_State* L, const Mat4& m) { return push_object(L, kKey, m); }

}  // namespace

Vec3 check_axis(lua_State* L, int idx) {
  if (lua_type(L, idx) == LUA_TSTRING) {
    std::string s = lua_tostring(L, idx);
    if (s == "x" || s == "X") return Vec3::UnitX();
    if (s == "y" || s == "Y") return Vec3::UnitY();
    if (s == "z" || s == "Z") return Vec3::UnitZ();
    throw ArgError{idx, "axis must be {x, y, z} or \"x\", \"y\", \"z\", got '" + s + "'"};
  }
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{idx, "axis {x, y, z} expected, got " + type_name(L, idx)};
  Vec3 a = to_vec3(L, idx, idx, "axis");
  if (a == Vec3::Zero()) throw ArgError{idx, "axis must be non-zero"};
  return a;
}

namespace {

int identity_fn(lua_State* L) {
  return guarded(L, [&] {
    push_matrix(L, identity());
    return 1;
  });
}

// matrix.translate(x, y, z) or matrix.translate{x, y, z}
int translate_fn(lua_State* L) {
  return guarded(L, [&] {
    Vec3 d = lua_type(L, 1) == LUA_TTABLE ? check_vec3(L, 1, true)
                                           : Vec3{check_number(L, 1), check_number(L, 2), opt_number(L, 3, 0)};
    push_matrix(L, translate(d));
    return 1;
  });
}

// matrix.rotate(angle, axis [, pivot])
int rotate_fn(lua_State* L) {
  return guarded(L, [&] {
    double a = check_number(L, 1);
    Vec3 axis = lua_isnoneornil(L, 2) ? Vec3::UnitZ() : check_axis(L, 2);
    if (lua_isnoneornil(L, 3)) push_matrix(L, rotate(a, axis));
    else push_matrix(L, rotate(a, axis, check_vec3(L, 3, true)));
    return 1;
  });
}

template <Mat4 (*F)(double)>
int rotate_axis_fn(lua_State* L) {
  return guarded(L, [&] {
    push_matrix(L, F(check_number(L, 1)));
    return 1;
  });
}

// matrix.euler(x, y, z): Rz * Ry * Rx
int euler_fn(lua_State* L) {
  return guarded(L, [&] {
    const double x = check_number(L, 1), y = check_number(L, 2), z = check_number(L, 3);
    push_matrix(L, rotate_euler(x, y, z));
    return 1;
  });
}

// matrix.scale(k) | matrix.scale(kx, ky, kz [, pivot])
int scale_fn(lua_State* L) {
  return guarded(L, [&] {
    double kx = check_number(L, 1);
    Vec3 k(kx, kx, kx);
    int pivot_arg = 2;
    if (!lua_isnoneornil(L, 2) && lua_type(L, 2) != LUA_TTABLE) {
      k = Vec3{kx, check_number(L, 2), check_number(L, 3)};
      pivot_arg = 4;
    }
    if (lua_isnoneornil(L, pivot_arg)) push_matrix(L, scale(k));
    else push_matrix(L, scale(k, check_vec3(L, pivot_arg, true)));
    return 1;
  });
}

// matrix.mirror(normal [, point])
int mirror_fn(lua_State* L) {
  return guarded(L, [&] {
    Vec3 n = check_axis(L, 1);
    Vec3 p = lua_isnoneornil(L, 2) ? Vec3::Zero() : check_vec3(L, 2, true);
    push_matrix(L, reflect(n, p));
    return 1;
  });
}

// matrix.shear{xy=, xz=, yx=, yz=, zx=, zy=}
int shear_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    push_matrix(L, shear(check_shear(L, 1)));
    return 1;
  });
}

// matrix.look_at(eye, center, up)
int look_at_fn(lua_State* L) {
  return guarded(L, [&] {
    const Vec3 eye = check_vec3(L, 1), center = check_vec3(L, 2), up = check_vec3(L, 3);
    push_matrix(L, look_at(eye, center, up));
    return 1;
  });
}

int perspective_fn(lua_State* L) {
  return guarded(L, [&] {
    const double fovy = check_number(L, 1), aspect = check_number(L, 2), near = check_number(L, 3), far = check_number(L, 4);
    push_matrix(L, perspective(fovy, aspect, near, far));
    return 1;
  });
}

template <Mat4 (*F)(double, double, double, double, double, double)>
int six_fn(lua_State* L) {
  return guarded(L, [&] {
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = check_number(L, i + 1);  // in order: the first bad one is named
    push_matrix(L, F(v[0], v[1], v[2], v[3], v[4], v[5]));
    return 1;
  });
}

// Reads (a, b) positionally or {ka=, kb=} from a table at argument 1, with defaults.
std::pair<double, double> two_numbers(lua_State* L, const char* ka, double da, const char* kb, double db) {
  if (lua_type(L, 1) == LUA_TTABLE) {
    Options o(L, 1);
    double a = o.number(ka, da), b = o.number(kb, db);
    o.finish();
    return {a, b};
  }
  if (!lua_isnoneornil(L, 1) && lua_type(L, 1) != LUA_TNUMBER)
    throw ArgError{1, std::string("table {") + ka + "=, " + kb + "=} or numbers expected, got " + type_name(L, 1)};
  return {opt_number(L, 1, da), opt_number(L, 2, db)};
}

// matrix.oblique{angle=45, ratio=0.5} or matrix.oblique(angle, ratio): the oblique parallel
// projection's shear in the view frame (render/camera.cpp): ratio 1 cavalier, 1/2 cabinet.
int oblique_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    auto [angle, ratio] = two_numbers(L, "angle", 45, "ratio", 0.5);
    if (!(ratio > 0))
      throw ArgError{lua_type(L, 1) == LUA_TTABLE ? 1 : 2, "ratio must be positive, got " + number_text(ratio)};
    push_matrix(L, render::oblique(angle, ratio));
    return 1;
  });
}

// matrix.axonometric{rx=, ry=} or matrix.axonometric(rx, ry): Rx(rx) * Ry(ry); by default the
// isometric rx = asin(tan 30) = 35.264..., ry = -45.
int axonometric_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    auto [rx, ry] = two_numbers(L, "rx", std::asin(std::tan(M_PI / 6)) * 180 / M_PI, "ry", -45);
    push_matrix(L, render::axonometric(rx, ry));
    return 1;
  });
}

// matrix.from{{row1}, {row2}, {row3}, {row4}}: rows as a person writes them.
int from_fn(lua_State* L) {
  return guarded(L, [&] {
    check_table(L, 1);
    if (lua_rawlen(L, 1) != 4) throw ArgError{1, "4 rows of 4 numbers expected, got " + std::to_string(lua_rawlen(L, 1)) + " rows"};
    Mat4 m;
    for (int r = 0; r < 4; ++r) {
      lua_rawgeti(L, 1, r + 1);
      std::string err;
      try {
        Eigen::Vector4d row;
        if (lua_type(L, -1) != LUA_TTABLE || lua_rawlen(L, -1) != 4) throw ArgError{1, "row " + std::to_string(r + 1) + " must hold 4 numbers"};
        for (int c = 0; c < 4; ++c) {
          lua_rawgeti(L, -1, c + 1);
          if (lua_type(L, -1) != LUA_TNUMBER) {
            lua_pop(L, 1);
            throw ArgError{1, "entry (" + std::to_string(r + 1) + ", " + std::to_string(c + 1) + ") must be a number"};
          }
          m(r, c) = lua_tonumber(L, -1);
          lua_pop(L, 1);
        }
      } catch (const ArgError& e) {
        err = e.message;
      }
      lua_pop(L, 1);
      if (!err.empty()) throw ArgError{1, err};
    }
    if (!m.allFinite()) throw ArgError{1, "matrix entries must be finite"};
    push_matrix(L, m);
    return 1;
  });
}

// --- methods ---

int mul_fn(lua_State* L) {
  return guarded(L, [&] {
    const Mat4& a = check_object<Mat4>(L, 1, kKey, "Matrix");
    const Mat4& b = check_object<Mat4>(L, 2, kKey, "Matrix");
    const Mat4 ab = a * b;
    // translate(1e308, 0, 0) * translate(1e308, 0, 0) gave a matrix holding inf.
    if (!ab.allFinite()) fail("the matrix product overflows: an entry is beyond the range of doubles");
    push_matrix(L, ab);
    return 1;
  });
}

int eq_fn(lua_State* L) {
  return guarded(L, [&] {
    const Mat4* a = test_object<Mat4>(L, 1, kKey);
    const Mat4* b = test_object<Mat4>(L, 2, kKey);
    lua_pushboolean(L, a && b && *a == *b);
    return 1;
  });
}

int inverse_fn(lua_State* L) {
  return guarded(L, [&] {
    push_matrix(L, inverse(check_object<Mat4>(L, 1, kKey, "Matrix")));
    return 1;
  });
}

int transpose_fn(lua_State* L) {
  return guarded(L, [&] {
    push_matrix(L, check_object<Mat4>(L, 1, kKey, "Matrix").transpose());
    return 1;
  });
}

int determinant_fn(lua_State* L) {
  return guarded(L, [&] {
    lua_pushnumber(L, check_object<Mat4>(L, 1, kKey, "Matrix").determinant());
    return 1;
  });
}

int apply_fn(lua_State* L) {
  return guarded(L, [&] {
    const Mat4& m = check_object<Mat4>(L, 1, kKey, "Matrix");
    bool is2d = lua_type(L, 2) == LUA_TTABLE && lua_rawlen(L, 2) == 2;
    Vec3 p = check_vec3(L, 2, true);
    Vec3 q = apply_point(m, p);
    if (is2d) push_vec2(L, q.head<2>());
    else push_vec3(L, q);
    return 1;
  });
}

int apply_vector_fn(lua_State* L) {
  return guarded(L, [&] {
    push_vec3(L, apply_vector(check_object<Mat4>(L, 1, kKey, "Matrix"), check_vec3(L, 2)));
    return 1;
  });
}

int apply_normal_fn(lua_State* L) {
  return guarded(L, [&] {
    push_vec3(L, apply_normal(check_object<Mat4>(L, 1, kKey, "Matrix"), check_vec3(L, 2)));
    return 1;
  });
}

// m:get(row, col), 1-based
int get_fn(lua_State* L) {
  return guarded(L, [&] {
    const Mat4& m = check_object<Mat4>(L, 1, kKey, "Matrix");
    int r = check_integer(L, 2), c = check_integer(L, 3);
    if (r < 1 || r > 4) throw ArgError{2, "row must be 1..4, got " + std::to_string(r)};
    if (c < 1 || c > 4) throw ArgError{3, "column must be 1..4, got " + std::to_string(c)};
    lua_pushnumber(L, m(r - 1, c - 1));
    return 1;
  });
}

// m:table(): rows {{m11, m12, m13, m14}, ...}
int table_fn(lua_State* L) {
  return guarded(L, [&] {
    const Mat4& m = check_object<Mat4>(L, 1, kKey, "Matrix");
    lua_createtable(L, 4, 0);
    for (int r = 0; r < 4; ++r) {
      lua_createtable(L, 4, 0);
      for (int c = 0; c < 4; ++c) {
        lua_pushnumber(L, m(r, c));
        lua_rawseti(L, -2, c + 1);
      }
      lua_rawseti(L, -2, r + 1);
    }
    return 1;
  });
}

int tostring_fn(lua_State* L) {
  return guarded(L, [&] {
    const Mat4& m = check_object<Mat4>(L, 1, kKey, "Matrix");
    std::ostringstream out;
    out.precision(6);
    out << "Matrix{";
    for (int r = 0; r < 4; ++r) {
      out << (r ? ", {" : "{");
      for (int c = 0; c < 4; ++c) out << (c ? ", " : "") << m(r, c);
      out << "}";
    }
    out << "}";
    std::string s = out.str();
    lua_pushlstring(L, s.data(), s.size());
    return 1;
  });
}

const luaL_Reg kMatrixFunctions[] = {
    {"identity", identity_fn},
    {"translate", translate_fn},
    {"rotate", rotate_fn},
    {"rotate_x", rotate_axis_fn<rotate_x>},
    {"rotate_y", rotate_axis_fn<rotate_y>},
    {"rotate_z", rotate_axis_fn<rotate_z>},
    {"euler", euler_fn},
    {"scale", scale_fn},
    {"mirror", mirror_fn},
    {"shear", shear_fn},
    {"look_at", look_at_fn},
    {"perspective", perspective_fn},
    {"frustum", six_fn<frustum>},
    {"ortho", six_fn<ortho>},
    {"from", from_fn},
    {"oblique", oblique_fn},
    {"axonometric", axonometric_fn},
    {nullptr, nullptr}};

const luaL_Reg kMethods[] = {
    {"inverse", inverse_fn},
    {"transpose", transpose_fn},
    {"determinant", determinant_fn},
    {"apply", apply_fn},
    {"apply_vector", apply_vector_fn},
    {"apply_normal", apply_normal_fn},
    {"get", get_fn},
    {"table", table_fn},
    {nullptr, nullptr}};

const luaL_Reg kMeta[] = {{"__mul", mul_fn}, {"__eq", eq_fn}, {"__tostring", tostring_fn}, {nullptr, nullptr}};

}  // namespace

const Mat4* test_matrix(lua_State* L, int idx) { return test_object<Mat4>(L, idx, kKey); }
const Mat4& check_matrix(lua_State* L, int idx) { return check_object<Mat4>(L, idx, kKey, "Matrix"); }
void push_matrix_value(lua_State* L, const Mat4& m) { push_matrix(L, m); }

void register_matrix(lua_State* L) {
  register_class(L, kKey, "Matrix", kMethods, kMeta, gc_object<Mat4>);
  lua_newtable(L);
  set_functions(L, kMatrixFunctions);
  lua_setfield(L, -2, "matrix");
}

}  // namespace wedge::lua
