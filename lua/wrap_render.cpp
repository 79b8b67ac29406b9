// Lua binding of render::render_scene: render{ mesh, out=, size=, camera=, lights=, ambient=,
// local_viewer=, two_side=, shading=, wireframe=, cull=, depth=, fog=, antialias=, background= }
// (API.md, "Rendering"). The thing drawn is a Solid (with the material of s:material{...}),
// anything else to_mesh() accepts, or a plain mesh table
// { vertices = {{x,y,z}, ...}, triangles = {{i,j,k}, ...} (1-based), material = {...} }.
// checker{n=, size=, colors=} makes a procedural texture for a material's texture= field.
// drawing{s, out=, views=, ...} is the multi-view sheet (render::render_drawing). view= takes the
// course's named views (render/camera.cpp), by name or as {name, options...}.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <unordered_map>
#include <map>
#include <tuple>
#include <optional>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_render.h"
#include "lua/wrap_scene.h"
#include "lua/wrap_solid.h"
#include "lua/wrap_wireframe.h"
#include "render/render.h"

namespace wedge::lua {

namespace {

using render::Vec4f;
using TexturePtr = std::shared_ptr<render::Texture>;
constexpr const char* kTextureKey = "wedge.Texture";

Vec4f to_color(lua_State* L, int idx, int arg, const std::string& what) {
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{arg, what + " must be a colour {r, g, b}, got " + type_name(L, idx)};
  Vec4f c(0, 0, 0, 1);
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  if (n < 3 || n > 4) throw ArgError{arg, what + " must have 3 or 4 components {r, g, b [, a]}, got " + std::to_string(n)};
  for (int k = 1; k <= n; ++k) {
    lua_geti(L, idx, k);
    const bool number = lua_type(L, -1) == LUA_TNUMBER;
    const double x = lua_tonumber(L, -1);
    const std::string got = number ? "" : type_name(L, -1);
    lua_pop(L, 1);
    if (!number) throw ArgError{arg, element_name(what, k, "component") + " must be a number, got " + got};
    // Colours are 0..1 (API.md); NaN or 7 would be drawn as some clamped colour without a word.
    if (!(x >= 0 && x <= 1))
      throw ArgError{arg, element_name(what, k, "component") + " must be within 0..1, got " + number_text(x)};
    c[k - 1] = float(x);
  }
  return c;
}

// out= must name a PNG file: the image is written as PNG whatever the name says.
void check_png_name(const std::string& out) {
  std::string ext = out.size() >= 4 ? out.substr(out.size() - 4) : "";
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  if (ext != ".png") throw ArgError{1, "field 'out' must name a .png file (the image is written as PNG), got '" + out + "'"};
}

// The pixel budget of one image: width x height x antialias^2 samples (each a colour and a depth,
// 8 bytes), by default 2^26 (an 8192 x 8192 image without supersampling, 512 MiB). A larger image
// is an error giving its sample count; max_pixels= raises the budget.
void check_pixel_budget(Options& o, const char* fn, int width, int height, int antialias) {
  double budget = o.number("max_pixels").value_or(double(1 << 26));
  if (!(budget >= 1 && budget <= 1e12 && budget == std::floor(budget)))
    throw ArgError{1, "field 'max_pixels' must be a whole number in 1..1e12, got " + number_text(budget)};
  const double samples = double(width) * height * antialias * antialias;
  if (samples > budget)
    throw ArgError{1, std::string(fn) + " of " + std::to_string(width) + " x " + std::to_string(height) + " at antialias " +
                          std::to_string(antialias) + " needs " + number_text(samples) + " samples, more than the budget of " +
                          number_text(budget) + " (raise it with max_pixels=)"};
}

// render{} and drawing{} take one table, so a bad option is named by its field path rather than
// by an argument number: "render: lights[2].position must be a point {x, y, z}, got string",
// "render: camera.near must be below camera.far", at the caller's line. The checks below throw
// ArgError on argument 1 with "field 'path' ..." messages (as every table option of the API does);
// options_call turns them into plain errors whose message starts with the path.
template <class F>
int options_call(lua_State* L, F&& body) {
  return table_call(L, 1, std::forward<F>(body));
}

Vec4f opt_color(Options& o, const char* key, const Vec4f& fallback) {
  lua_State* L = o.state();
  int t = o.push(key);
  Vec4f c = fallback;
  if (t != LUA_TNIL) {
    try {
      c = to_color(L, lua_gettop(L), o.arg(), "field '" + o.field(key) + "'");
    } catch (...) {
      lua_pop(L, 1);
      throw;
    }
  }
  lua_pop(L, 1);
  return c;
}

}  // namespace

render::Material read_material(lua_State* L, int idx, int arg, std::shared_ptr<const render::Texture>& texture) {
  Options o(L, idx, arg, "material");
  render::Material m;
  m.ambient = opt_color(o, "ambient", m.ambient);
  m.diffuse = opt_color(o, "diffuse", m.diffuse);
  m.specular = opt_color(o, "specular", m.specular);
  m.emission = opt_color(o, "emission", m.emission);
  if (o.has("color")) {
    Vec4f c = opt_color(o, "color", m.diffuse);
    m.ambient = m.diffuse = c;
  }
  const double shininess = o.number("shininess", 0);
  if (shininess < 0 || shininess > 128)
    throw ArgError{arg, "field '" + o.field("shininess") + "' must be within 0..128 (OpenGL's range), got " + number_text(shininess)};
  m.shininess = float(shininess);
  int t = o.push("texture");
  if (t == LUA_TSTRING) {
    std::string path = lua_tostring(L, -1);
    lua_pop(L, 1);
    sandbox_check_path(L, path, false);
    texture = as_arg(arg, [&] { return render::Texture::load_png(path); });
  } else if (t != LUA_TNIL) {
    TexturePtr* p = test_object<TexturePtr>(L, -1, kTextureKey);
    lua_pop(L, 1);
    if (!p) throw ArgError{arg, "field '" + o.field("texture") + "' must be checker{...} or a PNG file name"};
    texture = *p;
  } else {
    lua_pop(L, 1);
  }
  o.finish();
  return m;
}

namespace {

// A mesh table { vertices=, triangles=, material= }.
Mesh read_mesh(lua_State* L, int idx, render::Material& material, std::shared_ptr<const render::Texture>& texture) {
  idx = lua_absindex(L, idx);
  // Any other field is an error, as in every options table: normals={...} was silently ignored.
  lua_pushnil(L);
  while (lua_next(L, idx)) {
    lua_pop(L, 1);  // the value; the key stays for lua_next
    const bool known = lua_type(L, -1) == LUA_TSTRING && (std::strcmp(lua_tostring(L, -1), "vertices") == 0 ||
                                                          std::strcmp(lua_tostring(L, -1), "triangles") == 0 ||
                                                          std::strcmp(lua_tostring(L, -1), "material") == 0);
    if (!known) {
      const std::string key = lua_type(L, -1) == LUA_TSTRING ? "field '" + std::string(lua_tostring(L, -1)) + "'"
                                                              : "key " + describe(L, -1);
      lua_pop(L, 1);
      throw ArgError{1, "the mesh table has an unknown " + key + " (known: vertices, triangles, material)"};
    }
  }
  Mesh m;
  lua_getfield(L, idx, "vertices");
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    throw ArgError{1, "mesh table needs 'vertices' = {{x, y, z}, ...}"};
  }
  int vt = lua_gettop(L);
  for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, vt)); i <= n; ++i) {
    lua_geti(L, vt, i);
    Vec3 p = to_vec3(L, lua_gettop(L), 1, "vertex " + std::to_string(i));
    lua_pop(L, 1);
    m.add_vertex(p);
  }
  lua_pop(L, 1);
  lua_getfield(L, idx, "triangles");
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    throw ArgError{1, "mesh table needs 'triangles' = {{i, j, k}, ...}"};
  }
  int tt = lua_gettop(L);
  for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, tt)); i <= n; ++i) {
    lua_geti(L, tt, i);
    Vec3 t = to_vec3(L, lua_gettop(L), 1, "triangle " + std::to_string(i));
    lua_pop(L, 1);
    std::uint32_t ids[3];
    for (int k = 0; k < 3; ++k) {
      double v = t[k];
      if (v != std::floor(v) || v < 1 || v > double(m.vertex_count()))
        throw ArgError{1, "triangle " + std::to_string(i) + " refers to vertex " + number_text(v) + ", not in 1.." +
                              std::to_string(m.vertex_count())};
      ids[k] = std::uint32_t(v) - 1;
    }
    m.add_triangle(ids[0], ids[1], ids[2]);
  }
  lua_pop(L, 1);
  lua_getfield(L, idx, "material");
  if (lua_istable(L, -1)) material = read_material(L, lua_gettop(L), 1, texture);
  lua_pop(L, 1);
  return m;
}

