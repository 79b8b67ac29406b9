// A hostile fuzzer for the exact mesh-boolean engine (csg/boolean.h): seeded random cases from
// adversarial generators (coarse grids with exact coplanarities, copies a few ulps or 1e-9 rad
// apart, touching and nested operands, n-ary unions through one point, slivers, extreme scales,
// chains of results, skinny fans, bad operands), each boolean checked against the engine's
// promise: a valid result (tests/support result_defect: closed, 2-manifold, outward, no exact
// self-intersection), exact volume identities (vol(A u B) + vol(A n B) = vol A + vol B,
// vol(A - B) = vol A - vol(A n B)), CGAL's exact corefinement on small cases, exact box volumes on
// axis-parallel boxes, the same bits at 1 and 2 threads, and for bad operands a wedge::Error naming
// the operand. Each case runs in a forked child under a watchdog (a boolean over --hang seconds is
// a hang); a crash or hang leaves the operands of the boolean that was running.
//
//   fuzz_boolean [--gen a,b,...] [--seed N] [--cases N] [--minutes M] [--out DIR] [--hang S]
//   fuzz_boolean --replay DIR     (DIR/op.txt: union|intersection|difference; DIR/operand*.off)
//   fuzz_boolean --list
//
// Failures go to OUT/fail/<gen>_<seed>_<k>/ (operands as OFF with %.17g, op.txt, README), the
// per-generator counts to stdout at the end. Run it niced: it is CPU-bound.
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "csg/boolean.h"
#include "kernel/error.h"
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

using namespace wedge;
using namespace wedge::testing;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double now_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

// ---------------------------------------------------------------- shared state (parent <-> child)
enum Outcome { kOk, kUnroundable, kBudget, kError, kInvalid, kPinchMerged, kPinchNew, kVolume, kOracle, kBadAccepted, kBadMsg, kBitsDiffer,
               kCrash, kHang, kSlow, kSkipped, kOutcomes };
const char* kOutcomeName[kOutcomes] = {"ok", "unroundable", "budget", "error", "invalid", "pinch-merged", "pinch-new", "volume", "oracle",
                                        "bad-accepted", "bad-message", "bits-differ", "crash", "hang", "slow(>2s)",
                                        "skipped-operand"};
constexpr int kMaxGens = 32;
struct Shared {
  volatile double bool_start;  // wall time the running boolean started, 0 when none runs
  int booleans[kMaxGens];  // written by the child, read by the parent after it ends
  int outcome[kMaxGens][kOutcomes];
  int failures;
  char current[512];  // what the child is doing (for the parent's report)
};
Shared* g_sh = nullptr;
int g_gen = 0;
std::string g_out = "/tmp/fuzz";
std::string g_case;  // "<gen>_<seed>"
int g_fail_k = 0;
double g_hang = 30;

// ---------------------------------------------------------------- OFF in and out
void write_off(const std::string& path, const Mesh& m) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return;
  std::fprintf(f, "OFF\n%zu %zu 0\n", m.positions.size(), m.triangles.size());
  for (const auto& p : m.positions) std::fprintf(f, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  for (const auto& t : m.triangles) std::fprintf(f, "3 %u %u %u\n", t[0], t[1], t[2]);
  std::fclose(f);
}
Mesh read_off(const std::string& path) {
  std::ifstream in(path);
  std::string head;
  in >> head;
  if (head != "OFF") throw Error(path + ": not OFF");
  std::size_t nv, nf, ne;
  in >> nv >> nf >> ne;
  Mesh m;
  for (std::size_t i = 0; i < nv; ++i) {
    std::string s[3];
    in >> s[0] >> s[1] >> s[2];
    m.positions.push_back(Vec3(std::strtod(s[0].c_str(), nullptr), std::strtod(s[1].c_str(), nullptr),
                               std::strtod(s[2].c_str(), nullptr)));
  }
  for (std::size_t i = 0; i < nf; ++i) {
    int k;
    std::uint32_t a, b, c;
    in >> k >> a >> b >> c;
    m.triangles.push_back({a, b, c});
  }
  return m;
}

std::string op_word(BooleanOp op) { return boolean_op_name(op); }

void save_operands(const std::string& dir, BooleanOp op, const std::vector<const Mesh*>& ops) {
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".off") fs::remove(e.path());
  for (std::size_t i = 0; i < ops.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "/operand%02zu.off", i);
    write_off(dir + name, *ops[i]);
  }
  std::ofstream(dir + "/op.txt") << op_word(op) << "\n";
}

void count(Outcome o) { ++g_sh->outcome[g_gen][o]; }

void record_failure(Outcome o, BooleanOp op, const std::vector<const Mesh*>& ops, const std::string& what) {
  count(o);
  ++g_sh->failures;
  const std::string dir = g_out + "/fail/" + g_case + "_" + std::to_string(g_fail_k++);
  if (g_sh->outcome[g_gen][o] > 6) {  // enough of this kind from this generator: report, do not save
    std::fprintf(stdout, "FAIL %s %s %s (not saved): %s\n", g_case.c_str(), op_word(op).c_str(), kOutcomeName[o], what.c_str());
    return;
  }
  save_operands(dir, op, ops);
  std::ofstream(dir + "/README") << op_word(op) << ": " << kOutcomeName[o] << ": " << what
                                 << "\nrun: fuzz_boolean --replay " << dir << "\n";
  std::fprintf(stdout, "FAIL %s %s %s: %s\n", g_case.c_str(), op_word(op).c_str(), kOutcomeName[o], what.c_str());
  std::fflush(stdout);
}

// ---------------------------------------------------------------- mesh helpers
using Rng = std::mt19937_64;
double uni(Rng& r, double a, double b) { return std::uniform_real_distribution<double>(a, b)(r); }
int irand(Rng& r, int a, int b) { return std::uniform_int_distribution<int>(a, b)(r); }
double ir(Rng& r, int a, int b) { return irand(r, a, b); }  // an integer as a coordinate
bool coin(Rng& r, double p = 0.5) { return uni(r, 0, 1) < p; }
Vec3 rand_dir(Rng& r) {
  for (;;) {
    Vec3 v(uni(r, -1, 1), uni(r, -1, 1), uni(r, -1, 1));
    if (v.norm() > 0.1 && v.norm() <= 1) return v.normalized();
  }
}
Mesh xf(const Mesh& m, const Mat4& t) { return m.transformed(t); }
Mesh rot(const Mesh& m, double deg, const Vec3& axis, const Point3& pivot) { return m.transformed(rotate(deg, axis, pivot)); }
Mesh moved(const Mesh& m, const Vec3& d) {
  Mesh o = m;
  for (auto& p : o.positions) p += d;
  return o;
}
Mesh scaled_pow2(const Mesh& m, int e) {
  Mesh o = m;
  for (auto& p : o.positions) p = Vec3(std::ldexp(p.x(), e), std::ldexp(p.y(), e), std::ldexp(p.z(), e));
  return o;
}
Mesh ulp_shift(const Mesh& m, int k, const Vec3& dir) {  // each coordinate k ulps toward sign(dir)
  Mesh o = m;
  for (auto& p : o.positions)
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < k; ++i)
        if (dir[c] != 0) p[c] = std::nextafter(p[c], dir[c] > 0 ? INFINITY : -INFINITY);
  return o;
}
Mesh jitter_ulps(const Mesh& m, int k, Rng& r) {
  Mesh o = m;
  for (auto& p : o.positions)
    for (int c = 0; c < 3; ++c) {
      const int n = irand(r, -k, k);
      for (int i = 0; i < std::abs(n); ++i) p[c] = std::nextafter(p[c], n > 0 ? INFINITY : -INFINITY);
    }
  return o;
}
Mesh snapped(const Mesh& m, double grid) {
  Mesh o = m;
  for (auto& p : o.positions)
    for (int c = 0; c < 3; ++c) p[c] = std::round(p[c] / grid) * grid;
  return o;
}
Mesh flipped(const Mesh& m) {
  Mesh o = m;
  for (auto& t : o.triangles) std::swap(t[1], t[2]);
  return o;
}
// A tetrahedron, outward whatever the order of the corners (none coplanar).
Mesh tetra(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  if ((b - a).cross(c - a).dot(d - a) > 0) std::swap(b, c);
  Mesh m;
  m.add_vertex(a), m.add_vertex(b), m.add_vertex(c), m.add_vertex(d);
  m.add_triangle(0, 1, 2), m.add_triangle(0, 3, 1), m.add_triangle(1, 3, 2), m.add_triangle(0, 2, 3);
  return m;
}
// A prism over a convex polygon (counter-clockwise in xy) from z0 to z1, caps fanned from vertex 0
// (skinny triangles for many nearly collinear points) or from a centre vertex.
Mesh prism(const std::vector<Vec2>& poly, double z0, double z1, bool centre_fan) {
  Mesh m;
  const std::uint32_t n = static_cast<std::uint32_t>(poly.size());
  for (const auto& p : poly) m.add_vertex({p.x(), p.y(), z0});
  for (const auto& p : poly) m.add_vertex({p.x(), p.y(), z1});
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.add_triangle(i, j, n + j), m.add_triangle(i, n + j, n + i);
  }
  if (centre_fan) {
    Vec2 c(0, 0);
    for (const auto& p : poly) c += p;
    c /= n;
    const auto b = m.add_vertex({c.x(), c.y(), z0}), t = m.add_vertex({c.x(), c.y(), z1});
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t j = (i + 1) % n;
      m.add_triangle(b, j, i), m.add_triangle(t, n + i, n + j);
    }
  } else {
    for (std::uint32_t i = 1; i + 1 < n; ++i) m.add_triangle(0, i + 1, i), m.add_triangle(n, n + i, n + i + 1);
  }
  return m;
}
double reach_of(const std::vector<const Mesh*>& ms) {
  double r = 0;
  for (auto* m : ms)
    for (const auto& p : m->positions) r = std::max(r, p.cwiseAbs().maxCoeff());
  return r;
}

