// Threads: rasterisation by bands of rows. With Context::threads > 1, primitives are not drawn
// as they are set up but queued (Raster::sink, a Queue per stretch of the batch); each queue is
// binned by the bands of kBandRows rows its primitives may touch, and the bands are drawn in
// parallel, each by one thread that owns its pixels and draws its primitives queue by queue in
// submission order, so the image is the same as drawing them one by one.

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/parallel_for.h>

#include "render/raster.h"

namespace wedge::render::raster {

// --- queueing for banded rasterisation ---
// The general path's attributes may live in scratch vectors: the job points at copies.
void Raster::copy_vert(WinVert& d, const WinVert& w) {
  d = w;
  d.a = sink->store.add(w.a);
}
Job& Raster::new_job(Job::Kind k, int side, const float* flat) {
  Job& j = sink->jobs.emplace_back();
  j.kind = k;
  j.side = std::uint8_t(side);
  j.flat = flat ? sink->store.add(flat) : nullptr;
  return j;
}
void Raster::emit_triangle(const WinVert& a, const WinVert& b, const WinVert& c, int side, const float* flat) {
  if (!sink) return triangle(a, b, c, side, flat);
  Job& j = new_job(Job::Tri, side, flat);
  WinVert* v = sink->verts.add(3);
  copy_vert(v[0], a), copy_vert(v[1], b), copy_vert(v[2], c);
  j.v = v;
  j.row0 = int(std::floor(std::min({a.y, b.y, c.y}))) - 1;
  j.row1 = int(std::floor(std::max({a.y, b.y, c.y}))) + 1;
}
// A triangle whose window vertices w[0..2] and attribute sets outlive the queue (the triangle
// path's chunk outputs): the job points at them, no copies.
void Raster::emit_triangle_direct(const WinVert* w, int side, const float* flat) {
  const WinVert &a = w[0], &b = w[1], &c = w[2];
  if (!sink) return triangle(a, b, c, side, flat);
  Job& j = sink->jobs.emplace_back();
  j.kind = Job::Tri;
  j.side = std::uint8_t(side);
  j.flat = flat;
  j.v = w;
  j.row0 = int(std::floor(std::min({a.y, b.y, c.y}))) - 1;
  j.row1 = int(std::floor(std::max({a.y, b.y, c.y}))) + 1;
}
void Raster::emit_line(const WinVert& a, const WinVert& b, int side, const float* flat) {
  if (!sink) return line(a, b, side, flat);
  Job& j = new_job(Job::Line, side, flat);
  WinVert* v = sink->verts.add(2);
  copy_vert(v[0], a), copy_vert(v[1], b);
  j.v = v;
  const int pad = int(std::ceil(s.line_width)) + 1;
  j.row0 = int(std::floor(std::min(a.y, b.y))) - pad;
  j.row1 = int(std::floor(std::max(a.y, b.y))) + pad;
}
void Raster::emit_point(const WinVert& p, int side) {
  if (!sink) return point(p, side);
  Job& j = new_job(Job::Point, side, nullptr);
  WinVert* v = sink->verts.add(1);
  copy_vert(v[0], p);
  j.v = v;
  const int pad = int(std::ceil(s.point_size)) + 1;
  j.row0 = int(std::floor(p.y)) - pad;
  j.row1 = int(std::floor(p.y)) + pad;
}
void Raster::exec(const Job& j) {
  if (j.kind == Job::Tri) triangle(j.v[0], j.v[1], j.v[2], j.side, j.flat);
  else if (j.kind == Job::Line) line(j.v[0], j.v[1], j.side, j.flat);
  else point(j.v[0], j.side);
}

// One arena per Context, kept between batches: constructing an arena for each stage of each
// batch (a 1M-triangle draw has hundreds of batches) cost more than the second thread gained.
tbb::task_arena& Scratch::arena(int threads) {
  if (!arena_ || arena_threads_ != threads) {
    arena_ = std::make_unique<tbb::task_arena>(threads);
    arena_threads_ = threads;
  }
  return *arena_;
}

// Draws queued primitives by bands of rows in parallel: each band owns its pixels and draws its
// primitives queue by queue, each in submission order (queues already binned).
void draw_bands(const Raster& r, Queue* const* queues, std::size_t nq) {
  const int bands = (r.height + kBandRows - 1) / kBandRows;
  tbb::task_arena& arena = r.scratch->arena(r.s.threads);
  arena.execute([&] {
    tbb::parallel_for(0, bands, [&](int b) {
      bool any = false;
      for (std::size_t q = 0; q < nq && !any; ++q) any = queues[q]->band_start[b + 1] > queues[q]->band_start[b];
      if (!any) return;
      Raster band = r;
      band.sink = nullptr;
      band.band_y0 = std::max(r.y0, b * kBandRows);
      band.band_y1 = std::min(r.y1, (b + 1) * kBandRows);
      // Consecutive triangles by runs (Raster::triangle_run), lines and points one by one.
      Raster::RunTri run[kRunMax];
      std::size_t n = 0;
      RunSetup rs;  // (the band's own, on its thread's stack)
      for (std::size_t q = 0; q < nq; ++q) {
        const Queue& qu = *queues[q];
        for (std::uint32_t k = qu.band_start[b]; k < qu.band_start[b + 1]; ++k) {
          const Job& j = qu.jobs[qu.band_jobs[k]];
          if (j.kind == Job::Tri) {
            run[n++] = Raster::RunTri{j.v, j.side, j.flat};
            if (n < kRunMax) continue;
          }
          band.triangle_run(run, n, rs);
          n = 0;
          if (j.kind != Job::Tri) band.exec(j);
        }
      }
      band.triangle_run(run, n, rs);
    });
  });
}

}  // namespace wedge::render::raster