// A view: a name ("cabinet"), or a table with the name first and the view's options
// ({"cabinet", angle=30}, {name="trimetric", rx=25, ry=-40}); `field` names it in messages.
struct ViewChoice {
  std::string name;
  render::ViewParams params;
};

ViewChoice read_view(lua_State* L, int idx, const std::string& field) {
  idx = lua_absindex(L, idx);
  ViewChoice v;
  if (lua_type(L, idx) == LUA_TSTRING) {
    v.name = lua_tostring(L, idx);
  } else if (lua_type(L, idx) == LUA_TTABLE) {
    Options o(L, idx, 1, field);
    o.allow_positional();
    if (lua_rawgeti(L, idx, 1) == LUA_TSTRING) v.name = lua_tostring(L, -1);
    lua_pop(L, 1);
    if (lua_rawlen(L, idx) > 1) throw ArgError{1, "field '" + field + "' must hold one view name, then named options"};
    std::string named = o.string("name", "");
    if (!named.empty() && !v.name.empty()) throw ArgError{1, "field '" + field + "' names its view twice"};
    if (v.name.empty()) v.name = named;
    if (v.name.empty()) throw ArgError{1, "field '" + field + "' needs a view name, as {\"cabinet\", angle=30}"};
    v.params.rx = o.number("rx").value_or(NAN);
    v.params.ry = o.number("ry").value_or(NAN);
    v.params.angle = o.number("angle").value_or(NAN);
    v.params.ratio = o.number("ratio").value_or(NAN);
    v.params.distance = o.number("distance").value_or(NAN);
    o.finish();
  } else {
    throw ArgError{1, "field '" + field + "' must be a view name or {name, options...}, got " + type_name(L, idx)};
  }
  const auto& names = render::view_names();
  if (std::find(names.begin(), names.end(), v.name) == names.end()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw ArgError{1, "field '" + field + "': unknown view '" + v.name + "' (expected " + list + ")"};
  }
  return v;
}

