// Lua bindings of scenes (API.md "Scenes"): group{}, g:add(), instance(), array{}, radial_array{},
// g:copy(), g:bounds(), g:table(); a group exports and renders as the meshes of its leaves placed
// by their world matrices. The model, the traversal and the instance table are scene/scene.h's.
#include "lua/wrap_scene.h"

#include <cmath>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_matrix.h"
#include "lua/wrap_render.h"
#include "lua/wrap_solid.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Group";
using NodePtr = std::shared_ptr<SceneNode>;

NodePtr& self(lua_State* L) { return check_object<NodePtr>(L, 1, kKey, "Group"); }
NodePtr* test_group(lua_State* L, int idx) { return test_object<NodePtr>(L, idx, kKey); }

void push_group(lua_State* L, NodePtr node) { push_object(L, kKey, std::move(node)); }

// A transform for a scene node: a finite, affine, invertible Matrix.
Mat4 checked_transform(const Mat4& m, int arg, const std::string& what) {
  return as_arg(arg, [&] { return scene::checked_transform(m, what); });
}

// The value at idx as a child node: a group as itself (shared), anything drawable as a new leaf.
NodePtr child_node(lua_State* L, int idx, int arg) {
  idx = lua_absindex(L, idx);
  if (NodePtr* g = test_group(L, idx)) return *g;
  auto leaf = std::make_shared<SceneLeaf>();
  if (const Solid* s = test_solid(L, idx)) {
    if (s->empty()) throw ArgError{arg, "the empty solid cannot be part of a scene"};
    // A boolean with nothing left (box(1,1,1) - box(1,1,1)) is refused here too, whichever
    // function adds it: let in, it was a row of table() for a part that does not exist, and bounds,
    // export, render and drawing each answered it differently (an error, a white picture).
    bool nothing = false;
    {
      Stage stage(L, "mesh");
      nothing = s->evaluates_empty(current_tolerance(L));
    }
    if (nothing)
      throw ArgError{arg, "the solid is empty (its boolean leaves nothing): the empty solid cannot be part of a scene"};
    leaf->solid = *s;
    if (push_material(L, idx) == LUA_TTABLE) {
      std::shared_ptr<const render::Texture> texture;
      leaf->material = read_material(L, lua_gettop(L), arg, texture);
      leaf->texture = texture;
    }
    lua_pop(L, 1);
  } else if (lua_type(L, idx) == LUA_TNIL || lua_type(L, idx) == LUA_TNONE) {
    throw ArgError{arg, "Group, Solid or surface expected, got nil"};
  } else {
    try {
      Stage stage(L, "mesh");  // a surface is meshed when it joins the scene
      leaf->mesh = to_mesh(L, idx, arg, current_tolerance(L));
    } catch (const ArgError&) {
      throw ArgError{arg, "Group, Solid or surface expected, got " + type_name(L, idx)};
    }
    if (leaf->mesh.empty()) throw ArgError{arg, "a scene part needs triangles; this " + type_name(L, idx) + " has none"};
  }
  auto node = std::make_shared<SceneNode>();
  node->leaf = std::move(leaf);
  return node;
}

void add_child(SceneNode& parent, NodePtr child, int arg) {
  as_arg(arg, [&] { scene::add(parent, std::move(child)); });
}

// Reads transform=, name=, material= from the options into a node.
void read_node_options(lua_State* L, Options& o, SceneNode& node) {
  if (o.push("transform") != LUA_TNIL) {
    const Mat4* m = test_matrix(L, -1);
    if (!m) throw ArgError{o.arg(), "field 'transform' must be a Matrix (from matrix.*), got " + type_name(L, -1)};
    node.transform = checked_transform(*m, o.arg(), "field 'transform'");
  }
  lua_pop(L, 1);
  node.name = o.string("name", "");
  if (o.push("material") != LUA_TNIL) {
    std::shared_ptr<const render::Texture> texture;
    node.material = read_material(L, lua_gettop(L), o.arg(), texture);
    node.texture = texture;
  }
  lua_pop(L, 1);
}

