// Lane helpers of the rasterizer (private to render/): the vector types of its SIMD code and the
// few operations on them that GCC's vector extensions do not give directly.
//
// Notation. Lanes are written with GCC's vector extensions, so that one template serves the
// default x86-64 build (SSE2) and the AVX2 build (functions compiled with target("avx2"), chosen
// at run time per draw: Raster::avx2):
//   F4, I4, U4   4 floats / ints / unsigneds (SSE2: one register)   F8, I8, U8  8 of them (AVX2)
//   D2, D4, D8   2 / 4 / 8 doubles (D2, D4: a register of each build) X2<T>     two T as one (F16
//   = X2<F8>: the AVX2 lighting's 16 lanes, two independent groups whose operations interleave)
//   Lanes<V>     V's mask type I, unsigned type U, the register-wide double type D, width W
// Comparisons give masks (all ones per true lane); sel(m, a, b) and vsel pick per lane. No FMA in
// either build (the AVX2 target does not include it), so both give the same bits.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#include <immintrin.h>  // AVX2 intrinsics, used only in functions built with target("avx2")
#endif

#include "render/render.h"

// -Wpsabi notes that 32-byte vectors (__m256, F8, D4) passed by value travel differently with
// and without AVX. Every function of the rasterizer that takes or returns one by value is always
// inlined (so no call crosses that difference: one left out of line would be compiled for the base
// target and misread its AVX2 caller's registers, as happened in the unoptimised build); GCC
// reports the notes where it instantiates templates, at the end of a file, so this holds for all
// of every file that includes this header.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace wedge::render::raster {

// llvmpipe's level-of-detail log2 (gallivm's fast log2): the float's exponent minus one plus its
// mantissa in [1, 2), a piecewise-linear log2 exact at powers of two. Its blend fraction between
// two mipmap levels follows this curve, not the true logarithm.
[[gnu::always_inline]] inline float fast_log2(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, 4);
  const int biased = int(bits >> 23);
  if (biased > 0 && biased < 255) {
    // A positive normal float without a library call: x = m1 2^e, m1 in [1, 2), the same value
    // as frexp's m 2^(e + 1) below.
    const std::uint32_t mb = (bits & 0x7fffffu) | 0x3f800000u;
    float m1;
    std::memcpy(&m1, &mb, 4);
    return float(biased - 128) + m1;
  }
  int e = 0;
  float m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  return float(e - 2) + 2 * m;
}

// The level of detail of a 2x2 quad (GL 1.5, 3.8.8, as llvmpipe takes it): from the differences
// of (u, v) = (s W, t H) across the quad in x and in y, lambda = log2 of the longer one
// (fast_log2 of its square, halved); -100 (magnified) when (u, v) does not change; at most 1000
// (extrapolated lanes outside a triangle gone astray: inf, NaN). The one formula of the 4- and
// 8-lane quad loops and the one-pixel loop.
[[gnu::always_inline]] inline float quad_lod(float dux, float dvx, float duy, float dvy) {
  const float rho2 = std::max(dux * dux + dvx * dvx, duy * duy + dvy * dvy);
  const float lambda = rho2 > 0 ? 0.5f * fast_log2(rho2) : -100.0f;
  return lambda <= 1000.0f ? lambda : 1000.0f;
}

// Vectors of doubles: SSE2 pairs, AVX2 quadruples, and eight (the AVX2 quad loop's depth lanes).
typedef double D2 __attribute__((vector_size(16)));
typedef double D4 __attribute__((vector_size(32)));
typedef double D8 __attribute__((vector_size(64)));

// min(max(x, 0), 1) on lanes (or one float) as SSE's maxps then minps: a NaN becomes 0 (Eigen's
// cwiseMax / cwiseMin keep it: vclamp01 below).
template <class V>
[[gnu::always_inline]] inline V clamp01_sse(V x) {
  x = x > 0.0f ? x : V{};
  return x < 1.0f ? x : V{} + 1.0f;
}

// A float plane of the quad fragment loop (quad_loop.cpp): its value at the centre of the first
// quad's first pixel, and its steps per pixel in x and y.
struct QPlane {
  float c, dx, dy;
};

