// The depth test (the z-buffer) of the rasterizer, private to render/: GL 1.x section 4.1.6.
//
// The depth buffer holds floats, but as OpenGL with a 24-bit depth buffer (Mesa's default) every
// fragment's window z is clamped to [0, 1] and quantised to k / (2^24 - 1), k an integer, before
// the comparison and the write: round to nearest even by adding and removing 2^52 (no libm call),
// then times 1 / (2^24 - 1) (a multiply, not a division: the double product is within 2 ulps of
// the quotient, while k / (2^24 - 1) lies at least about 2^-50 (relative) from any float rounding
// boundary, so the float is the same; checked for all 2^24 values). The comparison is the state's
// depth function; the write happens when the test passes and the depth mask is on.
//   quantise_depth_lanes   the quantisation, written once for lanes of any width; through it
//     quantise_depth       one fragment (Raster::depth_stage_t: lines, points, the one-pixel
//                          triangle loop; Raster::tiny_pixel)
//     quantise_depth4      four lanes (the SSE2 quad loop, fragments.cpp)
//     quantise_depth8      eight lanes (the AVX2 two-quad loop, fragments_avx2.cpp)
//   depth_pass             the comparison, one fragment; through depth_cmp_lanes (the same on
//     depth_cmp4, depth_cmp8  lanes) four (SSE2) and eight (AVX2) lanes
#pragma once
#include <type_traits>

#include "render/simd.h"

namespace wedge::render::raster {

// Lanes of one type converted to another of the same count (a scalar is one lane).
template <class To, class From>
[[gnu::always_inline]] inline To lanes_as(From v) {
  if constexpr (std::is_arithmetic_v<From>) return To(v);
  else return __builtin_convertvector(v, To);
}

// z quantised as the depth buffer holds it, on lanes: F floats (float, F4, F8), D the doubles of
// the same count (double, D4, D8). Clamped by z > 0 ? z : 0, then z < 1 ? z : 1 (SSE's max and
// min: a NaN becomes 0), then rounded in double and converted back.
template <class F, class D>
[[gnu::always_inline]] inline F quantise_depth_lanes(F z) {
  z = z > 0.0f ? z : F{};
  z = z < 1.0f ? z : F{} + 1.0f;
  constexpr double kRound = 0x1p52;  // not folded: no -ffast-math (no reassociation)
  constexpr double kInvMax = 1.0 / 16777215.0;
  D d = lanes_as<D>(z) * 16777215.0;
  d = (d + kRound) - kRound;
  return lanes_as<F>(d * kInvMax);
}

// One fragment's z, quantised.
[[gnu::always_inline]] inline float quantise_depth(float z) { return quantise_depth_lanes<float, double>(z); }

// Whether a fragment at (quantised) depth z passes against the stored d.
[[gnu::always_inline]] inline bool depth_pass(DepthFunc f, float z, float d) {
  switch (f) {
    case DepthFunc::Never: return false;
    case DepthFunc::Less: return z < d;
    case DepthFunc::Equal: return z == d;
    case DepthFunc::LessEqual: return z <= d;
    case DepthFunc::Greater: return z > d;
    case DepthFunc::NotEqual: return z != d;
    case DepthFunc::GreaterEqual: return z >= d;
    case DepthFunc::Always: return true;
  }
  return false;
}

// The depth test on lanes (F4, F8), as depth_pass lane by lane: all ones in the passing lanes.
template <class F>
[[gnu::always_inline]] inline auto depth_cmp_lanes(DepthFunc f, F z, F d) {
  using M = decltype(z < d);
  switch (f) {
    case DepthFunc::Never: return M{};
    case DepthFunc::Less: return z < d;
    case DepthFunc::Equal: return z == d;
    case DepthFunc::LessEqual: return z <= d;
    case DepthFunc::Greater: return z > d;
    case DepthFunc::NotEqual: return z != d;
    case DepthFunc::GreaterEqual: return z >= d;
    case DepthFunc::Always: return M{} == M{};
  }
  return M{};
}

#if defined(__SSE2__)
// The depth test on four lanes: a bit per passing lane.
[[gnu::always_inline]] inline int depth_cmp4(DepthFunc f, __m128 z, __m128 d) {
  return _mm_movemask_ps(__m128(depth_cmp_lanes(f, F4(z), F4(d))));
}
// The same on eight lanes (AVX2).
__attribute__((target("avx2"), always_inline)) inline int depth_cmp8(DepthFunc f, __m256 z, __m256 d) {
  return _mm256_movemask_ps(__m256(depth_cmp_lanes(f, F8(z), F8(d))));
}
// Window depth (lanes 0-1 in lo, 2-3 in hi, double) rounded to float, then quantised.
[[gnu::always_inline]] inline __m128 quantise_depth4(__m128d lo, __m128d hi) {
  const __m128 z = _mm_movelh_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi));
  return __m128(quantise_depth_lanes<F4, D4>(F4(z)));
}
// Window depth (lanes 0-3 in lo, 4-7 in hi, double) rounded to float, then quantised (AVX2).
typedef double D8 __attribute__((vector_size(64)));
__attribute__((target("avx2"), always_inline)) inline __m256 quantise_depth8(__m256d lo, __m256d hi) {
  const __m256 z = _mm256_set_m128(_mm256_cvtpd_ps(hi), _mm256_cvtpd_ps(lo));
  return __m256(quantise_depth_lanes<F8, D8>(F8(z)));
}
#endif

}  // namespace wedge::render::raster
