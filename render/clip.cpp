// Clipping in homogeneous clip space, before the divide by w (GL 1.x section 2.12): a vertex is
// inside plane i when its signed distance (Raster::plane_dist) is not negative: w + x, w - x,
// w + y, w - y, w + z, w - z for the view volume -w <= x, y, z <= w, then p . eye for each
// enabled user plane p (in eye space). Polygons by Sutherland-Hodgman, one plane at a time, each
// new vertex interpolated from the inside vertex of its edge (so that an edge shared by two
// polygons clips to the same point) with edge flags for polygon-mode lines; lines by their
// parameter interval [t0, t1] against every plane (Liang-Barsky's idea in clip space); points
// dropped unless inside all planes.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

namespace {
PVert lerp(const PVert& a, const PVert& b, double t) {
  PVert r;
  r.clip = a.clip + t * (b.clip - a.clip);
  for (int k = 0; k < kAttrs; ++k) r.a[k] = float(a.a[k] + t * (b.a[k] - a.a[k]));
  return r;
}
}  // namespace

// Sutherland-Hodgman in homogeneous coordinates, one plane at a time.
void Raster::clip_polygon(std::vector<PVert>& poly) {
  std::vector<PVert>& out = clip_scratch;
  for (int p = 0; p < plane_count() && !poly.empty(); ++p) {
    bool all_in = true;
    for (auto& v : poly)
      if (plane_dist(v, p) < 0) all_in = false;
    if (all_in) continue;
    out.clear();
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const PVert& a = poly[i];
      const PVert& b = poly[(i + 1) % n];
      double da = plane_dist(a, p), db = plane_dist(b, p);
      if (da >= 0) out.push_back(a);
      if ((da >= 0) != (db >= 0)) {
        // Always interpolate from the inside vertex, so a shared edge clips identically.
        PVert v = da >= 0 ? lerp(a, b, da / (da - db)) : lerp(b, a, db / (db - da));
        // Leaving: the next edge runs along the plane (made by clipping). Entering: the rest
        // of the original edge a-b.
        v.edge = da >= 0 ? false : a.edge;
        out.push_back(v);
      }
    }
    poly.swap(out);
  }
}

void Raster::draw_point(const PVert& v) {
  for (int p = 0; p < plane_count(); ++p)
    if (plane_dist(v, p) < 0) return;
  emit_point(to_window(v), 0);
}

void Raster::draw_line(const PVert& a0, const PVert& b0, const PVert& provoking) {
  // Parametric clipping in homogeneous space (Liang-Barsky's idea applied to the clip volume).
  double t0 = 0, t1 = 1;
  for (int p = 0; p < plane_count(); ++p) {
    double da = plane_dist(a0, p), db = plane_dist(b0, p);
    if (da < 0 && db < 0) return;
    if (da < 0) t0 = std::max(t0, da / (da - db));
    else if (db < 0) t1 = std::min(t1, da / (da - db));
  }
  if (t0 > t1) return;
  PVert a = t0 > 0 ? lerp(a0, b0, t0) : a0;
  PVert b = t1 < 1 ? lerp(a0, b0, t1) : b0;
  const bool flat = s.shade == ShadeModel::Flat;
  emit_line(to_window(a), to_window(b), 0, flat ? provoking.a : nullptr);
}

}  // namespace wedge::render::raster