#if defined(__SSE2__)
// llround (half away from zero) without a library call, for |x| < 2^52 (window coordinates
// times 256); beyond that x is an integer and is returned as it is.
[[gnu::always_inline]] inline std::int64_t round_half_away(double x) {
  std::int64_t i = std::int64_t(x);
  const double f = x - double(i);
  return i + (f >= 0.5) - (f <= -0.5);
}
// The texture environment (GL 1.x, table 3.22) on lanes: the fragment colours c (r, g, b, a) by
// the texels t (r, g, b, a) of a texture of format fmt, env the environment colour (r, g, b).
// For __m128 and __m256 alike through GCC's vector operators: the same multiplies and adds in the
// same order in the quad loop's 4- and 8-lane builds (no FMA in either build: the same bits).
template <class V>
[[gnu::always_inline]] inline void tex_env(TexEnvMode mode, TexFormat fmt, const V* t, const V* env, V one, V* c) {
  const bool rgba = fmt == TexFormat::RGBA;
  switch (mode) {
    case TexEnvMode::Modulate:
      for (int k = 0; k < 3; ++k) c[k] = c[k] * t[k];
      if (rgba) c[3] = c[3] * t[3];
      break;
    case TexEnvMode::Replace:
      for (int k = 0; k < 3; ++k) c[k] = t[k];
      if (rgba) c[3] = t[3];
      break;
    case TexEnvMode::Decal:
      if (rgba) {
        const V ia = one - t[3];
        for (int k = 0; k < 3; ++k) c[k] = c[k] * ia + t[k] * t[3];
      } else if (fmt == TexFormat::RGB) {
        for (int k = 0; k < 3; ++k) c[k] = t[k];
      }
      break;
    case TexEnvMode::Blend:
      for (int k = 0; k < 3; ++k) c[k] = c[k] * (one - t[k]) + env[k] * t[k];
      if (rgba) c[3] = c[3] * t[3];
      break;
  }
}
#endif

