// render_scene: a mesh drawn through a Context with a camera, lights and materials, the way
// Lua's render{} asks for it. Supersampling renders at antialias x the size and box-filters down.
// Besides the z-buffer, two classic visibility modes draw back to front with the depth test off:
// the painter's algorithm (Newell, Newell & Sancha 1972: a depth sort refined by their overlap
// tests, see depth_sort) and a BSP tree (Fuchs, Kedem & Naylor 1980), built once over the
// world-space triangles and walked far side - node - near side from the eye.
#include <cmath>
#include <thread>

#include "render/render.h"

namespace wedge::render {

namespace {

struct WorldTri {
  Point3 p[3];
  Vec3 n[3];
  Vec2 uv[3];
  Vec3 face_normal;
  int item = 0;
};

// A BSP tree over triangles (Fuchs, Kedem & Naylor 1980; Foley et al. 15.5.2): each node holds
// the triangles on its splitting plane; triangles straddling a plane are cut in two or three.
class BspTree {
 public:
  explicit BspTree(std::vector<WorldTri> tris) {
    if (!tris.empty()) root_ = build(std::move(tris));
  }
  // Back to front as seen from the point `eye` (perspective), or, when `view_dir` is given, along
  // that direction (orthographic: the eye is at infinity, so a node's front side is the one
  // facing against the view direction, wherever the eye point lies).
  std::vector<WorldTri> back_to_front(const Point3& eye, const Vec3* view_dir = nullptr) const {
    std::vector<WorldTri> out;
    if (root_ >= 0) walk(root_, eye, view_dir, out);
    return out;
  }

 private:
  struct Node {
    Vec3 n = Vec3::Zero();
    double d = 0;
    std::vector<WorldTri> on;
    int front = -1, back = -1;
  };
  std::vector<Node> nodes_;
  int root_ = -1;

  static WorldTri lerp_tri(const WorldTri& src, const std::array<int, 3>& a, const std::array<int, 3>& b,
                           const std::array<double, 3>& t) {
    WorldTri w = src;
    for (int j = 0; j < 3; ++j) {
      w.p[j] = src.p[a[j]] + t[j] * (src.p[b[j]] - src.p[a[j]]);
      w.n[j] = src.n[a[j]] + t[j] * (src.n[b[j]] - src.n[a[j]]);
      w.uv[j] = src.uv[a[j]] + t[j] * (src.uv[b[j]] - src.uv[a[j]]);
    }
    return w;
  }

  // Built and walked with explicit stacks, not recursion: the tree of a convex mesh is a chain as
  // deep as the mesh has triangles (every other triangle lies behind each one's plane), which
  // overflowed the call stack for a 20k-triangle sphere. Triangles (and the pieces of split ones)
  // live in one pool and are partitioned by index: the chain's quadratic number of partition
  // steps moves 4-byte indices, not whole triangles.
  int build(std::vector<WorldTri> tris) {
    std::vector<WorldTri> pool = std::move(tris);
    struct Work {
      std::vector<std::uint32_t> tris;
      int parent;
      bool front;
    };
    std::vector<Work> todo(1);
    todo[0].parent = -1, todo[0].front = false;
    todo[0].tris.resize(pool.size());
    for (std::size_t i = 0; i < pool.size(); ++i) todo[0].tris[i] = std::uint32_t(i);
    int root = -1;
    std::vector<WorldTri> front_pieces, back_pieces;
    while (!todo.empty()) {
      Work w = std::move(todo.back());
      todo.pop_back();
      const int id = int(nodes_.size());
      nodes_.push_back({});
      if (w.parent < 0) root = id;
      else (w.front ? nodes_[w.parent].front : nodes_[w.parent].back) = id;
      const WorldTri& s = pool[w.tris.front()];
      const Vec3 n = s.face_normal;
      const double d = -n.dot(s.p[0]);
      const double scale = 1e-9 * (1 + s.p[0].norm());
      std::vector<std::uint32_t> front, back;
      std::vector<WorldTri> on;
      for (const std::uint32_t ti : w.tris) {
        double dist[3];
        int pos = 0, neg = 0;
        for (int j = 0; j < 3; ++j) {
          dist[j] = n.dot(pool[ti].p[j]) + d;
          if (std::abs(dist[j]) <= scale) dist[j] = 0;
          pos += dist[j] > 0, neg += dist[j] < 0;
        }
        if (!pos && !neg) on.push_back(pool[ti]);
        else if (!neg) front.push_back(ti);
        else if (!pos) back.push_back(ti);
        else {
          front_pieces.clear(), back_pieces.clear();
          split(pool[ti], dist, front_pieces, back_pieces);
          for (auto& piece : front_pieces) front.push_back(std::uint32_t(pool.size())), pool.push_back(piece);
          for (auto& piece : back_pieces) back.push_back(std::uint32_t(pool.size())), pool.push_back(piece);
        }
      }
      nodes_[id].n = n, nodes_[id].d = d, nodes_[id].on = std::move(on);
      if (!front.empty()) todo.push_back({std::move(front), id, true});
      if (!back.empty()) todo.push_back({std::move(back), id, false});
    }
    return root;
  }

