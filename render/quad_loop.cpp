// The quad fragment loop (GL 1.x section 3.5 and the per-fragment operations of chapter 4),
// written once for lanes of two widths: V = F4, one 2x2 quad per block (the default x86-64
// build: SSE2), or V = F8, two quads side by side per block (compiled with target("avx2"),
// chosen at run time: Raster::avx2). Lane l of a block is pixel (qx + lane_x(l), qy + lane_y(l)):
// the quad at qx in lanes 0-3 (0 (x, y), 1 (x+1, y), 2 (x, y+1), 3 (x+1, y+1), window y up) and,
// 8 lanes wide, the quad at qx + 2 in lanes 4-7 in the same order. Every lane does the same
// operations in the same order in both widths (GCC's vector operators, no FMA in either build),
// so both give the same bits (tests/render/test_fragment_paths.cpp checks it).
//
// Per block: coverage by the exact 32-bit edge functions (sign bits), the depth test (depth plane
// in double, depth_test.h), 1/w and the attributes a/w from float planes (perspective-correct:
// a = (a/w) / (1/w)), the colour (Phong lighting per lane, smooth, or flat), texturing (level of
// detail per quad from its (u, v) differences), fog, then the colour write: packed RGBA8 in the
// common state, else blending and the colour mask per lane (Raster::write_color). On wide
// triangles each pair of rows starts and ends at the columns the edges leave open.
//
// The body uses vector operators, SSE2 intrinsics and inline assembly only (never an AVX
// intrinsic): it is always inlined into its two builds, and GCC refuses to inline an AVX
// intrinsic into a function compiled for the base target, even one that is itself inlined into
// an AVX2 function.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

