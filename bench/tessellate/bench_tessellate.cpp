// Tessellation of curved solids, wedge against OpenCASCADE's BRepMesh_IncrementalMesh, in the
// same run: a sphere, a torus, a revolved closed NURBS profile and a circle swept along a cubic
// Bezier path, at chordal tolerances 1e-2, 1e-3 and 1e-4 (OCCT: linear deflection, absolute).
// Both get the same angular limit (0.5 rad, OCCT's default). For each: the triangles, the time
// (best of 3 meshings in this run; OCCT's triangulation is removed with BRepTools::Clean between
// meshings), and the measured chordal error: the largest distance from the exact surface to the
// centroid and edge midpoints of every triangle on a curved face, by closed form (sphere, torus),
// or by projection onto the exact profile or path (coarse samples, then Newton) for the others.
// Planar faces are exact in both and are not sampled.
#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepOffsetAPI_MakePipe.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GC_MakeCircle.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BezierCurve.hxx>
#include <Poly_Triangulation.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "tessellate/brep_mesh.h"

using namespace wedge;

namespace {

using Dist = std::function<double(const Point3&)>;

struct Tri {
  Point3 a, b, c;
};

double measured_error(const std::vector<Tri>& tris, const Dist& dist) {
  double worst = 0;
  for (const Tri& t : tris)
    for (const Point3& p : {Point3((t.a + t.b + t.c) / 3), Point3((t.a + t.b) / 2), Point3((t.b + t.c) / 2), Point3((t.c + t.a) / 2)})
      worst = std::max(worst, dist(p));
  return worst;
}

// The nearest point of a curve to x: the nearest of n samples, then Newton on (C(t) - x).C'(t).
double curve_distance(const Curve& c, const std::vector<double>& ts, const std::vector<Point3>& ps, const Point3& x) {
  std::size_t best = 0;
  double bd = 1e300;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    double d = (ps[i] - x).squaredNorm();
    if (d < bd) bd = d, best = i;
  }
  auto [a, b] = c.domain();
  auto newton = [&](double t) {
    for (int it = 0; it < 12; ++it) {
      Vec3 d = c.eval(t) - x, d1 = c.derivative(t, 1), d2 = c.derivative(t, 2);
      double f = d.dot(d1), g = d1.dot(d1) + d.dot(d2);
      if (!(std::abs(g) > 0)) break;
      t = std::clamp(t - f / g, a, b);
    }
    return (c.eval(t) - x).norm();
  };
  double d = newton(ts[best]);
  // Near the joint of a closed curve the nearest point may lie across it: start there too.
  if (c.closed() && (best < 4 || best + 4 >= ts.size())) d = std::min({d, newton(a), newton(b)});
  return d;
}

