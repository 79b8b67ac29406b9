// Multi-view orthographic sheets (drawing{} in API.md): the views of a set of items rendered
// side by side on a grid, as the first-angle/third-angle sheets of technical drawing show them.
// Each view is a camera from named_view(), its window fitted to the items' bounding box as the view
// sees it (the eight corners in eye space), plus a margin;
// cells are optionally framed by a one-pixel border and labelled with the view's name in a
// small 5x7 bitmap font defined here (capital letters, digits and a few signs; other characters
// are drawn blank).
#include <algorithm>
#include <cctype>
#include <cmath>

#include "kernel/transform.h"
#include "render/render.h"

namespace wedge::render {

namespace {

// 5x7 glyphs, one byte per row from the top, bit 4 the leftmost column.
struct Glyph {
  char c;
  std::uint8_t rows[7];
};
constexpr Glyph kFont[] = {
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}}, {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}}, {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
};

const Glyph* glyph(char c) {
  c = char(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont)
    if (g.c == c) return &g;
  return nullptr;
}

void put(Image& im, int x, int y, const std::array<std::uint8_t, 4>& c) {
  if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
  std::copy(c.begin(), c.end(), &im.rgba[(std::size_t(y) * im.width + x) * 4]);
}

// An item's edges in world space: feature edges, always drawn, and the edges inside a smooth
// face, drawn in a view where they are on the silhouette (one of their triangles faces the viewer
// and the other does not).
struct Edges {
  std::vector<std::array<Point3, 2>> features;
  struct Smooth {
    Point3 a, b;
    Vec3 n1, n2;
  };
  std::vector<Smooth> smooth;
};

Edges item_edges(const DrawItem& it, double crease_deg, bool tangent_features) {
  Edges out;
  if (!it.mesh || it.mesh->triangles.empty()) return out;
  const Mesh w = it.mesh->welded();  // shared edges by position, across normal and uv splits
  std::vector<Point3> p(w.positions.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = apply_point(it.transform, w.positions[i]);
  std::vector<Vec3> normal(w.triangles.size());
  for (std::size_t t = 0; t < w.triangles.size(); ++t) {
    const auto& tri = w.triangles[t];
    Vec3 n = (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]);
    normal[t] = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
  }
  struct Use {
    std::uint32_t a, b;
    std::uint32_t t;
  };
  std::vector<Use> uses;
  uses.reserve(w.triangles.size() * 3);
  for (std::size_t t = 0; t < w.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = w.triangles[t][k], b = w.triangles[t][(k + 1) % 3];
      if (a > b) std::swap(a, b);
      uses.push_back({a, b, std::uint32_t(t)});
    }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
  const double cos_crease = std::cos(crease_deg * 3.14159265358979323846 / 180);
  // Two faces that meet tangentially: the seam between a cylinder's two half faces, a fillet
  // running into a plane. Unless `tangent_features`, such an edge is left out (it is drawn only where it is on the
  // silhouette, as an edge inside a face): drawn, the seam was a line down the middle of a
  // cylinder's side view that a reader takes for a step. The test is the shading normals of both
  // faces at both ends of the edge (one surface's normal at one point, so equal on a seam), or,
  // without shading normals, the two triangles' own normals; within half a degree is tangent.
  const Mesh& m = *it.mesh;
  const bool shading_normals = m.normals.size() == m.positions.size();
  const double cos_tangent = std::cos(0.5 * 3.14159265358979323846 / 180);
  auto corner_normal = [&](std::uint32_t t, std::uint32_t v) -> Vec3 {
    for (int k = 0; k < 3; ++k)
      if (w.triangles[t][k] == v) {
        const Vec3 n = m.normals[m.triangles[t][k]];
        return n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
      }
    return Vec3::Zero();
  };
  auto tangent = [&](std::uint32_t t1, std::uint32_t t2, std::uint32_t a, std::uint32_t b) {
    if (!shading_normals) return normal[t1].dot(normal[t2]) >= cos_tangent;
    return corner_normal(t1, a).dot(corner_normal(t2, a)) >= cos_tangent &&
           corner_normal(t1, b).dot(corner_normal(t2, b)) >= cos_tangent;
  };
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
    const Point3 a = p[uses[i].a], b = p[uses[i].b];
    if (j - i != 2) {
      out.features.push_back({a, b});  // a boundary (or a non-manifold edge)
    } else {
      const std::uint32_t t1 = uses[i].t, t2 = uses[i + 1].t;
      const bool ids = !w.face_ids.empty() && w.face_ids[t1] >= 0 && w.face_ids[t2] >= 0;
      const bool feature = ids ? w.face_ids[t1] != w.face_ids[t2] && (tangent_features || !tangent(t1, t2, uses[i].a, uses[i].b))
                               : normal[t1].dot(normal[t2]) < cos_crease;
      if (feature) out.features.push_back({a, b});
      else out.smooth.push_back({a, b, normal[t1], normal[t2]});
    }
    i = j;
  }
  return out;
}

