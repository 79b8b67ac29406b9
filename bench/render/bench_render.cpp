// Frame time of wedge's rasterizer and of Mesa's llvmpipe (OSMesa) on the scenes: a
// 20k-triangle sphere at 800x600 with a point light, a 1M-triangle sphere at 1920x1080, a
// textured checker plane with fog, a wireframe torus, and clear-only frames. Both receive the
// same calls (vertex arrays); GL frames end with glFinish. Best of N frames, milliseconds.
// llvmpipe's thread count comes from LP_NUM_THREADS, read when the context is created.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>

#include "gl_oracle.h"
#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

struct Arrays {
  std::vector<double> pos, nrm, tex;
  int count = 0;
  VertexArrays va() const {
    VertexArrays a;
    a.positions = pos.data();
    a.normals = nrm.empty() ? nullptr : nrm.data();
    a.texcoords = tex.empty() ? nullptr : tex.data();
    return a;
  }
};

// Non-indexed triangles of a UV sphere with about `tris` triangles.
Arrays sphere(int tris) {
  int stacks = int(std::sqrt(tris / 2.0)), slices = tris / (2 * stacks);
  Arrays a;
  auto vert = [&](int i, int j) {
    double t = kPi * i / stacks - kPi / 2, p = 2 * kPi * j / slices;
    double x = std::cos(t) * std::cos(p), y = std::cos(t) * std::sin(p), z = std::sin(t);
    a.pos.insert(a.pos.end(), {x, y, z});
    a.nrm.insert(a.nrm.end(), {x, y, z});
    ++a.count;
  };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      vert(i, j), vert(i, j + 1), vert(i + 1, j + 1);
      vert(i, j), vert(i + 1, j + 1), vert(i + 1, j);
    }
  return a;
}

Arrays torus(int n, int m) {
  Arrays a;
  auto vert = [&](int i, int j) {
    double u = 2 * kPi * i / n, v = 2 * kPi * j / m;
    double x = (1 + 0.35 * std::cos(v)) * std::cos(u), y = (1 + 0.35 * std::cos(v)) * std::sin(u), z = 0.35 * std::sin(v);
    a.pos.insert(a.pos.end(), {x, y, z});
    a.nrm.insert(a.nrm.end(), {std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)});
    ++a.count;
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      vert(i, j), vert(i + 1, j), vert(i + 1, j + 1);
      vert(i, j), vert(i + 1, j + 1), vert(i, j + 1);
    }
  return a;
}

Arrays plane() {
  Arrays a;
  const double p[4][3] = {{-20, -1, 5}, {20, -1, 5}, {20, -1, -60}, {-20, -1, -60}};
  const double t[4][2] = {{0, 0}, {20, 0}, {20, 32}, {0, 32}};
  for (int k : {0, 1, 2, 0, 2, 3}) {
    a.pos.insert(a.pos.end(), {p[k][0], p[k][1], p[k][2]});
    a.tex.insert(a.tex.end(), {t[k][0], t[k][1]});
    ++a.count;
  }
  return a;
}

template <class G>
void camera(G& g, int w, int h, double dist) {
  g.viewport(0, 0, w, h);
  g.matrix_mode(MatrixMode::Projection);
  g.load_identity();
  g.perspective(45, double(w) / h, 0.5, 100);
  g.matrix_mode(MatrixMode::ModelView);
  g.load_identity();
  g.look_at(Point3(0, 0.8, dist), Point3(0, 0, 0), Vec3(0, 1, 0));
}

template <class G>
void lit_sphere(G& g, const Arrays& a, int w, int h) {
  g.clear_color(0.1f, 0.1f, 0.1f, 1);
  g.clear();
  camera(g, w, h, 3);
  g.enable(Cap::DepthTest);
  g.enable(Cap::CullFace);
  g.enable(Cap::Lighting);
  g.enable(Cap::Light0);
  g.light_position(0, Vec4f(2, 2, 3, 1));
  g.material_specular(Face::FrontAndBack, Vec4f(0.5f, 0.5f, 0.5f, 1));
  g.material_shininess(Face::FrontAndBack, 30);
  g.draw_arrays(Primitive::Triangles, a.va(), 0, a.count);
}

template <class G>
void fog_plane(G& g, const Arrays& a, std::shared_ptr<Texture> tex, int w, int h) {
  g.clear_color(0.7f, 0.7f, 0.75f, 1);
  g.clear();
  camera(g, w, h, 3);
  g.enable(Cap::DepthTest);
  g.enable(Cap::Texture2D);
  g.bind_texture(tex);
  g.tex_env_mode(TexEnvMode::Modulate);
  g.enable(Cap::Fog);
  g.fog_mode(FogMode::Linear);
  g.fog_color(Vec4f(0.7f, 0.7f, 0.75f, 1));
  g.fog_start(2);
  g.fog_end(40);
  g.draw_arrays(Primitive::Triangles, a.va(), 0, a.count);
}

