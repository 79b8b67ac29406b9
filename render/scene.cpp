// render_scene: a mesh drawn through a Context with a camera, lights and materials, the way
// Lua's render{} asks for it. Supersampling renders at antialias x the size and box-filters down.
#include <cmath>

#include "render/render.h"

namespace wedge::render {

Camera named_view(const std::string& name, const Box3& bounds) {
  Camera c;
  Vec3 dir;
  Vec3 up(0, 0, 1);
  if (name == "iso") dir = Vec3(1, -1, 1);
  else if (name == "dimetric") dir = Vec3(1, -2, 1.5);
  else if (name == "front") dir = Vec3(0, -1, 0);
  else if (name == "top") dir = Vec3(0, 0, 1), up = Vec3(0, 1, 0);
  else if (name == "side") dir = Vec3(1, 0, 0);
  else if (name == "oblique") dir = Vec3(0.5, -1, 0.5);
  else fail("unknown view '", name, "' (expected iso, dimetric, front, top, side or oblique)");
  Point3 center = bounds.empty() ? Point3::Zero() : Point3(bounds.center());
  double r = bounds.empty() ? 1.0 : std::max(1e-9, 0.5 * bounds.diagonal());
  c.orthographic = true;
  c.center = center;
  c.eye = center + dir.normalized() * (3 * r);
  c.up = up;
  c.left = -r * 1.1, c.right = r * 1.1, c.bottom = -r * 1.1, c.top = r * 1.1;
  c.near = r * 0.5, c.far = r * 6;
  c.fit = true;
  return c;
}

Image downsample(const Image& im, int f) {
  if (f <= 1) return im;
  Image out;
  out.width = im.width / f, out.height = im.height / f;
  out.rgba.resize(std::size_t(out.width) * out.height * 4);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int k = 0; k < 4; ++k) {
        int sum = 0;
        for (int dy = 0; dy < f; ++dy)
          for (int dx = 0; dx < f; ++dx) sum += im.rgba[((std::size_t(y) * f + dy) * im.width + x * f + dx) * 4 + k];
        out.rgba[(std::size_t(y) * out.width + x) * 4 + k] = std::uint8_t((sum + f * f / 2) / (f * f));
      }
  return out;
}

