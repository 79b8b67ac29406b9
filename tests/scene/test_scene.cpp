// Scenes from C++ (scene/scene.h): inheritance of transforms by the depth-first traversal, sharing
// by instances against copies, arrays, the instance table, materials reaching parts, the picture,
// and the errors. Expected values are worked out by hand from the transforms.
#include <catch2/catch.hpp>

#include <cmath>

#include "brep/brep.h"
#include "csg/boolean.h"
#include "csg/brep_leaf.h"
#include "scene/scene.h"

using namespace wedge;

namespace {
Solid block(double x, double y, double z) { return brep_solid(box(Vec3(x, y, z))); }
void check_box(const Box3& b, const Vec3& lo, const Vec3& hi) {
  for (int k = 0; k < 3; ++k) {
    CHECK(b.min[k] == Approx(lo[k]).margin(1e-12));
    CHECK(b.max[k] == Approx(hi[k]).margin(1e-12));
  }
}
}  // namespace

TEST_CASE("a part is placed by M_world = M_parent * M_local", "[scene]") {
  auto root = scene::group(translate(Vec3(10, 0, 0)), "root");
  auto arm = scene::group(rotate_z(90), "arm");
  scene::add(*root, arm);
  scene::add(*arm, scene::part(block(1, 2, 3)));
  // The 1 x 2 x 3 block turned a quarter about z lies in x -2..0, y 0..1; then moved by 10 in x.
  check_box(scene::bounds(*root, Tolerance{}), Vec3(8, 0, 0), Vec3(10, 1, 3));
  const auto rows = scene::instance_table(*root);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].symbol == "arm");
  CHECK(rows[0].path == "root/arm");
  CHECK(rows[0].rotation.z() == Approx(90));
  CHECK(rows[0].translation.x() == Approx(10));
  // Changing a group's transform moves what is under it.
  arm->transform = translate(Vec3(0, 0, 5));
  check_box(scene::bounds(*root, Tolerance{}), Vec3(10, 0, 5), Vec3(11, 2, 8));
}

TEST_CASE("an instance shares its prototype, a copy does not", "[scene]") {
  auto proto = scene::group("finger");
  scene::add(*proto, scene::part(block(1, 1, 1)));
  auto shared = scene::instance(proto, translate(Vec3(0, 5, 0)));
  auto copied = scene::copy(proto);
  scene::add(*proto, scene::part(block(1, 1, 1).transformed(translate(Vec3(0, 0, 4)))));
  check_box(scene::bounds(*shared, Tolerance{}), Vec3(0, 5, 0), Vec3(1, 6, 5));  // sees the new part
  check_box(scene::bounds(*copied, Tolerance{}), Vec3(0, 0, 0), Vec3(1, 1, 1));  // does not
  CHECK(scene::flatten(*shared).size() == 2);
  CHECK(scene::flatten(*copied).size() == 1);
  // Every instance's leaves are the prototype's leaves: one object, several placements.
  auto pair = scene::group();
  scene::add(*pair, scene::instance(proto, translate(Vec3(-2, 0, 0))));
  scene::add(*pair, scene::instance(proto, translate(Vec3(2, 0, 0))));
  const auto occ = scene::flatten(*pair);
  REQUIRE(occ.size() == 4);
  CHECK(occ[0].leaf == occ[2].leaf);
  CHECK(occ[1].leaf == occ[3].leaf);
  CHECK(occ[0].world(0, 3) == -2);
  CHECK(occ[2].world(0, 3) == 2);
}

TEST_CASE("array and radial_array place their instances by hand-worked transforms", "[scene]") {
  auto row = scene::array(scene::part(block(1, 1, 1)), 5, Vec3(2, 0, 0));
  check_box(scene::bounds(*row, Tolerance{}), Vec3(0, 0, 0), Vec3(9, 1, 1));
  auto ring = scene::radial_array(scene::part(brep_solid(box(Vec3(0.2, 0.2, 0.2), Point3(-0.1, -0.1, -0.1)))), 4, 5);
  const auto rows = scene::instance_table(*ring);
  REQUIRE(rows.size() == 4);
  const double want[4][3] = {{5, 0, 0}, {0, 5, 90}, {-5, 0, 180}, {0, -5, -90}};
  for (int k = 0; k < 4; ++k) {
    CHECK(rows[std::size_t(k)].translation.x() == Approx(want[k][0]).margin(1e-12));
    CHECK(rows[std::size_t(k)].translation.y() == Approx(want[k][1]).margin(1e-12));
    CHECK(std::abs(rows[std::size_t(k)].rotation.z()) == Approx(std::abs(want[k][2])).margin(1e-9));
  }
  // Half a turn with both ends used: 0, 90, 180 degrees.
  auto fan = scene::radial_array(scene::part(block(1, 1, 1)), 3, 2, Vec3(0, 0, 1), Point3(0, 0, 0), 180);
  const auto fan_rows = scene::instance_table(*fan);
  CHECK(fan_rows[1].rotation.z() == Approx(90));
  CHECK(fan_rows[2].translation.x() == Approx(-2));
}