// group() | group{child, ..., transform=, name=, material=}
int group_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    check_no_more(L, 1);  // group({}, 5) ignored the 5; box(1, 1, 1, 1) is refused
    auto node = std::make_shared<SceneNode>();
    if (!lua_isnoneornil(L, 1)) {
      Options o(L, 1);
      o.allow_positional();
      read_node_options(L, o, *node);
      o.finish();
      const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, 1));
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, 1, i);
        if (lua_isnil(L, -1)) throw ArgError{1, "element " + std::to_string(i) + " is nil"};
        NodePtr child;
        try {
          child = child_node(L, -1, 1);
        } catch (const ArgError& e) {
          throw ArgError{1, "element " + std::to_string(i) + ": " + e.message};
        }
        add_child(*node, std::move(child), 1);
        lua_pop(L, 1);
      }
    }
    push_group(L, std::move(node));
    return 1;
  });
}

// g:add(x, ...): adds each as a child; returns g.
int add_m(lua_State* L) {
  return guarded(L, [&] {
    NodePtr g = self(L);
    const int n = lua_gettop(L);
    if (n < 2) throw ArgError{2, "Group, Solid or surface expected, got no value"};
    std::vector<NodePtr> children;
    for (int i = 2; i <= n; ++i) children.push_back(child_node(L, i, i));
    for (int i = 2; i <= n; ++i) add_child(*g, children[std::size_t(i - 2)], i);
    lua_settop(L, 1);
    return 1;
  });
}

// g:copy(): a new tree equal to g now; later changes to g or its parts do not reach it.
int copy_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    push_group(L, scene::copy(self(L)));
    return 1;
  });
}

// The table form's one positional element (the thing to share or repeat) is there, alone. The
// message does not name the function: the error's prefix does ("array: ...").
void one_element(lua_State* L, const char* what, const char* then) {
  const auto n = lua_rawlen(L, 1);
  if (n == 0) throw ArgError{1, std::string(what) + " expected as the first element, then " + then + "; got none"};
  if (n > 1) throw ArgError{1, std::string(what) + " expected as the first element, then " + then + "; got " + std::to_string(n) + " elements"};
}

// instance(x [, {transform=, name=, material=}]): a node that shares x (a Group: every change to it
// shows in every instance) under a transform of its own.
// Also in the table form, instance{x, transform=, name=, material=}, as array{} and group{}.
int instance_fn(lua_State* L) {
  return table_call(L, 2, [&] {
    auto node = std::make_shared<SceneNode>();
    // A plain table is never a thing to share (those are Groups, Solids and surfaces): it is the
    // table form, also when its first element is missing (instance{}).
    const bool table_form = lua_type(L, 1) == LUA_TTABLE;
    if (table_form) {
      if (!lua_isnone(L, 2)) throw ArgError{2, "the table form instance{x, ...} takes its options inside the table, got a second argument"};
      try {  // an error in the one table is named by its field, as array{} names its own
        Options o(L, 1);
        o.allow_positional();
        one_element(L, "one thing to share", "transform=, name=, material=");
        read_node_options(L, o, *node);
        o.finish();
        lua_rawgeti(L, 1, 1);
        NodePtr proto = child_node(L, -1, 1);
        lua_pop(L, 1);
        add_child(*node, std::move(proto), 1);
      } catch (const ArgError& e) {
        if (e.arg != 1) throw;
        throw Error(field_message(e.message));
      }
      push_group(L, std::move(node));
      return 1;
    }
    check_no_more(L, 2);
    NodePtr proto = child_node(L, 1, 1);
    if (!lua_isnoneornil(L, 2)) {
      Options o(L, 2);
      read_node_options(L, o, *node);
      o.finish();
    }
    add_child(*node, std::move(proto), 1);
    push_group(L, std::move(node));
    return 1;
  });
}

int required_count(Options& o) {
  if (!o.has("count")) throw ArgError{1, "field 'count' is missing (how many copies)"};
  // The range before the integer test: 2^53 and math.maxinteger are integers, and were told
  // "must be an integer".
  const double count = *o.number("count");
  if (count != std::floor(count)) throw ArgError{1, "field 'count' must be an integer, got " + number_text(count)};
  if (count < 1 || count > 100000) throw ArgError{1, "field 'count' must be within 1..100000, got " + number_text(count)};
  return static_cast<int>(count);
}

