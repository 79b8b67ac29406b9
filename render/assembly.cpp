// Primitive assembly (GL 1.x section 2.6): a batch of vertices, after the vertex stage, as the
// primitives of its type (points, lines, strips, loops, triangles, fans, quads, polygons), each
// polygon split into triangles as Mesa splits them, with GL's provoking vertex for flat shading
// (table 2.12) and edge flags that hide inner diagonals in polygon-mode line; then facing and
// culling by the signed window-space area (sections 2.14.1, 3.5.1) and the fill, outline or
// vertices per the polygon mode. Independent filled triangles without user clip planes take the
// batched path instead (triangles.cpp).

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "render/raster.h"

namespace wedge::render::raster {

// A filled triangle wholly inside the clip volume, in window coordinates: facing, culling,
// then the fill (polygon modes both Fill).
void Raster::draw_inside_triangle(const WinVert* w, const PVert& provoking) {
  const bool front = (facing_area(w, 3) > 0) == (s.front_face == FrontFace::CCW);
  if (s.on(Cap::CullFace)) {
    if (s.cull_face == Face::FrontAndBack) return;
    if ((s.cull_face == Face::Front) == front) return;
  }
  const int side = (!front && two_sided_lighting(s)) ? 1 : 0;
  emit_triangle(w[0], w[1], w[2], side, s.shade == ShadeModel::Flat ? provoking.a : nullptr);
}

// A polygon with its provoking vertex (for flat shading): clip, find its facing, cull, then
// fill it as a triangle fan or draw its outline or vertices per the polygon mode.
void Raster::draw_triangle(const PVert& a, const PVert& b, const PVert& c, const PVert& provoking) {
  // Fast path: a filled triangle wholly inside the clip volume needs no polygon copies (the
  // same window coordinates, area and cull decisions as the general path below).
  if (s.poly_front == PolygonMode::Fill && s.poly_back == PolygonMode::Fill) {
    bool inside = true;
    for (int p = 0; p < plane_count() && inside; ++p)
      if (plane_dist(a, p) < 0 || plane_dist(b, p) < 0 || plane_dist(c, p) < 0) inside = false;
    if (inside) {
      const WinVert w[3] = {to_window(a), to_window(b), to_window(c)};
      return draw_inside_triangle(w, provoking);
    }
  }
  std::vector<PVert>& poly = poly_scratch;
  poly.clear();
  poly.push_back(a), poly.push_back(b), poly.push_back(c);
  const PVert& prov = provoking;
  clip_polygon(poly);
  if (poly.size() < 3) return;
  std::vector<WinVert>& w = win_scratch;
  w.resize(poly.size());
  for (std::size_t i = 0; i < poly.size(); ++i) w[i] = to_window(poly[i]);
  const bool front = (facing_area(w.data(), w.size()) > 0) == (s.front_face == FrontFace::CCW);
  if (s.on(Cap::CullFace)) {
    if (s.cull_face == Face::FrontAndBack) return;
    if ((s.cull_face == Face::Front) == front) return;
  }
  const int side = (!front && two_sided_lighting(s)) ? 1 : 0;
  const bool flat = s.shade == ShadeModel::Flat;
  const float* flat_attrs = flat ? prov.a : nullptr;
  PolygonMode mode = front ? s.poly_front : s.poly_back;
  if (mode == PolygonMode::Fill) {
    for (std::size_t i = 1; i + 1 < w.size(); ++i) emit_triangle(w[0], w[i], w[i + 1], side, flat_attrs);
  } else if (mode == PolygonMode::Line) {
    for (std::size_t i = 0, n = w.size(); i < n; ++i)
      if (poly[i].edge) emit_line(w[i], w[(i + 1) % n], side, flat_attrs);
  } else {
    // As Mesa's unfilled stage: a vertex is drawn when the edge leaving it is an original one.
    for (std::size_t i = 0; i < w.size(); ++i)
      if (poly[i].edge) emit_point(w[i], side);
  }
}

}  // namespace wedge::render::raster