// ---------------------------------------------------------------- a case
struct Case {
  std::vector<Mesh> ops;
  bool bad = false;          // operands deliberately invalid: every op must throw naming bad_index
  int bad_index = -1;
  bool axis_boxes = false;   // operands are axis-parallel boxes (boxes_volume is the reference)
  std::vector<std::array<Vec3, 2>> boxes;
  int pow2 = 0;              // operands are a unit-size case scaled by 2^pow2: volumes compared scaled back
  bool chain = false;        // run as a chain of steps (ops[0] then each later operand with a random op)
  std::string note;
};

Mesh random_primitive(Rng& r, double size = 1) {
  const Vec3 c(uni(r, -0.5, 0.5) * size, uni(r, -0.5, 0.5) * size, uni(r, -0.5, 0.5) * size);
  switch (irand(r, 0, 5)) {
    case 0: return box_mesh(c, Vec3(uni(r, 0.3, 1.2), uni(r, 0.3, 1.2), uni(r, 0.3, 1.2)) * size,
                            rotate(uni(r, 0, 360), rand_dir(r), c));
    case 1: return icosphere(c, uni(r, 0.3, 0.9) * size, coin(r) ? 80 : 320);
    case 2: return cylinder_mesh(uni(r, 0.2, 0.7) * size, -0.6 * size, 0.6 * size, irand(r, 3, 8),
                                 translate(c) * rotate(uni(r, 0, 360), rand_dir(r)));
    case 3: return uv_sphere(c, uni(r, 0.3, 0.9) * size, irand(r, 24, 200));
    case 4: return grid_box(c, c + Vec3(uni(r, 0.3, 1), uni(r, 0.3, 1), uni(r, 0.3, 1)) * size, irand(r, 1, 4));
    default: {
      Vec3 a = c, b = c + rand_dir(r) * size, d = c + rand_dir(r) * size, e = c + rand_dir(r) * size;
      if (std::abs((b - a).cross(d - a).dot(e - a)) < 0.05 * size * size * size) return box_mesh(c, Vec3(size, size, size));
      return tetra(a, b, d, e);
    }
  }
}