struct Shape {
  std::string name;
  Model wedge_model;
  TopoDS_Shape occt;
  Dist dist;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<Tri> occt_curved_triangles(const TopoDS_Shape& s, long* total) {
  std::vector<Tri> out;
  *total = 0;
  for (TopExp_Explorer ex(s, TopAbs_FACE); ex.More(); ex.Next()) {
    const TopoDS_Face& f = TopoDS::Face(ex.Current());
    TopLoc_Location loc;
    Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(f, loc);
    if (tri.IsNull()) continue;
    *total += tri->NbTriangles();
    if (BRepAdaptor_Surface(f).GetType() == GeomAbs_Plane) continue;
    gp_Trsf tr = loc.Transformation();
    for (int i = 1; i <= tri->NbTriangles(); ++i) {
      int n[3];
      tri->Triangle(i).Get(n[0], n[1], n[2]);
      Point3 p[3];
      for (int k = 0; k < 3; ++k) {
        gp_Pnt q = tri->Node(n[k]).Transformed(tr);
        p[k] = Point3(q.X(), q.Y(), q.Z());
      }
      out.push_back({p[0], p[1], p[2]});
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const double pi = kPi;
  // Optional: --counts (wedge alone, one meshing each: triangle counts and measured errors, no
  // times, no OCCT) or --repeat N (wedge alone, N meshings of each shape: for a profiler), then the
  // tolerances to run (default 1e-2 1e-3 1e-4).
  bool counts_only = argc > 1 && std::string(argv[1]) == "--counts";
  int repeat = argc > 2 && std::string(argv[1]) == "--repeat" ? std::atoi(argv[2]) : 0;
  int first = counts_only ? 2 : repeat > 0 ? 3 : 1;
  std::vector<double> tolerances{1e-2, 1e-3, 1e-4};
  if (argc > first) {
    tolerances.clear();
    for (int i = first; i < argc; ++i) tolerances.push_back(std::atof(argv[i]));
  }
  std::vector<Shape> shapes;
  // Sphere r = 1 and torus R = 2, r = 0.5.
  shapes.push_back({"sphere r=1", sphere(1), BRepPrimAPI_MakeSphere(1.0).Shape(), [](const Point3& p) { return std::abs(p.norm() - 1); }});
  shapes.push_back({"torus R=2 r=0.5", torus(2, 0.5), BRepPrimAPI_MakeTorus(2.0, 0.5).Shape(),
                    [](const Point3& p) { return std::abs(std::hypot(std::hypot(p.x(), p.y()) - 2, p.z()) - 0.5); }});
  // A closed cubic B-spline profile (x the radius, y the height) revolved a full turn about z.
  std::vector<Point3> ctrl{{1.5, 0, 0}, {2, 0, 0}, {2.2, 0.5, 0}, {1.8, 1, 0}, {1.2, 1.1, 0}, {1, 0.5, 0}, {1, 0, 0}, {1.5, 0, 0}};
  std::vector<double> knots{0, 0, 0, 0, 0.2, 0.4, 0.6, 0.8, 1, 1, 1, 1};
  auto profile = std::make_shared<const NurbsCurve>(3, ctrl, knots);
  {
    TColgp_Array1OfPnt poles(1, int(ctrl.size()));
    for (std::size_t i = 0; i < ctrl.size(); ++i) poles(int(i) + 1) = gp_Pnt(ctrl[i].x(), 0, ctrl[i].y());  // the XZ plane
    TColStd_Array1OfReal kv(1, 6);
    TColStd_Array1OfInteger mult(1, 6);
    double ks[6] = {0, 0.2, 0.4, 0.6, 0.8, 1};
    int ms[6] = {4, 1, 1, 1, 1, 4};
    for (int i = 0; i < 6; ++i) kv(i + 1) = ks[i], mult(i + 1) = ms[i];
    Handle(Geom_BSplineCurve) c = new Geom_BSplineCurve(poles, kv, mult, 3);
    TopoDS_Wire w = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(c).Edge()).Wire();
    TopoDS_Face f = BRepBuilderAPI_MakeFace(w, Standard_True).Face();
    TopoDS_Shape rev = BRepPrimAPI_MakeRevol(f, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 2 * pi).Shape();
    std::vector<double> ts;
    std::vector<Point3> ps;
    for (int i = 0; i <= 512; ++i) ts.push_back(i / 512.0), ps.push_back(profile->eval(i / 512.0));
    shapes.push_back({"revolved NURBS profile", revolve(Section{loop_of_curve(profile), {}}, 2 * pi), rev,
                      [profile, ts, ps](const Point3& p) { return curve_distance(*profile, ts, ps, Point3(std::hypot(p.x(), p.y()), p.z(), 0)); }});
  }
  // A circle of radius 0.3 swept along a cubic Bezier path: the tube around the path (the section
  // is round, so the frames' roll does not change the surface).
  std::vector<Point3> path_pts{{0, 0, 0}, {1, 0, 1}, {2, 1, 1}, {3, 1, 2}};
  auto path = std::make_shared<const BezierCurve>(path_pts);
  {
    TColgp_Array1OfPnt poles(1, 4);
    for (int i = 0; i < 4; ++i) poles(i + 1) = gp_Pnt(path_pts[std::size_t(i)].x(), path_pts[std::size_t(i)].y(), path_pts[std::size_t(i)].z());
    Handle(Geom_BezierCurve) c = new Geom_BezierCurve(poles);
    TopoDS_Wire spine = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(c).Edge()).Wire();
    Vec3 t0 = path->derivative(0, 1).normalized();
    gp_Circ circ(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(t0.x(), t0.y(), t0.z())), 0.3);
    TopoDS_Face disc = BRepBuilderAPI_MakeFace(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circ).Edge()).Wire()).Face();
    TopoDS_Shape pipe = BRepOffsetAPI_MakePipe(spine, disc).Shape();
    std::vector<double> ts;
    std::vector<Point3> ps;
    for (int i = 0; i <= 512; ++i) ts.push_back(i / 512.0), ps.push_back(path->eval(i / 512.0));
    shapes.push_back({"circle swept along a Bezier", sweep_along(Section{circle_loop(Vec2::Zero(), 0.3), {}}, path), pipe,
                      [path, ts, ps](const Point3& p) { return std::abs(curve_distance(*path, ts, ps, p) - 0.3); }});
  }

  std::printf("| shape | tolerance | wedge triangles | wedge ms | wedge error | OCCT triangles | OCCT ms | OCCT error | time OCCT/wedge "
              "| wedge at OCCT's error: triangles, error |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  // WEDGE_BENCH_SHAPE=word runs only the shapes whose name contains it (for a profiler).
  const char* only = std::getenv("WEDGE_BENCH_SHAPE");
  for (Shape& s : shapes)
    for (double tol : tolerances) {
      if (only && s.name.find(only) == std::string::npos) continue;
      Tolerance t;
      t.chordal = tol;
      t.angular = 0.5 * 180 / pi;
      double wt = 1e300, ot = 1e300;
      Mesh mesh;
      if (repeat > 0) {
        auto t0 = std::chrono::steady_clock::now();
        for (int rep = 0; rep < repeat; ++rep) mesh = tessellate(s.wedge_model, t);
        std::printf("| %s | %g | %zu | %.3f ms each |\n", s.name.c_str(), tol, mesh.triangles.size(), seconds_since(t0) * 1e3 / repeat);
        std::fflush(stdout);
        continue;
      }
      if (counts_only) {
        mesh = tessellate(s.wedge_model, t);
        std::vector<Tri> tris;
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
          if (!s.wedge_model.surface(FaceId{mesh.face_ids[i]}).parametric) continue;
          const auto& tr = mesh.triangles[i];
          tris.push_back({mesh.positions[tr[0]], mesh.positions[tr[1]], mesh.positions[tr[2]]});
        }
        std::printf("| %s | %g | %zu | %.2e |\n", s.name.c_str(), tol, mesh.triangles.size(), measured_error(tris, s.dist));
        std::fflush(stdout);
        continue;
      }
      const int reps = tol < 1e-3 ? 1 : 3;  // 1e-4 takes seconds: one meshing per run
      for (int rep = 0; rep < reps; ++rep) {
        auto t0 = std::chrono::steady_clock::now();
        mesh = tessellate(s.wedge_model, t);
        wt = std::min(wt, seconds_since(t0));
      }
      long occt_total = 0;
      for (int rep = 0; rep < reps; ++rep) {
        BRepTools::Clean(s.occt);
        auto t0 = std::chrono::steady_clock::now();
        BRepMesh_IncrementalMesh mesher(s.occt, tol, Standard_False, 0.5, Standard_False);
        ot = std::min(ot, seconds_since(t0));
        if (!mesher.IsDone()) {
          std::fprintf(stderr, "OCCT meshing failed: %s at %g\n", s.name.c_str(), tol);
          return 1;
        }
      }
      auto curved = [&](const Mesh& mm) {
        std::vector<Tri> out;
        for (std::size_t i = 0; i < mm.triangles.size(); ++i) {
          const FaceSurface& fs = s.wedge_model.surface(FaceId{mm.face_ids[i]});
          if (!fs.parametric) continue;
          const auto& tr = mm.triangles[i];
          out.push_back({mm.positions[tr[0]], mm.positions[tr[1]], mm.positions[tr[2]]});
        }
        return out;
      };
      std::vector<Tri> oc_tris = occt_curved_triangles(s.occt, &occt_total);
      double we = measured_error(curved(mesh), s.dist), oe = measured_error(oc_tris, s.dist);
      // wedge asked for OCCT's measured error: the triangles it needs for the same error.
      Tolerance same = t;
      same.chordal = oe;
      Mesh at_same = tessellate(s.wedge_model, same);
      std::printf("| %s | %g | %zu | %.3f | %.2e | %ld | %.3f | %.2e | %.2f | %zu, %.2e |\n", s.name.c_str(), tol, mesh.triangles.size(), wt * 1e3,
                  we, occt_total, ot * 1e3, oe, ot / wt, at_same.triangles.size(), measured_error(curved(at_same), s.dist));
      std::fflush(stdout);
    }
}