// Draws the edges of one view over its cell. `depth` is the view's depth buffer (bottom row first,
// (rw * aa) x (rh * aa)); an edge point is visible where no surface lies clearly in front of it.
void draw_edges(Image& sheet, int ox, int oy, int rw, int rh, int aa, const std::vector<float>& depth,
                const std::vector<Edges>& edges, const Camera& camera, const Box3& bounds,
                const std::vector<Point3>& points, bool dashed) {
  const CameraMatrices cm = camera_matrices(camera, bounds, double(rw) / rh, points);
  const Mat4 pv = cm.projection * cm.view;
  const int W = rw * aa, H = rh * aa;
  // The farthest depth within a final pixel (its aa x aa samples); 1 where nothing was drawn.
  auto block_depth = [&](int px, int py) {
    float z = 0;
    for (int y = py * aa; y < (py + 1) * aa; ++y)
      for (int x = px * aa; x < (px + 1) * aa; ++x) z = std::max(z, depth[std::size_t(y) * W + x]);
    return z;
  };
  // A point of an edge at window depth z over pixel (px, py) is visible unless the surface drawn
  // there is nearer by more than the surface's own change of depth to a neighbouring pixel (an
  // edge lies on its faces, whose depth varies across the pixel), plus a little.
  auto visible_at = [&](int px, int py, double z) {
    const float zc = block_depth(px, py);
    if (zc >= 1.0f) return true;  // nothing drawn under the line
    float slope = 0;
    const int nx[4] = {px - 1, px + 1, px, px}, ny[4] = {py, py, py - 1, py + 1};
    for (int k = 0; k < 4; ++k) {
      if (nx[k] < 0 || ny[k] < 0 || nx[k] >= W / aa || ny[k] >= H / aa) continue;
      const float zn = block_depth(nx[k], ny[k]);
      if (zn < 1.0f) slope = std::max(slope, std::abs(zn - zc));
    }
    return z <= zc + slope + 2e-3;
  };
  const std::array<std::uint8_t, 4> visible_ink{20, 20, 20, 255}, hidden_ink{150, 150, 150, 255};
  struct Segment {
    Vec3 a, b;  // final-pixel x, y (y up) and window depth
  };
  std::vector<Segment> segments;
  auto project = [&](const Point3& p, Vec3& out) {
    const Vec4 c = pv * p.homogeneous();
    if (!(c.w() > 1e-12)) return false;
    out = Vec3((c.x() / c.w() + 1) * 0.5 * rw, (c.y() / c.w() + 1) * 0.5 * rh, (c.z() / c.w() + 1) * 0.5);
    return true;
  };
  auto add = [&](const Point3& a, const Point3& b) {
    Segment s;
    if (project(a, s.a) && project(b, s.b)) segments.push_back(s);
  };
  for (const Edges& e : edges) {
    for (const auto& f : e.features) add(f[0], f[1]);
    for (const auto& sm : e.smooth) {
      const Vec3 d = camera.orthographic ? cm.projector : Vec3(0.5 * (sm.a + sm.b) - camera.eye);
      if ((sm.n1.dot(d) < 0) != (sm.n2.dot(d) < 0)) add(sm.a, sm.b);
    }
  }
  // Hidden parts first (dashed, if asked), then the visible ones over them.
  for (int pass = dashed ? 0 : 1; pass < 2; ++pass)
    for (const Segment& s : segments) {
      const double len = std::max(std::abs(s.b.x() - s.a.x()), std::abs(s.b.y() - s.a.y()));
      const int steps = std::max(1, int(std::ceil(2 * len)));
      for (int k = 0; k <= steps; ++k) {
        const double t = double(k) / steps;
        const Vec3 q = s.a + t * (s.b - s.a);
        const int px = int(std::floor(q.x())), py = int(std::floor(q.y()));
        if (px < 0 || py < 0 || px >= rw || py >= rh) continue;
        const bool visible = visible_at(px, py, q.z());
        if (pass == 1 && visible) put(sheet, ox + px, oy + rh - 1 - py, visible_ink);
        // dashes of 4 pixels on, 3 off along the segment
        if (pass == 0 && !visible && std::fmod(t * len, 7.0) < 4.0) put(sheet, ox + px, oy + rh - 1 - py, hidden_ink);
      }
    }
}

}  // namespace

