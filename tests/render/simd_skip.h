// The SSE2-versus-AVX2 tests compare the two builds of the rasterizer's vector code. On a CPU
// without AVX2 the AVX2 builds never run (the run-time choice falls back to SSE2), so such a test
// would compare SSE2 with itself and pass without checking anything: it asks avx2_missing()
// first, which says so in the test output (a warning naming the test) and tells it to skip.
#pragma once
#include <catch2/catch.hpp>

namespace wedge::render::test {

inline bool cpu_has_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

inline bool avx2_missing(const char* what) {
  if (cpu_has_avx2()) return false;
  WARN("skipped on this CPU (no AVX2): " << what << " would compare the SSE2 build with itself");
  return true;
}

}  // namespace wedge::render::test