// array{x, count=, step={dx, dy, dz}, transform=, name=}: count instances of x, the k-th (from 0)
// translated by k * step.
int array_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    check_table(L, 1);
    check_no_more(L, 1);
    Options o(L, 1);
    o.allow_positional();
    one_element(L, "one thing to repeat", "count= and step=");
    const int count = required_count(o);
    auto step = o.vec3("step");
    if (!step) throw ArgError{1, "field 'step' is missing (the offset between copies, {dx, dy, dz})"};
    auto node = std::make_shared<SceneNode>();
    read_node_options(L, o, *node);
    o.finish();
    lua_rawgeti(L, 1, 1);
    NodePtr proto = child_node(L, -1, 1);
    lua_pop(L, 1);
    // The last copy's offset, (count - 1) * step, within the coordinates a solid may have.
    const Vec3 reach = double(count - 1) * *step;
    if (!(reach.cwiseAbs().maxCoeff() <= kMaxCoordinate))
      throw ArgError{1, "field 'step' {" + number_text(step->x()) + ", " + number_text(step->y()) + ", " + number_text(step->z()) +
                            "} puts copy " + std::to_string(count) + " at " + number_text(reach.cwiseAbs().maxCoeff()) +
                            ", beyond +-" + number_text(kMaxCoordinate)};
    NodePtr copies = as_arg(1, [&] { return scene::array(proto, count, *step); });
    node->children = std::move(copies->children);
    push_group(L, std::move(node));
    return 1;
  });
}

// radial_array{x, count=, radius=, axis={0,0,1}, center={0,0,0}, angle=360, transform=, name=}:
// count instances of x, each moved `radius` out from the axis (towards the direction of x
// perpendicular to the axis, or y if the axis is x) and turned about the axis through `center` by
// k * angle / count (k * angle / (count - 1) when angle < 360, so that both ends are used).
int radial_array_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    check_table(L, 1);
    check_no_more(L, 1);
    Options o(L, 1);
    o.allow_positional();
    one_element(L, "one thing to repeat", "count= and radius=");
    const int count = required_count(o);
    if (!o.has("radius")) throw ArgError{1, "field 'radius' is missing (the distance from the axis)"};
    const double radius = o.number("radius", 0);
    if (radius < 0) throw ArgError{1, "field 'radius' must not be negative, got " + number_text(radius)};
    const Vec3 axis = o.vec3("axis", Vec3(0, 0, 1));
    if (axis.norm() == 0) throw ArgError{1, "field 'axis' must be non-zero"};
    const Vec3 center = o.vec3("center", Vec3::Zero());
    // Within the coordinates a solid may have, as array's step is (radius = 1e300 put every copy
    // there, flattened to a point by rounding).
    if (!(radius + center.cwiseAbs().maxCoeff() <= kMaxCoordinate))
      throw ArgError{1, "field 'radius' " + number_text(radius) + " about center {" + number_text(center.x()) + ", " +
                            number_text(center.y()) + ", " + number_text(center.z()) + "} puts the copies beyond +-" +
                            number_text(kMaxCoordinate)};
    const double angle = o.number("angle", 360);
    if (!(angle > 0) || angle > 360) throw ArgError{1, "field 'angle' must be within 0..360 (above 0), got " + number_text(angle)};
    auto node = std::make_shared<SceneNode>();
    read_node_options(L, o, *node);
    o.finish();
    lua_rawgeti(L, 1, 1);
    NodePtr proto = child_node(L, -1, 1);
    lua_pop(L, 1);
    NodePtr copies = as_arg(1, [&] { return scene::radial_array(proto, count, radius, axis, Point3(center), angle); });
    node->children = std::move(copies->children);
    push_group(L, std::move(node));
    return 1;
  });
}

std::optional<Mesh> scene_to_mesh(lua_State* L, int idx, const Tolerance& tol) {
  if (const SceneNode* n = test_scene(L, idx)) return scene::mesh(*n, tol);
  return std::nullopt;
}

// g:bounds(): {min=, max=} of the leaves' meshes in world coordinates.
int bounds_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    const Box3 b = scene::bounds(*self(L), current_tolerance(L));
    // Parts that are all empty solids (box(1,1,1) - box(1,1,1)) have no extent: an error, not
    // min = inf, max = -inf.
    if (b.empty()) throw Error("the scene's parts are all empty solids: it has no bounds");
    lua_createtable(L, 0, 2);
    push_vec3(L, b.min);
    lua_setfield(L, -2, "min");
    push_vec3(L, b.max);
    lua_setfield(L, -2, "max");
    return 1;
  });
}

