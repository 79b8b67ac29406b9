-- The course's three-joint robot arm as a scene graph: each link is a group whose transform is its
-- joint (a rotation at the end of the link before it), so a child inherits everything above it
-- (M_world = M_parent * M_local). Joint angles are script arguments:
--   wedge run examples/robot_arm.lua base=30 shoulder=40 elbow=-70 wrist=20 [out=directory]
-- Without angles it draws three poses.
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")

-- A link of length `len` along +z, its joint at the origin.
local function link(len, w, color)
  return box{size = {w, w, len}}:translate(-w / 2, -w / 2, 0):material{diffuse = color, specular = {0.3, 0.3, 0.3}, shininess = 20}
end

local function arm(pose)
  local root = group{name = "robot"}
  local base = group{name = "base", transform = matrix.rotate(pose.base, "z")}
  local upper = group{name = "upper_arm", transform = matrix.translate(0, 0, 1) * matrix.rotate(pose.shoulder, "y")}
  local fore = group{name = "forearm", transform = matrix.translate(0, 0, 3) * matrix.rotate(pose.elbow, "y")}
  local hand = group{name = "hand", transform = matrix.translate(0, 0, 2.5) * matrix.rotate(pose.wrist, "y")}
  root:add(box{size = {3, 3, 0.3}}:translate(-1.5, -1.5, -0.3):material{diffuse = {0.4, 0.4, 0.45}})
  root:add(base)
  base:add(link(1, 1.2, {0.8, 0.3, 0.2}), upper)
  upper:add(link(3, 0.6, {0.9, 0.6, 0.2}), fore)
  fore:add(link(2.5, 0.45, {0.3, 0.6, 0.9}), hand)
  -- two fingers: instances of one prototype
  local finger = group{name = "finger"}
  finger:add(link(0.6, 0.15, {0.2, 0.2, 0.2}))
  hand:add(instance(finger, {transform = matrix.translate(0.15, 0, 0)}),
           instance(finger, {transform = matrix.translate(-0.15, 0, 0)}))
  return root
end

local poses
if params.shoulder or params.elbow or params.wrist or params.base then
  poses = {{base = params.base or 0, shoulder = params.shoulder or 0, elbow = params.elbow or 0, wrist = params.wrist or 0}}
else
  poses = {{base = 0, shoulder = 0, elbow = 0, wrist = 0},
           {base = 30, shoulder = 40, elbow = -70, wrist = 20},
           {base = -45, shoulder = -30, elbow = 100, wrist = -40}}
end

for i, pose in ipairs(poses) do
  local robot = arm(pose)
  local file = string.format("%s/robot-arm-%d.png", out, i)
  render{robot, out = file, size = {480, 480}, view = "iso",
         lights = {{type = "directional", direction = {-0.5, 0.3, -1}}}}
  print(string.format("pose %d (base %g, shoulder %g, elbow %g, wrist %g): wrote %s",
                      i, pose.base, pose.shoulder, pose.elbow, pose.wrist, file))
  if i == #poses then
    -- The instance table: every part with its symbol and world scale, rotation, translation.
    print(string.format("%-3s %-10s %-26s %-26s %s", "#", "symbol", "translation", "rotation (deg)", "scale"))
    for k, row in ipairs(robot:table()) do
      local v = function(t) return string.format("(%.2f, %.2f, %.2f)", t[1], t[2], t[3]) end
      print(string.format("%-3d %-10s %-26s %-26s %s", k, row.symbol, v(row.translation), v(row.rotation), v(row.scale)))
    end
    local b = robot:bounds()
    print(string.format("bounds (%.2f, %.2f, %.2f) .. (%.2f, %.2f, %.2f)", b.min[1], b.min[2], b.min[3], b.max[1], b.max[2], b.max[3]))
    export(robot, out .. "/robot-arm.obj")
    print("wrote " .. out .. "/robot-arm.obj")
  end
end
