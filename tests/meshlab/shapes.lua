-- Every primitive and builder of the Lua API, exported as STL, PLY and OFF into arg[1], with the
-- topology MeshLab must find in each, worked out by hand: one line per file,
-- "path components genus" (genus summed over the components).
local out = arg[1]
local square = polygon{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}
local holed = polygon{outer = {{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, holes = {{{-1, -1}, {-1, 1}, {1, 1}, {1, -1}}}}
local rect = polygon{{1, 0}, {2, 0}, {2, 1}, {1, 1}}
local pot = teapot()
local function pot_patches(ranges)
  local out = {}
  for _, r in ipairs(ranges) do
    for i = r[1], r[2] do out[#out + 1] = pot:patch(i) end
  end
  return out
end
local shapes = {
  {"box", box(1, 2, 3), 1, 0},
  {"polyhedron", polyhedron{points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, faces = {{1, 3, 2}, {1, 2, 4}, {1, 4, 3}, {2, 3, 4}}}, 1, 0},
  {"sphere", sphere(1), 1, 0},
  {"cylinder", cylinder(1, 2), 1, 0},
  {"frustum", cone{r1 = 1, r2 = 0.5, h = 2}, 1, 0},
  {"cone", cone{r1 = 1, r2 = 0, h = 2}, 1, 0},
  {"torus", torus{R = 2, r = 0.5}, 1, 1},
  {"tube", tube{r_outer = 2, r_inner = 1, h = 1}, 1, 1},
  {"prism_with_hole", extrude(holed, 1), 1, 1},
  {"prism_with_circle_holes", extrude(polygon{outer = {{-3, -2}, {3, -2}, {3, 2}, {-3, 2}}, holes = {circle(0.5), {{1.5, -0.5}, {2.5, -0.5}, {2.5, 0.5}, {1.5, 0.5}}}}, 1), 1, 2},
  {"twisted", extrude(square, 2, {twist = 90}), 1, 0},
  {"twisted_scaled_circle", extrude(circle(1), 2, {twist = 45, scale = 0.5}), 1, 0},
  {"scaled_with_hole", extrude(holed, 1, {scale = 0.5}), 1, 1},
  {"pyramid", extrude(square, 1, {scale = 0}), 1, 0},
  {"revolved", revolve(rect), 1, 1},
  {"revolved_90", revolve(rect, {angle = 90}), 1, 0},
  {"revolved_on_axis", revolve(polygon{{0, 0}, {1, 0}, {0, 1}}), 1, 0},
  {"revolved_with_hole", revolve(polygon{outer = {{1, -1}, {3, -1}, {3, 1}, {1, 1}}, holes = {{{1.5, -0.5}, {2.5, -0.5}, {2.5, 0.5}, {1.5, 0.5}}}}), 2, 2},
  {"swept", sweep(circle(0.3), bezier{{0, 0, 0}, {1, 0, 1}, {2, 1, 1}, {3, 1, 2}}), 1, 0},
  {"swept_closed", sweep(circle(0.5), circle(2)), 1, 1},
  {"lofted", loft{profiles = {circle(1), circle(2), circle(1)}, heights = {0, 1, 2}}, 1, 0},
  {"teapot_body", patch_solid(pot_patches{{1, 12}, {29, 32}}), 1, 0},
  {"teapot_lid", patch_solid(pot_patches{{21, 28}}), 1, 0},
  {"lofted_squares", loft{profiles = {square, polygon{{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}}, heights = {0, 2}}, 1, 0},
}
tolerance(0.01)
for _, s in ipairs(shapes) do
  local name, solid, components, genus = s[1], s[2], s[3], s[4]
  for _, ext in ipairs{"stl", "ply", "off"} do
    local path = out .. "/" .. name .. "." .. ext
    export(solid, path)
    print(path, components, genus)
  end
end