render::Camera view_camera(const ViewChoice& v, const Box3& bounds) {
  return as_arg(1, [&] { return render::named_view(v.name, bounds, v.params); });
}

render::Camera read_camera(lua_State* L, int idx, const Box3& bounds) {
  Options o(L, idx, 1, "camera");
  render::Camera c = render::named_view("iso", bounds);
  if (o.push("view") != LUA_TNIL) {
    c = view_camera(read_view(L, lua_gettop(L), "camera.view"), bounds);
    lua_pop(L, 1);
  } else {
    lua_pop(L, 1);
    c.fit_window = false;
    bool up_given = false;
    std::string proj = o.string("projection", "perspective");
    if (proj == "perspective") {
      c.orthographic = false;
      c.eye = o.vec3("eye", Vec3(5, 5, 5));
      c.center = o.vec3("center", Vec3(0, 0, 0));
      up_given = o.has("up");
      c.up = o.vec3("up", Vec3(0, 0, 1));
      c.fovy = o.positive("fovy", 45);
      bool explicit_range = o.has("near") || o.has("far");
      c.near = o.positive("near", 0.1);
      c.far = o.positive("far", 100);
      c.fit = !explicit_range;
    } else if (proj == "ortho") {
      c.orthographic = true;
      c.eye = o.vec3("eye", c.eye);
      c.center = o.vec3("center", c.center);
      up_given = o.has("up");
      c.up = o.vec3("up", c.up);
      c.left = o.number("left", c.left), c.right = o.number("right", c.right);
      c.bottom = o.number("bottom", c.bottom), c.top = o.number("top", c.top);
      bool explicit_range = o.has("near") || o.has("far");
      c.near = o.number("near", c.near), c.far = o.number("far", c.far);
      c.fit = !explicit_range;
    } else {
      throw ArgError{1, "field 'camera.projection' must be \"perspective\" or \"ortho\", got '" + proj + "'"};
    }
    // What OpenGL would take without complaint and draw as nothing, or as nonsense. An eye at
    // 1e300 made the view matrix overflow and was blamed on camera.up.
    for (const auto& [name, p] : {std::pair<const char*, const Vec3&>{"eye", c.eye}, {"center", c.center}})
      for (int k = 0; k < 3; ++k)
        if (std::abs(p[k]) > 1e100)
          throw ArgError{1, std::string("field 'camera.") + name + "[" + std::to_string(k + 1) + "]' is " + number_text(p[k]) +
                                ", beyond +-1e100"};
    if (c.fovy >= 180) throw ArgError{1, "field 'camera.fovy' must be below 180, got " + number_text(c.fovy)};
    if (!(c.near < c.far))
      throw ArgError{1, "camera.near must be below camera.far, got " + number_text(c.near) + " and " + number_text(c.far)};
    if (c.orthographic && !(c.left < c.right))
      throw ArgError{1, "camera.left must be below camera.right, got " + number_text(c.left) + " and " + number_text(c.right)};
    if (c.orthographic && !(c.bottom < c.top))
      throw ArgError{1, "camera.bottom must be below camera.top, got " + number_text(c.bottom) + " and " + number_text(c.top)};
    const Vec3 sight = c.center - c.eye;
    if (sight.norm() == 0) throw ArgError{1, "camera.eye and camera.center must differ"};
    // Looking straight down (or up) with no up= given: the default up, +z, is along the line of
    // sight; +y is up in the picture instead (as in a top view).
    if (!up_given && !(c.up.cross(sight).norm() > 1e-12 * c.up.norm() * sight.norm())) c.up = Vec3(0, 1, 0);
    if (!(c.up.cross(sight).norm() > 1e-12 * c.up.norm() * sight.norm()))
      throw ArgError{1, "camera.up must be a non-zero vector not along the line of sight"};
  }
  o.finish();
  return c;
}

