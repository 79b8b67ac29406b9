-- Lighting, texture and fog: a textured block and a row of posts under a point light and a spot
-- light, shaded flat, Gouraud and Phong, and the same row fading into fog.
-- Run: wedge run examples/lighting.lua [out=directory] [shininess=40]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local shininess = params.shininess or 40

local block = box{size = {2, 2, 2}, center = true}:material{texture = checker{n = 8}, specular = {0.5, 0.5, 0.5}, shininess = shininess}
local post = box(0.6, 0.6, 2):material{diffuse = {0.8, 0.3, 0.2}, specular = {0.6, 0.6, 0.6}, shininess = shininess}
local row = array{post, count = 6, step = {0, 1.5, 0}}
local lights = {{type = "point", position = {4, -4, 5}, diffuse = {0.9, 0.9, 0.8}},
                {type = "spot", position = {0, 0, 6}, direction = {0, 0, -1}, cutoff = 25, exponent = 4,
                 diffuse = {0.4, 0.4, 1}}}
for _, shading in ipairs{"flat", "gouraud", "phong"} do
  render{block, out = out .. "/lighting-" .. shading .. ".png", size = {240, 240}, shading = shading,
         camera = {eye = {5, -6, 4}, center = {0, 0, 0}, up = {0, 0, 1}, fovy = 35}, lights = lights}
  print("wrote " .. out .. "/lighting-" .. shading .. ".png")
end
render{row, out = out .. "/fog.png", size = {400, 240}, shading = "phong",
       camera = {eye = {6, -3, 3}, center = {0, 4, 0.5}, up = {0, 0, 1}, fovy = 40},
       fog = {start = 4, stop = 14, color = {0.85, 0.85, 0.9}}, background = {0.85, 0.85, 0.9}}
print("wrote " .. out .. "/fog.png")