  // Cuts a straddling triangle: the vertex alone on its side gives one triangle there and a
  // quad (two triangles) on the other; a vertex on the plane gives one triangle each side.
  static void split(const WorldTri& t, const double* dist, std::vector<WorldTri>& front, std::vector<WorldTri>& back) {
    for (int r = 0; r < 3; ++r) {
      int i = r, j = (r + 1) % 3, k = (r + 2) % 3;
      if (dist[i] == 0) {  // j and k on opposite sides
        double tt = dist[j] / (dist[j] - dist[k]);
        WorldTri a = lerp_tri(t, {i, j, j}, {i, j, k}, {0, 0, tt});
        WorldTri b = lerp_tri(t, {i, j, k}, {i, k, k}, {0, tt, 0});
        (dist[j] > 0 ? front : back).push_back(a);
        (dist[k] > 0 ? front : back).push_back(b);
        return;
      }
    }
    for (int r = 0; r < 3; ++r) {
      int i = r, j = (r + 1) % 3, k = (r + 2) % 3;
      if ((dist[i] > 0) != (dist[j] > 0) && (dist[i] > 0) != (dist[k] > 0)) {  // i alone
        double tij = dist[i] / (dist[i] - dist[j]), tik = dist[i] / (dist[i] - dist[k]);
        WorldTri alone = lerp_tri(t, {i, i, i}, {i, j, k}, {0, tij, tik});
        WorldTri q1 = lerp_tri(t, {i, j, k}, {j, j, k}, {tij, 0, 0});
        WorldTri q2 = lerp_tri(t, {i, k, i}, {j, k, k}, {tij, 0, tik});
        (dist[i] > 0 ? front : back).push_back(alone);
        (dist[i] > 0 ? back : front).push_back(q1);
        (dist[i] > 0 ? back : front).push_back(q2);
        return;
      }
    }
  }