// (Always inlined into the AVX2 and the default builds of run_setup.)
template <class V, class L>
[[gnu::always_inline]] inline V vsel(L m, V a, V b) { return m ? a : b; }
template <class V>
[[gnu::always_inline]] inline V vmin(V a, V b) { return b < a ? b : a; }  // std::min's choice (equal: a)
template <class V>
[[gnu::always_inline]] inline V vmax(V a, V b) { return a < b ? b : a; }
template <class V>
[[gnu::always_inline]] inline V vabs(V a) { return a < 0.0 ? -a : a; }
// Nearest integer, ties to even, for |a| < 2^51; floor from it.
template <class V>
[[gnu::always_inline]] inline V vnearest(V a) {
  const V m = V{} + 0x1.8p52;
  return (a + m) - m;
}
template <class V>
[[gnu::always_inline]] inline V vfloor(V a) {
  const V t = vnearest(a);
  return vsel(a < t, t - 1.0, t);
}
// round_half_away (llround) for |a| < 2^51: nearest, then ties moved away from zero.
template <class V>
[[gnu::always_inline]] inline V vhalf_away(V a) {
  const V t = vnearest(a), d = a - t, one = V{} + 1.0;
  return t + vsel((d == 0.5) & (a > 0.0), one, V{}) - vsel((d == -0.5) & (a < 0.0), one, V{});
}
template <class V>
[[gnu::always_inline]] inline V vload(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Lighting four or sixteen vertices at once (SoA, GCC vector extensions): F4 (SSE2, the default
// x86-64 build) or F16, two F8 side by side (AVX2, compiled with target("avx2") and chosen at run
// time). Both are written once, as templates on the vector type, with the same operations lane by
// lane as the scalar light_vertex, and no FMA (the AVX2 target does not include it), so every lane
// gives light_vertex's bits.
typedef float F4 __attribute__((vector_size(16)));
typedef int I4 __attribute__((vector_size(16)));
typedef unsigned U4 __attribute__((vector_size(16)));
typedef float F8 __attribute__((vector_size(32)));
typedef int I8 __attribute__((vector_size(32)));
typedef unsigned U8 __attribute__((vector_size(32)));

// The integer (mask) vector of a float vector's lanes, and the register-wide double vector that
// holds half of them (a float vector's doubles are two of these: wider vectors than the target's
// registers compile poorly, selects lane by lane).
template <class V> struct Lanes;
template <> struct Lanes<F4> {
  typedef I4 I;
  typedef U4 U;
  typedef D2 D;
  enum { W = 4 };
};
template <> struct Lanes<F8> {
  typedef I8 I;
  typedef U8 U;
  typedef D4 D;
  enum { W = 8 };
};

// Two vectors as one: the AVX2 lighting's 16 lanes, two independent groups of 8 whose operations
// alternate, so that the lighting's long dependency chains (square root, divide, the pow's divide
// and polynomials) overlap. Operators apply to both halves; vector selects are written sel(m, x, y)
// (the same as m ? x : y on plain vectors, which cannot be overloaded).
template <class T>
struct X2 {
  T a, b;
  // (Always inlined: see the note at the -Wpsabi pragma.)
  X2() = default;
  [[gnu::always_inline]] constexpr X2(T a_, T b_) : a(a_), b(b_) {}
  template <class S>
  [[gnu::always_inline]] explicit X2(const X2<S>& o) : a(T(o.a)), b(T(o.b)) {}  // bits reinterpreted, as T(S) does
};
template <class T> struct IsX2 : std::false_type {};
template <class T> struct IsX2<X2<T>> : std::true_type {};
#define WEDGE_X2_OP(op)                                                                                   \
  template <class T>                                                                                      \
  [[gnu::always_inline]] inline auto operator op(const X2<T>& x, const X2<T>& y) {                        \
    return X2<decltype(x.a op y.a)>{x.a op y.a, x.b op y.b};                                              \
  }                                                                                                       \
  template <class T, class S>                                                                             \
    requires std::is_arithmetic_v<S>                                                                      \
  [[gnu::always_inline]] inline auto operator op(const X2<T>& x, S y) {                                   \
    return X2<decltype(x.a op y)>{x.a op y, x.b op y};                                                    \
  }                                                                                                       \
  template <class T, class S>                                                                             \
    requires std::is_arithmetic_v<S>                                                                      \
  [[gnu::always_inline]] inline auto operator op(S x, const X2<T>& y) {                                   \
    return X2<decltype(x op y.a)>{x op y.a, x op y.b};                                                    \
  }
WEDGE_X2_OP(+)
WEDGE_X2_OP(-)
WEDGE_X2_OP(*)
WEDGE_X2_OP(/)
WEDGE_X2_OP(&)
WEDGE_X2_OP(|)
WEDGE_X2_OP(<<)
WEDGE_X2_OP(>>)
WEDGE_X2_OP(<)
WEDGE_X2_OP(>)
WEDGE_X2_OP(==)
WEDGE_X2_OP(!=)
#undef WEDGE_X2_OP
template <class T>
[[gnu::always_inline]] inline X2<T> operator-(const X2<T>& x) {
  return {-x.a, -x.b};
}
template <class T>
[[gnu::always_inline]] inline X2<T> operator~(const X2<T>& x) {
  return {~x.a, ~x.b};
}
template <> struct Lanes<X2<F8>> {
  typedef X2<I8> I;
  typedef X2<U8> U;
  typedef X2<D4> D;
  enum { W = 16 };
};
// m ? x : y, lane by lane (m: a comparison's mask).
template <class M, class T>
[[gnu::always_inline]] inline T sel(const M& m, const T& x, const T& y) {
  if constexpr (IsX2<T>::value) return T{sel(m.a, x.a, y.a), sel(m.b, x.b, y.b)};
  else return m ? x : y;
}

// x in every lane (an element-wise copy: x - 0 or x + 0 would turn a -0 into +0).
template <class V>
[[gnu::always_inline]] inline V splat(float x) {
  if constexpr (IsX2<V>::value) {
    return V{splat<decltype(V::a)>(x), splat<decltype(V::a)>(x)};
  } else {
    V r;
    for (int l = 0; l < Lanes<V>::W; ++l) r[l] = x;
    return r;
  }
}
[[gnu::always_inline]] inline F4 bcast(float x) { return splat<F4>(x); }

// Halves of an eight-lane vector.
[[gnu::always_inline]] inline F4 lo(F8 x) { return __builtin_shufflevector(x, x, 0, 1, 2, 3); }
[[gnu::always_inline]] inline F4 hi(F8 x) { return __builtin_shufflevector(x, x, 4, 5, 6, 7); }
[[gnu::always_inline]] inline I4 lo(I8 x) { return __builtin_shufflevector(x, x, 0, 1, 2, 3); }
[[gnu::always_inline]] inline I4 hi(I8 x) { return __builtin_shufflevector(x, x, 4, 5, 6, 7); }

[[gnu::always_inline]] inline F4 vsqrt(F4 x) {
#if defined(__SSE2__)
  return _mm_sqrt_ps(x);
#else
  return F4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}
// The eight-lane and four-double ones, used only inside the AVX2 build, as one 256-bit instruction
// (not two halves: a shorter dependency chain), written as inline assembly since an AVX intrinsic
// cannot be called from the lighting templates, which are also compiled for the default target.
[[gnu::always_inline]] inline F8 vsqrt(F8 x) {
  F8 r;
  asm("vsqrtps %1, %0" : "=x"(r) : "x"(x));
  return r;
}
[[gnu::always_inline]] inline D2 vsqrt(D2 x) {
#if defined(__SSE2__)
  return _mm_sqrt_pd(x);
#else
  return D2{std::sqrt(x[0]), std::sqrt(x[1])};
#endif
}
[[gnu::always_inline]] inline D4 vsqrt(D4 x) {
  D4 r;
  asm("vsqrtpd %1, %0" : "=x"(r) : "x"(x));
  return r;
}
template <class T>
[[gnu::always_inline]] inline X2<T> vsqrt(const X2<T>& x) {
  return {vsqrt(x.a), vsqrt(x.b)};
}
// Float (or int) lanes to doubles, in two halves (exact), and doubles back to floats (rounded to
// nearest).
[[gnu::always_inline]] inline void widen(F4 x, D2* d) {
  d[0] = __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1), D2);
  d[1] = __builtin_convertvector(__builtin_shufflevector(x, x, 2, 3), D2);
}
[[gnu::always_inline]] inline void widen(I4 x, D2* d) {
  d[0] = __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1), D2);
  d[1] = __builtin_convertvector(__builtin_shufflevector(x, x, 2, 3), D2);
}
[[gnu::always_inline]] inline void widen(F8 x, D4* d) {
  d[0] = __builtin_convertvector(lo(x), D4), d[1] = __builtin_convertvector(hi(x), D4);
}
[[gnu::always_inline]] inline void widen(I8 x, D4* d) {
  d[0] = __builtin_convertvector(lo(x), D4), d[1] = __builtin_convertvector(hi(x), D4);
}
[[gnu::always_inline]] inline F4 narrow(const D2* d) {
#if defined(__SSE2__)
  return _mm_movelh_ps(_mm_cvtpd_ps(d[0]), _mm_cvtpd_ps(d[1]));
#else
  return F4{float(d[0][0]), float(d[0][1]), float(d[1][0]), float(d[1][1])};
#endif
}
[[gnu::always_inline]] inline F8 narrow(const D4* d) {
  const F4 a = __builtin_convertvector(d[0], F4), b = __builtin_convertvector(d[1], F4);
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}
[[gnu::always_inline]] inline bool any(I4 m) {
#if defined(__SSE2__)
  return _mm_movemask_ps(__m128(m)) != 0;
#else
  return (m[0] | m[1] | m[2] | m[3]) != 0;
#endif
}
[[gnu::always_inline]] inline bool any(I8 m) { return any(I4(lo(m) | hi(m))); }
// The same for two vectors as one: d[0] holds x.a's lanes, d[1] x.b's (in lane order, as the
// halves of a plain vector).
template <class T, class D>
[[gnu::always_inline]] inline void widen(const X2<T>& x, X2<D>* d) {
  D a[2], b[2];
  widen(x.a, a), widen(x.b, b);
  d[0] = {a[0], a[1]}, d[1] = {b[0], b[1]};
}
template <class D>
[[gnu::always_inline]] inline auto narrow(const X2<D>* d) {
  const D a[2] = {d[0].a, d[0].b}, b[2] = {d[1].a, d[1].b};
  return X2<decltype(narrow(a))>{narrow(a), narrow(b)};
}
template <class T>
[[gnu::always_inline]] inline bool any(const X2<T>& m) {
  return any(T(m.a | m.b));
}
// Eigen's order for a 3-vector's dot product and squared norm: a0 b0 + (a1 b1 + a2 b2).
template <class V>
[[gnu::always_inline]] inline V dot3(const V* a, const V* b) {
  return a[0] * b[0] + (a[1] * b[1] + a[2] * b[2]);
}
// Eigen's cwiseMax(0) then cwiseMin(1) (std::max / std::min: NaN stays NaN).
template <class V>
[[gnu::always_inline]] inline V vclamp01(V c) {
  c = sel(c < 0.0f, splat<V>(0.0f), c);
  return sel(1.0f < c, splat<V>(1.0f), c);
}

