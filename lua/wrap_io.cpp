// Lua bindings of mesh files: export(value, path [, {ascii=, tolerance=}]) and import(path).
#include <cctype>
#include <filesystem>
#include <map>

#include "kernel/file_io.h"
#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_curve.h"
#include "lua/wrap_render.h"
#include "lua/wrap_scene.h"
#include "lua/wrap_solid.h"
#include "lua/wrap_wireframe.h"
#include "tessellate/mesh_io.h"

namespace wedge::lua {

namespace {

// export(scene, "dir/name.ext", {split=true}): one file per leaf, "dir/name-K-symbol.ext" (K from 1
// in traversal order, the symbol's characters outside [A-Za-z0-9_-] as "_"); returns the list of
// paths written.
int export_split(lua_State* L, const std::string& path, const Tolerance& tol, const MeshWriteOptions& options) {
  const SceneNode* root = test_scene(L, 1);
  if (!root) throw ArgError{3, "field 'split' needs a scene group to split, got " + type_name(L, 1)};
  const std::size_t dot = path.find_last_of('.');  // mesh_format() has checked the extension
  const std::string stem = path.substr(0, dot), ext = path.substr(dot);
  std::vector<std::pair<std::string, Mesh>> files;
  {
    Stage stage(L, "mesh");
    const auto occs = scene::flatten(*root);
    Progress progress(L, "meshing the scene's parts", occs.size());
    for (std::size_t k = 0; k < occs.size(); ++k) {
      std::string symbol = occs[k].symbol;
      for (char& c : symbol)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
      std::string part = stem + "-" + std::to_string(k + 1) + "-" + symbol + ext;
      // Each part's own path under --sandbox, not only the base path: a symbolic link named
      // "out-1-solid.stl" beside the script led the write outside its folder. All are checked
      // before anything is meshed or written.
      sandbox_check_path(L, part, true);
      files.emplace_back(std::move(part), Mesh{});
    }
    for (std::size_t k = 0; k < occs.size(); ++k) {
      progress.step();
      files[k].second = scene::leaf_mesh(*occs[k].leaf, tol, false).transformed(occs[k].world);
    }
  }
  Stage stage(L, "write");
  // The set is written whole or not at all, as each file is: a part that could not be written
  // (part 3 a folder) left parts 1 and 2 behind. Every target is opened first (and dropped:
  // AtomicFile's checks of the folder and the name), so such a part stops the export before any
  // file is touched; a write that fails later (a full disk, Ctrl-C) removes the parts this export
  // has already written.
  for (const auto& file : files) AtomicFile probe(file.first);
  lua_createtable(L, int(files.size()), 0);
  Progress progress(L, "writing files", files.size());
  std::size_t written = 0;
  try {
    for (; written < files.size(); ++written) {
      progress.step();
      write_mesh(files[written].second, files[written].first, options);
      lua_pushstring(L, files[written].first.c_str());
      lua_rawseti(L, -2, lua_Integer(written + 1));
    }
  } catch (...) {
    for (std::size_t k = 0; k < written; ++k) {
      // What AtomicFile replaced: the file a symbolic link names, not the link.
      std::error_code ec;
      const auto target = std::filesystem::weakly_canonical(files[k].first, ec);
      std::filesystem::remove(ec ? std::filesystem::path(files[k].first) : target, ec);
    }
    throw;
  }
  return 1;
}

// The colour of each triangle of a solid's mesh (face ids indexing `tags`): the diffuse colour of
// the material its face came from (s:material{} on an operand of a boolean), else of the solid's
// own material, else OpenGL's default; empty when no face has a material.
std::vector<Vec3> triangle_colours(lua_State* L, int obj, const Mesh& mesh, const std::vector<int>& tags) {
  std::map<int, Vec3> colour;  // by tag; -1: the solid's own material
  bool any = false;
  auto of = [&](int tag) {
    auto it = colour.find(tag);
    if (it != colour.end()) return it->second;
    const int top = lua_gettop(L);
    const int type = tag >= 0 ? push_tag_material(L, tag) : push_material(L, obj);
    render::Material m;
    std::shared_ptr<const render::Texture> texture;
    if (type == LUA_TTABLE) {
      m = read_material(L, lua_gettop(L), 1, texture);
      any = true;
    }
    lua_settop(L, top);
    return colour[tag] = Vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
  };
  std::vector<Vec3> out(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::int32_t f = mesh.face_ids.empty() ? -1 : mesh.face_ids[t];
    out[t] = of(f >= 0 && static_cast<std::size_t>(f) < tags.size() ? tags[static_cast<std::size_t>(f)] : -1);
  }
  if (!any) out.clear();
  return out;
}

int export_fn(lua_State* L) {
  return table_call(L, 3, [&] {
    check_no_more(L, 3);
    std::string path = check_string(L, 2);
    sandbox_check_path(L, path, true);
    Tolerance tol = current_tolerance(L);
    MeshWriteOptions options;
    bool split = false;
    if (!lua_isnoneornil(L, 3)) {
      Options o(L, 3);
      options.ascii = o.boolean("ascii", false);
      tol.chordal = o.positive("tolerance", tol.chordal);
      if (auto n = o.number("max_triangles")) tol.max_triangles = std::size_t(check_max_triangles(*n, 3));
      if (auto n = o.number("max_crossings")) tol.max_crossings = std::size_t(check_budget("max_crossings", *n, 3));
      split = o.boolean("split", false);
      o.finish();
    }
    if (const Wireframe* w = test_wireframe(L, 1)) {
      if (split) throw ArgError{3, "field 'split' needs a scene group to split, got Wireframe"};
      Stage stage(L, "write");
      write_wireframe_obj(*w, path);
      std::size_t n = 0;
      for (const auto& line : w->lines) n += line.size() - 1;
      lua_pushinteger(L, lua_Integer(n));  // segments written
      return 1;
    }
    mesh_format(path);  // an unknown extension is an error before any tessellation work
    if (split) return export_split(L, path, tol, options);
    // A single surface is exported welded (closed seams merged, poles collapsed), so a closed
    // surface such as a sphere or torus makes a closed file; several patches are exported as
    // they are (patches are not welded to each other).
    const LuaSurface* surface = test_surface(L, 1);
    Mesh mesh;
    {
      Stage stage(L, "mesh");
      const std::string format = mesh_format(path);
      const Solid* solid = test_solid(L, 1);
      if (solid && (format == "obj" || format == "ply")) {
        // OBJ: each vertex's normal from its face's surface and its uv from the parameters
        // (vertices split per face; a reader welds them back by position). PLY: the shared
        // vertices that MeshLab checks for a 2-manifold. Both: a colour per face from the
        // materials of the solids the faces came from.
        mesh = format == "obj" ? solid->shaded_mesh(tol) : solid->tagged_mesh(tol);
        options.triangle_colors = triangle_colours(L, 1, mesh, solid->face_tags(tol));
        // The material library written beside an OBJ with colours is a path of its own, checked
        // as the OBJ's is (a symbolic link "x.mtl" would lead the write elsewhere).
        if (format == "obj" && !options.triangle_colors.empty())
          sandbox_check_path(L, path.substr(0, path.find_last_of('.')) + ".mtl", true);
      } else {
        mesh = surface && surface->patches.size() == 1 ? surface_mesh(*surface, tol.chordal, true, tol.max_triangles) : to_mesh(L, 1, 1, tol);
      }
    }
    Stage stage(L, "write");
    write_mesh(mesh, path, options);
    lua_pushinteger(L, static_cast<lua_Integer>(mesh.triangle_count()));
    return 1;
  });
}

int import_fn(lua_State* L) {
  return guarded(L, [&] {
    std::string path = check_string(L, 1);
    check_no_more(L, 1);
    sandbox_check_path(L, path, false);
    Stage stage(L, "read");
    push_solid(L, Solid::from_mesh(read_mesh(path), path));
    return 1;
  });
}

// Free-form surfaces (and the teapot's patches) export and render as their meshes.
std::optional<Mesh> surface_to_mesh(lua_State* L, int idx, const Tolerance& tol) {
  if (const LuaSurface* s = test_surface(L, idx)) return surface_mesh(*s, tol.chordal, false, tol.max_triangles);
  return std::nullopt;
}

const luaL_Reg kFunctions[] = {{"export", export_fn}, {"import", import_fn}, {nullptr, nullptr}};

}  // namespace

void register_io(lua_State* L) {
  set_functions(L, kFunctions);
  add_mesh_converter(L, surface_to_mesh);
}

}  // namespace wedge::lua
