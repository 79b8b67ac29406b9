// Runs of small triangles: most triangles of a dense mesh cover a pixel or two, where the setup
// of triangle_q costs more than the pixels. Raster::triangle_run sets up a run's triangles a few
// at a time, one per double lane (run_setup: four with AVX2, two with SSE2) and draws the small
// covered ones pixel by pixel (Raster::tiny_pixel), the others through Raster::triangle.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

namespace {
#if defined(__SSE2__)
// x0 y0 x1 y1: Raster's bounds; rows r0 .. r1 (half open) those drawn (Raster::band_y0, band_y1).
template <class V>
[[gnu::always_inline]] inline void run_setup(RunSetup& r, int n, int x0, int y0, int x1, int y1, int r0, int r1) {
  typedef decltype(V{} < V{}) L;
  constexpr int kW = sizeof(V) / sizeof(double);
  // First the coverage (few values live: the mask stays in a register), then the planes.
  for (int t = 0; t < n; t += kW) {
    V x[3], y[3];
    for (int i = 0; i < 3; ++i) x[i] = vload<V>(r.x[i] + t), y[i] = vload<V>(r.y[i] + t);
    // Snapped coordinates; lanes beyond 2^25 (1/256 pixels) or not finite go to triangle().
    V X[3], Y[3];
    L ok = x[0] == x[0];
    for (int i = 0; i < 3; ++i) {
      const V sx = x[i] * 256.0, sy = y[i] * 256.0;
      ok &= (vabs(sx) < 0x1p25) & (vabs(sy) < 0x1p25);
      X[i] = vhalf_away(vsel(ok, sx, V{})), Y[i] = vhalf_away(vsel(ok, sy, V{}));
    }
    V area = setup_area(X, Y);
    const L none = area == 0.0;
    const L flip = area < 0.0;
    auto swap12 = [&](V* a) {
      const V a1 = a[1];
      a[1] = vsel(flip, a[2], a[1]), a[2] = vsel(flip, a1, a[2]);
    };
    swap12(X), swap12(Y);
    std::memcpy(r.flip + t, &flip, sizeof flip);
    const V bx0 = vmax(V{} + double(x0), vfloor((vmin(vmin(X[0], X[1]), X[2]) + 127.0) * (1.0 / 256)));
    const V bx1 = vmin(V{} + double(x1 - 1), vfloor((vmax(vmax(X[0], X[1]), X[2]) - 128.0) * (1.0 / 256)));
    const V ty0 = vmax(V{} + double(y0), vfloor((vmin(vmin(Y[0], Y[1]), Y[2]) + 127.0) * (1.0 / 256)));
    const V ty1 = vmin(V{} + double(y1 - 1), vfloor((vmax(vmax(Y[0], Y[1]), Y[2]) - 128.0) * (1.0 / 256)));
    // The first quad from the box in all rows, the rows drawn from the band's (as triangle_q).
    const V by0 = vmax(ty0, V{} + double(r0)), by1 = vmin(ty1, V{} + double(r1 - 1));
    const L empty = (bx0 > bx1) | (by0 > by1);
    const V ox = vfloor(bx0 * 0.5) * 2.0, oy = vfloor(ty0 * 0.5) * 2.0;
    V A[3], B[3], e[3];
    L fits = ok;
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      const V dx = X[b] - X[a], dy = Y[b] - Y[a];
      A[i] = -dy, B[i] = dx;
      const L top_left = (dy < 0.0) | ((dy == 0.0) & (dx < 0.0));
      const V K = A[i] * (128.0 - X[a]) + B[i] * (128.0 - Y[a]) + vsel(top_left, V{}, V{} - 1.0);
      const V ci = A[i] * ox + B[i] * oy + vfloor(K * (1.0 / 256));
      fits &= vabs(ci) + vabs(A[i]) * (bx1 + 3.0 - ox) + vabs(B[i]) * (ty1 + 3.0 - oy) <= 0x1p30;
      e[i] = ci + B[i] * (by0 - oy) + A[i] * (bx0 - ox);  // at pixel (bx0, by0)
    }
    const L tiny = (bx1 - bx0 < 4.0) & (ty1 - ty0 < 4.0);
    // Centres (bx0 + k, by0 + j), k, j < 4 (those beyond bx1 or by1 are masked off per triangle
    // below) into bit 4 j + k: covered when no edge function is negative. A step in k adds A, a
    // step in j adds B (exact); the edge functions start at +0 (e + 0: no -0 arises from sums of
    // integers then), so "not negative" is a clear sign bit, and the sign bits of the three
    // ORed are shifted in, from (3, 3) down to (0, 0).
    typedef unsigned long long UL __attribute__((vector_size(sizeof(V))));
    UL mask{};
    V r0 = ((e[0] + 0.0) + B[0] * 3.0) + A[0] * 3.0, r1 = ((e[1] + 0.0) + B[1] * 3.0) + A[1] * 3.0,
      r2 = ((e[2] + 0.0) + B[2] * 3.0) + A[2] * 3.0;
#pragma GCC unroll 4
    for (int j = 3; j >= 0; --j) {
      V t0 = r0, t1 = r1, t2 = r2;
#pragma GCC unroll 4
      for (int k = 3; k >= 0; --k) {
        UL b0, b1, b2;
        std::memcpy(&b0, &t0, sizeof b0), std::memcpy(&b1, &t1, sizeof b1), std::memcpy(&b2, &t2, sizeof b2);
        mask = (mask + mask) | (~(b0 | b1 | b2) >> 63);
        t0 -= A[0], t1 -= A[1], t2 -= A[2];
      }
      r0 -= B[0], r1 -= B[1], r2 -= B[2];
    }
    // As triangle_q decides: nothing when the snapped area is zero or no centre is in the box;
    // triangle() when not small, beyond 32-bit edge functions or a sliver; else the covered
    // centres inside the box (none: nothing).
    alignas(32) unsigned long long mk[kW];
    alignas(32) long long st_none[kW], st_small[kW];
    const L drawn_none = ok & (none | empty);
    const L small = ok & fits & tiny;  // (and a triangle that snapping left the right way round: below)
    std::memcpy(mk, &mask, sizeof mk), std::memcpy(st_none, &drawn_none, sizeof mk), std::memcpy(st_small, &small, sizeof mk);
    alignas(32) double b6[6][kW];
    std::memcpy(r.oxd + t, &ox, sizeof(V)), std::memcpy(r.oyd + t, &oy, sizeof(V));
    std::memcpy(b6[0], &bx0, sizeof(V)), std::memcpy(b6[1], &by0, sizeof(V)), std::memcpy(b6[2], &ox, sizeof(V)),
        std::memcpy(b6[3], &oy, sizeof(V)), std::memcpy(b6[4], &bx1, sizeof(V)), std::memcpy(b6[5], &by1, sizeof(V));
    for (int l = 0; l < kW; ++l) {
      std::uint8_t st = RunSetup::kOther;
      std::uint32_t m = 0;
      if (st_none[l]) {
        st = RunSetup::kNone;
      } else if (st_small[l]) {
        const int w = int(b6[4][l] - b6[0][l]), h = int(b6[5][l] - b6[1][l]);  // 0 .. 3
        m = std::uint32_t(mk[l]) & (0x1111u * ((2u << w) - 1)) & ((2u << (4 * h + 3)) - 1);
        st = m ? RunSetup::kTiny : RunSetup::kNone;
      }
      r.status[t + l] = st;
      r.mask[t + l] = m;
      r.bx0[t + l] = int(b6[0][l]), r.by0[t + l] = int(b6[1][l]), r.ox[t + l] = int(b6[2][l]), r.oy[t + l] = int(b6[3][l]);
    }
  }
  for (int t = 0; t < n; t += kW) {
    V x[3], y[3], z[3], iw[3], c[3][4];
    for (int i = 0; i < 3; ++i) {
      x[i] = vload<V>(r.x[i] + t), y[i] = vload<V>(r.y[i] + t), z[i] = vload<V>(r.z[i] + t), iw[i] = vload<V>(r.iw[i] + t);
      for (int k = 0; k < 4; ++k) c[i][k] = vload<V>(r.col[i][k] + t);
    }
    L flip;
    std::memcpy(&flip, r.flip + t, sizeof flip);
    auto swap12 = [&](V* a) {
      const V a1 = a[1];
      a[1] = vsel(flip, a[2], a[1]), a[2] = vsel(flip, a1, a[2]);
    };
    swap12(x), swap12(y), swap12(z), swap12(iw);
    for (int k = 0; k < 4; ++k) {
      const V c1 = c[1][k];
      c[1][k] = vsel(flip, c[2][k], c[1][k]), c[2][k] = vsel(flip, c1, c[2][k]);
    }
    const V ox = vload<V>(r.oxd + t), oy = vload<V>(r.oyd + t);
    // Barycentric planes from the unsnapped positions (float_barycentrics); a sliver that
    // snapping turned over goes to triangle().
    const V area2 = setup_area(x, y);
    const L bary = (area2 > 0.0) & (area2 < __builtin_inf());
    const V inv = 1.0 / vsel(bary, area2, V{} + 1.0);
    V l0[3], gx[3], gy[3];
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      const V fa = (y[a] - y[b]) * inv, fb = (x[b] - x[a]) * inv, fc = -(fa * x[a] + fb * y[a]);
      l0[i] = fa * (ox + 0.5) + fb * (oy + 0.5) + fc, gx[i] = fa, gy[i] = fb;
    }
    // (A loop, not a lambda taking vectors: lambdas do not take the AVX2 target, and an
    // unoptimised build calls them with the vectors where the base target does not look.)
    for (int k = 0; k < 5; ++k) {
      const V f0 = k ? c[0][k - 1] * iw[0] : iw[0], f1 = k ? c[1][k - 1] * iw[1] : iw[1],
              f2 = k ? c[2][k - 1] * iw[2] : iw[2];
      typedef float FV __attribute__((vector_size(sizeof(V) / 2)));
      const FV pc = __builtin_convertvector((l0[0] * f0 + l0[1] * f1) + l0[2] * f2, FV);
      const FV px = __builtin_convertvector((gx[0] * f0 + gx[1] * f1) + gx[2] * f2, FV);
      const FV py = __builtin_convertvector((gy[0] * f0 + gy[1] * f1) + gy[2] * f2, FV);
      std::memcpy(r.pl[k][0] + t, &pc, sizeof(FV)), std::memcpy(r.pl[k][1] + t, &px, sizeof(FV));
      std::memcpy(r.pl[k][2] + t, &py, sizeof(FV));
    }
    V zc = V{}, zdx = V{}, zdy = V{};
    for (int i = 0; i < 3; ++i) zc += l0[i] * z[i], zdx += gx[i] * z[i], zdy += gy[i] * z[i];
    std::memcpy(r.zc + t, &zc, sizeof(V)), std::memcpy(r.zdx + t, &zdx, sizeof(V)), std::memcpy(r.zdy + t, &zdy, sizeof(V));
    alignas(32) long long bok[kW];
    std::memcpy(bok, &bary, sizeof bok);
    for (int l = 0; l < kW; ++l)
      if (!bok[l] && r.status[t + l] == RunSetup::kTiny) r.status[t + l] = RunSetup::kOther;
  }
}