render::LightSpec read_light(lua_State* L, int idx, const std::string& name) {
  Options o(L, idx, 1, name);
  const std::string prefix = "field '" + name + ".";
  render::LightSpec l;
  std::string type = o.string("type", "directional");
  if (type == "directional") l.type = render::LightSpec::Type::Directional;
  else if (type == "point") l.type = render::LightSpec::Type::Point;
  else if (type == "spot") l.type = render::LightSpec::Type::Spot;
  else throw ArgError{1, prefix + "type' must be \"directional\", \"point\" or \"spot\", got '" + type + "'"};
  // A field the light's type has no use for was taken and ignored: a point light given only a
  // direction lit nothing, with no word.
  if (l.type == render::LightSpec::Type::Directional && o.has("position"))
    throw ArgError{1, prefix + "position': a directional light has a direction= (it is at infinity), not a position"};
  if (l.type == render::LightSpec::Type::Point && o.has("direction"))
    throw ArgError{1, prefix + "direction': a point light shines every way from its position= (a spot light has both)"};
  for (const char* spot_only : {"cutoff", "exponent"})
    if (l.type != render::LightSpec::Type::Spot && o.has(spot_only))
      throw ArgError{1, prefix + spot_only + "': only a spot light has a " + spot_only + " (type=\"spot\")"};
  l.position = o.vec3("position", l.position);
  l.direction = o.vec3("direction", l.direction);
  // As the camera's eye: a light at 1e308 made every distance inf and the scene black.
  for (int k = 0; k < 3; ++k)
    if (std::abs(l.position[k]) > 1e100)
      throw ArgError{1, prefix + "position[" + std::to_string(k + 1) + "]' is " + number_text(l.position[k]) + ", beyond +-1e100"};
  l.ambient = opt_color(o, "ambient", l.ambient);
  l.diffuse = opt_color(o, "diffuse", l.diffuse);
  l.specular = opt_color(o, "specular", l.specular);
  if (l.direction == Vec3::Zero()) throw ArgError{1, prefix + "direction' must be a non-zero vector"};
  l.attenuation = o.vec3("attenuation", l.attenuation);
  if (l.attenuation.minCoeff() < 0 || l.attenuation.maxCoeff() == 0)
    throw ArgError{1, prefix + "attenuation' {constant, linear, quadratic} must be non-negative and not all zero"};
  const double cutoff = o.number("cutoff", 45), exponent = o.number("exponent", 0);
  if (!((cutoff >= 0 && cutoff <= 90) || cutoff == 180))
    throw ArgError{1, prefix + "cutoff' must be within 0..90 or 180 (OpenGL's range), got " + number_text(cutoff)};
  if (exponent < 0 || exponent > 128)
    throw ArgError{1, prefix + "exponent' must be within 0..128 (OpenGL's range), got " + number_text(exponent)};
  l.cutoff = float(cutoff), l.exponent = float(exponent);
  const std::string space = o.string("space", "world");
  if (space != "world" && space != "eye") throw ArgError{1, prefix + "space' must be \"world\" or \"eye\", got '" + space + "'"};
  l.eye_space = space == "eye";
  o.finish();
  return l;
}

// The thing to draw, t[1] of the options table at index 1: a Solid (with its material), a
// plain mesh table, or anything else to_mesh() accepts. Fills `mesh` and the item's material.
// The things drawn: t[1] of the options table at index 1. A Solid (with its material), a plain
// mesh table, or anything else to_mesh() accepts makes one item; a scene group makes one item per
// leaf, placed by its world matrix (each leaf's mesh made once, however many instances it has).
// The meshes live in `meshes` (a deque: items point into it).
struct Drawn {
  std::deque<Mesh> meshes;
  std::vector<render::DrawItem> items;
  // The bounds the cameras are fitted to. A coordinate beyond +-1e100 (as an eye or a light may
  // not be) is an error naming the bounds: vertices at +-1e300 made the bounds' size overflow, and
  // the fitted default camera failed with "eye must be finite, got (inf, -inf, inf)", an eye the
  // user never gave.
  Box3 bounds() const {
    Box3 b;
    for (const Point3& p : render::world_points(items)) b.extend(p);
    if (b.empty()) return b;
    const double reach = std::max(b.min.cwiseAbs().maxCoeff(), b.max.cwiseAbs().maxCoeff());
    if (!(reach <= 1e100))
      throw ArgError{1, "the scene's bounds overflow: a vertex coordinate reaches " + number_text(reach) +
                            ", beyond +-1e100, and a camera fitted to them would not be finite (scale the vertices down)"};
    return b;
  }
};

// A texture on a mesh without texture coordinates: the two-step box mapping.
Mesh with_uvs_if_textured(Mesh mesh, bool textured) {
  if (textured && mesh.uvs.empty()) return render::with_uv_mapping(mesh, render::UvMapping::Box);
  return mesh;
}