// ---------------------------------------------------------------- generators
// Axis-parallel boxes with integer corners in [0, 4]: shared faces, edges, vertices, T-junctions.
Case gen_grid_boxes(Rng& r) {
  Case c;
  c.axis_boxes = true;
  const int n = irand(r, 2, 5);
  for (int i = 0; i < n; ++i) {
    Vec3 lo(irand(r, 0, 3), irand(r, 0, 3), irand(r, 0, 3));
    Vec3 hi = lo + Vec3(ir(r, 1, 3), ir(r, 1, 3), ir(r, 1, 3));
    if (coin(r, 0.3)) lo *= 0.5, hi *= 0.5;  // half grid: more partial coincidence
    c.boxes.push_back({lo, hi});
    c.ops.push_back(coin(r, 0.4) ? grid_box(lo, hi, irand(r, 2, 4)) : box_mesh(lo, hi - lo));
  }
  return c;
}
// Grid shapes that are not boxes: snapped low-poly spheres and cylinders, boxes turned 90 / 45
// degrees about grid points, tetrahedra and prisms on integer corners (sloped exact coplanarity).
Case gen_grid_mixed(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) {
    const Vec3 g(irand(r, 0, 3), irand(r, 0, 3), irand(r, 0, 3));
    switch (irand(r, 0, 4)) {
      case 0: c.ops.push_back(snapped(icosphere(g, irand(r, 2, 4), 80), coin(r) ? 1.0 : 0.5)); break;
      case 1: c.ops.push_back(snapped(cylinder_mesh(irand(r, 1, 3), 0, irand(r, 1, 4), irand(r, 3, 8),
                                                    translate(g) * rotate(90.0 * irand(r, 0, 3), Vec3::UnitX())), 0.5));
        break;
      case 2: c.ops.push_back(box_mesh(g, Vec3(ir(r, 1, 3), ir(r, 1, 3), ir(r, 1, 3)),
                                       rotate(coin(r) ? 45.0 : 90.0, Vec3::Unit(irand(r, 0, 2)), g)));
        break;
      case 3: {
        Vec3 p[4];
        for (auto& q : p) q = g + Vec3(ir(r, -2, 2), ir(r, -2, 2), ir(r, -2, 2));
        if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) == 0) p[3] += Vec3(1, 1, 1);
        if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) == 0) p[3] = p[0] + Vec3(0, 0, 1), p[1] = p[0] + Vec3(1, 0, 0), p[2] = p[0] + Vec3(0, 1, 0);
        c.ops.push_back(tetra(p[0], p[1], p[2], p[3]));
        break;
      }
      default: {
        std::vector<Vec2> poly = {{0, 0}, {2, 0}, {3, 1}, {2, 2}, {0, 2}};
        for (auto& q : poly) q += Vec2(g.x(), g.y());
        c.ops.push_back(prism(poly, g.z(), g.z() + irand(r, 1, 3), coin(r)));
      }
    }
  }
  return c;
}
// A mesh and a copy that nearly coincides: moved by 1-3 ulps, by 1e-12, turned 1e-9 rad,
// vertices jittered by ulps, mirrored through its centre, or re-triangulated.
Case gen_near_copy(Rng& r) {
  Case c;
  Mesh a = random_primitive(r);
  if (coin(r, 0.3)) a = moved(a, Vec3(uni(r, -1e3, 1e3), uni(r, -1e3, 1e3), 0));
  c.ops.push_back(a);
  const int k = irand(r, 1, 3);
  const int nc = coin(r, 0.3) ? irand(r, 2, 4) : 1;
  for (int i = 0; i < nc; ++i) {
    const int how = irand(r, 0, 6);
    c.note += std::to_string(how);
    Vec3 ctr = Vec3::Zero();
    for (auto& p : a.positions) ctr += p;
    ctr /= a.positions.size();
    switch (how) {
      case 0: c.ops.push_back(ulp_shift(a, k, Vec3(ir(r, -1, 1), ir(r, -1, 1), ir(r, -1, 1)))); break;
      case 1: c.ops.push_back(moved(a, rand_dir(r) * 1e-12)); break;
      case 2: c.ops.push_back(rot(a, 1e-9 * 180 / M_PI * irand(r, 1, 3), rand_dir(r), coin(r) ? ctr : a.positions[0])); break;
      case 3: c.ops.push_back(jitter_ulps(a, k, r)); break;
      case 4: c.ops.push_back(xf(a, reflect(rand_dir(r), ctr))); break;
      case 5: c.ops.push_back(rot(a, uni(r, -1e-6, 1e-6), rand_dir(r), ctr)); break;
      default: c.ops.push_back(moved(a, Vec3(std::ldexp(1.0, -irand(r, 40, 52)), 0, 0))); break;
    }
  }
  if (c.ops.size() == 2 && coin(r, 0.3)) std::swap(c.ops[0], c.ops[1]);
  return c;
}
// Exact contact: shared faces, flush pockets, nesting that touches at a vertex, an edge or a face,
// shared edges or vertices only; built on integers then moved by an exact transform (axis
// permutation, mirror, integer shift, power-of-two scale) or, sometimes, a rotation for all.
Case gen_touching(Rng& r) {
  Case c;
  const int kind = irand(r, 0, 7);
  c.note = std::to_string(kind);
  Mesh a, b;
  switch (kind) {
    case 0: a = box_mesh({0, 0, 0}, {2, 2, 2}), b = box_mesh({2, ir(r, -1, 1), ir(r, -1, 1)}, {2, 2, 2}); break;  // faces
    case 1: a = box_mesh({0, 0, 0}, {4, 4, 4}), b = box_mesh({1, 1, ir(r, 2, 3)}, {2, 2, ir(r, 1, 3)}); break;   // pocket
    case 2: a = box_mesh({0, 0, 0}, {4, 4, 4}), b = tetra({0, 0, 0}, {1, 1, 2}, {2, 1, 1}, {1, 2, 1}); break;        // inside at vertex
    case 3: a = box_mesh({0, 0, 0}, {4, 4, 4}), b = tetra({0, 0, 0}, {2, 0, 0}, {1, 1, 1}, {1, 2, 1}); break;        // inside at edge
    case 4: a = box_mesh({0, 0, 0}, {2, 2, 2}), b = box_mesh({2, 2, ir(r, -1, 1)}, {2, 2, 2}); break;              // edge
    case 5: a = box_mesh({0, 0, 0}, {2, 2, 2}), b = box_mesh({2, 2, 2}, {2, 2, 2}); break;                            // vertex
    case 6: a = icosphere({0, 0, 0}, 2, 80), b = box_mesh({-1, -1, -1}, {2, 2, 2}); b = xf(b, scale(Vec3(1, 1, 1) * 0.5)); break;
    default: a = grid_box({0, 0, 0}, {4, 4, 4}, ir(r, 2, 4)), b = grid_box({ir(r, 0, 2), ir(r, 0, 2), 4}, {4, 4, 6}, ir(r, 1, 3)); break;
  }
  if (kind == 6) {  // a sphere's vertex touching a box corner from outside: vertex-vertex contact
    const Vec3 v = a.positions[irand(r, 0, static_cast<int>(a.positions.size()) - 1)];
    b = moved(box_mesh({0, 0, 0}, {1, 1, 1}), v - Vec3(coin(r) ? 0 : 1, coin(r) ? 0 : 1, coin(r) ? 0 : 1));
    b = box_mesh(v, Vec3(v.x() >= 0 ? 1 : -1, v.y() >= 0 ? 1 : -1, v.z() >= 0 ? 1 : -1).cwiseAbs());
    b = moved(b, Vec3(v.x() >= 0 ? 0 : -1, v.y() >= 0 ? 0 : -1, v.z() >= 0 ? 0 : -1));
  }
  std::vector<Mesh> ms = {a, b};
  if (coin(r, 0.3)) ms.push_back(box_mesh({ir(r, -1, 3), ir(r, -1, 3), ir(r, -1, 3)}, {2, 2, 2}));
  Mat4 t = Mat4::Identity();
  switch (irand(r, 0, 3)) {
    case 0: break;
    case 1: t = translate(Vec3(ir(r, -5, 5), ir(r, -5, 5), ir(r, -5, 5))) * scale(Vec3(1, 1, 1) * std::ldexp(1.0, ir(r, -3, 3)));
      break;
    case 2: t = reflect(Vec3::Unit(irand(r, 0, 2))); break;
    default: t = rotate(uni(r, 0, 360), rand_dir(r)); break;  // inexact, same for all: contacts stay near
  }
  for (auto& m : ms) c.ops.push_back(xf(m, t));
  if (coin(r)) std::reverse(c.ops.begin(), c.ops.end());
  return c;
}
// Identical operands, the same solid triangulated differently, n copies.
Case gen_identical(Rng& r) {
  Case c;
  Mesh a = random_primitive(r);
  const int how = irand(r, 0, 3);
  c.note = std::to_string(how);
  if (how == 0) c.ops = {a, a};
  else if (how == 1) c.ops = {a, a, a};
  else if (how == 2) {
    const Vec3 lo(uni(r, -1, 0), uni(r, -1, 0), uni(r, -1, 0));
    const Vec3 hi = lo + Vec3(ir(r, 1, 2), ir(r, 1, 2), ir(r, 1, 2));
    c.ops = {box_mesh(lo, hi - lo), grid_box(lo, hi, irand(r, 2, 5))};
  } else {
    // the same polygon prism fanned two ways
    std::vector<Vec2> poly;
    const int n = irand(r, 5, 12);
    for (int i = 0; i < n; ++i) poly.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n)});
    c.ops = {prism(poly, 0, 1, true), prism(poly, 0, 1, false)};
  }
  return c;
}
// 3 to 10 operands through one point (the origin, exactly): boxes with a corner there, turned
// about it; tetrahedra with an apex there; cylinders whose cap centre is there.
Case gen_nary_point(Rng& r) {
  Case c;
  const int n = irand(r, 3, 10);
  const bool exact = coin(r, 0.4);
  for (int i = 0; i < n; ++i) {
    Mesh m;
    switch (irand(r, 0, 2)) {
      case 0: m = box_mesh({0, 0, 0}, {uni(r, 0.5, 1.5), uni(r, 0.5, 1.5), uni(r, 0.5, 1.5)}); break;
      case 1: m = tetra({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}); break;
      default: m = cylinder_mesh(uni(r, 0.3, 1), 0, uni(r, 0.5, 1.5), irand(r, 3, 8)); break;
    }
    if (exact) {  // octant mirrors and axis permutations: exact, many coincident faces
      Mat4 t = Mat4::Identity();
      for (int k = 0; k < 3; ++k)
        if (coin(r)) t = reflect(Vec3::Unit(k)) * t;
      if (coin(r)) t = rotate(90.0 * irand(r, 1, 3), Vec3::Unit(irand(r, 0, 2))) * t;
      m = xf(m, t);
      for (auto& p : m.positions)
        for (int k = 0; k < 3; ++k) p[k] = std::round(p[k] * 1e12) / 1e12;  // clean the 90-degree turns' noise
      for (auto& p : m.positions)
        for (int k = 0; k < 3; ++k)
          if (std::abs(p[k]) < 1e-9) p[k] = 0;
    } else {
      m = rot(m, uni(r, 0, 360), rand_dir(r), Vec3::Zero());
    }
    c.ops.push_back(m);
  }
  return c;
}
// Turned low-side cylinders and icospheres, near one another.
Case gen_cyl_ico(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) {
    const Vec3 p(uni(r, -0.3, 0.3), uni(r, -0.3, 0.3), uni(r, -0.3, 0.3));
    if (coin(r)) c.ops.push_back(cylinder_mesh(uni(r, 0.2, 0.8), uni(r, -1, 0), uni(r, 0.1, 1), irand(r, 3, 8),
                                               translate(p) * rotate(uni(r, 0, 360), rand_dir(r))));
    else c.ops.push_back(icosphere(p, uni(r, 0.2, 0.8), coin(r) ? 20 : 80));
  }
  return c;
}
// Slivers: boxes 1e-9 (or 1e-15) thick crossing others, thin wedges, nearly parallel faces.
Case gen_sliver(Rng& r) {
  Case c;
  const double th = coin(r) ? 1e-9 : std::ldexp(1.0, -irand(r, 30, 50));
  c.ops.push_back(coin(r) ? box_mesh({0, 0, 0}, {1, 1, 1}) : icosphere({0.5, 0.5, 0.5}, 0.6, 80));
  const int n = irand(r, 1, 3);
  for (int i = 0; i < n; ++i) {
    switch (irand(r, 0, 3)) {
      case 0: c.ops.push_back(box_mesh({-0.5, -0.5, uni(r, 0, 1)}, {2, 2, th}, rotate(uni(r, 0, 1e-3), rand_dir(r), {0.5, 0.5, 0.5}))); break;
      case 1: c.ops.push_back(box_mesh({-0.5, -0.5, coin(r) ? 1.0 : 1.0 - th}, {2, 2, th})); break;  // flush sliver
      case 2: c.ops.push_back(tetra({-0.5, -0.5, 0.5}, {1.5, -0.5, 0.5}, {0.5, 1.5, 0.5}, {0.5, 0.5, 0.5 + th})); break;
      default: {  // a wedge whose top face tilts by th over the unit
        std::vector<Vec2> tri = {{-0.5, -0.5}, {1.5, 0.2}, {0.2, 1.5}};
        Mesh w = prism(tri, 0.3, 0.7, false);
        for (auto& p : w.positions)
          if (p.z() > 0.5) p.z() += th * p.x();
        c.ops.push_back(w);
      }
    }
  }
  return c;
}
// Extreme coordinates: a unit case scaled by 2^e (|e| up to 1000), or moved to around 1e8 with
// unit features, or mixing a huge operand with a tiny one.
Case gen_scale(Rng& r) {
  Case c;
  Rng r2(r());
  Case base;
  switch (irand(r, 0, 2)) {
    case 0: base = gen_touching(r2); break;
    case 1: base = gen_cyl_ico(r2); break;
    default: base = gen_near_copy(r2); break;
  }
  const int kind = irand(r, 0, 3);
  c.note = std::to_string(kind);
  if (kind <= 1) {
    static const int es[] = {-1060, -1000, -900, -600, -333, -100, 100, 333, 600, 900, 1000, 1018};
    c.pow2 = es[irand(r, 0, 11)];
    for (auto& m : base.ops) c.ops.push_back(scaled_pow2(m, c.pow2));
    c.note += " 2^" + std::to_string(c.pow2);
  } else if (kind == 2) {
    const Vec3 off(uni(r, 0.5, 2) * 1e8, uni(r, -2, 2) * 1e8, std::ldexp(1.0, 27));
    for (auto& m : base.ops) c.ops.push_back(moved(m, off));
  } else {  // mixed: a big box and small features near the origin
    const int e = irand(r, 40, 400);
    c.ops.push_back(box_mesh(Vec3(-1, -1, -1) * std::ldexp(1.0, e), Vec3(2, 2, 2) * std::ldexp(1.0, e)));
    for (auto& m : base.ops) c.ops.push_back(scaled_pow2(m, -irand(r, 0, 600)));
    if (coin(r)) c.ops.push_back(box_mesh({0, 0, 0}, Vec3(1, 1, 1) * std::ldexp(1.0, e)));  // shares the big box's corner region
    c.note += " mixed 2^" + std::to_string(e);
  }
  return c;
}
// Skinny triangles: fans of 300-1000 around one vertex (prisms over many-sided polygons fanned
// from a corner, nearly collinear points), crossed by a box or a cylinder.
Case gen_fan(Rng& r) {
  Case c;
  const int n = irand(r, 300, 1000);
  std::vector<Vec2> poly;
  if (coin(r)) {
    for (int i = 0; i < n; ++i) poly.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n)});
  } else {  // a very flat arc: points nearly collinear
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / (n - 1);
      poly.push_back({2 * t - 1, -1e-3 * 4 * t * (1 - t)});
    }
    poly.push_back({0, 1});
  }
  c.ops.push_back(prism(poly, 0, 1, coin(r, 0.3)));
  if (coin(r)) c.ops.push_back(box_mesh({0, -0.5, 0.5}, {1, 1, 1}, rotate(uni(r, 0, 90), Vec3::UnitZ(), {0, 0, 0})));
  else c.ops.push_back(cylinder_mesh(0.5, 0.25, 2, irand(r, 3, 64), rotate(uni(r, 0, 30), rand_dir(r), {0, 0, 0.5})));
  if (coin(r, 0.3)) c.ops.push_back(box_mesh({-1, -1e-3, -1}, {2, 1e-3, 3}));  // the arc's chord region
  return c;
}
// Disjoint operands, and operands far apart, plus an empty one sometimes.
Case gen_disjoint(Rng& r) {
  Case c;
  const int n = irand(r, 2, 5);
  for (int i = 0; i < n; ++i) c.ops.push_back(moved(random_primitive(r), Vec3(3.0 * i, coin(r) ? 0 : 1e-300, 0)));
  return c;
}
// General position: random primitives overlapping (the baseline).
Case gen_random(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) c.ops.push_back(random_primitive(r));
  return c;
}
// Chains: a start and 10-20 further operands; each step's three results are checked, one goes on.
Case gen_chain(Rng& r) {
  Case c;
  c.chain = true;
  c.ops.push_back(random_primitive(r));
  const int n = irand(r, 10, 20);
  for (int i = 0; i < n; ++i) {
    switch (irand(r, 0, 5)) {
      case 0: c.ops.push_back(gen_grid_mixed(r).ops[0]); break;
      case 1: c.ops.push_back(snapped(random_primitive(r), 0.25)); break;
      default: c.ops.push_back(random_primitive(r)); break;
    }
  }
  return c;
}
// Bad operands: open, flipped, non-manifold, self-intersecting, NaN / inf, index out of range,
// zero-area, duplicated triangles. Every op must throw wedge::Error naming that operand.
Case gen_bad(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) c.ops.push_back(random_primitive(r));
  const int bi = irand(r, 0, n - 1);
  Mesh& m = c.ops[bi];
  c.bad = true;
  c.bad_index = bi;
  const int kind = irand(r, 0, 9);
  c.note = std::to_string(kind);
  switch (kind) {
    case 0: m.triangles.pop_back(); if (!m.face_ids.empty()) m.face_ids.pop_back(); break;  // open
    case 1: m = flipped(m); break;                                                            // inside out
    case 2: { Mesh o = m; o = moved(o, Vec3(0.1, 0.05, 0.02)); m.append(o); break; }         // self-intersecting
    case 3: m.positions[irand(r, 0, static_cast<int>(m.positions.size()) - 1)].x() = NAN; break;
    case 4: m.positions[irand(r, 0, static_cast<int>(m.positions.size()) - 1)].y() = -INFINITY; break;
    case 5: m.triangles[0][1] = static_cast<std::uint32_t>(m.positions.size() + 5); break;
    case 6: { m.triangles.push_back(m.triangles[0]); if (!m.face_ids.empty()) m.face_ids.push_back(-1); break; }  // 3 at an edge
    case 7: { Mesh o = m; m.append(o); break; }  // two coincident shells
    case 8: { auto& t = m.triangles[0]; m.positions[t[1]] = m.positions[t[0]]; break; }  // collapsed edge
    default: { Mesh o = flipped(m); m.append(o); break; }  // a shell and its inside-out copy
  }
  return c;
}