  void walk(int root, const Point3& eye, const Vec3* view_dir, std::vector<WorldTri>& out) const {
    // (node, false): visit its far side first; (node, true): draw its own triangles, then the near side.
    std::vector<std::pair<int, bool>> todo{{root, false}};
    while (!todo.empty()) {
      auto [id, far_done] = todo.back();
      todo.pop_back();
      const Node& nd = nodes_[id];
      const bool eye_front = view_dir ? nd.n.dot(*view_dir) <= 0 : nd.n.dot(eye) + nd.d >= 0;
      const int first = eye_front ? nd.back : nd.front, second = eye_front ? nd.front : nd.back;
      if (!far_done) {
        todo.push_back({id, true});
        if (first >= 0) todo.push_back({first, false});
      } else {
        out.insert(out.end(), nd.on.begin(), nd.on.end());
        if (second >= 0) todo.push_back({second, false});
      }
    }
  }
};

// The painter's algorithm with Newell, Newell & Sancha's overlap tests (1972; Foley et al.
// 15.5.1). Triangles are sorted by their farthest depth (d = -z in eye space); before the farthest
// remaining triangle P is drawn, it is tested against every other remaining Q whose depth range
// reaches behind P's nearest point. P may go first if any of these holds for that Q:
//   1-2. their screen x or y extents are disjoint;
//   3.   P lies wholly on the far side of Q's plane (seen from the eye);
//   4.   Q lies wholly on the near side of P's plane;
//   5.   their screen projections do not overlap (separating axis test).
// If all fail, Q is tested the other way round (3' Q wholly behind P's plane, or 4' P wholly in
// front of Q's plane); if Q may go first it is moved ahead of P, marked, and the tests restart
// with Q. The order so found is exactly the z-buffer's wherever the scene has no cyclic overlap
// (and no interpenetration). Cyclic overlap - a marked Q that would have to move again, or a pair
// that neither test orders - is out of scope: no triangle is split, P is drawn where it stands
// (so such a scene may differ from the z-buffer there); use the BSP tree, which splits.
std::vector<WorldTri> depth_sort(const std::vector<WorldTri>& tris, const Mat4& view, bool orthographic) {
  const std::size_t n = tris.size();
  struct Tri {
    Vec3 e[3];        // eye space
    Vec2 s[3];        // screen: (x, y) orthographic, (x/d, y/d) perspective
    double dmin, dmax;  // depth range, d = -z
    double x0, x1, y0, y1;
    Vec3 normal;      // unit plane normal in eye space (zero if degenerate)
    double offset;    // plane: normal . x + offset = 0
    double eye_side;  // the sign of the eye's side of the plane (0: edge-on)
    bool screen_ok;   // false if a vertex is at or behind the eye (perspective)
  };
  std::vector<Tri> t(n);
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec4 h = view * tris[i].p[j].homogeneous();
      t[i].e[j] = h.head<3>();
      scale = std::max(scale, t[i].e[j].cwiseAbs().maxCoeff());
    }
  const double eps = 1e-9 * std::max(scale, 1e-300);  // plane-distance tolerance (shared vertices)
  for (auto& T : t) {
    T.dmin = 1e300, T.dmax = -1e300;
    T.screen_ok = true;
    for (int j = 0; j < 3; ++j) {
      const double d = -T.e[j].z();
      T.dmin = std::min(T.dmin, d), T.dmax = std::max(T.dmax, d);
      if (orthographic) T.s[j] = T.e[j].head<2>();
      else if (d > eps) T.s[j] = T.e[j].head<2>() / d;
      else T.screen_ok = false, T.s[j] = Vec2::Zero();
    }
    T.x0 = std::min({T.s[0].x(), T.s[1].x(), T.s[2].x()}), T.x1 = std::max({T.s[0].x(), T.s[1].x(), T.s[2].x()});
    T.y0 = std::min({T.s[0].y(), T.s[1].y(), T.s[2].y()}), T.y1 = std::max({T.s[0].y(), T.s[1].y(), T.s[2].y()});
    Vec3 nn = (T.e[1] - T.e[0]).cross(T.e[2] - T.e[0]);
    const double len = nn.norm();
    T.normal = len > 0 ? Vec3(nn / len) : Vec3::Zero();
    T.offset = -T.normal.dot(T.e[0]);
    // The eye: the origin (perspective) or the point at infinity along +z (orthographic).
    const double at_eye = orthographic ? T.normal.z() * scale : T.offset;
    T.eye_side = std::abs(at_eye) <= eps ? 0.0 : at_eye > 0 ? 1.0 : -1.0;
  }
  // All of A's vertices on the side of B's plane away from the eye (`far`) or towards it, within
  // eps. An edge-on or degenerate B draws no area, so either side will do.
  auto side = [&](const Tri& a, const Tri& b, bool far) {
    if (b.eye_side == 0) return true;
    for (const auto& p : a.e) {
      const double dist = (b.normal.dot(p) + b.offset) * b.eye_side;  // > 0: the eye's side
      if (far ? dist > eps : dist < -eps) return false;
    }
    return true;
  };
  // Separating axis test of the screen triangles: no axis separates -> the interiors overlap.
  // Touching along an edge or at a vertex is not overlap.
  auto screens_overlap = [&](const Tri& a, const Tri& b) {
    if (!a.screen_ok || !b.screen_ok) return true;
    const double sx = std::max({a.x1 - a.x0, a.y1 - a.y0, b.x1 - b.x0, b.y1 - b.y0, 1e-300});
    const double tol = 1e-9 * sx * sx;
    for (const Tri* tri : {&a, &b}) {
      const Tri& o = tri == &a ? b : a;
      double area = (tri->s[1] - tri->s[0]).x() * (tri->s[2] - tri->s[0]).y() -
                    (tri->s[1] - tri->s[0]).y() * (tri->s[2] - tri->s[0]).x();
      if (std::abs(area) <= tol) return false;  // no screen area: draws nothing to overlap
      const double orient = area > 0 ? 1 : -1;
      for (int k = 0; k < 3; ++k) {
        const Vec2& p = tri->s[k];
        const Vec2& q = tri->s[(k + 1) % 3];
        bool separated = true;
        for (const auto& r : o.s) {
          // r inside (strictly) relative to edge p->q of tri?
          const double cr = orient * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
          if (cr > tol) {
            separated = false;
            break;
          }
        }
        if (separated) return false;
      }
    }
    return true;
  };
  // P may be drawn before Q: P obscures no part of Q.
  auto may_precede = [&](const Tri& P, const Tri& Q) {
    if (P.screen_ok && Q.screen_ok && (P.x1 <= Q.x0 || Q.x1 <= P.x0 || P.y1 <= Q.y0 || Q.y1 <= P.y0)) return true;
    if (side(P, Q, true) || side(Q, P, false)) return true;
    return !screens_overlap(P, Q);
  };

  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return t[a].dmax > t[b].dmax; });
  std::vector<char> done(n, 0), moved(n, 0), stacked(n, 0);
  std::vector<std::size_t> stack;  // triangles moved ahead of the sorted rest, the last one first
  std::vector<WorldTri> out;
  out.reserve(n);
  std::size_t head = 0;
  for (;;) {
    while (head < n && (done[order[head]] || stacked[order[head]])) ++head;
    if (stack.empty() && head == n) break;
    const std::size_t p = stack.empty() ? order[head] : stack.back();
    const Tri& P = t[p];
    std::size_t blocker = n;
    for (auto it = stack.rbegin(); it != stack.rend() && blocker == n; ++it)
      if (*it != p && t[*it].dmax > P.dmin && !may_precede(P, t[*it])) blocker = *it;
    for (std::size_t i = head; i < n && blocker == n; ++i) {
      const std::size_t q = order[i];
      if (t[q].dmax <= P.dmin) break;  // sorted: this and the rest lie wholly nearer than P
      if (q == p || done[q] || stacked[q]) continue;
      if (!may_precede(P, t[q])) blocker = q;
    }
    if (blocker != n && !moved[blocker] && (side(t[blocker], P, true) || side(P, t[blocker], false))) {
      moved[blocker] = stacked[blocker] = 1;  // Q goes first; test it in turn
      stack.push_back(blocker);
      continue;
    }
    // Drawn: no triangle it obscures remains, or a cyclic overlap (out of scope, see above).
    out.push_back(tris[p]);
    done[p] = 1;
    if (!stack.empty() && stack.back() == p) stacked[p] = 0, stack.pop_back();
  }
  return out;
}

}  // namespace

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