// A solid's mesh for drawing: normals from its faces' surfaces (Solid::shaded_mesh). Its uvs (the
// surfaces' parameters, in each surface's own units) are dropped: a texture on a solid is laid
// on by the box mapping, the same on every face.
Mesh shading_mesh(const Solid& s, const Tolerance& tol) {
  Mesh m = s.shaded_mesh(tol);
  m.uvs.clear();
  if (m.normals.empty()) m = m.with_face_normals();
  return m;
}

// A solid whose faces carry the materials of several solids (a boolean of solids with
// s:material{}): one item per material, each face drawn in the material of the solid it came
// from. Adds nothing and returns false when the faces carry at most one material.
bool draw_by_face_tags(lua_State* L, int obj, const Solid& s, Drawn& drawn) {
  const Tolerance tol = current_tolerance(L);
  std::map<int, Mesh> parts;
  {
    Stage stage(L, "mesh");
    parts = scene::split_by_tags(s, tol);
  }
  if (parts.size() < 2) return false;
  for (auto& [tag, part] : parts) {
    render::DrawItem item;
    const int top = lua_gettop(L);
    const int type = tag >= 0 ? push_tag_material(L, tag) : push_material(L, obj);
    if (type == LUA_TTABLE) item.material = read_material(L, lua_gettop(L), 1, item.texture);
    lua_settop(L, top);
    drawn.meshes.push_back(with_uvs_if_textured(std::move(part), item.texture != nullptr));
    item.mesh = &drawn.meshes.back();
    drawn.items.push_back(std::move(item));
  }
  return true;
}

// size={w, h} of render{} and drawing{}: whole pixels, 1..8192 each; the message repeats what was
// given ("size must be ... within 1..8192, got {100000, 100000}").
Vec2 image_size(Options& o) {
  lua_State* L = o.state();
  const int type = o.push("size");
  if (type != LUA_TNIL && (type != LUA_TTABLE || lua_rawlen(L, -1) != 2)) {
    const std::string got = type == LUA_TTABLE ? "a table of " + std::to_string(lua_rawlen(L, -1)) + (lua_rawlen(L, -1) == 1 ? " element" : " elements") : describe(L, -1);
    lua_pop(L, 1);
    throw ArgError{o.arg(), "field 'size' must be {width, height} in pixels, got " + got};
  }
  lua_pop(L, 1);
  const Vec2 size = o.vec2("size", Vec2(800, 600));
  auto whole = [](double v) { return v >= 1 && v <= 8192 && v == std::floor(v); };
  if (!whole(size.x()) || !whole(size.y()))
    throw ArgError{o.arg(), "field 'size' must be two whole numbers within 1..8192 (width, height in pixels), got {" +
                                number_text(size.x()) + ", " + number_text(size.y()) + "}"};
  return size;
}

void read_drawn(lua_State* L, const char* fn, Drawn& drawn) {
  lua_geti(L, 1, 1);
  const int obj = lua_gettop(L);
  if (lua_isnil(L, obj)) throw ArgError{1, "needs the thing to draw as its first element, as " + std::string(fn) + "{s, out=...}"};
  if (const Wireframe* w = test_wireframe(L, obj)) {
    render::DrawItem item;
    item.lines = &w->lines;  // the Wireframe stays on the stack (t[1]) while it is drawn
    item.material.diffuse = w->color;
    drawn.items.push_back(item);
    lua_pop(L, 1);
    return;
  }
  if (const SceneNode* root = test_scene(L, obj)) {
    Stage stage(L, "mesh");
    Progress progress(L, "meshing the scene's parts", scene::flatten(*root).size());
    // A part that is a boolean of solids with their own materials shows each face in its solid's.
    const scene::TagMaterial tag_material = [L](int tag) -> std::optional<scene::OwnMaterial> {
      const int top = lua_gettop(L);
      std::optional<scene::OwnMaterial> own;
      if (push_tag_material(L, tag) == LUA_TTABLE) {
        own.emplace();
        try {
          own->first = read_material(L, lua_gettop(L), 1, own->second);
        } catch (...) {
          lua_settop(L, top);
          throw;
        }
      }
      lua_settop(L, top);
      return own;
    };
    scene::Drawable d = scene::draw_items(*root, current_tolerance(L), [&] { progress.step(); }, tag_material);
    // `drawn` is still empty here; swap keeps the items' pointers into the meshes valid.
    drawn.meshes.swap(d.meshes);
    drawn.items.swap(d.items);
    lua_pop(L, 1);
    return;
  }
  if (const Solid* s = test_solid(L, obj); s && draw_by_face_tags(L, obj, *s, drawn)) {
    lua_pop(L, 1);
    return;
  }
  render::DrawItem item;
  Mesh mesh;
  if (lua_istable(L, obj) && lua_getfield(L, obj, "vertices") != LUA_TNIL) {
    lua_pop(L, 1);
    mesh = read_mesh(L, obj, item.material, item.texture);
  } else {
    if (lua_istable(L, obj)) lua_pop(L, 1);
    {
      Stage stage(L, "mesh");
      // A solid shades flat across its faces' edges and smooth within a curved face, with the
      // normals of its surfaces.
      const Solid* s = test_solid(L, obj);
      mesh = s ? shading_mesh(*s, current_tolerance(L)) : to_mesh(L, obj, 1, current_tolerance(L));
    }
    if (test_solid(L, obj) && push_material(L, obj) == LUA_TTABLE) item.material = read_material(L, lua_gettop(L), 1, item.texture);
    else if (lua_gettop(L) > obj) lua_pop(L, 1);
    lua_settop(L, obj);
  }
  lua_pop(L, 1);
  drawn.meshes.push_back(with_uvs_if_textured(std::move(mesh), item.texture != nullptr));
  item.mesh = &drawn.meshes.back();
  drawn.items.push_back(std::move(item));
}