// A grid case (boxes or mixed) turned as a whole by one inexact rotation: faces that were exactly
// flush are now flush within ulps (nearly coincident planes, nearly shared edges and vertices).
Case gen_grid_rot(Rng& r) {
  Case c = coin(r) ? gen_grid_boxes(r) : gen_grid_mixed(r);
  c.axis_boxes = false;
  const Mat4 t = rotate(uni(r, 0, 360), rand_dir(r), Vec3(uni(r, -2, 2), uni(r, -2, 2), uni(r, -2, 2)));
  for (auto& m : c.ops) m = xf(m, t);
  if (coin(r, 0.3)) {  // and one operand turned again by a hair
    auto& m = c.ops[irand(r, 0, static_cast<int>(c.ops.size()) - 1)];
    m = rot(m, uni(r, 1e-12, 1e-6), rand_dir(r), m.positions[0]);
  }
  return c;
}
// 3-10 prisms standing on the plane z = 0 with tops at z = 1 (or z = 0.5 / 2), each turned about
// the z axis (exact in z): exactly coplanar overlapping faces of many operands at once.
Case gen_coplanar_stack(Rng& r) {
  Case c;
  const int n = irand(r, 2, 10);
  for (int i = 0; i < n; ++i) {
    Mesh m;
    const double top = coin(r, 0.7) ? 1.0 : (coin(r) ? 0.5 : 2.0);
    if (coin(r)) m = box_mesh({-0.5, -0.5, 0}, {1, uni(r, 0.2, 1), top});
    else {
      std::vector<Vec2> poly;
      const int k = irand(r, 3, 8);
      for (int j = 0; j < k; ++j) poly.push_back({0.6 * std::cos(2 * M_PI * j / k), 0.6 * std::sin(2 * M_PI * j / k)});
      m = prism(poly, 0, top, coin(r));
    }
    const Vec2 d(uni(r, -0.4, 0.4), uni(r, -0.4, 0.4));
    const double a = coin(r, 0.2) ? 90.0 * irand(r, 0, 3) : uni(r, 0, 360);
    for (auto& p : m.positions) {  // a turn about z, z untouched
      const double ca = std::cos(a * M_PI / 180), sa = std::sin(a * M_PI / 180);
      p = Vec3(ca * p.x() - sa * p.y() + d.x(), sa * p.x() + ca * p.y() + d.y(), p.z());
    }
    if (coin(r, 0.2)) for (auto& p : m.positions) p.z() = -p.z();  // hangs below instead
    if (coin(r, 0.2)) m = flipped(m);
    c.ops.push_back(m);
  }
  // an even number of z flips turns a solid inside out; repair orientation by volume
  for (auto& m : c.ops)
    if (m.volume() < 0) m = flipped(m);
  return c;
}
// A result with touching shells (cubes sharing an edge or a vertex, made by the engine) crossed by
// another operand near the contact, in every op.
Case gen_nonmanifold_ops(Rng& r) {
  Case c;
  const Mesh a = box_mesh({0, 0, 0}, {1, 1, 1});
  const Mesh b = coin(r) ? box_mesh({1, 1, 0}, {1, 1, 1}) : box_mesh({1, 1, 1}, {1, 1, 1});
  Mesh u = boolean(BooleanOp::Union, {&a, &b}).mesh;
  const Mat4 t = coin(r) ? Mat4::Identity() : rotate(uni(r, 0, 360), rand_dir(r));
  u = xf(u, t);
  c.ops.push_back(u);
  const Vec3 at = apply_point(t, Vec3(1, 1, 1));
  switch (irand(r, 0, 3)) {
    case 0: c.ops.push_back(icosphere(at + rand_dir(r) * uni(r, 0, 0.3), uni(r, 0.1, 0.6), 80)); break;
    case 1: c.ops.push_back(box_mesh(at - Vec3(0.25, 0.25, 0.25), {0.5, 0.5, 0.5})); break;
    case 2: c.ops.push_back(cylinder_mesh(0.3, -1, 1, irand(r, 3, 8), translate(at) * rotate(uni(r, 0, 360), rand_dir(r)))); break;
    default: c.ops.push_back(box_mesh(at, {1, 1, 1})); break;  // a third cube at the contact point
  }
  return c;
}
// Near copies at higher resolution (rounding repair has more to do).
Case gen_hires_near(Rng& r) {
  Case c;
  Mesh a = coin(r) ? uv_sphere({0, 0, 0}, 1, irand(r, 1000, 4000)) : cylinder_mesh(1, -1, 1, irand(r, 64, 400));
  c.ops.push_back(a);
  switch (irand(r, 0, 3)) {
    case 0: c.ops.push_back(rot(a, std::pow(10.0, -uni(r, 6, 14)), rand_dir(r), {0, 0, 0})); break;
    case 1: c.ops.push_back(moved(a, rand_dir(r) * std::pow(10.0, -uni(r, 9, 15)))); break;
    case 2: c.ops.push_back(xf(a, reflect(rand_dir(r), {0, 0, 0}))); break;
    default: c.ops.push_back(xf(a, scale(Vec3(1, 1, 1) * (1 - std::pow(10.0, -uni(r, 8, 15)))))); break;
  }
  if (coin(r, 0.3)) c.ops.push_back(rot(a, uni(r, 1e-9, 1e-4), rand_dir(r), {0, 0, 0}));
  return c;
}

