// A CAD-style application using wedge from C++: builds a part, measures it, exports an STL and
// renders a picture, through the installed package (#include <wedge/wedge.h>, wedge::wedge).
// Usage: app <output-directory>
#include <wedge/wedge.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  using namespace wedge;
  const std::string out = argc > 1 ? argv[1] : ".";
  try {
    // A 2 x 3 x 4 block, turned a quarter about z and moved: a Solid is an immutable value.
    const Solid block = brep_solid(box(Vec3(2, 3, 4)));
    const Solid placed = block.transformed(translate(Vec3(10, 0, 0)) * rotate_z(90));
    const Tolerance tol;
    const MassProperties mp = placed.mass_properties(tol);
    const EulerCounts e = placed.euler(tol);
    const Box3 b = placed.bounds();
    std::printf("volume %.6g area %.6g\n", mp.volume, mp.area);
    std::printf("euler V=%ld E=%ld F=%ld S=%ld\n", long(e.V), long(e.E), long(e.F), long(e.S));
    std::printf("bounds %.6g %.6g %.6g .. %.6g %.6g %.6g\n", b.min.x(), b.min.y(), b.min.z(), b.max.x(), b.max.y(), b.max.z());
    const Mesh mesh = placed.mesh(tol);
    write_mesh(mesh, out + "/app-block.stl");
    const Mesh back = read_mesh(out + "/app-block.stl");
    std::printf("stl triangles %zu volume %.6g\n", back.triangle_count(), back.volume());
    // A picture, drawn by the software OpenGL 1.x pipeline in an isometric view.
    render::DrawItem item;
    const Mesh shaded = mesh.with_face_normals();
    item.mesh = &shaded;
    render::RenderOptions ro;
    ro.width = 160, ro.height = 120;
    ro.camera = render::named_view("iso", shaded.bounds());
    render::write_png(out + "/app-block.png", render::render_scene({item}, ro));
    std::printf("wrote %s/app-block.png\n", out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "app: %s\n", e.what());
    return 1;
  }
  return 0;
}
