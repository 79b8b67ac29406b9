// The boolean engine at extreme scales (issue 11: "exact on every double input"): the same
// configurations at sizes from 1e-150 to 1e150, where products of coordinates underflow to
// subnormals or overflow to infinity, must give the result they give at size 1, scaled; and
// near-degenerate configurations (slivers, faces turned by a hair, points an ulp apart) must stay
// exact there too. Every result is checked closed, 2-manifold, outward and free of
// self-intersections (exactly), and its volume against the one at size 1 (itself checked against
// CGAL's exact corefinement or a closed form).
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "csg/boolean.h"
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

using namespace wedge;
using namespace wedge::testing;

namespace {

const BooleanOp kOps[] = {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference};

// m with every coordinate times s (exact when s is a power of two and nothing leaves the normal range).
Mesh scaled(Mesh m, double s) {
  for (Point3& p : m.positions) p *= s;
  return m;
}

// The volume of m measured at size 1: m scaled by 1 / s first (a volume of 1e-450 is not a double).
double unit_volume(const Mesh& m, double s) { return exact_volume(scaled(m, 1 / s)); }

void require_valid(const Mesh& m) {
  // The checks judge the mesh at size 1 where its own volume would under- or overflow; scaling by
  // a power of two keeps every orientation and intersection as it is.
  const double s = std::exp2(std::round(std::log2(std::max(1e-300, m.bounds().diagonal()))));
  const Mesh unit = m.empty() ? m : scaled(m, 1 / s);
  const std::string defect = closed_manifold_outward(unit);
  INFO(defect);
  REQUIRE(defect.empty());
  std::string where;
  const bool crossing = exact_self_intersects(m, &where);
  INFO(where);
  REQUIRE_FALSE(crossing);
}

// Sizes from about 1e-150 to 1e150: powers of ten (scaling rounds) and of two (scaling is exact).
std::vector<double> ladder() {
  std::vector<double> s;
  for (int e = -150; e <= 150; e += 10) s.push_back(std::pow(10.0, e));
  for (int e = -498; e <= 498; e += 83) s.push_back(std::ldexp(1.0, e));
  return s;
}

std::string name(double s) {
  std::ostringstream o;
  o.precision(3);
  o << "size " << s;
  return o.str();
}

}  // namespace

TEST_CASE("boolean scale: a box and a sphere at sizes 1e-150 .. 1e150 give the size-1 result, scaled", "[boolean]") {
  const Mesh box1 = box_mesh({0, 0, 0}, {1, 1, 1});
  const Mesh ball1 = uv_sphere({0, 0, 0}, 1, 800);
  double want[3];
  for (int o = 0; o < 3; ++o) {
    const BooleanResult r = boolean(kOps[o], {&box1, &ball1});
    require_valid(r.mesh);
    const OracleResult oracle = oracle_boolean(kOps[o], box1, ball1);
    REQUIRE(oracle.ok);
    want[o] = exact_volume(r.mesh);
    REQUIRE(want[o] == Approx(oracle.volume).epsilon(1e-12));
  }
  for (double s : ladder()) {
    const Mesh box = scaled(box1, s), ball = scaled(ball1, s);
    for (int o = 0; o < 3; ++o) {
      INFO(name(s) << ", " << boolean_op_name(kOps[o]));
      const BooleanResult r = boolean(kOps[o], {&box, &ball});
      require_valid(r.mesh);
      CHECK(unit_volume(r.mesh, s) == Approx(want[o]).epsilon(1e-9));
    }
  }
}
