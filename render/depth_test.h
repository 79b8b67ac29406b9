// The depth test (the z-buffer) of the rasterizer, private to render/: GL 1.x section 4.1.6.
//
// The depth buffer holds floats, but as OpenGL with a 24-bit depth buffer (Mesa's default) every
// fragment's window z is clamped to [0, 1] and quantised to k / (2^24 - 1), k an integer, before
// the comparison and the write: round to nearest even by adding and removing 2^52 (no libm call),
// then times 1 / (2^24 - 1) (a multiply, not a division: the double product is within 2 ulps of
// the quotient, while k / (2^24 - 1) lies at least about 2^-50 (relative) from any float rounding
// boundary, so the float is the same; checked for all 2^24 values). The comparison is the state's
// depth function; the write happens when the test passes and the depth mask is on.
//   quantise_depth_lanes   the quantisation, written once for lanes of any width (float, F4, F8;
//                          the quad loop, quad_loop.cpp); through it
//     quantise_depth       one fragment (Raster::depth_stage_t: lines, points, the one-pixel
//                          triangle loop; Raster::tiny_pixel)
//   depth_cmp_lanes        the comparison, written once for lanes of any width (a scalar is one
//                          lane: a bool); through it
//     depth_pass           one fragment
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
  z = clamp01_sse(z);
  constexpr double kRound = 0x1p52;  // not folded: no -ffast-math (no reassociation)
  constexpr double kInvMax = 1.0 / 16777215.0;
  D d = lanes_as<D>(z) * 16777215.0;
  d = (d + kRound) - kRound;
  return lanes_as<F>(d * kInvMax);
}

// One fragment's z, quantised.
[[gnu::always_inline]] inline float quantise_depth(float z) { return quantise_depth_lanes<float, double>(z); }

// The depth test on lanes (float, F4, F8): z (quantised) against the stored d by the depth
// function; all ones in the passing lanes (true for one float).
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

// Whether one fragment at (quantised) depth z passes against the stored d.
[[gnu::always_inline]] inline bool depth_pass(DepthFunc f, float z, float d) { return depth_cmp_lanes(f, z, d); }

}  // namespace wedge::render::raster