TEST_CASE("the instance table splits a mirror and a scale, and flags a shear", "[scene]") {
  auto root = scene::group();
  scene::add(*root, scene::instance(scene::part(block(1, 1, 1)), scale(Vec3(-2, 3, 4))));
  Mat4 shear = Mat4::Identity();
  shear(0, 1) = 0.5;
  scene::add(*root, scene::instance(scene::part(block(1, 1, 1)), shear));
  const auto rows = scene::instance_table(*root);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].scale.x() == Approx(-2));
  CHECK(rows[0].scale.y() == Approx(3));
  CHECK(rows[0].scale.z() == Approx(4));
  CHECK_FALSE(rows[0].shear);
  CHECK(rows[1].shear);
}

TEST_CASE("a group's material reaches the parts without one, and the picture shows it", "[scene]") {
  render::Material red;
  red.ambient = red.diffuse = render::Vec4f(1, 0, 0, 1);
  render::Material blue;
  blue.ambient = blue.diffuse = render::Vec4f(0, 0, 1, 1);
  auto root = scene::group();
  root->material = red;
  scene::add(*root, scene::part(brep_solid(box(Vec3(1, 1, 1), Point3(-0.5, -0.5, -0.5)))));                 // red, from the group
  scene::add(*root, scene::instance(scene::part(brep_solid(box(Vec3(1, 1, 1), Point3(-0.5, -0.5, -0.5))), blue),  // its own blue
                                    translate(Vec3(3, 0, 0))));
  const auto occ = scene::flatten(*root);
  CHECK(occ[0].material.diffuse == red.diffuse);
  CHECK(occ[1].material.diffuse == blue.diffuse);
  render::RenderOptions ro;
  ro.width = 80, ro.height = 40;
  ro.camera = render::named_view("front", scene::bounds(*root, Tolerance{}));
  const render::Image im = scene::picture(*root, ro, Tolerance{});
  // The front view fits x -0.5..3.5 across the image: the red block's middle at a quarter of the
  // width (x = 0 is 1/8 in, then the window's margin), the blue one's towards the right.
  auto at = [&](double fx) { return im.pixel(int(fx * ro.width), ro.height / 2); };
  const auto left = at(0.2), right = at(0.8), corner = im.pixel(0, 0);
  CHECK(int(left[0]) > 100);
  CHECK(int(left[2]) < 30);
  CHECK(int(right[2]) > 100);
  CHECK(int(right[0]) < 30);
  CHECK(int(corner[0]) == 255);  // the white background
  CHECK(int(corner[2]) == 255);
}

TEST_CASE("a boolean part is drawn in the materials of the solids its faces came from", "[scene]") {
  // [0,2]^3 minus the same block moved 1 along x: [0,1] x [0,2] x [0,2]. Its cut face x = 1
  // (area 4) comes from the second block, the other five (4 + 2 + 2 + 2 + 2 = 12) from the first.
  const Solid a = block(2, 2, 2).tagged(0), b = block(2, 2, 2).transformed(translate(Vec3(1, 0, 0))).tagged(1);
  auto root = scene::group();
  scene::add(*root, scene::instance(scene::part(Solid::boolean(BooleanOp::Difference, {a, b})), translate(Vec3(5, 0, 0))));
  render::Material red, blue;
  red.diffuse = render::Vec4f(1, 0, 0, 1);
  blue.diffuse = render::Vec4f(0, 0, 1, 1);
  const scene::TagMaterial by_tag = [&](int tag) -> std::optional<scene::OwnMaterial> {
    return scene::OwnMaterial{tag == 0 ? red : blue, nullptr};
  };
  const scene::Drawable d = scene::draw_items(*root, Tolerance{}, {}, by_tag);
  REQUIRE(d.items.size() == 2);
  double red_area = 0, blue_area = 0;
  for (const render::DrawItem& item : d.items) {
    CHECK(item.transform(0, 3) == 5);
    (item.material.diffuse == red.diffuse ? red_area : blue_area) += item.mesh->area();
  }
  CHECK(red_area == Approx(12));
  CHECK(blue_area == Approx(4));
  // Without a tag resolver the part is one piece in the scene's material.
  CHECK(scene::draw_items(*root, Tolerance{}).items.size() == 1);
}