int render_fn(lua_State* L) {
  return options_call(L, [&] {
    check_table(L, 1);
    check_no_more(L, 1);
    Options o(L, 1);
    o.allow_positional();
    Drawn drawn;
    read_drawn(L, "render", drawn);
    const Box3 bounds = drawn.bounds();

    render::RenderOptions ro;
    std::string out = o.string("out", "");
    if (out.empty()) throw ArgError{1, "field 'out' is missing (the .png file to write)"};
    check_png_name(out);
    sandbox_check_path(L, out, true);
    const Vec2 size = image_size(o);
    ro.width = int(size.x()), ro.height = int(size.y());
    // camera={...}, or a named view: view="front" or view={"cabinet", angle=30} (or camera="front").
    std::optional<ViewChoice> view;
    if (o.push("view") != LUA_TNIL) view = read_view(L, lua_gettop(L), "view");
    lua_pop(L, 1);
    int camera_type = o.push("camera");
    if (camera_type != LUA_TNIL && view) throw ArgError{1, "give either camera={...} or view=, not both"};
    if (camera_type == LUA_TTABLE) {
      ro.camera = read_camera(L, lua_gettop(L), bounds);
    } else if (camera_type == LUA_TSTRING) {
      ro.camera = view_camera(read_view(L, lua_gettop(L), "camera"), bounds);
    } else if (camera_type != LUA_TNIL) {
      throw ArgError{1, "field 'camera' must be a table or a view name, got " + type_name(L, -1)};
    } else {
      ro.camera = view ? view_camera(*view, bounds) : render::named_view("iso", bounds);
    }
    lua_pop(L, 1);
    const int lights_type = o.push("lights");
    if (lights_type == LUA_TTABLE) {
      int top = lua_gettop(L);
      const auto n = static_cast<lua_Integer>(lua_rawlen(L, top));
      // One light without the list around it (lights={type="point", ...}) was a list of none.
      lua_pushnil(L);
      while (lua_next(L, top)) {
        lua_pop(L, 1);
        if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n) {
          const std::string key = lua_type(L, -1) == LUA_TSTRING ? "'" + std::string(lua_tostring(L, -1)) + "'" : type_name(L, -1);
          throw ArgError{1, "field 'lights' must be a list of lights, as lights={{type=\"point\", position={0, 0, 5}}}; it has a key " + key};
        }
      }
      if (n > 8) throw ArgError{1, "field 'lights' lists " + std::to_string(n) + " lights; OpenGL has 8"};
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_geti(L, top, i);
        const std::string name = "lights[" + std::to_string(i) + "]";
        if (!lua_istable(L, -1)) throw ArgError{1, "field '" + name + "' must be a table {type=, ...}, got " + type_name(L, -1)};
        ro.lights.push_back(read_light(L, lua_gettop(L), name));
        lua_pop(L, 1);
      }
    } else if (lights_type != LUA_TNIL) {
      throw ArgError{1, "field 'lights' must be a list of light tables {{type=, ...}, ...}, got " + describe(L, -1)};
    }
    lua_pop(L, 1);
    ro.ambient = opt_color(o, "ambient", ro.ambient);
    ro.local_viewer = o.boolean("local_viewer", false);
    ro.two_side = o.boolean("two_side", false);
    std::string shading = o.string("shading", "gouraud");
    if (shading == "flat") ro.shading = render::ShadeModel::Flat;
    else if (shading == "gouraud" || shading == "smooth") ro.shading = render::ShadeModel::Smooth;
    else if (shading == "phong") ro.shading = render::ShadeModel::Phong;
    else throw ArgError{1, "shading must be \"flat\", \"gouraud\" or \"phong\", got '" + shading + "'"};
    ro.wireframe = o.boolean("wireframe", false);
    ro.cull = o.string("cull", "back");
    if (ro.cull != "none" && ro.cull != "back" && ro.cull != "front" && ro.cull != "both")
      throw ArgError{1, "cull must be \"none\", \"back\", \"front\" or \"both\", got '" + ro.cull + "'"};
    std::string depth = o.string("depth", "less");
    const char* names[] = {"never", "less", "equal", "lequal", "greater", "notequal", "gequal", "always"};
    bool found = false;
    for (int i = 0; i < 8; ++i)
      if (depth == names[i]) ro.depth = static_cast<render::DepthFunc>(i), found = true;
    if (!found) throw ArgError{1, "depth must be one of never, less, equal, lequal, greater, notequal, gequal, always; got '" + depth + "'"};
    const int fog_type = o.push("fog");
    if (fog_type != LUA_TTABLE && fog_type != LUA_TNIL)
      throw ArgError{1, "field 'fog' must be a table {start=, stop=, color=}, got " + describe(L, -1)};
    if (fog_type == LUA_TTABLE) {
      int top = lua_gettop(L);
      Options f(L, top, 1, "fog");
      ro.fog = true;
      std::string mode = f.string("mode", "linear");
      ro.fog_mode = mode == "exp" ? render::FogMode::Exp : mode == "exp2" ? render::FogMode::Exp2 : render::FogMode::Linear;
      if (mode != "linear" && mode != "exp" && mode != "exp2")
        throw ArgError{1, "field 'fog.mode' must be \"linear\", \"exp\" or \"exp2\", got '" + mode + "'"};
      ro.fog_start = float(f.number("start", 0));
      ro.fog_end = float(f.number("stop", 1));
      ro.fog_density = float(f.number("density", 1));
      if (ro.fog_mode == render::FogMode::Linear && !(ro.fog_start < ro.fog_end))
        throw ArgError{1, "fog.start must be below fog.stop, got " + number_text(ro.fog_start) + " and " + number_text(ro.fog_end)};
      if (ro.fog_density < 0) throw ArgError{1, "field 'fog.density' must not be negative, got " + number_text(ro.fog_density)};
      ro.fog_color = opt_color(f, "color", ro.fog_color);
      f.finish();
    }
    lua_pop(L, 1);
    ro.antialias = o.integer("antialias", 1);
    if (ro.antialias < 1 || ro.antialias > 4) throw ArgError{1, "antialias must be 1, 2, 3 or 4"};
    check_pixel_budget(o, "an image", ro.width, ro.height, ro.antialias);
    ro.background = opt_color(o, "background", ro.background);
    o.finish();
    render::Image im;
    {
      Stage stage(L, "render");
      // A progress bar for a large render (on a terminal, after half a second): one step per
      // batch of triangles handed to the rasterizer.
      constexpr std::size_t kBatch = render::RenderOptions::kProgressTriangles;
      std::optional<Progress> bar;
      std::size_t batches_shown = 0;
      ro.progress = [&](std::size_t done, std::size_t total) {
        if (!bar) bar.emplace(L, "rendering", (total + kBatch - 1) / kBatch);
        for (const std::size_t batches = (done + kBatch - 1) / kBatch; batches_shown < batches; ++batches_shown) bar->step();
      };
      im = render::render_scene(drawn.items, ro);
    }
    Stage stage(L, "write");
    render::write_png(out, im);
    return 0;
  });
}