#if defined(__SSE2__)
namespace {

// The double lanes of the same count (the depth plane is evaluated in double).
template <class V> struct DepthLanes;
template <> struct DepthLanes<F4> { typedef D4 D; };
template <> struct DepthLanes<F8> { typedef D8 D; };

// A lane's pixel offset from the block's first pixel.
constexpr int lane_x(int l) { return 2 * (l >> 2) + (l & 1); }
constexpr int lane_y(int l) { return (l >> 1) & 1; }
// The lanes with a given offset, as bits: the lower row (y 0), a column (x offset k).
constexpr int row0_lanes(int w) { return w == 4 ? 0x3 : 0x33; }
constexpr int column_lanes(int k) { return (k < 2 ? 0x5 : 0x50) << (k & 1); }

// x in every lane (x - 0 is x for every x, -0 included). Eight lanes by vbroadcastss: GCC
// builds them insert by insert here.
template <class V>
[[gnu::always_inline]] inline V bcast_lanes(float x) {
  if constexpr (Lanes<V>::W == 4) {
    return x - V{};
  } else {
    V r;
    asm("vbroadcastss %1, %0" : "=x"(r) : "x"(x));  // (only ever inlined into the AVX2 build)
    return r;
  }
}
// Lanes to memory and back (aligned; not memcpy, whose small arrays GCC splits into pieces).
template <class V, class T>
[[gnu::always_inline]] inline void store_lanes(T* p, V v) {
  typedef V VA __attribute__((may_alias, aligned(sizeof(V))));
  *reinterpret_cast<VA*>(p) = v;
}
template <class V, class T>
[[gnu::always_inline]] inline V load_lanes(const T* p) {
  typedef V VA __attribute__((may_alias, aligned(sizeof(V))));
  return *reinterpret_cast<const VA*>(p);
}
// min(max(x, 0), 1) by SSE's maxps and minps (GCC writes x > 0 ? x : 0 on vectors as compares
// and masks): a NaN becomes 0.
[[gnu::always_inline]] inline F4 clamp01_lanes(F4 x) {
  return _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(1.0f));
}
[[gnu::always_inline]] inline F8 clamp01_lanes(F8 x) {
  const F8 zero{}, one = bcast_lanes<F8>(1.0f);
  F8 r;
  asm("vmaxps %2, %1, %0\n\tvminps %3, %0, %0" : "=&x"(r) : "x"(x), "x"(zero), "x"(one));
  return r;
}
// A bit per lane whose sign bit is set.
[[gnu::always_inline]] inline int sign_bits(I4 x) { return _mm_movemask_ps(__m128(x)); }
[[gnu::always_inline]] inline int sign_bits(I8 x) {
  int r;
  asm("vmovmskps %1, %0" : "=r"(r) : "x"(x));  // (only ever inlined into the AVX2 build)
  return r;
}
// All ones in the lanes whose bit is set in m.
template <class I>
[[gnu::always_inline]] inline I lanes_of(int m) {
  I bits;
  for (int l = 0; l < int(sizeof(I) / 4); ++l) bits[l] = 1 << l;
  return ((I{} + m) & bits) == bits;
}
// A block's lanes from its two rows of pixels (r0: the lower row, r1 the upper; W/2 values of 4
// bytes each), and back.
[[gnu::always_inline]] inline void load_rows(const void* r0, const void* r1, F4& v) {
  double a, b;
  std::memcpy(&a, r0, 8), std::memcpy(&b, r1, 8);
  v = F4(D2{a, b});
}
[[gnu::always_inline]] inline void load_rows(const void* r0, const void* r1, F8& v) {
  F4 a, b;
  std::memcpy(&a, r0, 16), std::memcpy(&b, r1, 16);
  v = __builtin_shufflevector(a, b, 0, 1, 4, 5, 2, 3, 6, 7);
}
[[gnu::always_inline]] inline void store_rows(void* r0, void* r1, F4 v) {
  const D2 d = D2(v);
  std::memcpy(r0, &d[0], 8), std::memcpy(r1, &d[1], 8);
}
[[gnu::always_inline]] inline void store_rows(void* r0, void* r1, F8 v) {
  const F4 a = __builtin_shufflevector(v, v, 0, 1, 4, 5), b = __builtin_shufflevector(v, v, 2, 3, 6, 7);
  std::memcpy(r0, &a, 16), std::memcpy(r1, &b, 16);
}
// A plane splat across lanes; its value at the block's row (Y: the lanes' y from the first
// quad), then at its lanes.
template <class V>
struct LanePlane {
  V c, dx, dy;
};
template <class V>
[[gnu::always_inline]] inline LanePlane<V> lane_plane(const QPlane& p) {
  return {bcast_lanes<V>(p.c), bcast_lanes<V>(p.dx), bcast_lanes<V>(p.dy)};
}
template <class V>
[[gnu::always_inline]] inline V plane_row(const LanePlane<V>& p, V Y) {
  return p.c + Y * p.dy;
}
template <class V>
[[gnu::always_inline]] inline V plane_at(V row, const LanePlane<V>& p, V X) {
  return row + X * p.dx;
}
// The colour write's rounding (c 255 + 1/2, truncated), packed RGBA8 per lane.
template <class V, class I>
[[gnu::always_inline]] inline I pack_rgba8(V r, V g, V b, V a) {
  const V k255 = bcast_lanes<V>(255.0f), half = bcast_lanes<V>(0.5f);
  const I R = __builtin_convertvector(r * k255 + half, I), G = __builtin_convertvector(g * k255 + half, I);
  const I B = __builtin_convertvector(b * k255 + half, I), A = __builtin_convertvector(a * k255 + half, I);
  return (R | (G << 8)) | ((B << 16) | (A << 24));
}
// The sampled texels of a block's quads (4 RGBA texels per quad, 16 floats) as r, g, b, a lanes.
[[gnu::always_inline]] inline void texel_lanes(const float* texel, F4* t) {
  __m128 r = _mm_load_ps(texel), g = _mm_load_ps(texel + 4), b = _mm_load_ps(texel + 8), a = _mm_load_ps(texel + 12);
  _MM_TRANSPOSE4_PS(r, g, b, a);
  t[0] = r, t[1] = g, t[2] = b, t[3] = a;
}
[[gnu::always_inline]] inline void texel_lanes(const float* texel, F8* t) {
  F4 a[4], b[4];
  texel_lanes(texel, a), texel_lanes(texel + 16, b);
  for (int k = 0; k < 4; ++k) t[k] = __builtin_shufflevector(a[k], b[k], 0, 1, 2, 3, 4, 5, 6, 7);
}

}  // namespace

