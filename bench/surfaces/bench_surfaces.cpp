// Points per second: a cubic B-spline curve (64 control points, open-uniform knots) evaluated at
// 4 million parameters, and a rational bicubic NURBS surface (16 x 16 control points, uneven
// weights) on a 2000 x 2000 parameter grid. Best of 5 runs, one thread. The peer, when built, is
// OpenCASCADE's Geom_BSplineCurve::D0 / Geom_BSplineSurface::D0 on the same data, and the largest
// difference between the two kernels' points is printed as a check that both compute the same thing.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>

#include "surfaces/surfaces.h"

#ifdef WEDGE_BENCH_OCCT
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#endif

using namespace wedge;

namespace {

double best_seconds(const std::function<double()>& run, double& checksum) {
  double best = 1e300;
  for (int r = 0; r < 5; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    checksum = run();
    auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  return best;
}

// Distinct knots and their multiplicities, as OCCT wants them.
void split_knots(const std::vector<double>& U, std::vector<double>& knots, std::vector<int>& mults) {
  for (double u : U) {
    if (!knots.empty() && knots.back() == u) ++mults.back();
    else {
      knots.push_back(u);
      mults.push_back(1);
    }
  }
}

}  // namespace

int main() {
  const int curve_samples = 4'000'000, grid = 2000;
  std::vector<Point3> P;
  for (int i = 0; i < 64; ++i) P.emplace_back(i, std::sin(0.7 * i) * 3, std::cos(0.3 * i));
  NurbsCurve curve(3, P, open_uniform_knots(3, P.size()));
  std::vector<std::vector<Point3>> S(16, std::vector<Point3>(16));
  std::vector<std::vector<double>> W(16, std::vector<double>(16));
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j) {
      S[i][j] = Point3(i, j, std::sin(0.5 * i) * std::cos(0.4 * j));
      W[i][j] = 1 + 0.5 * std::sin(i + 2.0 * j) * std::sin(i + 2.0 * j);
    }
  NurbsSurface surface(3, 3, S, open_uniform_knots(3, 16), open_uniform_knots(3, 16), W);

  double sum = 0;
  double tc = best_seconds([&] {
    double s = 0;
    for (int i = 0; i < curve_samples; ++i) s += curve.eval(double(i) / (curve_samples - 1)).sum();
    return s;
  }, sum);
  std::printf("wedge  cubic B-spline curve:   %.3g points/s (checksum %.6g)\n", curve_samples / tc, sum);
  double ts = best_seconds([&] {
    double s = 0;
    for (int i = 0; i < grid; ++i)
      for (int j = 0; j < grid; ++j) s += surface.eval(double(i) / (grid - 1), double(j) / (grid - 1)).sum();
    return s;
  }, sum);
  std::printf("wedge  bicubic NURBS surface: %.3g points/s (checksum %.6g)\n", double(grid) * grid / ts, sum);

#ifdef WEDGE_BENCH_OCCT
  {
    TColgp_Array1OfPnt poles(1, int(P.size()));
    for (std::size_t i = 0; i < P.size(); ++i) poles(int(i) + 1) = gp_Pnt(P[i].x(), P[i].y(), P[i].z());
    std::vector<double> k;
    std::vector<int> m;
    split_knots(curve.knots(), k, m);
    TColStd_Array1OfReal knots(1, int(k.size()));
    TColStd_Array1OfInteger mults(1, int(m.size()));
    for (std::size_t i = 0; i < k.size(); ++i) {
      knots(int(i) + 1) = k[i];
      mults(int(i) + 1) = m[i];
    }
    Handle(Geom_BSplineCurve) occ = new Geom_BSplineCurve(poles, knots, mults, 3);
    double diff = 0;
    for (int i = 0; i <= 1000; ++i) {
      gp_Pnt q = occ->Value(i / 1000.0);
      diff = std::max(diff, (Point3(q.X(), q.Y(), q.Z()) - curve.eval(i / 1000.0)).norm());
    }
    double to = best_seconds([&] {
      double s = 0;
      gp_Pnt q;
      for (int i = 0; i < curve_samples; ++i) {
        occ->D0(double(i) / (curve_samples - 1), q);
        s += q.X() + q.Y() + q.Z();
      }
      return s;
    }, sum);
    std::printf("OCCT   cubic B-spline curve:   %.3g points/s (checksum %.6g, max difference %.2g)\n",
                curve_samples / to, sum, diff);
    std::printf("ratio  wedge / OCCT curve:     %.2f\n", to / tc);
  }
  {
    TColgp_Array2OfPnt poles(1, 16, 1, 16);
    TColStd_Array2OfReal weights(1, 16, 1, 16);
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) {
        poles(i + 1, j + 1) = gp_Pnt(S[i][j].x(), S[i][j].y(), S[i][j].z());
        weights(i + 1, j + 1) = W[i][j];
      }
    std::vector<double> k;
    std::vector<int> m;
    split_knots(surface.uknots(), k, m);
    TColStd_Array1OfReal knots(1, int(k.size()));
    TColStd_Array1OfInteger mults(1, int(m.size()));
    for (std::size_t i = 0; i < k.size(); ++i) {
      knots(int(i) + 1) = k[i];
      mults(int(i) + 1) = m[i];
    }
    Handle(Geom_BSplineSurface) occ = new Geom_BSplineSurface(poles, weights, knots, knots, mults, mults, 3, 3);
    double diff = 0;
    for (int i = 0; i <= 50; ++i)
      for (int j = 0; j <= 50; ++j) {
        gp_Pnt q = occ->Value(i / 50.0, j / 50.0);
        diff = std::max(diff, (Point3(q.X(), q.Y(), q.Z()) - surface.eval(i / 50.0, j / 50.0)).norm());
      }
    double to = best_seconds([&] {
      double s = 0;
      gp_Pnt q;
      for (int i = 0; i < grid; ++i)
        for (int j = 0; j < grid; ++j) {
          occ->D0(double(i) / (grid - 1), double(j) / (grid - 1), q);
          s += q.X() + q.Y() + q.Z();
        }
      return s;
    }, sum);
    std::printf("OCCT   bicubic NURBS surface: %.3g points/s (checksum %.6g, max difference %.2g)\n",
                double(grid) * grid / to, sum, diff);
    std::printf("ratio  wedge / OCCT surface:   %.2f\n", to / ts);
  }
#else
  std::printf("OCCT not found: no peer figures (install libocct-modeling-data-dev)\n");
#endif
  return 0;
}