__attribute__((target("avx2"))) void run_setup_avx2(RunSetup& r, int n, int x0, int y0, int x1, int y1, int r0,
                                                    int r1) {
  run_setup<D4>(r, n, x0, y0, x1, y1, r0, r1);
}
void run_setup_default(RunSetup& r, int n, int x0, int y0, int x1, int y1, int r0, int r1) {
  run_setup<D2>(r, n, x0, y0, x1, y1, r0, r1);
}
#endif
}  // namespace

#if defined(__SSE2__)
void Raster::triangle_run(const RunTri* tri, std::size_t n, RunSetup& rs) {
  if (phong || texturing || fog || blend || !all_mask) {
    for (std::size_t k = 0; k < n; ++k) triangle(tri[k].v[0], tri[k].v[1], tri[k].v[2], tri[k].side, tri[k].flat);
    return;
  }
  // Stretches of triangles that may be small (vertices within 5 pixels each way: no more than
  // 4 x 4 centres) go to small_run; larger ones straight to triangle(), in order.
  auto may_be_small = [](const RunTri& t) {
    const WinVert* v = t.v;
    return std::max({v[0].x, v[1].x, v[2].x}) - std::min({v[0].x, v[1].x, v[2].x}) < 5.0 &&
           std::max({v[0].y, v[1].y, v[2].y}) - std::min({v[0].y, v[1].y, v[2].y}) < 5.0;
  };
  for (std::size_t k = 0; k < n;) {
    std::size_t e = k;
    while (e < n && e - k < std::size_t(RunSetup::kMax) && may_be_small(tri[e])) ++e;
    if (e > k) {
      small_run(tri + k, int(e - k), rs);
      k = e;
    } else {
      triangle(tri[k].v[0], tri[k].v[1], tri[k].v[2], tri[k].side, tri[k].flat);
      ++k;
    }
  }
}
// Up to RunSetup::kMax triangles of triangle_run, set up together.
void Raster::small_run(const RunTri* tri, int m, RunSetup& rs) {
  const int m4 = (m + 3) & ~3;
  for (int t = 0; t < m4; ++t) {
    const RunTri& rt = tri[std::min(t, m - 1)];  // (the padding lanes repeat the last)
    const int col = rt.side ? kBack : kFront;
    for (int i = 0; i < 3; ++i) {
      const WinVert& w = rt.v[i];
      rs.x[i][t] = w.x, rs.y[i][t] = w.y, rs.z[i][t] = float(w.z), rs.iw[i][t] = w.inv_w;
      for (int c = 0; c < 4; ++c) rs.col[i][c][t] = w.a[col + c];
    }
  }
#if defined(__x86_64__) && defined(__GNUC__)
  if (avx2) run_setup_avx2(rs, m4, x0, y0, x1, y1, band_y0, band_y1);
  else run_setup_default(rs, m4, x0, y0, x1, y1, band_y0, band_y1);
#else
  run_setup_default(rs, m4, x0, y0, x1, y1, band_y0, band_y1);
#endif
  const DepthFunc dfunc = s.depth_func;
  const bool dmask = s.depth_mask;
  // The framebuffer lines of the first and last covered centre of a triangle a few ahead are
  // fetched while this one is drawn (a mesh's triangles come in no screen order: they miss).
  constexpr int kAhead = 8;
  for (int t = -kAhead; t < m; ++t) {
    const int f = t + kAhead;
    if (f < m && rs.status[f] == RunSetup::kTiny) {
      const std::uint32_t mk = rs.mask[f];
      const int b0 = __builtin_ctz(mk), b1 = 31 - __builtin_clz(mk);
      const std::size_t i0 = std::size_t(rs.by0[f] + (b0 >> 2)) * width + std::size_t(rs.bx0[f] + (b0 & 3));
      const std::size_t i1 = std::size_t(rs.by0[f] + (b1 >> 2)) * width + std::size_t(rs.bx0[f] + (b1 & 3));
      __builtin_prefetch(depth + i0, 1), __builtin_prefetch(color + 4 * i0, 1);
      __builtin_prefetch(depth + i1, 1), __builtin_prefetch(color + 4 * i1, 1);
    }
    if (t < 0) continue;
    const RunTri& rt = tri[t];
    if (rs.status[t] == RunSetup::kNone) continue;
    if (rs.status[t] == RunSetup::kOther) {
      triangle(rt.v[0], rt.v[1], rt.v[2], rt.side, rt.flat);
      continue;
    }
    const int col = rt.side ? kBack : kFront;
    const float* flat = flat_colour(rt.v[0], rt.v[1], rt.v[2], rt.side, rt.flat);
    float pl[5][3];
    for (int k = 0; k < 5; ++k)
      for (int q = 0; q < 3; ++q) pl[k][q] = rs.pl[k][q][t];
    const int bx0 = rs.bx0[t], by0 = rs.by0[t], ox = rs.ox[t], oy = rs.oy[t];
    const double zc = rs.zc[t], zdx = rs.zdx[t], zdy = rs.zdy[t];
    for (std::uint32_t mk = rs.mask[t]; mk; mk &= mk - 1) {
      const int b = __builtin_ctz(mk), px = bx0 + (b & 3), py = by0 + (b >> 2);
      const float X = float(px - ox), Y = float(py - oy);
      if (flat) {
        if (depth_test) tiny_pixel<false, true>(px, py, X, Y, zc, zdx, zdy, pl, flat + col, dfunc, dmask);
        else tiny_pixel<false, false>(px, py, X, Y, zc, zdx, zdy, pl, flat + col, dfunc, dmask);
      } else {
        if (depth_test) tiny_pixel<true, true>(px, py, X, Y, zc, zdx, zdy, pl, nullptr, dfunc, dmask);
        else tiny_pixel<true, false>(px, py, X, Y, zc, zdx, zdy, pl, nullptr, dfunc, dmask);
      }
    }
  }
}
#else
void Raster::triangle_run(const RunTri* tri, std::size_t n, RunSetup&) {
  for (std::size_t k = 0; k < n; ++k) triangle(tri[k].v[0], tri[k].v[1], tri[k].v[2], tri[k].side, tri[k].flat);
}
#endif

}  // namespace wedge::render::raster