// Operands with cavities (an outer shell and an inside-out inner shell in one mesh), crossed by,
// inside, or exactly filling the cavity; sometimes a second cavity or an island inside it.
Case gen_hollow(Rng& r) {
  Case c;
  const bool boxy = coin(r);
  Mesh outer = boxy ? box_mesh({-2, -2, -2}, {4, 4, 4}) : icosphere({0, 0, 0}, 2, 320);
  Mesh inner = boxy ? box_mesh({-1, -1, -1}, {2, 2, 2}) : icosphere({0, 0, 0}, 1, coin(r) ? 80 : 320);
  if (!boxy && coin(r)) inner = xf(inner, rotate(uni(r, 0, 360), rand_dir(r)));
  Mesh a = outer;
  a.append(flipped(inner));
  if (coin(r, 0.3)) a.append(box_mesh({-0.5, -0.5, -0.5}, {1, 1, 1}));  // an island in the cavity
  c.ops.push_back(a);
  switch (irand(r, 0, 5)) {
    case 0: c.ops.push_back(inner); break;                                         // fills the cavity exactly
    case 1: c.ops.push_back(box_mesh({-0.5, -0.5, -0.5}, {1, 1, 1})); break;       // inside the cavity (or = island)
    case 2: c.ops.push_back(box_mesh({-3, -0.5, -0.5}, {6, 1, 1})); break;         // a bar through everything
    case 3: c.ops.push_back(box_mesh({-1, -1, -1}, {1, 1, 1})); break;             // flush in the cavity's corner
    case 4: c.ops.push_back(xf(a, rotate(uni(r, 0, 90), rand_dir(r)))); break;    // another hollow one
    default: c.ops.push_back(moved(inner, Vec3(std::ldexp(1.0, -irand(r, 30, 52)), 0, 0))); break;
  }
  if (coin(r, 0.3)) std::swap(c.ops[0], c.ops[1]);
  return c;
}
// Unreferenced vertices (allowed by Mesh) placed on the other operands' vertices, edges and faces,
// and an empty operand now and then.
Case gen_unused_verts(Rng& r) {
  Case c = coin(r) ? gen_touching(r) : gen_random(r);
  std::vector<Vec3> spots;
  for (auto& m : c.ops)
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &d = m.positions[t[2]];
      spots.push_back(a), spots.push_back((a + b) / 2), spots.push_back((a + b + d) / 3);
    }
  for (auto& m : c.ops)
    for (int k = irand(r, 1, 20); k > 0; --k) m.positions.push_back(spots[irand(r, 0, static_cast<int>(spots.size()) - 1)]);
  if (coin(r, 0.3)) c.ops.insert(c.ops.begin() + irand(r, 0, static_cast<int>(c.ops.size())), Mesh());
  return c;
}

// 3-10 copies of one primitive, each turned by its own tiny angle about its centre: many nearly
// coincident sheets in one n-ary pass (the work budget's territory; slow cases are reported).
Case gen_many_near(Rng& r) {
  Case c;
  Mesh a;
  switch (irand(r, 0, 2)) {
    case 0: a = icosphere({0, 0, 0}, 1, coin(r) ? 80 : 320); break;
    case 1: a = cylinder_mesh(1, -1, 1, irand(r, 3, 32)); break;
    default: a = box_mesh({-1, -1, -1}, {2, 2, 2}); break;
  }
  const int n = irand(r, 3, 10);
  c.ops.push_back(a);
  for (int i = 1; i < n; ++i) c.ops.push_back(rot(a, std::pow(10.0, -uni(r, 4, 12)), rand_dir(r), {0, 0, 0}));
  return c;
}

// A prism between two triangles (a0 b0 c0) and (a1 b1 c1), outward whatever their order.
Mesh prism6(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1, const Vec3& c1) {
  Mesh m;
  for (const Vec3& p : {a0, b0, c0, a1, b1, c1}) m.add_vertex(p);
  m.add_triangle(0, 2, 1), m.add_triangle(3, 4, 5);
  const int q[3][4] = {{0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
  for (auto& f : q) m.add_triangle(f[0], f[1], f[2]), m.add_triangle(f[0], f[2], f[3]);
  if (m.volume() < 0) m = flipped(m);
  return m;
}
// Operands that touch at one point only, exactly: an edge crossing an edge (a point inside both
// edges, a vertex of neither), a vertex on a face, a vertex inside an edge, apex to apex; the
// regularised union is non-manifold there and its shells must come back apart.
Case gen_point_contact(Rng& r) {
  Case c;
  const Mesh a = box_mesh({0, 0, 0}, {1, 1, 1});
  c.ops.push_back(a);
  const int n = irand(r, 1, 3);
  for (int i = 0; i < n; ++i) {
    const int kind = irand(r, 0, 3);
    c.note += std::to_string(kind);
    const double x = irand(r, 1, 3) * 0.25;
    Mesh b;
    if (kind == 0) {  // its edge along (0, 1, -1) crosses the cube's edge y = z = 1 at (x, 1, 1)
      const Vec3 p(x, 1, 1), e(0, 1, -1), u(-0.5, 1, 1), v(0.5, 1, 1);
      b = prism6(p - 0.5 * e, p - 0.5 * e + u, p - 0.5 * e + v, p + 0.5 * e, p + 0.5 * e + u, p + 0.5 * e + v);
    } else if (kind == 1) {  // a tetrahedron's vertex on the top face
      const Vec3 p(x, irand(r, 1, 3) * 0.25, 1);
      b = tetra(p, p + Vec3(-0.5, -0.5, 1), p + Vec3(0.5, -0.5, 1), p + Vec3(0, 0.5, 1));
    } else if (kind == 2) {  // a tetrahedron's vertex inside the edge y = z = 1
      const Vec3 p(x, 1, 1);
      b = tetra(p, p + Vec3(-0.25, 0.5, 0.5), p + Vec3(0.25, 0.5, 0.5), p + Vec3(0, 1, 0.25));
    } else {  // vertex to vertex: a tetrahedron on the corner (1, 1, 1)
      const Vec3 p(1, 1, 1);
      b = tetra(p, p + Vec3(1, 0.5, 0.5), p + Vec3(0.5, 1, 0.5), p + Vec3(0.5, 0.5, 1));
    }
    c.ops.push_back(b);
  }
  Mat4 t = Mat4::Identity();
  switch (irand(r, 0, 4)) {
    case 0: case 1: break;
    case 2: t = translate(Vec3(ir(r, -3, 3), ir(r, -3, 3), ir(r, -3, 3))) * reflect(Vec3::Unit(irand(r, 0, 2))); break;
    case 3: t = scale(Vec3(1, 1, 1) * std::ldexp(1.0, irand(r, -20, 20))); break;
    default: t = rotate(uni(r, 0, 360), rand_dir(r)); break;
  }
  for (auto& m : c.ops) m = xf(m, t);
  if (coin(r)) std::reverse(c.ops.begin(), c.ops.end());
  return c;
}

struct Gen {
  const char* name;
  std::function<Case(Rng&)> make;
};
const std::vector<Gen>& generators() {
  static const std::vector<Gen> g = {
      {"grid_boxes", gen_grid_boxes}, {"grid_mixed", gen_grid_mixed}, {"near_copy", gen_near_copy},
      {"touching", gen_touching},     {"identical", gen_identical},   {"nary_point", gen_nary_point},
      {"cyl_ico", gen_cyl_ico},       {"sliver", gen_sliver},         {"scale", gen_scale},
      {"fan", gen_fan},               {"disjoint", gen_disjoint},     {"random", gen_random},
      {"chain", gen_chain},           {"bad", gen_bad},               {"grid_rot", gen_grid_rot},
      {"coplanar_stack", gen_coplanar_stack}, {"nonmanifold_ops", gen_nonmanifold_ops}, {"hires_near", gen_hires_near},
      {"hollow", gen_hollow},         {"unused_verts", gen_unused_verts}, {"many_near", gen_many_near},
      {"point_contact", gen_point_contact}};
  return g;
}

// ---------------------------------------------------------------- running and checking
struct Run {
  bool ok = false;
  BooleanResult r;
  std::string error;
  BooleanStats st;
  double seconds = 0;
};

std::uint64_t bits_of(const Mesh& m) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&](std::uint64_t v) { h = (h ^ v) * 0x100000001b3ull; };
  for (const auto& q : m.positions)
    for (int k = 0; k < 3; ++k) {
      std::uint64_t u;
      std::memcpy(&u, &q[k], 8);
      mix(u);
    }
  for (const auto& t : m.triangles) mix(static_cast<std::uint64_t>(t[0]) << 42 ^ static_cast<std::uint64_t>(t[1]) << 21 ^ t[2]);
  return h;
}

