// Texture sampling alone: the 2x2 quads of bench_render's textured plane (800x600, the same
// camera and plane, 256^2 RGBA checker, LINEAR_MIPMAP_LINEAR, repeat), their (s, t) and level of
// detail computed here analytically, then sampled with four Texture::sample calls per quad and
// with one Texture::sample4. Prints nanoseconds per sample.
// Usage: bench_texture [passes] [sample|sample4|all] [sse2]  (one method only: for callgrind;
// sse2: keep sample4 off its AVX2 path).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

struct Quad {
  float s[4], t[4], lambda;
};

// Rays through the pixel centres of an 800x600 view (eye (0, 0.8, 3) looking at the origin,
// fovy 45 degrees) hit the plane y = -1, x in [-20, 20], z in [-60, 5], textured with
// s = (x + 20) / 2, t = (5 - z) * 32 / 65; quads fully on the plane are kept.
std::vector<Quad> plane_quads(int size) {
  const int W = 800, H = 600;
  const double ex = 0, ey = 0.8, ez = 3;
  double fx = -ex, fy = -ey, fz = -ez;
  double fl = std::sqrt(fx * fx + fy * fy + fz * fz);
  fx /= fl, fy /= fl, fz /= fl;
  double rx = -fz, ry = 0, rz = fx;  // f x (0, 1, 0)
  double rl = std::sqrt(rx * rx + rz * rz);
  rx /= rl, rz /= rl;
  const double ux = ry * fz - rz * fy, uy = rz * fx - rx * fz, uz = rx * fy - ry * fx;
  const double th = std::tan(22.5 * 3.14159265358979 / 180), aspect = double(W) / H;
  auto st = [&](double px, double py, double& s, double& t) {
    double dx = ((px + 0.5) / (W / 2) - 1) * th * aspect, dy = ((py + 0.5) / (H / 2) - 1) * th;
    double vx = rx * dx + ux * dy + fx, vy = ry * dx + uy * dy + fy, vz = rz * dx + uz * dy + fz;
    if (vy >= 0) return false;
    double k = (-1 - ey) / vy, x = ex + k * vx, z = ez + k * vz;
    if (std::abs(x) > 20 || z < -60 || z > 5) return false;
    s = (x + 20) / 2, t = (5 - z) * 32 / 65;
    return true;
  };
  std::vector<Quad> quads;
  for (int py = 0; py < H; py += 2)
    for (int px = 0; px < W; px += 2) {
      double s[4], t[4];
      bool in = true;
      for (int k = 0; k < 4; ++k) in = in && st(px + (k & 1), py + (k >> 1), s[k], t[k]);
      if (!in) continue;
      Quad q;
      for (int k = 0; k < 4; ++k) q.s[k] = float(s[k]), q.t[k] = float(t[k]);
      double dsx = (s[1] - s[0]) * size, dtx = (t[1] - t[0]) * size, dsy = (s[2] - s[0]) * size,
             dty = (t[2] - t[0]) * size;
      double rho2 = std::max(dsx * dsx + dtx * dtx, dsy * dsy + dty * dty);
      q.lambda = rho2 > 0 ? float(0.5 * std::log2(rho2)) : -100.0f;
      quads.push_back(q);
    }
  return quads;
}

}  // namespace

int main(int argc, char** argv) {
  const int passes = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  const char* only = argc > 2 && std::strcmp(argv[2], "all") != 0 ? argv[2] : nullptr;
  const Simd simd = argc > 3 && std::strcmp(argv[3], "sse2") == 0 ? Simd::Sse2 : Simd::Auto;
  auto tex = Texture::checker(256, 16, Vec4f(1, 1, 1, 1), Vec4f(0.2f, 0.3f, 0.6f, 1));
  tex->min_filter = TexFilter::LinearMipmapLinear;
  const std::vector<Quad> quads = plane_quads(256);
  int minified = 0;
  for (const Quad& q : quads) minified += q.lambda > 0;
  std::printf("%zu quads (%zu fragments), %.0f%% minified\n", quads.size(), 4 * quads.size(),
              100.0 * minified / quads.size());
  // The machine is shared: a pass of several milliseconds is rarely left alone, so each chunk of
  // 512 quads is timed `passes` times and the best times of the chunks are summed.
  float sink = 0;
  auto time = [&](const char* name, auto&& body) {
    if (only && std::strcmp(only, name) != 0) return;
    double total = 0;
    for (std::size_t c = 0; c < quads.size(); c += 512) {
      const std::size_t e = std::min(quads.size(), c + 512);
      double best = 1e300;
      for (int p = 0; p < passes; ++p) {
        auto t0 = std::chrono::steady_clock::now();
        body(c, e);
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      total += best;
    }
    std::printf("%-8s %6.2f ns/sample  %6.3f ms/frame\n", name, total * 1e6 / (4.0 * quads.size()), total);
  };
  time("sample", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Quad& q = quads[i];
      for (int k = 0; k < 4; ++k) sink += tex->sample(q.s[k], q.t[k], q.lambda)[k];
    }
  });
  time("sample4", [&](std::size_t b, std::size_t e) {
    float out[16];
    for (std::size_t i = b; i < e; ++i) {
      const Quad& q = quads[i];
      tex->sample4(q.s, q.t, q.lambda, out, simd);
      sink += out[0] + out[5] + out[10] + out[15];
    }
  });
  std::printf("(checksum %g)\n", double(sink));
  return 0;
}