template <class V, bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
[[gnu::always_inline]] inline void Raster::quad_loop(const QuadSetup& q) {
  typedef typename Lanes<V>::I I;
  typedef typename DepthLanes<V>::D D;
  constexpr int W = Lanes<V>::W;  // lanes per block
  constexpr int kStep = W / 2;    // columns per block
  constexpr int kAll = (1 << W) - 1;
  // What the loop reads, in locals: the colour and depth stores may alias memory, and the
  // compiler would read the setup and the members again after each of them.
  const int ox = q.ox, oy = q.oy, bx0 = q.bx0, bx1 = q.bx1, by0 = q.by0, by1 = q.by1;
  const int fb_x0 = x0, fb_x1 = x1, fb_y0 = y0, fb_y1 = y1;
  const std::size_t stride = std::size_t(width);
  float* const zbuf = depth;
  std::uint8_t* const cbuf = color;
  const bool tex_q = q.tex_q, dmask = q.dmask, fast_write = q.fast_write;
  const DepthFunc dfunc = q.dfunc;
  const double zc = q.zc, zdx = q.zdx, zdy = q.zdy;
  const Texture* const texture = q.texture;
  const float tex_w = q.tex_w, tex_h = q.tex_h;
  const TexEnvMode env = q.env;
  const TexFormat fmt = q.fmt;
  const FogMode fog_mode = q.fog_mode;
  const float fog_end = q.fog_end, fog_range = q.fog_range, fog_density = q.fog_density;
  const float* const flat = q.flat;
  const int side = q.side;
  const std::int64_t A[3] = {q.A[0], q.A[1], q.A[2]}, B[3] = {q.B[0], q.B[1], q.B[2]}, C[3] = {q.c[0], q.c[1], q.c[2]};
  const V zero{}, one = bcast_lanes<V>(1.0f);
  const LanePlane<V> pw = lane_plane<V>(q.pw);
  LanePlane<V> pc[4], pt[3], pf{};
  if constexpr (Smooth && !Phong)
    for (int k = 0; k < 4; ++k) pc[k] = lane_plane<V>(q.pc[k]);
  if constexpr (Tex)
    for (int k = 0; k < 3; ++k) pt[k] = lane_plane<V>(q.pt[k]);
  if constexpr (Fog) pf = lane_plane<V>(q.pf);
  QPlane pa[Phong ? kAttrs : 1];
  if constexpr (Phong) std::copy(q.pa, q.pa + kAttrs, pa);
  V lane_dx, lane_dy;
  D lane_dxd;
  for (int l = 0; l < W; ++l) lane_dx[l] = float(lane_x(l)), lane_dy[l] = float(lane_y(l)), lane_dxd[l] = lane_x(l);
  V flat_c[4] = {zero, zero, zero, zero};
  if constexpr (!Smooth && !Phong)
    for (int k = 0; k < 4; ++k) flat_c[k] = bcast_lanes<V>(flat[q.col + k]);
  const V fog_c[3] = {bcast_lanes<V>(s.fog_color[0]), bcast_lanes<V>(s.fog_color[1]), bcast_lanes<V>(s.fog_color[2])};
  const V env_c[3] = {bcast_lanes<V>(s.env_color[0]), bcast_lanes<V>(s.env_color[1]), bcast_lanes<V>(s.env_color[2])};
  const Simd sample_simd = avx2 ? Simd::Auto : Simd::Sse2;
  // Edge functions at the block's lanes in the first pair of rows drawn (oy, or a band's first
  // row), their steps per block (x) and per pair of rows (y).
  const int qy0 = by0 & ~1;
  I estep[3], erow[3], estepy[3];
  for (int i = 0; i < 3; ++i) {
    const int a = int(A[i]), b = int(B[i]);
    estep[i] = I{} + kStep * a;
    estepy[i] = I{} + 2 * b;
    const int c0 = int(C[i] + B[i] * (qy0 - oy));
    for (int l = 0; l < W; ++l) erow[i][l] = c0 + (lane_x(l) * a + lane_y(l) * b);
  }
  const bool wide = bx1 - ox >= 64;
  for (int qy = qy0; qy <= by1; qy += 2) {
    int rowm = kAll;
    if (qy < by0) rowm &= ~row0_lanes(W);
    if (qy + 1 > by1) rowm &= kAll & ~(row0_lanes(W) << 2);
    I e[3] = {erow[0], erow[1], erow[2]};
    for (int i = 0; i < 3; ++i) erow[i] += estepy[i];
    // On wide triangles, the columns where this pair of rows can be covered: each edge's
    // e(x) >= 0 solved for x on either row, widened by two pixels (the per-lane edge test
    // still decides coverage; this only skips blocks that cannot pass it).
    int qx_first = ox, qx_last = bx1;
    if (wide) {
      double lo = 0, hi = bx1 - ox;
      bool empty = false;
      for (int i = 0; i < 3; ++i) {
        const double e0 = double(C[i] + B[i] * (qy - oy)), e1 = e0 + double(B[i]);
        if (A[i] > 0) lo = std::max(lo, std::min(-e0, -e1) / double(A[i]));
        else if (A[i] < 0) hi = std::min(hi, std::max(e0, e1) / double(-A[i]));
        else if (e0 < 0 && e1 < 0) empty = true;
      }
      if (empty || lo > hi + 4) continue;
      qx_first = ox + (std::max(0, int(lo) - 2) & ~1);
      qx_last = std::min(bx1, ox + int(hi) + 2);
      if (qx_first > ox)
        for (int i = 0; i < 3; ++i) e[i] += I{} + int(A[i]) * (qx_first - ox);
    }
    const float fy = float(qy - oy);
    const V Y = bcast_lanes<V>(fy) + lane_dy;
    const V rw_row = plane_row(pw, Y);
    V c_row[4] = {zero, zero, zero, zero}, t_row[3] = {zero, zero, zero}, f_row = zero;
    if constexpr (Smooth && !Phong)
#pragma GCC unroll 4
      for (int k = 0; k < 4; ++k) c_row[k] = plane_row(pc[k], Y);
    if constexpr (Tex) {
      t_row[0] = plane_row(pt[0], Y), t_row[1] = plane_row(pt[1], Y);
      if (tex_q) t_row[2] = plane_row(pt[2], Y);
    }
    if constexpr (Fog) f_row = plane_row(pf, Y);
    const double zrow_lo = zc + double(fy) * zdy, zrow_hi = zc + double(fy + 1) * zdy;
    D zrow;
    for (int l = 0; l < W; ++l) zrow[l] = lane_y(l) ? zrow_hi : zrow_lo;
    for (int qx = qx_first; qx <= qx_last; qx += kStep, e[0] += estep[0], e[1] += estep[1], e[2] += estep[2]) {
      // A lane is covered when no edge function is negative (sign bits).
      int m = ~sign_bits(e[0] | e[1] | e[2]) & rowm;
      if (qx < bx0 || qx + kStep - 1 > bx1)
        for (int k = 0; k < kStep; ++k)
          if (qx + k < bx0 || qx + k > bx1) m &= ~column_lanes(k);
      if (!m) continue;
      // Partial blocks at the edge of the drawable bounds are read and written lane by lane.
      const bool inb = qx >= fb_x0 && qx + kStep - 1 < fb_x1 && qy >= fb_y0 && qy + 1 < fb_y1;
      const std::size_t i0 = std::size_t(qy) * stride + qx, i1 = i0 + stride;
      auto index = [&](int l) { return (lane_y(l) ? i1 : i0) + lane_x(l); };
      const float fx = float(qx - ox);
      const V X = bcast_lanes<V>(fx) + lane_dx;
      if constexpr (Depth) {
        const V z = __builtin_convertvector(zrow + ((D{} + double(fx)) + lane_dxd) * zdx, V);
        const V zq = quantise_depth_lanes<V, D>(z);
        V d;
        if (m == kAll || inb) {
          load_rows(zbuf + i0, zbuf + i1, d);
        } else {
          alignas(32) float t[W] = {};
          for (int l = 0; l < W; ++l)
            if (m >> l & 1) t[l] = zbuf[index(l)];
          d = load_lanes<V>(t);
        }
        m &= sign_bits(I(depth_cmp_lanes(dfunc, zq, d)));
        if (!m) continue;
        if (dmask) {
          if (m == kAll || inb) {
            store_rows(zbuf + i0, zbuf + i1, V(sel(lanes_of<I>(m), zq, d)));
          } else {
            alignas(32) float t[W];
            store_lanes(t, zq);
            for (int l = 0; l < W; ++l)
              if (m >> l & 1) zbuf[index(l)] = t[l];
          }
        }
      }
      const V rw = one / plane_at(rw_row, pw, X);
      V cr, cg, cb, ca;
      if constexpr (Phong) {
        alignas(32) float pc4[4][W] = {}, rw4[W];
        store_lanes(rw4, rw);
        for (int l = 0; l < W; ++l) {
          if (!(m >> l & 1)) continue;
          const float lx = fx + float(lane_x(l)), ly = fy + float(lane_y(l));
          float attrs[kAttrs];
          for (int k = 0; k < kAttrs; ++k) attrs[k] = (pa[k].c + ly * pa[k].dy + lx * pa[k].dx) * rw4[l];
          if constexpr (!Smooth)
            for (int k = 0; k < 4; ++k) attrs[kFront + k] = flat[kFront + k];
          const Vec4f pcol = phong_color(attrs, side);
          for (int k = 0; k < 4; ++k) pc4[k][l] = pcol[k];
        }
        cr = load_lanes<V>(pc4[0]), cg = load_lanes<V>(pc4[1]), cb = load_lanes<V>(pc4[2]), ca = load_lanes<V>(pc4[3]);
      } else if constexpr (Smooth) {
        cr = plane_at(c_row[0], pc[0], X) * rw, cg = plane_at(c_row[1], pc[1], X) * rw;
        cb = plane_at(c_row[2], pc[2], X) * rw, ca = plane_at(c_row[3], pc[3], X) * rw;
      } else {
        cr = flat_c[0], cg = flat_c[1], cb = flat_c[2], ca = flat_c[3];
      }
      if constexpr (Tex) {
        V ts = plane_at(t_row[0], pt[0], X) * rw, tt = plane_at(t_row[1], pt[1], X) * rw;
        if (tex_q) {
          V tq = plane_at(t_row[2], pt[2], X) * rw;
          tq = tq != 0.0f ? tq : one;
          ts = ts / tq, tt = tt / tq;
        }
        alignas(32) float S[W], T[W], U[W], Vt[W], texel[4 * W];
        const V u = ts * bcast_lanes<V>(tex_w), v = tt * bcast_lanes<V>(tex_h);
        store_lanes(U, u), store_lanes(Vt, v), store_lanes(S, ts), store_lanes(T, tt);
        for (int h = 0; h < W / 4; ++h) {
          const int mh = m >> (4 * h) & 15;
          float* const Sh = S + 4 * h;
          float* const Th = T + 4 * h;
          const float* const Uh = U + 4 * h;
          const float* const Vh = Vt + 4 * h;
          if (!mh) {
            std::memset(texel + 16 * h, 0, 16 * sizeof(float));
            continue;
          }
          // Level of detail from the quad's (u, v) = (s W, t H): x differences along its upper
          // row, y differences down its left column (reference: the top-left pixel).
          const float lambda = quad_lod(Uh[3] - Uh[2], Vh[3] - Vh[2], Uh[0] - Uh[2], Vh[0] - Vh[2]);
          if (mh != 15) {
            // Lanes outside the triangle may hold extrapolated coordinates (even infinite):
            // sample a covered lane's instead.
            const int l0 = __builtin_ctz(unsigned(mh));
            for (int l = 0; l < 4; ++l)
              if (!(mh >> l & 1)) Sh[l] = Sh[l0], Th[l] = Th[l0];
          }
          texture->sample4(Sh, Th, lambda, texel + 16 * h, sample_simd);
        }
        V t[4], c[4] = {cr, cg, cb, ca};
        texel_lanes(texel, t);
        tex_env(env, fmt, t, env_c, one, c);
        cr = c[0], cg = c[1], cb = c[2], ca = c[3];
      }
      if constexpr (Fog) {
        const V fz = plane_at(f_row, pf, X) * rw;
        V f = one;
        if (fog_mode == FogMode::Linear) {
          if (fog_range != 0) f = (bcast_lanes<V>(fog_end) - fz) / bcast_lanes<V>(fog_range);
        } else {
          alignas(32) float z4[W], f4[W];
          store_lanes(z4, fz);
          for (int l = 0; l < W; ++l) {
            const float dz = fog_density * z4[l];
            f4[l] = std::exp(fog_mode == FogMode::Exp ? -dz : -dz * dz);
          }
          f = load_lanes<V>(f4);
        }
        f = clamp01_lanes(f);
        const V g = one - f;
        cr = f * cr + g * fog_c[0], cg = f * cg + g * fog_c[1], cb = f * cb + g * fog_c[2];
      }
      cr = clamp01_lanes(cr), cg = clamp01_lanes(cg), cb = clamp01_lanes(cb), ca = clamp01_lanes(ca);
      if (fast_write) {
        I px = pack_rgba8<V, I>(cr, cg, cb, ca);
        std::uint8_t* const p0 = cbuf + i0 * 4;
        std::uint8_t* const p1 = cbuf + i1 * 4;
        if (m == kAll || inb) {
          if (m != kAll) {
            V old;
            load_rows(p0, p1, old);
            px = sel(lanes_of<I>(m), px, I(old));
          }
          store_rows(p0, p1, V(px));
        } else {
          alignas(32) std::uint32_t P[W];
          store_lanes(P, px);
          for (int l = 0; l < W; ++l)
            if (m >> l & 1) std::memcpy(cbuf + index(l) * 4, &P[l], 4);
        }
      } else {
        alignas(32) float C[4][W];
        store_lanes(C[0], cr), store_lanes(C[1], cg), store_lanes(C[2], cb), store_lanes(C[3], ca);
        for (int l = 0; l < W; ++l)
          if (m >> l & 1) write_color(qx + lane_x(l), qy + lane_y(l), Vec4f(C[0][l], C[1][l], C[2][l], C[3][l]));
      }
    }
  }
}