Run run_boolean(BooleanOp op, const std::vector<const Mesh*>& ops) {
  save_operands(g_out + "/work/" + std::to_string(getpid()), op, ops);
  std::snprintf(g_sh->current, sizeof g_sh->current, "%s %s (%zu operands)", g_case.c_str(), op_word(op).c_str(), ops.size());
  Run run;
  ++g_sh->booleans[g_gen];
  const double t0 = now_s();
  g_sh->bool_start = t0;
  try {
    run.r = boolean(op, ops, &run.st);
    run.ok = true;
  } catch (const Error& e) {
    run.error = e.what();
  } catch (const std::exception& e) {
    run.error = std::string("NON-wedge::Error exception: ") + e.what();
  }
  g_sh->bool_start = 0;
  run.seconds = now_s() - t0;
  if (run.seconds > 2) {
    count(kSlow);
    std::size_t tris = 0;
    for (auto* m : ops) tris += m->triangles.size();
    std::printf("SLOW %s %s %.1fs operands=%zu triangles=%zu result=%zu %s\n", g_case.c_str(), op_word(op).c_str(),
                run.seconds, ops.size(), tris, run.ok ? run.r.mesh.triangles.size() : 0, run.ok ? "" : run.error.c_str());
    std::fflush(stdout);
  }
  return run;
}

// The mesh with every vertex whose triangles form k > 1 fans split into k vertices (same
// position); `pinched` gets the positions split.
Mesh split_fans(const Mesh& m, std::vector<Vec3>* pinched) {
  Mesh o = m;
  const std::size_t nv = m.positions.size();
  std::vector<std::vector<std::pair<std::uint32_t, std::size_t>>> around(nv);  // (corner k, triangle)
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) around[m.triangles[t][k]].push_back({static_cast<std::uint32_t>(k), t});
  for (std::size_t v = 0; v < nv; ++v) {
    auto& a = around[v];
    if (a.size() < 3) continue;
    // union-find over the wedges: wedge (b, c) joins the wedge whose b is this c
    std::map<std::uint32_t, std::size_t> by_b;
    for (std::size_t i = 0; i < a.size(); ++i) by_b[m.triangles[a[i].second][(a[i].first + 1) % 3]] = i;
    std::vector<std::size_t> par(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) par[i] = i;
    std::function<std::size_t(std::size_t)> find = [&](std::size_t x) { return par[x] == x ? x : par[x] = find(par[x]); };
    for (std::size_t i = 0; i < a.size(); ++i) {
      auto it = by_b.find(m.triangles[a[i].second][(a[i].first + 2) % 3]);
      if (it != by_b.end()) par[find(i)] = find(it->second);
    }
    std::map<std::size_t, std::uint32_t> root_index;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::size_t r = find(i);
      if (root_index.empty()) root_index[r] = static_cast<std::uint32_t>(v);
      if (!root_index.count(r)) {
        root_index[r] = static_cast<std::uint32_t>(o.positions.size());
        o.positions.push_back(m.positions[v]);
      }
      o.triangles[a[i].second][a[i].first] = root_index[r];
    }
    if (root_index.size() > 1 && pinched) pinched->push_back(m.positions[v]);
  }
  return o;
}

bool is_rounding_error(const std::string& e) { return e.find("rounded") != std::string::npos || e.find("rounding") != std::string::npos; }

// Classifies a boolean on valid operands; true when it produced a result that passed.
bool check_run(BooleanOp op, const std::vector<const Mesh*>& ops, Run& run) {
  if (!run.ok) {
    if (run.error.find("NON-wedge") == std::string::npos && is_rounding_error(run.error)) {
      count(kUnroundable);
      std::printf("UNROUNDABLE %s %s: %s\n", g_case.c_str(), op_word(op).c_str(), run.error.c_str());
      const std::string dir = g_out + "/unroundable/" + g_case + "_" + op_word(op);
      save_operands(dir, op, ops);
      std::ofstream(dir + "/README") << op_word(op) << ": " << run.error << "\n";
    } else if (run.error.find("budget") != std::string::npos) {
      count(kBudget);
    } else {
      record_failure(kError, op, ops, "error on valid operands: " + run.error);
    }
    return false;
  }
  const Mesh& m = run.r.mesh;
  std::string d = result_defect(m);
  if (d.find("is not positive") != std::string::npos && exact_volume(m) > 0) {
    // The support's volume is summed in long double: on results of slivers (shells 1e-28 in
    // volume) its sign can be wrong. Exactly positive: check what result_defect stopped before.
    std::string where;
    d = exact_self_intersects(m, &where) ? "self-intersection: " + where : "";
  }
  if (d.empty()) {
    if (run.r.operand.size() != m.triangles.size() || run.r.source.size() != m.triangles.size())
      d = "operand/source arrays not one per triangle";
    else
      for (std::size_t t = 0; t < m.triangles.size() && d.empty(); ++t) {
        const int o = run.r.operand[t];
        if (o < 0 || o >= static_cast<int>(ops.size()) || run.r.source[t] < 0 ||
            run.r.source[t] >= static_cast<int>(ops[o]->triangles.size()))
          d = "provenance out of range at triangle " + std::to_string(t);
      }
  }
  if (!d.empty() && d.find("non-manifold vertex") != std::string::npos) {
    // A vertex index shared by two fans: is that all, and were the points coincident vertices of
    // an operand (touching shells passed through: bug 1) or made by this boolean?
    std::vector<Vec3> pinched;
    const Mesh split = split_fans(m, &pinched);
    if (result_defect(split).empty()) {
      bool merged = true;
      for (const Vec3& q : pinched) {
        bool dup = false;
        for (auto* o : ops) {
          int n = 0;
          for (const auto& p : o->positions) n += p == q;
          dup |= n > 1;
        }
        merged &= dup;
      }
      record_failure(merged ? kPinchMerged : kPinchNew, op, ops,
                     std::to_string(pinched.size()) + " pinched vertices (" + std::to_string(m.triangles.size()) +
                         " triangles; valid once split): " + d);
      return false;
    }
  }
  if (!d.empty()) {
    record_failure(kInvalid, op, ops, "invalid result (" + std::to_string(m.triangles.size()) + " triangles): " + d);
    return false;
  }
  const std::string own = mesh_solid_defect(m, "result");
  if (!own.empty()) {
    record_failure(kInvalid, op, ops, "CGAL finds the result valid but mesh_solid_defect says: " + own);
    return false;
  }
  return true;
}

// Volume of a mesh, scaled back by 2^-pow2 per length (exact where the coordinates stay normal).
double vol(const Mesh& m, int pow2) {
  if (pow2 == 0) return exact_volume(m);
  return exact_volume(scaled_pow2(m, -pow2));
}

void compare(const char* what, double got, double want, double tol, BooleanOp op, const std::vector<const Mesh*>& ops,
             Outcome o = kVolume) {
  if (std::isfinite(got) && std::isfinite(want) && std::abs(got - want) <= tol) return;
  char buf[400];
  std::snprintf(buf, sizeof buf, "%s: %.17g, expected %.17g (diff %.3g, tolerance %.3g)", what, got, want, got - want, tol);
  record_failure(o, op, ops, buf);
}

int g_threads_check_every = 8;
std::unique_ptr<tbb::global_control> g_one;  // the child's 1-thread limit

// CGAL's corefinement in a forked process: it crashes on some of these inputs (a CGAL problem,
// not the engine's), which must not end the case. ok false when it refused or crashed.
int shells(const Mesh& m) {
  std::vector<std::uint32_t> par(m.positions.size());
  for (std::uint32_t i = 0; i < par.size(); ++i) par[i] = i;
  std::function<std::uint32_t(std::uint32_t)> find = [&](std::uint32_t x) { return par[x] == x ? x : par[x] = find(par[x]); };
  for (const auto& t : m.triangles) par[find(t[0])] = find(t[1]), par[find(t[1])] = find(t[2]);
  std::vector<std::uint32_t> roots;
  for (const auto& t : m.triangles) roots.push_back(find(t[0]));
  std::sort(roots.begin(), roots.end());
  return static_cast<int>(std::unique(roots.begin(), roots.end()) - roots.begin());
}

bool has_coincident_vertices(const Mesh& m) {
  std::vector<Vec3> p = m.positions;
  std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
    return a.x() != b.x() ? a.x() < b.x() : a.y() != b.y() ? a.y() < b.y() : a.z() < b.z();
  });
  return std::adjacent_find(p.begin(), p.end()) != p.end();
}