template <class G>
void wire_torus(G& g, const Arrays& a, int w, int h) {
  g.clear_color(0, 0, 0, 1);
  g.clear();
  camera(g, w, h, 3.5);
  g.rotate(60, 1, 0, 0);
  g.polygon_mode(Face::FrontAndBack, PolygonMode::Line);
  g.draw_arrays(Primitive::Triangles, a.va(), 0, a.count);
}

// Wall time and CPU time (all of the process's threads: llvmpipe rasterises on its own
// threads, LP_NUM_THREADS of them, while the calling thread transforms, lights, sets up and bins)
// of the best frame by wall time, milliseconds.
struct Times {
  double wall = 1e300, cpu = 0;
};

double cpu_ms() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

Times best_ms(int frames, const std::function<void()>& frame) {
  Times best;
  for (int i = 0; i < frames; ++i) {
    const double c0 = cpu_ms();
    auto t0 = std::chrono::steady_clock::now();
    frame();
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ms < best.wall) best = {ms, cpu_ms() - c0};
  }
  return best;
}

int g_threads = 1;
const char* g_only = nullptr;  // run only the scenes whose name contains this
int g_profile = 0;             // WEDGE_BENCH_PROFILE=N: wedge alone, N frames (for perf record)
Simd g_simd = Simd::Auto;      // WEDGE_RENDER_SIMD=sse2: wedge's SSE2 code (Context::simd)

template <class Scene>
void run(const char* name, int w, int h, int frames, Scene scene) {
  if (g_only && !std::strstr(name, g_only)) return;
  Times ours, gl;
  {
    Context c(w, h);
    c.threads(g_threads);
    c.simd(g_simd);
    ours = best_ms(g_profile ? g_profile : frames, [&] { scene(c); });
    // WEDGE_BENCH_DUMP=dir: wedge's last frame as dir/<first word of the scene>.png (to compare
    // images across changes).
    if (const char* dir = std::getenv("WEDGE_BENCH_DUMP"))
      write_png(std::string(dir) + "/" + std::string(name, std::strcspn(name, " ,")) + "_" +
                    std::to_string(w) + ".png", c.image());
  }
  if (g_profile) {
    std::printf("| %s | %.2f | - | - | %.2f | - |\n", name, ours.wall, ours.cpu);
    return;
  }
  {
    oracle::GlContext g(w, h);
    gl = best_ms(frames, [&] {
      scene(g);
      g.finish();
    });
  }
  std::printf("| %s | %.2f | %.2f | %.2fx | %.2f | %.2f |\n", name, ours.wall, gl.wall, gl.wall / ours.wall, ours.cpu,
              gl.cpu);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1) g_only = argv[1];
  if (const char* p = std::getenv("WEDGE_BENCH_PROFILE")) g_profile = std::max(0, std::atoi(p));
  if (const char* s = std::getenv("WEDGE_RENDER_SIMD")) g_simd = std::strcmp(s, "sse2") == 0 ? Simd::Sse2 : Simd::Auto;
  const char* threads = std::getenv("LP_NUM_THREADS");
  g_threads = threads ? std::max(1, std::atoi(threads)) : 1;
  std::printf("threads: wedge %d, llvmpipe (LP_NUM_THREADS) %s\n", g_threads, threads ? threads : "default");
  std::printf("| scene | wedge ms | llvmpipe ms | speed-up | wedge CPU ms | llvmpipe CPU ms |\n|---|---|---|---|---|---|\n");
  Arrays s20k = sphere(20000);
  run("sphere 20k tris, 800x600, point light", 800, 600, 10, [&](auto& g) { lit_sphere(g, s20k, 800, 600); });
  {
    Arrays s1m = sphere(1000000);
    run("sphere 1M tris, 1920x1080", 1920, 1080, 3, [&](auto& g) { lit_sphere(g, s1m, 1920, 1080); });
  }
  Arrays pl = plane();
  auto tex = Texture::checker(256, 16, Vec4f(1, 1, 1, 1), Vec4f(0.2f, 0.3f, 0.6f, 1));
  tex->min_filter = TexFilter::LinearMipmapLinear;
  run("textured checker plane + fog, 800x600", 800, 600, 10, [&](auto& g) { fog_plane(g, pl, tex, 800, 600); });
  Arrays tor = torus(96, 48);
  run("wireframe torus 9k tris, 800x600", 800, 600, 10, [&](auto& g) { wire_torus(g, tor, 800, 600); });
  run("clear only, 1920x1080", 1920, 1080, 20, [&](auto& g) {
    g.clear_color(0.2f, 0.3f, 0.4f, 1);
    g.clear();
  });
  return 0;
}