TEST_CASE("bad scenes are errors naming what is wrong", "[scene][errors]") {
  auto a = scene::group(), b = scene::group();
  scene::add(*a, b);
  CHECK_THROWS_WITH(scene::add(*b, a), Catch::Contains("the group would contain itself"));
  CHECK_THROWS_WITH(scene::add(*a, a), Catch::Contains("the group would contain itself"));
  CHECK_THROWS_WITH(scene::group(scale(Vec3(0, 1, 1))), Catch::Contains("transform is singular"));
  Mat4 projective = Mat4::Identity();
  projective(3, 2) = 1;
  CHECK_THROWS_WITH(scene::group(projective), Catch::Contains("must be affine"));
  CHECK_THROWS_WITH(scene::array(scene::part(block(1, 1, 1)), 0, Vec3(1, 0, 0)), Catch::Contains("count must be within 1..100000, got 0"));
  CHECK_THROWS_WITH(scene::radial_array(scene::part(block(1, 1, 1)), 3, -1), Catch::Contains("radius must be finite and not negative"));
  CHECK_THROWS_WITH(scene::radial_array(scene::part(block(1, 1, 1)), 3, 1, Vec3(0, 0, 0)), Catch::Contains("axis must be finite and non-zero"));
  CHECK_THROWS_WITH(scene::bounds(*scene::group(), Tolerance{}), Catch::Contains("the scene is empty"));
  CHECK_THROWS_WITH(scene::part(Mesh{}), Catch::Contains("needs triangles"));
}

// The depth limit counts the levels above the parent too: a chain built from the top (each new
// group added under the last) was let in at any depth, and then every use refused it. A copy
// counts its levels as flatten() does (one of 1001 levels was copied, then refused by table()).
TEST_CASE("the depth limit holds for scenes built from the top and from the bottom", "[scene][errors]") {
  std::vector<scene::NodePtr> chain{scene::group("root")};  // chain[i] at level i + 1
  while (chain.size() < 999) {
    auto next = scene::group();
    scene::add(*chain.back(), next);
    chain.push_back(next);
  }
  const auto& root = chain.front();
  const auto& deepest = chain.back();  // level 999
  auto part = scene::part(block(1, 1, 1));
  auto holder = scene::group("holder");
  scene::add(*holder, part);
  CHECK_THROWS_WITH(scene::add(*deepest, holder),
                    Catch::Contains("the scene would be deeper than 1000 levels: Group('holder', 1 child) added to Group(0 children) "
                                    "(at level 999) would reach level 1001"));
  scene::add(*deepest, part);  // level 1000: the deepest allowed
  CHECK(scene::flatten(*root).size() == 1);
  CHECK(scene::flatten(*scene::copy(root)).size() == 1);
  // under a new top every level moves down one
  auto top = scene::group("top");
  CHECK_THROWS_WITH(scene::add(*top, root),
                    Catch::Contains("Group('root', 1 child) added to Group('top', 0 children) (at level 1) would reach level 1001"));
  // a group that gains children after it was placed deep
  auto late = scene::group("late");
  scene::add(*deepest, late);  // level 1000, empty: allowed
  CHECK_THROWS_WITH(scene::add(*late, scene::part(block(1, 1, 1))), Catch::Contains("would reach level 1001"));
  // a small tree placed deep afterwards: its own children move down with it
  auto a = scene::group("a"), b = scene::group("b"), c = scene::group("c");
  scene::add(*a, b);
  scene::add(*chain[996], a);  // a at level 998, b at 999
  scene::add(*b, c);           // c at 1000
  CHECK_THROWS_WITH(scene::add(*c, scene::part(block(1, 1, 1))), Catch::Contains("would reach level 1001"));
}