OracleResult oracle_safe(BooleanOp op, const std::vector<const Mesh*>& ops) {
  int fd[2];
  OracleResult o;
  // Touching shells (coincident vertices) make CGAL's corefinement wrong or crash: no reference.
  // So do operands of several shells (cavities: CGAL's result was off by the cavity's volume).
  for (auto* m : ops)
    if (has_coincident_vertices(*m) || shells(*m) > 1) return o;
  if (pipe(fd) != 0) return o;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    OracleResult r = ops.size() == 2 ? oracle_boolean(op, *ops[0], *ops[1]) : oracle_nary(op, ops);
    double msg[2] = {r.ok ? 1.0 : 0.0, r.volume};
    if (write(fd[1], msg, sizeof msg) != sizeof msg) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  double msg[2] = {0, 0};
  const bool got = read(fd[0], msg, sizeof msg) == sizeof msg;
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!got || !WIFEXITED(status)) {
    std::printf("ORACLE-CRASH %s %s\n", g_case.c_str(), op_word(op).c_str());
    return o;
  }
  o.ok = msg[0] == 1.0;
  o.volume = msg[1];
  return o;
}

// The three ops on one set of operands, with the checks across them.
void run_set(const std::vector<const Mesh*>& ops, const Case& c, std::uint64_t seed, BooleanResult* keep = nullptr,
             BooleanOp keep_op = BooleanOp::Union) {
  const int p2 = c.pow2;
  double vs = 0;
  std::vector<double> vin;
  for (auto* m : ops) vin.push_back(vol(*m, p2)), vs += std::abs(vin.back());
  const double reach = reach_of(ops) * (p2 ? std::ldexp(1.0, -p2) : 1.0);
  double area = 0;
  for (auto* m : ops) area += (p2 ? scaled_pow2(*m, -p2) : *m).area();
  const double ulp = reach > 0 ? std::ldexp(1.0, std::ilogb(reach) - 52) : 0;
  const double tol = 1e-9 * vs + 256 * area * ulp;
  double v[3];
  bool have[3] = {false, false, false};
  const BooleanOp all[3] = {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference};
  for (int k = 0; k < 3; ++k) {
    Run run = run_boolean(all[k], ops);
    if (!check_run(all[k], ops, run)) continue;
    count(kOk);
    have[k] = true;
    v[k] = vol(run.r.mesh, p2);
    if (keep && all[k] == keep_op) *keep = run.r;
    // Same bits at 2 threads, now and then.
    if (seed % g_threads_check_every == 0 && k == static_cast<int>(seed / g_threads_check_every % 3)) {
      g_one.reset();  // (TBB takes the smallest of the live limits)
      Run again;
      {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        again = run_boolean(all[k], ops);
      }
      g_one = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
      if (!again.ok || bits_of(again.r.mesh) != bits_of(run.r.mesh))
        record_failure(kBitsDiffer, all[k], ops, again.ok ? "result bits differ at 2 threads" : "2 threads: " + again.error);
    }
    // Small cases: CGAL's exact corefinement as the reference (it refuses non-manifold results).
    std::size_t tris = 0;
    for (auto* m : ops) tris += m->triangles.size();
    if (tris <= 3000 && p2 == 0) {
      OracleResult o;
      std::snprintf(g_sh->current, sizeof g_sh->current, "%s oracle %s", g_case.c_str(), op_word(all[k]).c_str());
      if (ops.size() <= 5) o = oracle_safe(all[k], ops);
      if (o.ok && std::isfinite(vs) && o.volume >= -tol) compare((std::string("volume vs CGAL's ") + op_word(all[k])).c_str(), v[k], o.volume, tol, all[k], ops, kOracle);
    }
  }
  if (!std::isfinite(vs) || !std::isfinite(tol)) return;  // volumes overflow (a huge operand): validity only
  if (c.axis_boxes && p2 == 0) {
    if (have[0]) compare("union volume vs boxes_volume", v[0], boxes_volume(BooleanOp::Union, c.boxes), tol, BooleanOp::Union, ops);
    if (have[2]) compare("difference volume vs boxes_volume", v[2], boxes_volume(BooleanOp::Difference, c.boxes), tol, BooleanOp::Difference, ops);
  }
  double vmin = 1e300, vmax = 0, vsum = 0;
  for (double x : vin) vmin = std::min(vmin, x), vmax = std::max(vmax, x), vsum += x;
  if (have[0] && (v[0] < vmax - tol || v[0] > vsum + tol)) compare("union volume outside [max, sum]", v[0], vmax, tol, BooleanOp::Union, ops);
  if (have[1] && (v[1] < -tol || v[1] > vmin + tol)) compare("intersection volume outside [0, min]", v[1], vmin, tol, BooleanOp::Intersection, ops);
  if (have[2] && (v[2] < -tol || v[2] > vin[0] + tol)) compare("difference volume outside [0, vol A]", v[2], vin[0], tol, BooleanOp::Difference, ops);
  if (ops.size() == 2) {
    if (have[0] && have[1]) compare("vol(AuB)+vol(AnB) vs volA+volB", v[0] + v[1], vin[0] + vin[1], tol, BooleanOp::Union, ops);
    if (have[1] && have[2]) compare("vol(A-B) vs volA-vol(AnB)", v[2], vin[0] - v[1], tol, BooleanOp::Difference, ops);
  } else if (have[2]) {
    // first minus the rest = first minus (first n union(rest)), all by the engine, in separate booleans
    std::vector<const Mesh*> rest(ops.begin() + 1, ops.end());
    Run u = run_boolean(BooleanOp::Union, rest);
    if (check_run(BooleanOp::Union, rest, u)) {
      Run x = run_boolean(BooleanOp::Intersection, {ops[0], &u.r.mesh});
      if (check_run(BooleanOp::Intersection, {ops[0], &u.r.mesh}, x))
        compare("n-ary vol(A - rest) vs volA - vol(A n union(rest))", v[2], vin[0] - vol(x.r.mesh, p2), tol,
                BooleanOp::Difference, ops);
    }
    // n-ary union in one pass vs folded pairwise
    if (have[0]) {
      Mesh cur = *ops[0];
      bool fine = true;
      for (std::size_t i = 1; i < ops.size() && fine; ++i) {
        Run s = run_boolean(BooleanOp::Union, {&cur, ops[i]});
        fine = check_run(BooleanOp::Union, {&cur, ops[i]}, s);
        if (fine) cur = s.r.mesh;
      }
      if (fine) compare("n-ary union vs pairwise fold", v[0], vol(cur, p2), tol * ops.size(), BooleanOp::Union, ops);
    }
  }
}

void run_case(const Case& c, std::uint64_t seed, Rng& r) {
  std::vector<const Mesh*> ops;
  for (auto& m : c.ops) ops.push_back(&m);
  if (c.bad) {
    for (BooleanOp op : {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference}) {
      Run run = run_boolean(op, ops);
      if (run.ok && c.note == "8" && result_defect(run.r.mesh).empty()) {
        count(kOk);  // a collapsed edge is mended (csg/boolean_soup.cpp), by design: valid result is fine
        continue;
      }
      if (run.ok) {
        record_failure(kBadAccepted, op, ops, "bad operand " + std::to_string(c.bad_index + 1) + " (kind " + c.note +
                                                  ") accepted; result defect: '" + result_defect(run.r.mesh) + "'");
        continue;
      }
      const std::string want = ops.size() == 2 ? (c.bad_index == 0 ? "first operand" : "second operand")
                                               : "operand " + std::to_string(c.bad_index + 1);
      if (run.error.find("NON-wedge") != std::string::npos || run.error.find(want) == std::string::npos)
        record_failure(kBadMsg, op, ops, "bad operand " + std::to_string(c.bad_index + 1) + " (kind " + c.note +
                                             "): message does not name '" + want + "': " + run.error);
      else
        count(kOk);
    }
    return;
  }
  // Operands must be valid for the promise to apply; an invalid one must be refused.
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const std::string d = result_defect(*ops[i]);
    if (!d.empty()) {
      count(kSkipped);
      Run run = run_boolean(BooleanOp::Union, ops);
      if (run.ok) {
        const std::string rd = result_defect(run.r.mesh);
        if (!rd.empty())
          record_failure(kBadAccepted, BooleanOp::Union, ops,
                         "operand " + std::to_string(i + 1) + " invalid (" + d + ") accepted, result invalid: " + rd);
        else
          std::printf("NOTE %s operand %zu invalid per CGAL (%s) but accepted, result valid\n", g_case.c_str(), i + 1, d.c_str());
      }
      return;
    }
  }
  if (!c.chain) {
    run_set(ops, c, seed);
    return;
  }
  Mesh cur = c.ops[0];
  for (std::size_t i = 1; i < c.ops.size(); ++i) {
    Mesh other = c.ops[i];
    // Sometimes the other operand is the current result itself, moved a little (nearly coincident sheets).
    if (coin(r, 0.2) && !cur.empty()) {
      Vec3 ctr = Vec3::Zero();
      for (auto& p : cur.positions) ctr += p;
      ctr /= cur.positions.size();
      const int how = irand(r, 0, 2);
      other = how == 0 ? rot(cur, uni(r, 1e-9, 1e-3), rand_dir(r), ctr)
              : how == 1 ? moved(cur, rand_dir(r) * uni(r, 1e-12, 1e-3))
                         : xf(cur, reflect(rand_dir(r), ctr));
      if (!result_defect(other).empty()) other = c.ops[i];
    }
    const BooleanOp next = static_cast<BooleanOp>(irand(r, 0, 2));
    BooleanResult kept;
    kept.mesh.positions.push_back(Vec3(NAN, 0, 0));  // marks "not produced"
    std::snprintf(g_sh->current, sizeof g_sh->current, "%s step %zu", g_case.c_str(), i);
    run_set({&cur, &other}, c, seed, &kept, next);
    if (kept.mesh.positions.size() == 1 && std::isnan(kept.mesh.positions[0].x())) return;  // failed: stop the chain
    if (kept.mesh.empty()) cur = c.ops[i];
    else cur = kept.mesh;
    if (cur.triangles.size() > 60000) return;
  }
}