namespace wedge::render {
using namespace raster;

void run_primitive(Context::State& s, int width, int height, std::uint8_t* color, float* depth, Primitive p,
                   const std::vector<InVertex>& in) {
  if (in.empty()) return;
  if (p == Primitive::Triangles && fast_triangles_ok(s)) {
    Raster r(s, width, height, color, depth);
    return draw_triangles(r, InSource{in.data()}, in.size() / 3);
  }
  const Mat4& mv = s.top(MatrixMode::ModelView);
  const Mat3 nmat = mv.topLeftCorner<3, 3>().inverse().transpose();
  const Mat4& proj = s.top(MatrixMode::Projection);
  Raster r(s, width, height, color, depth);
  // Kept between calls (the Context's): a fresh megabyte-sized vector per batch costs page faults.
  std::vector<PVert>& v = r.scratch->verts;
  v.resize(in.size());
  const LightSetup& lights = r.lights;
  // Independent triangles with face culling: a triangle wholly inside the clip volume that the
  // cull test removes (decided exactly as draw_triangle would, on the same window coordinates)
  // is marked here and its vertices are never lit. Every vertex of a non-indexed batch belongs
  // to one triangle, so a closed lit mesh lights about half of its vertices.
  std::vector<std::uint8_t>& culled = r.scratch->culled;
  const bool precull = p == Primitive::Triangles && s.on(Cap::CullFace) && r.user_planes.empty();
  const std::size_t units = precull ? in.size() / 3 : in.size();
  if (precull) culled.assign(units, 0);
  auto stage = [&](std::size_t lo, std::size_t hi) {
    for (std::size_t u = lo; u < hi; ++u) {
      if (!precull) {
        const Vec4 eye = mv * in[u].position;
        v[u] = process_vertex(s, lights, in[u], eye, proj * eye, nmat);
        continue;
      }
      PVert c[3];
      Vec4 eye[3];
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        eye[k] = mv * in[3 * u + k].position;
        c[k].clip = proj * eye[k];
        for (int pl = 0; pl < 6; ++pl)
          if (r.plane_dist(c[k], pl) < 0) inside = false;
      }
      if (inside) {
        const WinVert w[3] = {r.to_window(c[0]), r.to_window(c[1]), r.to_window(c[2])};
        const bool front = (facing_area(w, 3) > 0) == (s.front_face == FrontFace::CCW);
        if (s.cull_face == Face::FrontAndBack || (s.cull_face == Face::Front) == front) {
          culled[u] = 1;
          continue;
        }
      }
      for (int k = 0; k < 3; ++k) v[3 * u + k] = process_vertex(s, lights, in[3 * u + k], eye[k], c[k].clip, nmat);
    }
  };
  if (s.threads > 1 && in.size() >= 1024) {
    // The vertex stage is independent per vertex.
    tbb::task_arena& arena = r.scratch->arena(s.threads);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, units, 256),
                        [&](const tbb::blocked_range<std::size_t>& br) { stage(br.begin(), br.end()); });
    });
  } else {
    stage(0, units);
  }
  Queue& jobs = r.scratch->queue;
  jobs.clear();
  std::vector<Queue*> queues;  // queued primitives, in order
  // Bands pay for many primitives, or for few on a large framebuffer (a couple of big textured
  // triangles are all fragment work).
  const bool banded = s.threads > 1 && (in.size() >= 64 || std::int64_t(width) * height >= 512 * 512);
  if (banded) r.sink = &jobs;
  const std::size_t n = v.size();
  // Every polygon is split into triangles before clipping, as Mesa does (quads as (0,1,2),
  // (0,2,3) keeping the last vertex as provoking; polygons as a fan from vertex 0); the edge
  // flags hide the inner diagonals in polygon-mode line.
  auto tri = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t prov, bool e0 = true, bool e1 = true,
                 bool e2 = true) {
    PVert va = v[a], vb = v[b], vc = v[c];
    va.edge = e0, vb.edge = e1, vc.edge = e2;
    r.draw_triangle(va, vb, vc, v[prov]);
  };
  // Which diagonal splits a quad changes how colours interpolate across it. GL leaves it open;
  // Mesa splits (0,1,2),(0,2,3) on its fast path and (0,1,3),(1,2,3) when the batch goes
  // through its clipping/two-side pipeline (some vertex outside the clip volume, or two-sided
  // lighting). We follow Mesa, so that images compare pixel for pixel.
  bool pipeline_split = false;
  if (p == Primitive::Quads || p == Primitive::QuadStrip) {
    pipeline_split = two_sided_lighting(s) || s.poly_front != PolygonMode::Fill || s.poly_back != PolygonMode::Fill;
    for (std::size_t i = 0; i < v.size() && !pipeline_split; ++i)
      for (int k = 0; k < r.plane_count(); ++k)
        if (r.plane_dist(v[i], k) < 0) {
          pipeline_split = true;
          break;
        }
  }
  auto quad = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t d, std::size_t prov) {
    if (pipeline_split) {
      tri(a, b, d, prov, true, false, true);
      tri(b, c, d, prov, true, true, false);
    } else {
      tri(a, b, c, prov, true, true, false);
      tri(a, c, d, prov, false, true, true);
    }
  };
  switch (p) {
    case Primitive::Points:
      for (auto& x : v) r.draw_point(x);
      break;
    case Primitive::Lines:
      for (std::size_t i = 0; i + 1 < n; i += 2) r.draw_line(v[i], v[i + 1], v[i + 1]);
      break;
    case Primitive::LineStrip:
      for (std::size_t i = 0; i + 1 < n; ++i) r.draw_line(v[i], v[i + 1], v[i + 1]);
      break;
    case Primitive::LineLoop:
      for (std::size_t i = 0; i + 1 < n; ++i) r.draw_line(v[i], v[i + 1], v[i + 1]);
      if (n > 1) r.draw_line(v[n - 1], v[0], v[0]);
      break;
    case Primitive::Triangles:
      if (banded && n >= 3 * 512) {
        // Clipping and setup in parallel over chunks of triangles, each into its own queue;
        // the queues are joined in chunk order, so submission order is kept.
        const std::size_t tris = n / 3, chunk = 256, chunks = (tris + chunk - 1) / chunk;
        // Kept between batches (the Context's): fresh 100 kB queues cost page faults.
        std::vector<std::unique_ptr<Queue>>& cq = r.scratch->chunk_queues;
        while (cq.size() < chunks) cq.push_back(std::make_unique<Queue>());
        const int bands = (height + kBandRows - 1) / kBandRows;
        tbb::task_arena& arena = r.scratch->arena(s.threads);
        arena.execute([&] {
          tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            Raster rc = r;
            cq[c]->clear();
            rc.sink = cq[c].get();
            for (std::size_t t = c * chunk; t < std::min(tris, (c + 1) * chunk); ++t)
              if (!precull || !culled[t]) rc.draw_triangle(v[3 * t], v[3 * t + 1], v[3 * t + 2], v[3 * t + 2]);
            cq[c]->bin(bands);
          });
        });
        // Drawn straight from the queues, in chunk order (no copy into one list).
        for (std::size_t c = 0; c < chunks; ++c) queues.push_back(cq[c].get());
      } else {
        // Vertices leave the vertex stage with their edge flags set: no copies needed.
        for (std::size_t i = 0; i + 2 < n; i += 3)
          if (!precull || !culled[i / 3]) r.draw_triangle(v[i], v[i + 1], v[i + 2], v[i + 2]);
      }
      break;
    case Primitive::TriangleStrip:
      for (std::size_t i = 0; i + 2 < n; ++i) {
        if (i % 2 == 0) tri(i, i + 1, i + 2, i + 2);
        else tri(i + 1, i, i + 2, i + 2);
      }
      break;
    case Primitive::TriangleFan:
      for (std::size_t i = 1; i + 1 < n; ++i) tri(0, i, i + 1, i + 1);
      break;
    case Primitive::Quads:
      for (std::size_t i = 0; i + 3 < n; i += 4) quad(i, i + 1, i + 2, i + 3, i + 3);
      break;
    case Primitive::QuadStrip:
      for (std::size_t i = 0; i + 3 < n; i += 2) {
        if (pipeline_split) quad(i + 2, i, i + 1, i + 3, i + 3);  // Mesa's QUAD(i+2, i, i+1, i+3)
        else quad(i, i + 1, i + 3, i + 2, i + 3);
      }
      break;
    case Primitive::Polygon:
      for (std::size_t i = 1; i + 1 < n; ++i) tri(0, i, i + 1, 0, i == 1, true, i + 2 == n);
      break;
  }
  if (!banded) return;
  if (!jobs.jobs.empty()) {
    jobs.bin((height + kBandRows - 1) / kBandRows);
    queues.push_back(&jobs);
  }
  r.sink = nullptr;
  if (!queues.empty()) draw_bands(r, queues.data(), queues.size());
}

}  // namespace wedge::render