// The two builds.
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
void Raster::quad_loop4(const QuadSetup& q) {
  quad_loop<F4, Phong, Smooth, Tex, Fog, Depth>(q);
}
template <bool Smooth, bool Tex, bool Fog, bool Depth>
__attribute__((target("avx2"))) void Raster::quad_loop8(const QuadSetup& q) {
  quad_loop<F8, false, Smooth, Tex, Fog, Depth>(q);
}

// The instances triangle_q calls: the 4-lane build in every state (Phong, Smooth, Tex, Fog,
// Depth), the 8-lane one without Phong (its lighting is per lane and scalar: an AVX2 copy would
// only add code; triangle_isa sends Phong triangles to the 4-lane build).
#define WEDGE_QUAD(P, S, T, F, D) template void Raster::quad_loop4<P, S, T, F, D>(const QuadSetup&);
#define WEDGE_QUAD8(S, T, F, D) template void Raster::quad_loop8<S, T, F, D>(const QuadSetup&);
#define WEDGE_QUADS(S, T, F, D) WEDGE_QUAD(false, S, T, F, D) WEDGE_QUAD(true, S, T, F, D) WEDGE_QUAD8(S, T, F, D)
#define WEDGE_QUADS_D(S, T, F) WEDGE_QUADS(S, T, F, false) WEDGE_QUADS(S, T, F, true)
#define WEDGE_QUADS_F(S, T) WEDGE_QUADS_D(S, T, false) WEDGE_QUADS_D(S, T, true)
WEDGE_QUADS_F(false, false)
WEDGE_QUADS_F(false, true)
WEDGE_QUADS_F(true, false)
WEDGE_QUADS_F(true, true)
#undef WEDGE_QUADS_F
#undef WEDGE_QUADS_D
#undef WEDGE_QUADS
#undef WEDGE_QUAD8
#undef WEDGE_QUAD
#endif

}  // namespace wedge::render::raster