// x^y for x >= 0 and y > 0 (the callers treat y = 0 as GL's 0^0 = 1), lane by lane: 2^(y log2 x)
// in double (so that y up to 128 does not magnify a rounding), rounded to float once at the end.
// Relative error below 1e-7 where the result is a normal float, within the last (subnormal) place
// below that (tests/render/test_lighting.cpp); 0^y = 0, inf^y = inf, NaN stays NaN; overflow gives
// inf.
template <class V>
[[gnu::always_inline]] inline V vpow(V x, float y) {
  typedef typename Lanes<V>::I I;
  typedef typename Lanes<V>::U U;
  typedef typename Lanes<V>::D D;
  typedef decltype(D{} < D{}) Q;  // 64-bit integer lanes
  // x = m 2^e with m in [sqrt(1/2), sqrt(2)): the bits less those of sqrt(1/2), shifted, give e
  // (subnormal x scaled by 2^24 first). (Unsigned arithmetic: no overflow for other inputs.)
  const I tiny = x < 0x1p-126f;
  const U b = U(sel(tiny, x * 0x1p24f, x));
  const I e = I(b - 0x3f3504f3u) >> 23;
  const V m = V(b - (U(e) << 23));
  // log2 m = 2 atanh(s) / ln 2, s = (m - 1) / (m + 1), |s| <= 0.1716: the odd series to s^11
  // (truncation below 2e-11). Then t = y log2 x (held to [-160, 160]: beyond, the float result
  // over- or underflows anyway), and 2^t = 2^i 2^f, i = t rounded to nearest, |f| <= 1/2: 2^f by
  // its Taylor series to f^7 (remainder below 6e-9), times 2^i (exact), then rounded to float.
  // Both polynomials by Estrin's scheme (pairs, then powers of the square), not Horner's: chains of
  // 7 and 6 operations, not 12 and 14 (the lighting's longest dependency chain runs through here).
  constexpr double k = 2 / 0.693147180559945309417232121458;
  constexpr double c1 = 0.6931471805599453, c2 = 0.2402265069591007, c3 = 0.055504108664821576,
                   c4 = 0.009618129107628477, c5 = 0.0013333558146428441, c6 = 0.00015403530393381606,
                   c7 = 1.5252733804059838e-05;
  D md[2], ed[2], rd[2];
  widen(m, md), widen(I(e - (tiny & 24)), ed);
#pragma GCC unroll 4
  for (int h = 0; h < 2; ++h) {
    const D s = (md[h] - 1.0) / (md[h] + 1.0);
    const D s2 = s * s, s4 = s2 * s2, s8 = s4 * s4;
    const D l = s * (((k + s2 * (k / 3)) + s4 * (k / 5 + s2 * (k / 7))) + s8 * (k / 9 + s2 * (k / 11)));
    D t = double(y) * (ed[h] + l);
    t = sel(t < -160.0, D{} - 160.0, t);
    t = sel(t > 160.0, D{} + 160.0, t);
    // r = 1.5 2^52 + i: its low bits hold i.
    const D r = t + 0x1.8p52;
    const D f = t - (r - 0x1.8p52);
    const D f2 = f * f, f4 = f2 * f2;
    const D p = ((1.0 + f * c1) + f2 * (c2 + f * c3)) + f4 * ((c4 + f * c5) + f2 * (c6 + f * c7));
    rd[h] = p * D((Q(r) + 1023) << 52);
  }
  V res = narrow(rd);
  res = sel(x == 0.0f, splat<V>(0.0f), res);
  res = sel(x == __builtin_huge_valf(), x, res);
  return sel(x != x, x, res);
}

