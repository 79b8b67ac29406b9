// The depth test (the z-buffer) of the rasterizer, private to render/: GL 1.x section 4.1.6.
//
// The depth buffer holds floats, but as OpenGL with a 24-bit depth buffer (Mesa's default) every
// fragment's window z is clamped to [0, 1] and quantised to k / (2^24 - 1), k an integer, before
// the comparison and the write: round to nearest even by adding and removing 2^52 (no libm call),
// then times 1 / (2^24 - 1) (a multiply, not a division: the double product is within 2 ulps of
// the quotient, while k / (2^24 - 1) lies at least about 2^-50 (relative) from any float rounding
// boundary, so the float is the same; checked for all 2^24 values). The comparison is the state's
// depth function; the write happens when the test passes and the depth mask is on.
//   quantise_depth, depth_pass   one fragment (Raster::depth_stage_t: lines, points, the
//                                one-pixel-at-a-time triangle loop)
//   quantise_depth4, depth_cmp4  four lanes (the SSE2 quad loop, fragments.cpp)
// The AVX2 two-quad loop (fragments_avx2.cpp) and the small-triangle pixels (Raster::tiny_pixel)
// apply the same quantisation to their own lanes, operation for operation.
#pragma once
#include <algorithm>

#include "render/simd.h"

namespace wedge::render::raster {

// z quantised as the depth buffer holds it.
[[gnu::always_inline]] inline float quantise_depth(float z) {
  constexpr double kRound = 0x1p52;  // not folded: no -ffast-math (no reassociation)
  double zr = double(std::clamp(z, 0.0f, 1.0f)) * 16777215.0;
  zr = (zr + kRound) - kRound;
  constexpr double kInvMax = 1.0 / 16777215.0;
  return float(zr * kInvMax);
}

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

#if defined(__SSE2__)
// The depth test on four lanes: a bit per passing lane.
[[gnu::always_inline]] inline int depth_cmp4(DepthFunc f, __m128 z, __m128 d) {
  switch (f) {
    case DepthFunc::Never: return 0;
    case DepthFunc::Less: return _mm_movemask_ps(_mm_cmplt_ps(z, d));
    case DepthFunc::Equal: return _mm_movemask_ps(_mm_cmpeq_ps(z, d));
    case DepthFunc::LessEqual: return _mm_movemask_ps(_mm_cmple_ps(z, d));
    case DepthFunc::Greater: return _mm_movemask_ps(_mm_cmpgt_ps(z, d));
    case DepthFunc::NotEqual: return _mm_movemask_ps(_mm_cmpneq_ps(z, d));
    case DepthFunc::GreaterEqual: return _mm_movemask_ps(_mm_cmpge_ps(z, d));
    case DepthFunc::Always: return 15;
  }
  return 0;
}
// Window depth (lanes 0-1 in lo, 2-3 in hi, double) rounded to float, clamped to [0, 1] and
// quantised to 24 bits as Raster::depth_stage_t does (round to nearest even by adding and
// removing 2^52, times 1/(2^24 - 1)).
[[gnu::always_inline]] inline __m128 quantise_depth4(__m128d lo, __m128d hi) {
  __m128 z = _mm_movelh_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi));
  z = _mm_min_ps(_mm_max_ps(z, _mm_setzero_ps()), _mm_set1_ps(1.0f));
  const __m128d k = _mm_set1_pd(16777215.0), r = _mm_set1_pd(0x1p52), inv = _mm_set1_pd(1.0 / 16777215.0);
  __m128d a = _mm_mul_pd(_mm_cvtps_pd(z), k), b = _mm_mul_pd(_mm_cvtps_pd(_mm_movehl_ps(z, z)), k);
  a = _mm_sub_pd(_mm_add_pd(a, r), r), b = _mm_sub_pd(_mm_add_pd(b, r), r);
  return _mm_movelh_ps(_mm_cvtpd_ps(_mm_mul_pd(a, inv)), _mm_cvtpd_ps(_mm_mul_pd(b, inv)));
}
#endif

}  // namespace wedge::render::raster