std::vector<std::array<Point3, 2>> feature_edges(const Mesh& mesh, double crease_deg, bool tangent_edges) {
  DrawItem it;
  it.mesh = &mesh;
  return item_edges(it, crease_deg, tangent_edges).features;
}

std::vector<std::vector<Point3>> polylines(const std::vector<std::array<Point3, 2>>& segments) {
  // Points are joined where they are exactly equal (the segments come from welded vertices).
  auto key_less = [](const Point3& a, const Point3& b) {
    return a.x() != b.x() ? a.x() < b.x() : a.y() != b.y() ? a.y() < b.y() : a.z() < b.z();
  };
  std::vector<Point3> points;
  for (const auto& s : segments) points.push_back(s[0]), points.push_back(s[1]);
  std::sort(points.begin(), points.end(), key_less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  auto id = [&](const Point3& p) {
    return std::size_t(std::lower_bound(points.begin(), points.end(), p, key_less) - points.begin());
  };
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> at(points.size());  // (other end, segment)
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const std::size_t a = id(segments[k][0]), b = id(segments[k][1]);
    at[a].push_back({b, k}), at[b].push_back({a, k});
  }
  std::vector<char> used(segments.size(), 0);
  std::vector<std::vector<Point3>> out;
  auto walk = [&](std::size_t start) {
    for (;;) {
      std::vector<Point3> line{points[start]};
      std::size_t v = start;
      bool moved = false;
      for (;;) {
        bool step = false;
        for (const auto& [w, k] : at[v])
          if (!used[k]) {
            used[k] = 1, v = w, step = true, moved = true;
            line.push_back(points[v]);
            break;
          }
        if (!step) break;
      }
      if (!moved) return;
      out.push_back(std::move(line));
    }
  };
  // Open chains start at their ends (points not met by exactly two segments), then closed loops.
  for (std::size_t v = 0; v < points.size(); ++v)
    if (at[v].size() != 2) walk(v);
  for (std::size_t v = 0; v < points.size(); ++v) walk(v);
  return out;
}

std::string view_title(const std::string& name) {
  static const std::pair<const char*, const char*> titles[] = {
      {"front", "FRONT"},       {"top", "TOP"},           {"side", "SIDE"},
      {"iso", "ISOMETRIC"},     {"isometric", "ISOMETRIC"}, {"dimetric", "DIMETRIC"},
      {"trimetric", "TRIMETRIC"}, {"cavalier", "CAVALIER"}, {"cabinet", "CABINET"},
      {"oblique", "OBLIQUE"},   {"one_point", "ONE-POINT PERSPECTIVE"},
      {"two_point", "TWO-POINT PERSPECTIVE"}, {"three_point", "THREE-POINT PERSPECTIVE"}};
  for (const auto& [n, t] : titles)
    if (name == n) return t;
  return name;
}