// g:table(): the instance table, one row per leaf in traversal order:
// {symbol=, path=, translation={x,y,z}, rotation={x,y,z} (degrees, matrix.euler's order),
//  scale={sx,sy,sz}, shear=false, matrix=M_world}
int table_m(lua_State* L) {
  return guarded(L, [&] {
    check_no_more_method(L, 1);
    const auto rows = scene::instance_table(*self(L));
    lua_createtable(L, int(rows.size()), 0);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const scene::InstanceRow& d = rows[i];
      lua_createtable(L, 0, 7);
      lua_pushstring(L, d.symbol.c_str());
      lua_setfield(L, -2, "symbol");
      lua_pushstring(L, d.path.c_str());
      lua_setfield(L, -2, "path");
      push_vec3(L, d.translation);
      lua_setfield(L, -2, "translation");
      push_vec3(L, d.rotation);
      lua_setfield(L, -2, "rotation");
      push_vec3(L, d.scale);
      lua_setfield(L, -2, "scale");
      lua_pushboolean(L, d.shear);
      lua_setfield(L, -2, "shear");
      push_matrix_value(L, d.world);
      lua_setfield(L, -2, "matrix");
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  });
}

const luaL_Reg kMethods[] = {{"add", add_m},       {"copy", copy_m}, {"bounds", bounds_m},
                             {"table", table_m},   {nullptr, nullptr}};

// g.transform, g.name (read and write), g.children (a list of the child groups; leaves appear as
// nil-free placeholders: their geometry is not a Lua value any more), #g, and the methods.
int index_m(lua_State* L) {
  return guarded(L, [&] {
    NodePtr& g = self(L);
    const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
    if (key == "transform") {
      push_matrix_value(L, g->transform);
      return 1;
    }
    if (key == "name") {
      lua_pushstring(L, g->name.c_str());
      return 1;
    }
    for (const luaL_Reg* m = kMethods; m->name; ++m)
      if (key == m->name) {
        lua_pushcfunction(L, m->func);
        return 1;
      }
    throw Error("Group has no field or method '" + (key.empty() ? describe(L, 2) : key) +
                "' (it has transform, name, add, copy, bounds, table)");
  });
}

int newindex_m(lua_State* L) {
  return guarded(L, [&] {
    NodePtr& g = self(L);
    const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
    if (key == "transform") {
      const Mat4* m = test_matrix(L, 3);
      if (!m) throw Error("Group transform must be a Matrix (from matrix.*), got " + type_name(L, 3));
      try {
        g->transform = checked_transform(*m, 3, "Group transform");
      } catch (const ArgError& e) {
        throw Error(e.message);
      }
    } else if (key == "name") {
      if (lua_type(L, 3) != LUA_TSTRING) throw Error("Group name must be a string, got " + type_name(L, 3));
      g->name = lua_tostring(L, 3);
    } else {
      throw Error("Group has no field '" + (key.empty() ? describe(L, 2) : key) + "' to set (transform, name)");
    }
    return 0;
  });
}

int len_m(lua_State* L) {
  return guarded(L, [&] {
    lua_pushinteger(L, lua_Integer(self(L)->children.size()));
    return 1;
  });
}

int tostring_m(lua_State* L) {
  return guarded(L, [&] {
    const std::string s = scene::describe(*self(L));  // as errors name groups
    lua_pushlstring(L, s.data(), s.size());
    return 1;
  });
}

const luaL_Reg kMeta[] = {{"__index", index_m},
                          {"__newindex", newindex_m},
                          {"__len", len_m},
                          {"__tostring", tostring_m},
                          {nullptr, nullptr}};

const luaL_Reg kFunctions[] = {{"group", group_fn},
                               {"instance", instance_fn},
                               {"array", array_fn},
                               {"radial_array", radial_array_fn},
                               {nullptr, nullptr}};

}  // namespace

const SceneNode* test_scene(lua_State* L, int idx) {
  NodePtr* g = test_group(L, idx);
  return g ? g->get() : nullptr;
}

void register_scene(lua_State* L) {
  // Methods are reached through __index (which also answers g.transform), so the class table of
  // methods stays empty; they are named "Group:add" etc. for errors all the same.
  register_class(L, kKey, "Group", kMethods, kMeta, gc_object<NodePtr>);
  set_functions(L, kFunctions);
  add_mesh_converter(L, scene_to_mesh);
}

}  // namespace wedge::lua