// drawing{s, out=, views={"front","top","side","iso"}, size={800, 600}, columns=, border=true,
// labels=true, titles=, edges=true, hidden="removed"|"dashed", background=, shading=, antialias=}:
// a sheet of views (any named view, or {name, options}), each titled, with the solid's edges drawn
// over its shaded faces and the hidden ones left out or dashed.
int drawing_fn(lua_State* L) {
  return options_call(L, [&] {
    check_table(L, 1);
    check_no_more(L, 1);
    Options o(L, 1);
    o.allow_positional();
    Drawn drawn;
    read_drawn(L, "drawing", drawn);
    const Box3 bounds = drawn.bounds();
    render::DrawingOptions d;
    std::string out = o.string("out", "");
    if (out.empty()) throw ArgError{1, "field 'out' is missing (the .png file to write)"};
    check_png_name(out);
    sandbox_check_path(L, out, true);
    int views_type = o.push("views");
    if (views_type == LUA_TTABLE) {
      int top = lua_gettop(L);
      d.views.clear();
      d.view_params.clear();
      for (lua_Integer i = 1, n = static_cast<lua_Integer>(lua_rawlen(L, top)); i <= n; ++i) {
        lua_geti(L, top, i);
        ViewChoice v = read_view(L, lua_gettop(L), "views[" + std::to_string(i) + "]");
        lua_pop(L, 1);
        view_camera(v, bounds);  // its options are checked here, before any rendering
        d.views.push_back(v.name);
        d.view_params.push_back(v.params);
      }
      if (d.views.empty() || d.views.size() > 16) throw ArgError{1, "views must list 1 to 16 view names"};
    } else if (views_type != LUA_TNIL) {
      throw ArgError{1, "field 'views' must be a list of view names, got " + type_name(L, -1)};
    }
    lua_pop(L, 1);
    const Vec2 size = image_size(o);
    d.width = int(size.x()), d.height = int(size.y());
    d.columns = o.integer("columns", 0);
    if (d.columns < 0 || d.columns > int(d.views.size()))
      throw ArgError{1, "field 'columns' must be within 0.." + std::to_string(d.views.size()) + " (0: automatic), got " +
                            std::to_string(d.columns)};
    d.border = o.boolean("border", true);
    d.labels = o.boolean("labels", true);
    d.edges = o.boolean("edges", true);
    const std::string hidden = o.string("hidden", "removed");
    if (hidden != "removed" && hidden != "dashed") throw ArgError{1, "field 'hidden' must be \"removed\" or \"dashed\", got '" + hidden + "'"};
    d.hidden_dashed = hidden == "dashed";
    if (o.push("titles") != LUA_TNIL) {
      const int top = lua_gettop(L);
      if (!lua_istable(L, top)) throw ArgError{1, "field 'titles' must be a list of strings, got " + type_name(L, top)};
      const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, top));
      if (std::size_t(n) != d.views.size())
        throw ArgError{1, "field 'titles' has " + std::to_string(n) + " titles for " + std::to_string(d.views.size()) + " views"};
      for (lua_Integer i = 1; i <= n; ++i) {
        if (lua_rawgeti(L, top, i) != LUA_TSTRING) throw ArgError{1, "titles[" + std::to_string(i) + "] must be a string, got " + type_name(L, -1)};
        d.titles.emplace_back(lua_tostring(L, -1));
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
    d.render.background = opt_color(o, "background", d.render.background);
    std::string shading = o.string("shading", "gouraud");
    if (shading == "flat") d.render.shading = render::ShadeModel::Flat;
    else if (shading == "gouraud" || shading == "smooth") d.render.shading = render::ShadeModel::Smooth;
    else if (shading == "phong") d.render.shading = render::ShadeModel::Phong;
    else throw ArgError{1, "shading must be \"flat\", \"gouraud\" or \"phong\", got '" + shading + "'"};
    d.render.antialias = o.integer("antialias", 1);
    if (d.render.antialias < 1 || d.render.antialias > 4) throw ArgError{1, "antialias must be 1, 2, 3 or 4"};
    check_pixel_budget(o, "a sheet", d.width, d.height, d.render.antialias);
    o.finish();
    render::Image im;
    {
      Stage stage(L, "render");
      Progress progress(L, "drawing views", d.views.size());
      d.view_done = [&] { progress.step(); };
      im = render::render_drawing(drawn.items, d);
    }
    Stage stage(L, "write");
    render::write_png(out, im);
    return 0;
  });
}