Image render_scene(const std::vector<DrawItem>& items, const RenderOptions& o) {
  if (o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192)
    fail("render: size ", o.width, "x", o.height, " must be within 1..8192");
  if (o.antialias < 1 || o.antialias > 4) fail("render: antialias ", o.antialias, " must be 1, 2, 3 or 4");
  if (o.lights.size() > 8) fail("render: at most 8 lights, got ", o.lights.size());
  const int aa = o.antialias, W = o.width * aa, H = o.height * aa;
  Context g(W, H);
  g.clear_color(o.background[0], o.background[1], o.background[2], o.background[3]);
  g.clear();
  Box3 bounds;
  for (const auto& it : items)
    if (it.mesh)
      for (const auto& p : it.mesh->positions) bounds.extend(apply_point(it.transform, p));

  const Camera& c = o.camera;
  const Mat4 view = look_at(c.eye, c.center, c.up);
  double n = c.near, f = c.far;
  if (c.fit && !bounds.empty()) {
    // Near and far just around the scene, so the depth buffer's precision is spent on it.
    double zmin = 1e300, zmax = -1e300;
    for (int i = 0; i < 8; ++i) {
      Point3 corner((i & 1) ? bounds.max.x() : bounds.min.x(), (i & 2) ? bounds.max.y() : bounds.min.y(),
                    (i & 4) ? bounds.max.z() : bounds.min.z());
      double z = -(view * corner.homogeneous()).z();
      zmin = std::min(zmin, z), zmax = std::max(zmax, z);
    }
    double pad = 0.01 * (zmax - zmin) + 1e-6;
    f = zmax + pad;
    n = c.orthographic ? zmin - pad : std::max(zmin - pad, f * 1e-4);
  }
  g.matrix_mode(MatrixMode::Projection);
  g.load_identity();
  const double aspect = double(W) / H;
  if (c.orthographic) {
    double l = c.left, r = c.right, b = c.bottom, t = c.top;
    // Keep square pixels: widen the box to the image's aspect.
    double cx = 0.5 * (l + r), hw = 0.5 * (r - l), hh = 0.5 * (t - b);
    if (hw / hh < aspect) hw = hh * aspect;
    else hh = hw / aspect;
    g.ortho(cx - hw, cx + hw, 0.5 * (b + t) - hh, 0.5 * (b + t) + hh, n, f);
  } else {
    g.perspective(c.fovy, aspect, n, f);
  }
  g.matrix_mode(MatrixMode::ModelView);
  g.load_identity();

  g.enable(Cap::Lighting);
  g.enable(Cap::Normalize);
  g.light_model_ambient(o.ambient);
  g.light_model_local_viewer(o.local_viewer);
  g.light_model_two_side(o.two_side);
  std::vector<LightSpec> lights = o.lights;
  if (lights.empty()) {
    LightSpec head;  // a headlight from over the viewer's shoulder
    head.type = LightSpec::Type::Directional;
    head.direction = Vec3(-0.3, -0.4, -1);
    head.eye_space = true;
    head.specular = Vec4f(0.3f, 0.3f, 0.3f, 1);
    lights.push_back(head);
  }
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const LightSpec& L = lights[i];
    const int k = int(i);
    g.load_identity();
    if (!L.eye_space) g.mult_matrix(view);
    g.enable(light_cap(k));
    g.light_ambient(k, L.ambient);
    g.light_diffuse(k, L.diffuse);
    g.light_specular(k, L.specular);
    if (L.type == LightSpec::Type::Directional) {
      Vec3 d = -L.direction;
      g.light_position(k, Vec4f(float(d.x()), float(d.y()), float(d.z()), 0));
    } else {
      g.light_position(k, Vec4f(float(L.position.x()), float(L.position.y()), float(L.position.z()), 1));
      g.light_attenuation(k, float(L.attenuation.x()), float(L.attenuation.y()), float(L.attenuation.z()));
      if (L.type == LightSpec::Type::Spot) {
        g.light_spot_direction(k, L.direction);
        g.light_spot(k, L.exponent, L.cutoff);
      }
    }
  }
  g.load_identity();
  g.mult_matrix(view);

  g.enable(Cap::DepthTest);
  g.depth_func(o.depth);
  if (o.cull != "none") {
    g.enable(Cap::CullFace);
    if (o.cull == "back") g.cull_face(Face::Back);
    else if (o.cull == "front") g.cull_face(Face::Front);
    else if (o.cull == "both") g.cull_face(Face::FrontAndBack);
    else fail("render: cull must be \"none\", \"back\", \"front\" or \"both\", got '", o.cull, "'");
  }
  g.shade_model(o.shading);
  if (o.wireframe) g.polygon_mode(Face::FrontAndBack, PolygonMode::Line);
  if (o.fog) {
    g.enable(Cap::Fog);
    g.fog_mode(o.fog_mode);
    g.fog_color(o.fog_color);
    g.fog_start(o.fog_start);
    g.fog_end(o.fog_end);
    g.fog_density(o.fog_density);
  }
  if (aa > 1) g.line_width(float(aa)), g.point_size(float(aa));

  for (const auto& it : items) {
    if (!it.mesh) continue;
    it.mesh->check();
    const Mesh& m = *it.mesh;
    g.push_matrix();
    g.mult_matrix(it.transform);
    g.material(Face::FrontAndBack, it.material);
    if (it.texture) {
      g.enable(Cap::Texture2D);
      g.bind_texture(it.texture);
      g.tex_env_mode(TexEnvMode::Modulate);
    } else {
      g.disable(Cap::Texture2D);
    }
    const bool flat = o.shading == ShadeModel::Flat;
    std::vector<Vec3> normals = m.normals;
    if (normals.empty() && !flat) {
      Mesh copy = m;
      copy.compute_vertex_normals();  // area-weighted, only where the mesh has none
      normals = copy.normals;
    }
    g.begin(Primitive::Triangles);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      if (flat) {
        Vec3 fn = m.triangle_normal(t);  // a flat face is lit with its geometric normal
        g.normal(fn.x(), fn.y(), fn.z());
      }
      for (std::uint32_t vi : tri) {
        if (!flat) g.normal(normals[vi].x(), normals[vi].y(), normals[vi].z());
        if (!m.uvs.empty()) g.tex_coord(m.uvs[vi].x(), m.uvs[vi].y());
        const Point3& p = m.positions[vi];
        g.vertex(p.x(), p.y(), p.z());
      }
    }
    g.end();
    g.pop_matrix();
  }
  return downsample(g.image(), aa);
}

}  // namespace wedge::render
