// render_scene's progress hook (what `wedge run` turns into a progress bar for a large render):
// called on the calling thread with the triangles handed to the pipeline, in steps of
// kProgressTriangles and once at the end, and never changing the picture.
#include <catch2/catch.hpp>

#include <thread>
#include <vector>

#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

// A grid of n x n quads (2 n^2 triangles) in the plane z = 0, facing +z.
Mesh grid(int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_vertex(Point3(double(i) / n, double(j) / n, 0));
  auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

}  // namespace

TEST_CASE("render_scene reports its progress by batches of triangles, ending at the total", "[render][progress]") {
  const Mesh m = grid(150);  // 45,000 triangles: two whole batches of 16,384 and a part
  REQUIRE(m.triangle_count() == 45000);
  DrawItem item;
  item.mesh = &m;
  RenderOptions o;
  o.width = 48, o.height = 48;
  o.camera.eye = Point3(0.5, 0.5, 3);
  o.camera.center = Point3(0.5, 0.5, 0);
  o.camera.up = Vec3(0, 1, 0);
  o.background = Vec4f(0, 0, 0, 1);
  const Image plain = render_scene({item}, o);

  std::vector<std::pair<std::size_t, std::size_t>> calls;
  const std::thread::id caller = std::this_thread::get_id();
  bool same_thread = true;
  o.progress = [&](std::size_t done, std::size_t total) {
    calls.emplace_back(done, total);
    same_thread = same_thread && std::this_thread::get_id() == caller;
  };
  const Image reported = render_scene({item}, o);
  CHECK(same_thread);
  REQUIRE(calls.size() == 3);  // after 16,384 and 32,768 triangles, then at the end
  CHECK(calls[0] == std::pair<std::size_t, std::size_t>{16384, 45000});
  CHECK(calls[1] == std::pair<std::size_t, std::size_t>{32768, 45000});
  CHECK(calls[2] == std::pair<std::size_t, std::size_t>{45000, 45000});
  CHECK(reported.rgba == plain.rgba);  // the hook does not change the picture
  // The grid fills part of the picture: it was drawn.
  int lit = 0;
  for (int y = 0; y < plain.height; ++y)
    for (int x = 0; x < plain.width; ++x) lit += plain.pixel(x, y)[0] > 20;
  CHECK(lit > 100);
}