Image render_scene(const std::vector<DrawItem>& items, const RenderOptions& o) { return render_scene(items, o, nullptr); }

Image render_scene(const std::vector<DrawItem>& items, const RenderOptions& o, std::vector<float>* depth) {
  if (o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192)
    fail("render: size ", o.width, "x", o.height, " must be within 1..8192");
  if (o.antialias < 1 || o.antialias > 4) fail("render: antialias ", o.antialias, " must be 1, 2, 3 or 4");
  if (o.lights.size() > 8) fail("render: at most 8 lights, got ", o.lights.size());
  const int aa = o.antialias, W = o.width * aa, H = o.height * aa;
  Context g(W, H);
  g.threads(o.threads > 0 ? o.threads : std::max(1, int(std::thread::hardware_concurrency())));
  g.simd(o.simd);
  g.clear_color(o.background[0], o.background[1], o.background[2], o.background[3]);
  g.clear();
  Box3 bounds;
  for (const Point3& p : world_points(items)) bounds.extend(p);

  const Camera& c = o.camera;
  const CameraMatrices cm = camera_matrices(c, bounds, double(W) / H, c.fit_window ? world_points(items) : std::vector<Point3>{});
  const Mat4& view = cm.view;
  g.matrix_mode(MatrixMode::Projection);
  g.load_matrix(cm.projection);
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

  const bool flat = o.shading == ShadeModel::Flat;
  // World-space triangles of every item, with the attributes the pipeline needs.
  std::vector<WorldTri> tris;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const DrawItem& it = items[k];
    if (!it.mesh) continue;
    it.mesh->check();
    const Mesh& m = *it.mesh;
    std::vector<Vec3> normals = m.normals;
    if (normals.empty() && !flat) {
      Mesh copy = m;
      copy.compute_vertex_normals();  // area-weighted, only where the mesh has none
      normals = copy.normals;
    }
    const bool mirror = reverses_orientation(it.transform);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      WorldTri w;
      w.item = int(k);
      auto tri = m.triangles[t];
      if (mirror) std::swap(tri[1], tri[2]);
      for (int j = 0; j < 3; ++j) {
        w.p[j] = apply_point(it.transform, m.positions[tri[j]]);
        w.n[j] = flat ? Vec3::Zero() : apply_normal(it.transform, normals[tri[j]]);
        w.uv[j] = m.uvs.empty() ? Vec2::Zero() : m.uvs[tri[j]];
      }
      w.face_normal = (w.p[1] - w.p[0]).cross(w.p[2] - w.p[0]).normalized();
      tris.push_back(w);
    }
  }
  if (o.visibility == Visibility::Painter) {
    tris = depth_sort(tris, cm.sort_view, c.orthographic);
    g.disable(Cap::DepthTest);
  } else if (o.visibility == Visibility::Bsp) {
    BspTree bsp(tris);
    tris = bsp.back_to_front(c.eye, c.orthographic ? &cm.projector : nullptr);
    g.disable(Cap::DepthTest);
  }
  int current = -1;
  g.begin(Primitive::Triangles);
  std::size_t submitted = 0;
  for (const auto& t : tris) {
    if (o.progress && ++submitted % RenderOptions::kProgressTriangles == 0) o.progress(submitted, tris.size());
    if (t.item != current) {
      g.end();
      current = t.item;
      const DrawItem& it = items[current];
      g.material(Face::FrontAndBack, it.material);
      if (it.texture) {
        g.enable(Cap::Texture2D);
        g.bind_texture(it.texture);
        g.tex_env_mode(TexEnvMode::Modulate);
      } else {
        g.disable(Cap::Texture2D);
      }
      g.begin(Primitive::Triangles);
    }
    const bool uvs = items[t.item].mesh && !items[t.item].mesh->uvs.empty();
    if (flat) g.normal(t.face_normal.x(), t.face_normal.y(), t.face_normal.z());  // a flat face's geometric normal
    for (int j = 0; j < 3; ++j) {
      if (!flat) g.normal(t.n[j].x(), t.n[j].y(), t.n[j].z());
      if (uvs) g.tex_coord(t.uv[j].x(), t.uv[j].y());
      g.vertex(t.p[j].x(), t.p[j].y(), t.p[j].z());
    }
  }
  g.end();
  if (o.progress) o.progress(tris.size(), tris.size());
  // Wireframe models: unlit lines in the material's diffuse colour.
  bool lit = true;
  for (const auto& it : items) {
    if (!it.lines) continue;
    if (lit) g.disable(Cap::Lighting), g.disable(Cap::Texture2D), lit = false;
    g.color(it.material.diffuse[0], it.material.diffuse[1], it.material.diffuse[2], it.material.diffuse[3]);
    for (const auto& line : *it.lines) {
      g.begin(Primitive::LineStrip);
      for (const Point3& p : line) {
        const Point3 q = apply_point(it.transform, p);
        g.vertex(q.x(), q.y(), q.z());
      }
      g.end();
    }
  }
  if (depth) *depth = g.depth_buffer();
  return downsample(g.image(), aa);
}

}  // namespace wedge::render
