// The batched path for independent filled triangles (GL_TRIANGLES from arrays or a begin/end
// batch, both polygon modes Fill, no user clip planes: the common case), by chunks of 256
// triangles: positions transformed by rows (4 doubles per instruction with AVX2, 2 with SSE2);
// a triangle wholly inside the clip volume gets its window coordinates, facing and cull test,
// and is dropped when it covers no pixel centre; only the vertices of the remaining triangles
// get their attributes (lit by light_needed_vertices); then the triangles are drawn by runs
// (triangle_run.cpp), or queued for the bands (bands.cpp). A triangle crossing the clip volume
// takes the general path (Raster::draw_triangle). The same decisions and arithmetic as that
// general path, but for the zero terms the position stage leaves out of the usual matrices (at
// most the sign of a zero differs).
#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/parallel_for.h>

#include "render/raster.h"

namespace wedge::render::raster {

// Whether a batch of independent triangles may take this path.
bool fast_triangles_ok(const Context::State& s) {
  if (s.poly_front != PolygonMode::Fill || s.poly_back != PolygonMode::Fill) return false;
  for (int i = 0; i < 6; ++i)
    if (s.on(clip_plane_cap(i))) return false;
  return true;
}

constexpr std::size_t kChunk = 256;  // triangles

// One chunk's buffers, kept between batches (one per worker: Scratch::chunks).
struct TriChunk {
  enum : std::uint8_t { kSkip, kDraw, kClip };
  // Per vertex, by rows (SoA): object position x y z w, eye x y z w, clip x y z w, window
  // x y z and 1 / w_clip; rows of `stride` (the vertex count rounded up to 4).
  enum Row { kPx, kPy, kPz, kPw, kEx, kEy, kEz, kEw, kCx, kCy, kCz, kCw, kWx, kWy, kWz, kIw, kRows };
  std::vector<double> soa;
  std::size_t stride = 0;
  double* row(int r) { return soa.data() + r * stride; }
  std::vector<std::uint8_t> vout;  // per vertex: outside the clip volume
  std::vector<std::uint8_t> status, side, flags;  // per triangle (flags: cull_rows')
  std::vector<std::uint32_t> need;         // vertices whose attributes are needed, in order
  std::vector<WinVert> run_v;              // window vertices of the triangles drawn by runs
  std::vector<Raster::RunTri> run;
};

// What a chunk hands to the bands: the attribute sets of its needed vertices (in `need`
// order), the window vertices of its triangles, and its queue, whose jobs point into them.
struct ChunkOut {
  std::vector<float> attrs;
  std::vector<WinVert> win;
  Queue queue;
};

Scratch::Scratch() = default;
Scratch::~Scratch() = default;

namespace {

// The position stage of a chunk, four vertices at a time by rows: eye = mv p, clip = proj eye
// (Eigen's operation order per element: ((c0 x + c1 y) + c2 z) + c3 w), the clip-volume test, and window
// coordinates (to_window's arithmetic) for every vertex. Compiled twice: for AVX2 (4 doubles
// per instruction, chosen at run time) and for the default target (SSE2: pairs).
struct PositionStage {
  double mv[16], proj[16];  // column-major
  double vpx, vpy, vpw, vph, dn, dr;
  // The usual case, taken with fewer operations: an affine modelview (last row 0 0 0 1) and a
  // projection shaped as glFrustum's and gluPerspective's (zeros where theirs are), with w = 1.
  bool frustum = false;
  PositionStage(const Context::State& s) {
    const Mat4& m = s.top(MatrixMode::ModelView);
    const Mat4& p = s.top(MatrixMode::Projection);
    for (int k = 0; k < 16; ++k) mv[k] = m(k % 4, k / 4), proj[k] = p(k % 4, k / 4);
    vpx = s.vp_x, vpy = s.vp_y, vpw = s.vp_w, vph = s.vp_h;
    dn = s.depth_near, dr = s.depth_far - s.depth_near;
    const bool affine = mv[3] == 0 && mv[7] == 0 && mv[11] == 0 && mv[15] == 1;
    bool shape = true;
    for (int k : {1, 2, 3, 4, 6, 7, 12, 13, 15}) shape = shape && proj[k] == 0;
    frustum = affine && shape;
  }
};

// V: a vector of doubles (D2 for the default target, D4 for AVX2); L its comparison mask.
// xyz: the chunk's positions packed x y z (w = 1) in the client array, its `count` vertices read
// there (the padding to the stride from zeros); else null, and the object rows hold them.
// Frustum (ps.frustum, xyz given): the terms whose matrix entries are zero (and w = 1) are left
// out; the others keep their order, so the results differ from the full products at most in
// the sign of a zero (and for infinite input, which the full products turn into NaN).
template <class V, bool Frustum>
[[gnu::always_inline]] inline void position_rows(const PositionStage& ps, TriChunk& ck, const double* xyz,
                                                 std::size_t count) {
  typedef decltype(V{} < V{}) L;
  constexpr int kW = sizeof(V) / sizeof(double);
  const std::size_t n = ck.stride;
  double* const b = ck.soa.data();
  std::uint8_t* const vout = ck.vout.data();
  const double* m = ps.mv;
  const double* p = ps.proj;
  for (std::size_t i = 0; i < n; i += kW) {
    double* const q = b + i;
    V X, Y, Z, W;
    if (xyz) {
      // kW vertices' x y z (3 kW doubles) as three vectors, then by lanes.
      alignas(32) double pad[3 * kW];
      const double* src = xyz + 3 * i;
      if (i + kW > count) {  // (the stride is a multiple of 4: a 2-lane group may lie wholly past the end)
        std::fill(std::begin(pad), std::end(pad), 0.0);
        if (i < count) std::memcpy(pad, src, 3 * (count - i) * sizeof(double));
        src = pad;
      }
      V v[3];
      rows_xyz(src, v);
      X = v[0], Y = v[1], Z = v[2];
      W = V{} + 1.0;
    } else {
      std::memcpy(&X, q, sizeof(V)), std::memcpy(&Y, q + n, sizeof(V));
      std::memcpy(&Z, q + 2 * n, sizeof(V)), std::memcpy(&W, q + 3 * n, sizeof(V));
    }
    V ex, ey, ez, ew, cx, cy, cz, cw;
    if constexpr (Frustum) {
      ex = ((m[0] * X + m[4] * Y) + m[8] * Z) + m[12];
      ey = ((m[1] * X + m[5] * Y) + m[9] * Z) + m[13];
      ez = ((m[2] * X + m[6] * Y) + m[10] * Z) + m[14];
      ew = V{} + 1.0;
      cx = p[0] * ex + p[8] * ez;
      cy = p[5] * ey + p[9] * ez;
      cz = p[10] * ez + p[14];
      cw = p[11] * ez;
    } else {
      ex = ((m[0] * X + m[4] * Y) + m[8] * Z) + m[12] * W;
      ey = ((m[1] * X + m[5] * Y) + m[9] * Z) + m[13] * W;
      ez = ((m[2] * X + m[6] * Y) + m[10] * Z) + m[14] * W;
      ew = ((m[3] * X + m[7] * Y) + m[11] * Z) + m[15] * W;
      cx = ((p[0] * ex + p[4] * ey) + p[8] * ez) + p[12] * ew;
      cy = ((p[1] * ex + p[5] * ey) + p[9] * ez) + p[13] * ew;
      cz = ((p[2] * ex + p[6] * ey) + p[10] * ez) + p[14] * ew;
      cw = ((p[3] * ex + p[7] * ey) + p[11] * ez) + p[15] * ew;
    }
    const L out = ((cw + cx) < 0.0) | ((cw - cx) < 0.0) | ((cw + cy) < 0.0) | ((cw - cy) < 0.0) | ((cw + cz) < 0.0) |
                  ((cw - cz) < 0.0);
    const V iw = 1.0 / cw;
    const V nx = cx * iw, ny = cy * iw, nz = cz * iw;
    const V wx = ps.vpx + (nx + 1.0) * 0.5 * ps.vpw, wy = ps.vpy + (ny + 1.0) * 0.5 * ps.vph;
    const V wz = ps.dn + (nz + 1.0) * 0.5 * ps.dr;
    std::memcpy(q + TriChunk::kEx * n, &ex, sizeof(V)), std::memcpy(q + TriChunk::kEy * n, &ey, sizeof(V));
    std::memcpy(q + TriChunk::kEz * n, &ez, sizeof(V)), std::memcpy(q + TriChunk::kEw * n, &ew, sizeof(V));
    std::memcpy(q + TriChunk::kCx * n, &cx, sizeof(V)), std::memcpy(q + TriChunk::kCy * n, &cy, sizeof(V));
    std::memcpy(q + TriChunk::kCz * n, &cz, sizeof(V)), std::memcpy(q + TriChunk::kCw * n, &cw, sizeof(V));
    std::memcpy(q + TriChunk::kWx * n, &wx, sizeof(V)), std::memcpy(q + TriChunk::kWy * n, &wy, sizeof(V));
    std::memcpy(q + TriChunk::kWz * n, &wz, sizeof(V)), std::memcpy(q + TriChunk::kIw * n, &iw, sizeof(V));
    // (One byte per lane, taken from the register: reading the mask's lanes back from memory
    // stalls on store forwarding.)
    for (int l = 0; l < kW; ++l) vout[i + l] = std::uint8_t(out[l] & 1);
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void position_rows_avx2(const PositionStage& ps, TriChunk& ck, const double* xyz,
                                                         std::size_t count) {
  if (xyz && ps.frustum) position_rows<D4, true>(ps, ck, xyz, count);
  else position_rows<D4, false>(ps, ck, xyz, count);
}
#endif
void position_rows_default(const PositionStage& ps, TriChunk& ck, const double* xyz, std::size_t count) {
  if (xyz && ps.frustum) position_rows<D2, true>(ps, ck, xyz, count);
  else position_rows<D2, false>(ps, ck, xyz, count);
}

// The facing and pixel-centre tests of a chunk's triangles, kW at a time (run_chunk's loop
// takes the bits): bit 0 front facing (draw_inside_triangle's area, lane by lane), bit 1 some
// pixel centre in the vertices' box, 1/256 pixel of slack: the centre columns c with c + 1/2 in
// [xmin - d, xmax + d] and x0 <= c < x1 end at min(floor(xmax - 1/2 + d), x1 - 1), which must
// be at least xmin - 1/2 - d and x0 (rows alike; false for NaN). (Lanes past the chunk's last
// triangle read the rows that follow: their bits are not used.)
struct CullBox {
  bool ccw;
  int x0, y0, x1, y1;
};
template <class V>
[[gnu::always_inline]] inline void cull_rows(const CullBox& cb, TriChunk& ck, std::size_t nt) {
  constexpr int kW = sizeof(V) / sizeof(double);
  const double* wx = ck.row(TriChunk::kWx);
  const double* wy = ck.row(TriChunk::kWy);
  constexpr double d = 1.0 / 256;
  for (std::size_t j = 0; j < nt; j += kW) {
    V x[3], y[3];
    rows_xyz(wx + 3 * j, x), rows_xyz(wy + 3 * j, y);  // (three vertices per triangle, by lanes)
    const V area = facing_area(x, y);
    const auto pos = area > 0.0;
    const auto front = cb.ccw ? pos : ~pos;
    const V xmin = vmin(vmin(x[0], x[1]), x[2]), xmax = vmax(vmax(x[0], x[1]), x[2]);
    const V ymin = vmin(vmin(y[0], y[1]), y[2]), ymax = vmax(vmax(y[0], y[1]), y[2]);
    const V hx = vmin(vfloor(xmax - 0.5 + d), V{} + double(cb.x1 - 1));
    const V hy = vmin(vfloor(ymax - 0.5 + d), V{} + double(cb.y1 - 1));
    const auto box = (hx >= xmin - 0.5 - d) & (hx >= double(cb.x0)) & (hy >= ymin - 0.5 - d) & (hy >= double(cb.y0));
    for (int l = 0; l < kW; ++l) ck.flags[j + l] = std::uint8_t((front[l] & 1) | (box[l] & 2));
  }
}
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void cull_rows_avx2(const CullBox& cb, TriChunk& ck, std::size_t nt) {
  cull_rows<D4>(cb, ck, nt);
}
#endif
void cull_rows_default(const CullBox& cb, TriChunk& ck, std::size_t nt) { cull_rows<D2>(cb, ck, nt); }

template <class Src>
void run_chunk(Raster& rc, const Src& src, const Mat3& nmat, const DrawLights& dl, TriChunk& ck, ChunkOut& co,
               RunSetup& rs, std::size_t t0, std::size_t t1) {
  const Context::State& s = rc.s;
  const std::size_t nt = t1 - t0, nv = 3 * nt, v0 = 3 * t0;
  ck.stride = (nv + 3) & ~std::size_t(3);
  ck.soa.resize(TriChunk::kRows * ck.stride), ck.vout.resize(ck.stride);
  ck.status.resize(nt), ck.side.resize(nt), ck.flags.resize(nt + 4);
  {
    const double* xyz = src.packed_xyz(v0);
    if (!xyz) {
      double* p[4] = {ck.row(TriChunk::kPx), ck.row(TriChunk::kPy), ck.row(TriChunk::kPz), ck.row(TriChunk::kPw)};
      src.positions(v0, nv, p[0], p[1], p[2], p[3]);
      for (std::size_t i = nv; i < ck.stride; ++i) p[0][i] = p[1][i] = p[2][i] = 0, p[3][i] = 1;
    }
    const PositionStage ps(s);
#if defined(__x86_64__) && defined(__GNUC__)
    if (rc.avx2) position_rows_avx2(ps, ck, xyz, nv);
    else position_rows_default(ps, ck, xyz, nv);
#else
    position_rows_default(ps, ck, xyz, nv);
#endif
  }
  const bool cull = s.on(Cap::CullFace);
  const bool two = two_sided_lighting(s);
  {
    // As draw_inside_triangle: signed area ((0 + t0) + t1) + t2 (0 + t0 only differs from t0
    // in the sign of a zero, which `area > 0` does not see), facing; and the centres in the box.
    const CullBox cb{s.front_face == FrontFace::CCW, rc.x0, rc.y0, rc.x1, rc.y1};
#if defined(__x86_64__) && defined(__GNUC__)
    if (rc.avx2) cull_rows_avx2(cb, ck, nt);
    else cull_rows_default(cb, ck, nt);
#else
    cull_rows_default(cb, ck, nt);
#endif
  }
  ck.need.clear();
  for (std::size_t j = 0; j < nt; ++j) {
    const std::size_t i = 3 * j;
    std::uint8_t st = TriChunk::kClip;
    if (!(ck.vout[i] | ck.vout[i + 1] | ck.vout[i + 2])) {
      // Facing, culling, then the pixel-centre test.
      const bool front = ck.flags[j] & 1;
      if (cull && (s.cull_face == Face::FrontAndBack || (s.cull_face == Face::Front) == front)) st = TriChunk::kSkip;
      else if (!(ck.flags[j] & 2)) st = TriChunk::kSkip;
      else st = TriChunk::kDraw, ck.side[j] = (!front && two) ? 1 : 0;
    }
    ck.status[j] = st;
    if (st != TriChunk::kSkip)
      for (int k = 0; k < 3; ++k) ck.need.push_back(std::uint32_t(i + k));
  }
  // Attributes of the needed vertices; lit ones W = 4 or 8 at a time (light_needed).
  const bool lit = vertex_lighting(s);
  const AttrNeeds needs(s);
  // Lit, nothing else read: the normal and colour alone (no InVertex, no texture stage), and
  // attribute sets cut to the colours the fill reads (a[kFront..] and, two-sided, a[kBack..]:
  // kFront = 0, kBack = 4), so queued triangles carry 16 or 32 bytes per vertex, not 80.
  const bool lean = lit && !needs.tex && !needs.fog && !needs.eye_normal;
  static_assert(kFront == 0 && kBack == 4, "lean attribute sets hold the colours first");
  const std::size_t astride = !lean ? kAttrs : s.two_side ? 8 : 4;
  // (Plus one full set of slack: a reader taking kAttrs floats from the last set stays inside.)
  co.attrs.resize(ck.need.size() * astride + kAttrs);
  float* const attrs = co.attrs.data();
  const double* ex = ck.row(TriChunk::kEx);
  const double* ey = ck.row(TriChunk::kEy);
  const double* ez = ck.row(TriChunk::kEz);
  const double* ew = ck.row(TriChunk::kEw);
  const std::size_t nn = ck.need.size();
  if (!lit) {
    for (std::size_t q = 0; q < nn; ++q) {
      const std::size_t i = ck.need[q];
      vertex_attrs(s, src.vertex(v0 + i), Vec4(ex[i], ey[i], ez[i], ew[i]), nmat, attrs + q * astride, needs);
    }
  } else {
    const NeededVerts nv{ck.need.data(), nn, {ex, ey, ez, ew}, v0};
    light_needed_vertices(dl, s, rc.lights, src, nmat, nv, lean, needs, attrs, astride);
  }

  // Draw (or queue) in submission order; a drawn triangle's vertices have consecutive slots.
  const bool flat = s.shade == ShadeModel::Flat;
  std::size_t slot = 0;
  const double* wx = ck.row(TriChunk::kWx);
  const double* wy = ck.row(TriChunk::kWy);
  const double* wz = ck.row(TriChunk::kWz);
  const double* iw = ck.row(TriChunk::kIw);
  const double *cx = ck.row(TriChunk::kCx), *cy = ck.row(TriChunk::kCy), *cz = ck.row(TriChunk::kCz),
               *cw = ck.row(TriChunk::kCw);
  // Drawn now (no bands): by runs (Raster::triangle_run), cut at each clipped triangle.
  // (Queued triangles point at theirs: the chunk output's, not the worker's buffers.)
  std::vector<WinVert>& run_v = rc.sink ? co.win : ck.run_v;
  std::vector<Raster::RunTri>& run = ck.run;
  run_v.resize(3 * nt), run.clear();
  auto flush = [&] {
    rc.triangle_run(run.data(), run.size(), rs);
    run.clear();
  };
  for (std::size_t j = 0; j < nt; ++j) {
    if (ck.status[j] == TriChunk::kSkip) continue;
    const float* a = attrs + slot * astride;
    slot += 3;
    if (ck.status[j] == TriChunk::kDraw) {
      WinVert* w = run_v.data() + 3 * j;
      for (int k = 0; k < 3; ++k) {
        const std::size_t i = 3 * j + k;
        w[k] = WinVert{wx[i], wy[i], wz[i], iw[i], a + k * astride};
      }
      if (rc.sink) rc.emit_triangle_direct(w, ck.side[j], flat ? w[2].a : nullptr);
      else run.push_back(Raster::RunTri{w, ck.side[j], flat ? w[2].a : nullptr});
      continue;
    }
    flush();
    PVert pv[3];
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = 3 * j + k;
      pv[k].clip = Vec4(cx[i], cy[i], cz[i], cw[i]);
      // (A lean set's missing attributes are zero, as vertex_attrs leaves unread ones.)
      std::fill(std::begin(pv[k].a), std::end(pv[k].a), 0.0f);
      std::memcpy(pv[k].a, a + k * astride, sizeof(float) * astride);
      if (astride == 4) std::memcpy(pv[k].a + kBack, a + k * astride, 4 * sizeof(float));
    }
    rc.draw_triangle(pv[0], pv[1], pv[2], pv[2]);
  }
  flush();
}
}  // namespace

// A batch of `tris` independent triangles from `src`, drawn through `r`.
template <class Src>
void draw_triangles(Raster& r, const Src& src, std::size_t tris) {
  if (tris == 0) return;
  const Context::State& s = r.s;
  const Mat3 nmat = s.top(MatrixMode::ModelView).topLeftCorner<3, 3>().inverse().transpose();
  const DrawLights dl(s, r.lights, r.avx2);
  const std::size_t chunks = (tris + kChunk - 1) / kChunk;
  // Kept between batches (the Context's): fresh buffers would cost page faults.
  Scratch& sc = *r.scratch;
  std::vector<std::unique_ptr<ChunkOut>>& ck = sc.chunk_outs;
  const bool banded = s.threads > 1 && (3 * tris >= 64 || std::int64_t(r.width) * r.height >= 512 * 512);
  const std::size_t need = banded ? chunks : 1;
  while (ck.size() < need) ck.push_back(std::make_unique<ChunkOut>());
  if (!banded) {
    r.sink = nullptr;
    if (sc.chunks.empty()) sc.chunks.push_back(std::make_unique<TriChunk>());
    RunSetup rs;
    for (std::size_t c = 0; c < chunks; ++c)
      run_chunk(r, src, nmat, dl, *sc.chunks[0], *ck[0], rs, c * kChunk, std::min(tris, (c + 1) * kChunk));
    return;
  }
  const int bands = (r.height + kBandRows - 1) / kBandRows;
  tbb::task_arena& arena = sc.arena(s.threads);
  while (sc.chunks.size() < std::size_t(arena.max_concurrency())) sc.chunks.push_back(std::make_unique<TriChunk>());
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      Raster rc = r;
      ChunkOut& k = *ck[c];
      k.queue.clear();
      rc.sink = &k.queue;
      RunSetup rs;  // (unused when queueing: the chunk's triangles go to the queue)
      TriChunk& buffers = *sc.chunks[std::size_t(tbb::this_task_arena::current_thread_index())];
      run_chunk(rc, src, nmat, dl, buffers, k, rs, c * kChunk, std::min(tris, (c + 1) * kChunk));
      k.queue.bin(bands);
    });
  });
  std::vector<Queue*>& queues = sc.queue_list;
  queues.clear();
  for (std::size_t c = 0; c < chunks; ++c) queues.push_back(&ck[c]->queue);
  draw_bands(r, queues.data(), queues.size());
}
template void draw_triangles<InSource>(Raster& r, const InSource& src, std::size_t tris);

}  // namespace wedge::render::raster

namespace wedge::render {
using namespace raster;

bool run_triangle_arrays(Context::State& s, int width, int height, std::uint8_t* color, float* depth,
                         const VertexArrays& a, const std::uint32_t* indices, int first, int count) {
  if (!fast_triangles_ok(s)) return false;
  Raster r(s, width, height, color, depth);
  // Batches bound the queued primitives' memory (about 6 MB for a batch of small lit
  // triangles). With threads, each batch costs two forks and joins: 32,768 triangles rather than
  // 16,384 gave the 1M sphere at 2 threads 1.66x -> 1.70x of its one-thread speed (medians of 12
  // interleaved runs; CPU 82-83 -> 81-82 ms per frame).
  constexpr std::size_t kBatch = 32768;  // triangles
  const std::size_t tris = std::size_t(count) / 3;
  for (std::size_t t = 0; t < tris; t += kBatch)
    draw_triangles(r, ArraySource{s, a, indices, std::size_t(first) + 3 * t}, std::min(kBatch, tris - t));
  return true;
}

}  // namespace wedge::render