// checker{n=8, size=256, colors={{1,1,1},{0,0,0}}}: an n x n checkerboard texture.
int checker_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    int n = 8, size = 256;
    Vec4f a(1, 1, 1, 1), b(0, 0, 0, 1);
    if (!lua_isnoneornil(L, 1)) {
      Options o(L, 1);
      n = o.integer("n", 8);
      size = o.integer("size", 256);
      const int type = o.push("colors");
      if (type == LUA_TTABLE) {
        int t = lua_gettop(L);
        if (lua_rawlen(L, t) != 2) throw ArgError{1, "field 'colors' must hold two colours, got " + std::to_string(lua_rawlen(L, t))};
        lua_rawgeti(L, t, 1);
        a = to_color(L, lua_gettop(L), 1, "field 'colors[1]'");
        lua_pop(L, 1);
        lua_rawgeti(L, t, 2);
        b = to_color(L, lua_gettop(L), 1, "field 'colors[2]'");
        lua_pop(L, 1);
      } else if (type != LUA_TNIL) {
        throw ArgError{1, "field 'colors' must be two colours {{r,g,b}, {r,g,b}}, got " + type_name(L, -1)};
      }
      lua_pop(L, 1);
      o.finish();
    }
    if (n < 1 || size < 1 || size > 4096 || n > size)
      throw ArgError{1, "needs 1 <= n <= size <= 4096, got n = " + std::to_string(n) + ", size = " + std::to_string(size)};
    push_object<TexturePtr>(L, kTextureKey, render::Texture::checker(size, n, a, b));
    return 1;
  });
}

}  // namespace

void register_render(lua_State* L) {
  static const luaL_Reg meta[] = {{nullptr, nullptr}};
  static const luaL_Reg methods[] = {{nullptr, nullptr}};
  register_class(L, kTextureKey, "Texture", methods, meta, gc_object<TexturePtr>);
  static const luaL_Reg functions[] = {{"render", render_fn}, {"drawing", drawing_fn}, {"checker", checker_fn}, {nullptr, nullptr}};
  set_functions(L, functions);
}

}  // namespace wedge::lua
