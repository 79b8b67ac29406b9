// Cameras and the course's named views (multiview orthographic, axonometric, oblique, perspective
// with one, two or three vanishing points), and the matrices render_scene loads for a camera.
//
// Frames. World: Z up; the front view looks along +Y, so the picture's x is world X and its y is
// world Z. The view frame (eye space, as OpenGL's): x right, y up, z towards the viewer; the
// viewer looks along -z.
//
// Axonometric (Hearn & Baker 7-?; Foley et al. 6.1.2): rotate the object about the vertical axis
// by ry, then about the horizontal picture axis by rx, then project orthographically. In the view
// frame of the front view, M = Rx(rx) Ry(ry) (right-handed rotations). The world axes are
// foreshortened by
//   X: sqrt(cos^2 ry + sin^2 rx sin^2 ry),  Y: sqrt(sin^2 ry + cos^2 ry sin^2 rx),  Z: cos rx;
// isometric (all three equal): ry = -45, rx = asin(tan 30) = 35.264 (the negative ry turns the
// right-hand face, +X, towards the viewer); dimetric 1 : 1/2 : 1 (X and Z whole, the receding Y
// at half): sin rx = 1/3, sin^2 ry = 1/8; trimetric: any other pair, by default rx = 20, ry = -30.
// Because M keeps world Z in the picture's y-z plane, every axonometric view is a look_at camera
// whose eye direction is M^T (0, 0, 1) and whose up is world Z.
//
// Oblique (Hearn & Baker's oblique parallel projection): projectors meet the picture plane at an
// angle, so depth shows as a receding axis drawn at `angle` from the picture's x axis, with its
// lengths multiplied by `ratio` (1: cavalier, 1/2: cabinet). In the view frame, with depth
// d = -z, x' = x + ratio cos(angle) d and y' = y + ratio sin(angle) d: the shear
//   H = [1 0 -ratio cos(angle) 0; 0 1 -ratio sin(angle) 0; 0 0 1 0; 0 0 0 1],
// which keeps z, so the z-buffer still sorts by true depth; the projection matrix is Ortho * H.
//
// Perspective: the number of vanishing points is the number of principal axes not parallel to the
// picture plane. One-point: the view direction is world +Y (X and Z stay parallel to the picture);
// two-point: a horizontal view direction between X and Y (Z stays vertical); three-point: a view
// direction oblique to all three. To show the object from above without tilting the view (which
// would add a vanishing point), the frustum is off-axis: its window is fitted around the object
// as seen from the eye (a shifted lens, as architectural cameras do).
#include <cmath>

#include "render/render.h"