// ---------------------------------------------------------------- replay
// Options of --replay: scale the operands by 2^pow2 first; crop each operand to the cube of half
// side `crop_r` about `crop_c` (an intersection by the engine, checked) and save the cropped
// operands to `save` (a smaller reproducer); another op.
int g_pow2 = 0;
double g_crop_r = 0;
Vec3 g_crop_c(0, 0, 0);
std::string g_save, g_opw;

int replay(const std::string& dir) {
  std::string opw;
  std::ifstream(dir + "/op.txt") >> opw;
  if (!g_opw.empty()) opw = g_opw;
  const BooleanOp op = opw == "union" ? BooleanOp::Union : opw == "intersection" ? BooleanOp::Intersection : BooleanOp::Difference;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".off") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  std::vector<Mesh> ms;
  for (auto& f : files) ms.push_back(read_off(f));
  if (g_pow2)
    for (auto& m : ms) m = scaled_pow2(m, g_pow2);
  if (g_crop_r > 0) {
    const Mesh box = box_mesh(g_crop_c - Vec3(1, 1, 1) * g_crop_r, Vec3(2, 2, 2) * g_crop_r);
    for (auto& m : ms) {
      BooleanResult c = boolean(BooleanOp::Intersection, {&m, &box});
      m = c.mesh;
      m.face_ids.clear();
    }
  }
  if (!g_save.empty()) {
    std::vector<const Mesh*> p;
    for (auto& m : ms) p.push_back(&m);
    save_operands(g_save, opw == "union" ? BooleanOp::Union : opw == "intersection" ? BooleanOp::Intersection : BooleanOp::Difference, p);

  }
  std::vector<const Mesh*> ops;
  for (auto& m : ms) ops.push_back(&m);
  for (std::size_t i = 0; i < ms.size(); ++i)
    std::printf("operand %zu: %zu triangles, exact volume %.17g, defect '%s'\n", i + 1, ms[i].triangles.size(),
                exact_volume(ms[i]), result_defect(ms[i]).c_str());
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const double t0 = now_s();
  try {
    BooleanStats st;
    BooleanResult r = boolean(op, ops, &st);
    std::printf("%s: %.3f s, %zu triangles, welded %zu, reorders %zu, resolutions %zu, collapses %zu, flat shells %zu\n",
                opw.c_str(), now_s() - t0, r.mesh.triangles.size(), st.welded, st.reorders, st.resolutions, st.collapses,
                st.flat_shells);
    std::string where;
    const bool crosses = exact_self_intersects(r.mesh, &where);
    std::printf("result defect: '%s'\nclosed_manifold_outward: '%s'\nexact self-intersection: %s %s\n"
                "mesh_solid_defect: '%s'\nexact volume %.17g\n", result_defect(r.mesh).c_str(),
                closed_manifold_outward(r.mesh).c_str(), crosses ? "YES" : "no", where.c_str(),
                mesh_solid_defect(r.mesh, "result").c_str(), exact_volume(r.mesh));
    write_off((g_save.empty() ? dir : g_save) + "/result.off.out", r.mesh);
  } catch (const Error& e) {
    std::printf("%s: wedge::Error after %.3f s: %s\n", opw.c_str(), now_s() - t0, e.what());
  }
  // (CGAL's corefinement of many nearly coincident operands can take many minutes: 5 at most.)
  OracleResult o = ops.size() <= 5 ? oracle_safe(op, ops) : OracleResult{};
  std::printf("CGAL: %s volume %.17g\n", o.ok ? "ok" : "refused/crashed/skipped (touching shells, > 5 operands)", o.volume);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> gens;
  std::uint64_t seed0 = 1;
  long cases = 1000000;
  double minutes = 10;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--pow2") g_pow2 = std::stoi(next());
    else if (a == "--crop") {
      g_crop_c.x() = std::stod(next()), g_crop_c.y() = std::stod(next()), g_crop_c.z() = std::stod(next());
      g_crop_r = std::stod(next());
    } else if (a == "--save") g_save = next();
    else if (a == "--op") g_opw = next();
    else if (a == "--replay") return replay(next());
    else if (a == "--list") {
      for (auto& g : generators()) std::printf("%s\n", g.name);
      return 0;
    }
    else if (a == "--gen") {
      std::stringstream ss(next());
      for (std::string s; std::getline(ss, s, ',');) gens.push_back(s);
    } else if (a == "--seed") seed0 = std::stoull(next());
    else if (a == "--cases") cases = std::stol(next());
    else if (a == "--minutes") minutes = std::stod(next());
    else if (a == "--out") g_out = next();
    else if (a == "--hang") g_hang = std::stod(next());
    else if (a == "--threads-every") g_threads_check_every = std::stoi(next());
    else {
      std::fprintf(stderr, "unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  std::vector<int> chosen;
  for (int i = 0; i < static_cast<int>(generators().size()); ++i)
    if (gens.empty() || std::find(gens.begin(), gens.end(), generators()[i].name) != gens.end()) chosen.push_back(i);
  if (chosen.empty()) return 2;
  fs::create_directories(g_out + "/fail");
  fs::create_directories(g_out + "/work");
  g_sh = static_cast<Shared*>(mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  std::memset(g_sh, 0, sizeof(Shared));
  const double end = now_s() + 60 * minutes;
  long done = 0;
  for (std::uint64_t seed = seed0; done < cases && now_s() < end; ++seed) {
    for (int gi : chosen) {
      if (done >= cases || now_s() >= end) break;
      ++done;
      g_gen = gi;
      g_case = std::string(generators()[gi].name) + "_" + std::to_string(seed);
      std::fflush(stdout);
      const pid_t pid = fork();
      if (pid == 0) {
        g_one = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
        Rng r(seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(gi) * 1000003ull);
        Case c;
        try {
          c = generators()[gi].make(r);
        } catch (const std::exception& e) {
          std::printf("GENERATOR %s threw: %s\n", g_case.c_str(), e.what());
          std::fflush(stdout);
          _exit(0);
        }
        run_case(c, seed, r);
        std::fflush(stdout);
        fs::remove_all(g_out + "/work/" + std::to_string(getpid()));
        _exit(0);
      }
      const double case_start = now_s();
      int status = 0;
      for (;;) {
        const pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid) break;
        const double bs = g_sh->bool_start;
        const double t = now_s();
        if ((bs > 0 && t - bs > g_hang) || t - case_start > 20 * g_hang) {
          kill(pid, SIGKILL);
          waitpid(pid, &status, 0);
          ++g_sh->outcome[gi][kHang];
          ++g_sh->failures;
          const std::string dir = g_out + "/fail/" + g_case + "_hang";
          fs::rename(g_out + "/work/" + std::to_string(pid), dir);
          std::ofstream(dir + "/README") << "hang: " << g_sh->current << " ran over " << g_hang << " s ("
                                         << (bs > 0 ? "in boolean" : "case total") << ")\nrun: fuzz_boolean --replay " << dir << "\n";
          std::printf("FAIL %s hang: %s\n", g_case.c_str(), g_sh->current);
          status = 0;
          break;
        }
        usleep(20000);
      }
      if (WIFSIGNALED(status) || (WIFEXITED(status) && WEXITSTATUS(status) != 0)) {
        ++g_sh->outcome[gi][kCrash];
        ++g_sh->failures;
        const std::string dir = g_out + "/fail/" + g_case + "_crash";
        std::error_code ec;
        fs::rename(g_out + "/work/" + std::to_string(pid), dir, ec);
        std::ofstream(dir + "/README") << "crash: " << (WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "exit code")
                                       << " " << (WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status)) << " during "
                                       << g_sh->current << "\nrun: fuzz_boolean --replay " << dir << "\n";
        std::printf("FAIL %s crash (%s) during %s\n", g_case.c_str(),
                    WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "nonzero exit", g_sh->current);
      }
      std::fflush(stdout);
    }
  }
  std::printf("\n%-12s %8s", "generator", "booleans");
  for (int o = 0; o < kOutcomes; ++o) std::printf(" %s", kOutcomeName[o]);
  std::printf("\n");
  for (int gi : chosen) {
    std::printf("%-12s %8d", generators()[gi].name, g_sh->booleans[gi]);
    for (int o = 0; o < kOutcomes; ++o) std::printf(" %d", g_sh->outcome[gi][o]);
    std::printf("\n");
  }
  std::printf("cases %ld, failures %d\n", done, g_sh->failures);
  return 0;
}