int text_width(const std::string& text, int scale) {
  return text.empty() ? 0 : int(text.size()) * 6 * scale - scale;
}

void draw_text(Image& im, int x, int y, const std::string& text, const std::array<std::uint8_t, 4>& color, int scale) {
  if (scale < 1) fail("draw_text: scale ", scale, " must be at least 1");
  for (std::size_t k = 0; k < text.size(); ++k) {
    const Glyph* g = glyph(text[k]);
    if (!g) continue;
    const int gx = x + int(k) * 6 * scale;
    for (int r = 0; r < 7; ++r)
      for (int col = 0; col < 5; ++col)
        if (g->rows[r] & (0x10 >> col))
          for (int dy = 0; dy < scale; ++dy)
            for (int dx = 0; dx < scale; ++dx) put(im, gx + col * scale + dx, y + r * scale + dy, color);
  }
}

Image render_drawing(const std::vector<DrawItem>& items, const DrawingOptions& o) {
  const int n = int(o.views.size());
  if (n < 1 || n > 16) fail("drawing: ", n, " views given, expected 1 to 16");
  if (o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192)
    fail("drawing: size ", o.width, "x", o.height, " must be within 1..8192");
  if (o.columns < 0 || o.columns > n) fail("drawing: columns ", o.columns, " must be within 0..", n, " (0: automatic)");
  Box3 bounds;
  for (const Point3& p : world_points(items)) bounds.extend(p);
  if (bounds.empty()) fail("drawing: nothing to draw (no vertices)");
  if (!o.view_params.empty() && o.view_params.size() != o.views.size())
    fail("drawing: ", o.view_params.size(), " view parameter sets for ", n, " views");
  auto camera = [&](int v) { return named_view(o.views[v], bounds, o.view_params.empty() ? ViewParams{} : o.view_params[v]); };
  for (int v = 0; v < n; ++v) camera(v);  // unknown names and bad options fail before any rendering
  if (!o.titles.empty() && o.titles.size() != o.views.size())
    fail("drawing: ", o.titles.size(), " titles for ", n, " views");
  const std::vector<Point3> points = world_points(items);
  std::vector<Edges> edges;
  if (o.edges)
    for (const auto& it : items) edges.push_back(item_edges(it, o.crease_angle, false));

  const int cols = o.columns > 0 ? o.columns : int(std::ceil(std::sqrt(double(n))));
  const int rows = (n + cols - 1) / cols;
  const int cw = o.width / cols, ch = o.height / rows;
  const int scale = ch >= 300 ? 2 : 1;
  const int band = o.labels ? 7 * scale + 4 * scale : 0;  // label height plus padding
  const int frame = o.border ? 1 : 0;
  const int rw = cw - 2 * frame, rh = ch - 2 * frame - band;
  if (rw < 8 || rh < 8)
    fail("drawing: size ", o.width, "x", o.height, " leaves cells of ", cw, "x", ch, " pixels for ", n,
         " views: too small");

  // The multiview orthographic views (front, top, side) at one scale, as an engineering drawing
  // has them: each fitted to its own extent, a box(1, 2, 3)'s x was 81 px wide in the front view
  // and 121 in the top. Each view's window is fitted as camera_matrices fits it (its extent, the
  // margin, widened to the cell's aspect); the widest is every one's, each about its own centre.
  std::vector<Camera> cams;
  for (int v = 0; v < n; ++v) cams.push_back(camera(v));
  {
    const double aspect = double(rw) / rh;
    auto multiview = [&](int v) { return o.views[v] == "front" || o.views[v] == "top" || o.views[v] == "side"; };
    double half = 0;
    std::vector<std::array<double, 2>> centre(n);
    for (int v = 0; v < n; ++v) {
      if (!multiview(v)) continue;
      const Camera& c = cams[v];
      const Mat4 view = look_at(c.eye, c.center, c.up);
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (const Point3& p : points) {
        const Vec4 e = view * p.homogeneous();
        x0 = std::min(x0, e.x()), x1 = std::max(x1, e.x()), y0 = std::min(y0, e.y()), y1 = std::max(y1, e.y());
      }
      const double margin = std::max(c.margin * std::max(x1 - x0, y1 - y0), std::max(1e-9, 1e-6 * bounds.diagonal()));
      const double hw = 0.5 * (x1 - x0) + margin, hh = 0.5 * (y1 - y0) + margin;
      half = std::max(half, std::max(hw, hh * aspect));
      centre[v] = {0.5 * (x0 + x1), 0.5 * (y0 + y1)};
    }
    if (half > 0 && std::isfinite(half))
      for (int v = 0; v < n; ++v) {
        if (!multiview(v)) continue;
        Camera& c = cams[v];
        c.fit_window = false;
        c.left = centre[v][0] - half, c.right = centre[v][0] + half;
        c.bottom = centre[v][1] - half / aspect, c.top = centre[v][1] + half / aspect;
      }
  }

  const Vec4f& bg = o.render.background;
  // As Context::clear converts the cells' background (ties to even), so sheet and cells agree.
  auto to8 = [](float v) { return !(v > 0.0f) ? std::uint8_t(0) : v >= 1.0f ? std::uint8_t(255) : std::uint8_t(std::lrint(v * 255.0f)); };
  Image sheet;
  sheet.width = o.width, sheet.height = o.height;
  sheet.rgba.resize(std::size_t(o.width) * o.height * 4);
  for (std::size_t i = 0; i < sheet.rgba.size(); i += 4)
    for (int k = 0; k < 4; ++k) sheet.rgba[i + k] = to8(bg[k]);
  const bool light_bg = 0.3f * bg[0] + 0.59f * bg[1] + 0.11f * bg[2] > 0.5f;
  const std::array<std::uint8_t, 4> ink = light_bg ? std::array<std::uint8_t, 4>{40, 40, 40, 255}
                                                   : std::array<std::uint8_t, 4>{220, 220, 220, 255};
  const std::array<std::uint8_t, 4> rule{128, 128, 128, 255};

  for (int v = 0; v < n; ++v) {
    const int cx = (v % cols) * cw, cy = (v / cols) * ch;
    RenderOptions ro = o.render;
    ro.width = rw, ro.height = rh;
    ro.camera = cams[v];
    std::vector<float> depth;
    Image im = render_scene(items, ro, o.edges ? &depth : nullptr);
    for (int y = 0; y < rh; ++y)
      std::copy_n(&im.rgba[std::size_t(y) * rw * 4], std::size_t(rw) * 4,
                  &sheet.rgba[(std::size_t(cy + frame + band + y) * o.width + cx + frame) * 4]);
    if (o.border) {
      for (int x = cx; x < cx + cw; ++x) put(sheet, x, cy, rule), put(sheet, x, cy + ch - 1, rule);
      for (int y = cy; y < cy + ch; ++y) put(sheet, cx, y, rule), put(sheet, cx + cw - 1, y, rule);
    }
    if (o.edges)
      draw_edges(sheet, cx + frame, cy + frame + band, rw, rh, ro.antialias, depth, edges, ro.camera, bounds,
                 ro.camera.fit_window ? points : std::vector<Point3>{}, o.hidden_dashed);
    if (o.view_done) o.view_done();
    if (o.labels)
      draw_text(sheet, cx + frame + 2 * scale, cy + frame + 2 * scale, o.titles.empty() ? view_title(o.views[v]) : o.titles[v],
                ink, scale);
  }
  return sheet;
}

}  // namespace wedge::render