namespace wedge::render {

namespace {


double rad(double deg) { return deg * kPi / 180.0; }
bool given(double v) { return !std::isnan(v); }

// The view-frame vector (x right, y up, z towards the viewer) of the front view, in world terms.
Vec3 world_from_front(const Vec3& v) { return Vec3(v.x(), -v.z(), v.y()); }

Point3 corner(const Box3& b, int i) {
  return Point3((i & 1) ? b.max.x() : b.min.x(), (i & 2) ? b.max.y() : b.min.y(), (i & 4) ? b.max.z() : b.min.z());
}

void check_angle(const char* view, const char* what, double v, double lo, double hi) {
  if (!std::isfinite(v) || v < lo || v > hi)
    fail("view '", view, "': ", what, " must be within ", lo, "..", hi, " degrees, got ", v);
}

}  // namespace

Mat4 axonometric(double rx, double ry) {
  if (!std::isfinite(rx) || !std::isfinite(ry)) fail("axonometric: angles must be finite, got rx=", rx, ", ry=", ry);
  return rotate_x(rx) * rotate_y(ry);
}

Mat4 oblique(double angle, double ratio) {
  if (!std::isfinite(angle)) fail("oblique: angle must be finite, got ", angle);
  if (!std::isfinite(ratio) || ratio <= 0) fail("oblique: ratio must be positive, got ", ratio);
  Mat4 h = Mat4::Identity();
  h(0, 2) = -ratio * std::cos(rad(angle));
  h(1, 2) = -ratio * std::sin(rad(angle));
  return h;
}

const std::vector<std::string>& view_names() {
  static const std::vector<std::string> names{"front",   "top",       "side",     "iso",       "isometric",
                                              "dimetric", "trimetric", "cavalier", "cabinet",   "oblique",
                                              "one_point", "two_point", "three_point"};
  return names;
}

Camera named_view(const std::string& name, const Box3& bounds, const ViewParams& p) {
  Camera c;
  const Point3 center = bounds.empty() ? Point3::Zero() : Point3(bounds.center());
  const double r = bounds.empty() ? 1.0 : std::max(1e-9, 0.5 * bounds.diagonal());
  c.center = center;
  c.up = Vec3(0, 0, 1);
  c.fit = true;
  c.fit_window = true;
  auto unused = [&](const char* what, double v) {
    if (given(v)) fail("view '", name, "' takes no ", what);
  };
  // An orthographic camera looking from direction `dir` (towards the eye).
  auto parallel = [&](const Vec3& dir) {
    c.orthographic = true;
    c.eye = center + dir.normalized() * (3 * r);
    c.left = -r * 1.1, c.right = r * 1.1, c.bottom = -r * 1.1, c.top = r * 1.1;
    c.near = r * 0.5, c.far = r * 6;
  };
  auto axonometric_view = [&](double rx, double ry) {
    check_angle(name.c_str(), "rx", rx, -89, 89);
    check_angle(name.c_str(), "ry", ry, -360, 360);
    const Mat4 m = axonometric(rx, ry);
    parallel(world_from_front(m.block<3, 3>(0, 0).transpose() * Vec3(0, 0, 1)));
  };
  const bool axo = name == "iso" || name == "isometric" || name == "dimetric" || name == "trimetric";
  const bool obl = name == "cavalier" || name == "cabinet" || name == "oblique";
  const bool persp = name == "one_point" || name == "two_point" || name == "three_point";
  if (!axo) unused("rx", p.rx), unused("ry", p.ry);
  if (!obl && name != "two_point") unused("angle", p.angle);
  if (name != "oblique") unused("ratio", p.ratio);
  if (!persp) unused("distance", p.distance);

  if (name == "front") parallel(Vec3(0, -1, 0));
  else if (name == "top") parallel(Vec3(0, 0, 1)), c.up = Vec3(0, 1, 0), c.eye = center + Vec3(0, 0, 3 * r);
  else if (name == "side") parallel(Vec3(1, 0, 0));
  else if (name == "iso" || name == "isometric") {
    if (given(p.rx) || given(p.ry)) fail("view '", name, "' has fixed angles; give rx= and ry= to 'trimetric'");
    axonometric_view(std::asin(std::tan(rad(30))) * 180 / kPi, -45);
  } else if (name == "dimetric") {
    if (given(p.rx) && given(p.ry)) fail("view 'dimetric' takes rx= or ry=, not both (the other follows)");
    // Two axes equally foreshortened: X and Z (the picture's width and height) by default, the
    // receding Y at half. Given rx alone, ry = -45 makes X and Y equal instead.
    double rx = std::asin(1.0 / 3) * 180 / kPi, ry = -std::asin(std::sqrt(1.0 / 8)) * 180 / kPi;
    if (given(p.rx)) rx = p.rx, ry = -45;
    if (given(p.ry)) {
      // X and Z equal: cos^2 ry + sin^2 rx sin^2 ry = cos^2 rx  =>  sin^2 rx = sin^2 ry / (1 + sin^2 ry).
      const double s2 = std::pow(std::sin(rad(p.ry)), 2);
      ry = p.ry, rx = std::asin(std::sqrt(s2 / (1 + s2))) * 180 / kPi;
    }
    axonometric_view(rx, ry);
  } else if (name == "trimetric") {
    axonometric_view(given(p.rx) ? p.rx : 20, given(p.ry) ? p.ry : -30);
  } else if (obl) {
    const double angle = given(p.angle) ? p.angle : 45;
    check_angle(name.c_str(), "angle", angle, -360, 360);
    const double ratio = name == "cavalier" ? 1.0 : name == "cabinet" ? 0.5 : given(p.ratio) ? p.ratio : 0.5;
    if (!std::isfinite(ratio) || ratio <= 0 || ratio > 10) fail("view 'oblique': ratio must be within 0..10 (above 0), got ", ratio);
    parallel(Vec3(0, -1, 0));
    c.shear = oblique(angle, ratio);
  } else if (persp) {
    const double dist = given(p.distance) ? p.distance : 3.0;
    if (!std::isfinite(dist) || dist < 1.5 || dist > 1000)
      fail("view '", name, "': distance must be within 1.5..1000 (times the object's radius), got ", dist);
    const double D = dist * r;
    c.orthographic = false;
    Vec3 dir;  // the view direction (from the eye into the scene)
    Vec3 offset;  // where the eye sits beside the view axis through the centre
    if (name == "one_point") {
      dir = Vec3(0, 1, 0);
      offset = Vec3(0.6 * r, 0, 0.6 * r);  // up and to the right: the top and the right side show
    } else if (name == "two_point") {
      const double a = given(p.angle) ? p.angle : 30;  // the view's azimuth, from the front
      check_angle(name.c_str(), "angle", a, 1, 89);
      dir = Vec3(-std::sin(rad(a)), std::cos(rad(a)), 0);
      offset = Vec3(0, 0, 0.6 * r);  // above: the top shows
    } else {
      dir = Vec3(-1, 1, -1).normalized();  // from above, in front, to the right
      offset = Vec3::Zero();
    }
    c.eye = center - dir * D + offset;
    c.center = c.eye + dir * D;
    c.fovy = 45;
    c.near = 0.1 * r, c.far = D + 2 * r;
  } else {
    std::string list;
    for (const auto& n : view_names()) list += (list.empty() ? "" : ", ") + n;
    fail("unknown view '", name, "' (expected ", list, ")");
  }
  return c;
}

Camera named_view(const std::string& name, const Box3& bounds) { return named_view(name, bounds, ViewParams{}); }

std::vector<Point3> world_points(const std::vector<DrawItem>& items) {
  std::vector<Point3> out;
  for (const auto& it : items) {
    if (it.mesh)
      for (const auto& p : it.mesh->positions) out.push_back(apply_point(it.transform, p));
    if (it.lines)
      for (const auto& line : *it.lines)
        for (const auto& p : line) out.push_back(apply_point(it.transform, p));
  }
  return out;
}

CameraMatrices camera_matrices(const Camera& c, const Box3& bounds, double aspect, const std::vector<Point3>& points) {
  if (!(aspect > 0) || !std::isfinite(aspect)) fail("camera: aspect ", aspect, " must be positive");
  CameraMatrices m;
  m.view = look_at(c.eye, c.center, c.up);
  const Mat4 sheared = c.shear * m.view;  // eye space after the oblique shear (identity: eye space)
  double n = c.near, f = c.far;
  if (c.fit && !bounds.empty()) {
    // Near and far just around the scene, so the depth buffer's precision is spent on it.
    double zmin = 1e300, zmax = -1e300;
    for (int i = 0; i < 8; ++i) {
      const double z = -(sheared * corner(bounds, i).homogeneous()).z();
      zmin = std::min(zmin, z), zmax = std::max(zmax, z);
    }
    const double pad = 0.01 * (zmax - zmin) + 1e-6;
    f = zmax + pad;
    n = c.orthographic ? zmin - pad : std::max(zmin - pad, f * 1e-4);
    // A perspective eye with the whole scene behind it: the fitted far is not in front of the eye
    // (near=-0.00069, far=-6.9 for a cube behind an eye looking away from it), and perspective()
    // refused them. Any frustum in front of the eye sees none of the scene, so the image is the
    // background, as it is with an explicit near and far.
    if (!c.orthographic && !(f > 0)) n = 1, f = 2;
  }
  // The window: given, or fitted around the bounds (an ortho box, or a frustum's window at
  // distance 1 in tangents, which may be off-axis).
  double l = c.left, r = c.right, b = c.bottom, t = c.top;
  bool have_window = c.orthographic;
  if (c.fit_window && !bounds.empty()) {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    bool ok = true;
    auto extend = [&](const Point3& p) {
      const Vec4 e = sheared * p.homogeneous();
      double x = e.x(), y = e.y();
      if (!c.orthographic) {
        if (!(-e.z() > 1e-12)) ok = false;
        x /= -e.z(), y /= -e.z();
      }
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    };
    if (points.empty())
      for (int i = 0; i < 8; ++i) extend(corner(bounds, i));
    else
      for (const Point3& p : points) extend(p);
    if (ok) {
      const double scale = std::max(x1 - x0, y1 - y0);
      const double margin = std::max(c.margin * scale, std::max(1e-9, 1e-6 * (c.orthographic ? bounds.diagonal() : 1.0)));
      l = x0 - margin, r = x1 + margin, b = y0 - margin, t = y1 + margin;
      have_window = true;
    }
  }
  if (have_window) {
    // Keep square pixels: widen the window to the image's aspect about its centre.
    const double cx = 0.5 * (l + r), cy = 0.5 * (b + t);
    double hw = 0.5 * (r - l), hh = 0.5 * (t - b);
    if (!(hw > 0) || !(hh > 0)) fail("camera: the window is empty (left ", l, ", right ", r, ", bottom ", b, ", top ", t, ")");
    if (hw / hh < aspect) hw = hh * aspect;
    else hh = hw / aspect;
    m.projection = c.orthographic ? Mat4(ortho(cx - hw, cx + hw, cy - hh, cy + hh, n, f) * c.shear)
                                  : frustum((cx - hw) * n, (cx + hw) * n, (cy - hh) * n, (cy + hh) * n, n, f);
  } else {
    m.projection = perspective(c.fovy, aspect, n, f);
  }
  m.sort_view = sheared;
  // The projectors' direction in world space (parallel projections): the pre-image of -z.
  const Mat4 inv = inverse(sheared);
  m.projector = (inv.block<3, 3>(0, 0) * Vec3(0, 0, -1)).normalized();
  return m;
}

}  // namespace wedge::render
