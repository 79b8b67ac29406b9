// The course's three-joint robot arm as a scene, from C++ (#include <wedge/wedge.h>): each link is a
// group whose transform is its joint, so a part inherits every joint above it
// (M_world = M_parent * M_local). Prints the instance table and draws the arm.
// Usage: robot <output-directory> [shoulder-degrees] [elbow-degrees]
#include <wedge/wedge.h>

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace wedge;

namespace {
// A link of length `len` along +z with its joint at the origin, in one colour.
scene::NodePtr link(double len, double w, float r, float g, float b) {
  render::Material m;
  m.ambient = m.diffuse = render::Vec4f(r, g, b, 1);
  return scene::part(brep_solid(box(Vec3(w, w, len), Point3(-w / 2, -w / 2, 0))), m);
}
}  // namespace

int main(int argc, char** argv) {
  const std::string out = argc > 1 ? argv[1] : ".";
  const double shoulder = argc > 2 ? std::atof(argv[2]) : 90, elbow = argc > 3 ? std::atof(argv[3]) : 0;
  try {
    auto robot = scene::group("robot");
    auto base = scene::group("base");
    auto upper = scene::group(translate(Vec3(0, 0, 1)) * rotate_y(shoulder), "upper_arm");
    auto fore = scene::group(translate(Vec3(0, 0, 3)) * rotate_y(elbow), "forearm");
    auto hand = scene::group(translate(Vec3(0, 0, 2.5)), "hand");
    scene::add(*robot, base);
    scene::add(*base, link(1, 1.2, 0.8f, 0.3f, 0.2f));
    scene::add(*base, upper);
    scene::add(*upper, link(3, 0.6, 0.9f, 0.6f, 0.2f));
    scene::add(*upper, fore);
    scene::add(*fore, link(2.5, 0.45, 0.3f, 0.6f, 0.9f));
    scene::add(*fore, hand);
    // two fingers: instances of one prototype
    auto finger = scene::group("finger");
    scene::add(*finger, link(0.6, 0.15, 0.2f, 0.2f, 0.2f));
    scene::add(*hand, scene::instance(finger, translate(Vec3(0.15, 0, 0))));
    scene::add(*hand, scene::instance(finger, translate(Vec3(-0.15, 0, 0))));

    for (const scene::InstanceRow& row : scene::instance_table(*robot))
      std::printf("%-10s at %6.3f %6.3f %6.3f  turned %6.1f %6.1f %6.1f\n", row.symbol.c_str(), row.translation.x(),
                  row.translation.y(), row.translation.z(), row.rotation.x(), row.rotation.y(), row.rotation.z());
    const Tolerance tol;
    const Box3 b = scene::bounds(*robot, tol);
    std::printf("bounds %.4g %.4g %.4g .. %.4g %.4g %.4g\n", b.min.x(), b.min.y(), b.min.z(), b.max.x(), b.max.y(), b.max.z());
    render::RenderOptions ro;
    ro.width = 240, ro.height = 240;
    ro.camera = render::named_view("iso", b);
    render::write_png(out + "/robot.png", scene::picture(*robot, ro, tol));
    std::printf("wrote %s/robot.png\n", out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robot: %s\n", e.what());
    return 1;
  }
  return 0;
}