// The scalar pow of the lighting equation: vpow's lane 0, so light_vertex and the vector
// lighting give the same bits.
[[gnu::always_inline]] inline float gl_pow(float x, float y) { return vpow(bcast(x), y)[0]; }

// Lanes from memory, in registers (no stack array written by lanes and read back whole: that
// stalls on store forwarding). A row's elements i[0], i[1], ... into the lanes of D:
template <class D>
[[gnu::always_inline]] inline D gather(const double* r, const std::uint32_t* i) {
  if constexpr (sizeof(D) == sizeof(D2)) return D{r[i[0]], r[i[1]]};
  else return D{r[i[0]], r[i[1]], r[i[2]], r[i[3]]};
}
template <class D>
[[gnu::always_inline]] inline D load(const double* p) {
  D v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// Packed x y z triples: those at p + 3 i[0], p + 3 i[1], ... by lanes into v[0..2],
[[gnu::always_inline]] inline void gather_xyz(const double* p, const std::uint32_t* i, D2* v) {
  const D2 a = load<D2>(p + 3 * i[0]), b = load<D2>(p + 3 * i[1]);
  v[0] = __builtin_shufflevector(a, b, 0, 2), v[1] = __builtin_shufflevector(a, b, 1, 3);
  v[2] = D2{p[3 * i[0] + 2], p[3 * i[1] + 2]};
}
[[gnu::always_inline]] inline void gather_xyz(const double* p, const std::uint32_t* i, D4* v) {
  D2 lo[3], hi[3];
  gather_xyz(p, i, lo), gather_xyz(p, i + 2, hi);
  for (int k = 0; k < 3; ++k) v[k] = __builtin_shufflevector(lo[k], hi[k], 0, 1, 2, 3);
}
// and those of consecutive vertices from p on (3 lanes' worth of doubles read as three vectors;
// also the position stage's packed positions and the facing test's window rows).
[[gnu::always_inline]] inline void rows_xyz(const double* p, D2* v) {
  const D2 a = load<D2>(p), b = load<D2>(p + 2), c = load<D2>(p + 4);  // x0 y0, z0 x1, y1 z1
  v[0] = __builtin_shufflevector(a, b, 0, 3), v[1] = __builtin_shufflevector(a, c, 1, 2);
  v[2] = __builtin_shufflevector(b, c, 0, 3);
}
[[gnu::always_inline]] inline void rows_xyz(const double* p, D4* v) {
  // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3
  const D4 a = load<D4>(p), b = load<D4>(p + 4), c = load<D4>(p + 8);
  const D4 x = __builtin_shufflevector(a, b, 0, 3, 6, 6), y = __builtin_shufflevector(a, b, 1, 4, 7, 7),
            z = __builtin_shufflevector(a, b, 2, 5, 5, 5);
  v[0] = __builtin_shufflevector(x, c, 0, 1, 2, 5), v[1] = __builtin_shufflevector(y, c, 0, 1, 2, 6);
  v[2] = __builtin_shufflevector(z, c, 0, 1, 4, 7);
}

}  // namespace wedge::render::raster
