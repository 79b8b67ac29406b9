// B-spline basis functions and knot vectors, after The NURBS Book (Piegl & Tiller, 2nd ed.),
// chapter 2: A2.1 finds the knot span by binary search, A2.2 computes the p + 1 non-vanishing
// basis functions by the triangular Cox-de Boor recurrence (left/right differences, no division
// by zero), A2.3 their derivatives from the same table. check_knots says in words what is wrong.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>

#include "surfaces/surfaces.h"

namespace wedge {

namespace {

// A knot as a message shows it: the shortest text that reads back as the same double. fail()
// prints 17 significant digits, so a knot given as 0.7 was shown as 0.69999999999999996.
std::string knot_text(double x) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return ec == std::errc() ? std::string(buf, end) : std::to_string(x);
}

}  // namespace

void check_knots(const std::vector<double>& knots, int degree, std::size_t count, const char* what) {
  // A surface names its direction ("uknots", "vknots"); a curve's messages keep their plain form.
  const bool curve = std::string_view(what) == "knots";
  if (degree < 1) {
    if (curve) fail("degree must be at least 1, got ", degree);
    fail(what, ": degree must be at least 1, got ", degree);
  }
  if (count < std::size_t(degree) + 1) {
    if (curve) fail("a curve of degree ", degree, " needs at least ", degree + 1, " control points, got ", count);
    fail(what, ": degree ", degree, " needs at least ", degree + 1, " control points in this direction, got ", count);
  }
  std::size_t expected = count + std::size_t(degree) + 1;
  if (knots.size() != expected)
    fail(what, ": ", count, " control points of degree ", degree, " need ", expected,
         " knots (points + degree + 1), got ", knots.size());
  for (std::size_t i = 0; i < knots.size(); ++i)
    if (!std::isfinite(knots[i])) fail(what, ": knot ", i + 1, " is not a finite number (", knots[i], ")");
  for (std::size_t i = 1; i < knots.size(); ++i)
    if (knots[i] < knots[i - 1])
      fail(what, " must be non-decreasing: knot ", i + 1, " (", knot_text(knots[i]), ") is less than knot ", i, " (",
           knot_text(knots[i - 1]), ")");
  for (std::size_t i = 0; i < knots.size();) {
    std::size_t j = i;
    while (j < knots.size() && knots[j] == knots[i]) ++j;
    std::size_t mult = j - i;
    bool end = i == 0 || j == knots.size();
    if (mult > std::size_t(degree) + 1 || (!end && mult > std::size_t(degree)))
      fail(what, ": knot ", knot_text(knots[i]), " appears ", mult, " times; at most ", end ? degree + 1 : degree,
           " allowed for degree ", degree, end ? " at an end" : " inside");
    i = j;
  }
  if (!(knots[degree] < knots[count]))
    fail(what, ": the curve's domain [knot ", degree + 1, ", knot ", count + 1, "] = [", knot_text(knots[degree]), ", ",
         knot_text(knots[count]), "] is empty");
}

void check_weights(const std::vector<double>& weights, std::size_t count, const char* what) {
  if (weights.size() != count) fail(what, ": need one weight per control point (", count, "), got ", weights.size());
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (!(std::isfinite(weights[i]) && weights[i] > 0))
      fail(what, ": weight ", i + 1, " must be a positive finite number, got ", weights[i]);
}

int find_span(int n, int p, double u, const std::vector<double>& U) {
  // n is the number of control points; the domain is [U[p], U[n]].
  if (u >= U[n]) {
    int k = n - 1;
    while (k > p && U[k] == U[n]) --k;
    return k;
  }
  if (u <= U[p]) {
    int k = p;
    while (k + 1 < n && U[k + 1] == U[p]) ++k;
    return k;
  }
  int low = p, high = n;
  int mid = (low + high) / 2;
  while (u < U[mid] || u >= U[mid + 1]) {
    if (u < U[mid]) high = mid;
    else low = mid;
    mid = (low + high) / 2;
  }
  return mid;
}

void basis_functions(int i, double u, int p, const std::vector<double>& U, double* N) {
  double left[32], right[32];
  N[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - U[i + 1 - j];
    right[j] = U[i + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      double temp = N[r] / (right[r + 1] + left[j - r]);
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
}

void basis_derivatives(int i, double u, int p, int n, const std::vector<double>& U, double* ders) {
  if (p > 31) fail("degree must be at most 31, got ", p);
  // ndu[j][r] (A2.3's table) at ndu[j * 32 + r]; a holds the two rows of the recurrence.
  double ndu[32 * 32], a[2][32], left[32], right[32];
  const int w = p + 1;
  std::fill(ders, ders + (n + 1) * w, 0.0);
  ndu[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - U[i + 1 - j];
    right[j] = U[i + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j * 32 + r] = right[r + 1] + left[j - r];  // lower triangle: knot differences
      double temp = ndu[r * 32 + j - 1] / ndu[j * 32 + r];
      ndu[r * 32 + j] = saved + right[r + 1] * temp;  // upper triangle: basis functions
      saved = left[j - r] * temp;
    }
    ndu[j * 32 + j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[j] = ndu[j * 32 + p];
  int dmax = std::min(n, p);
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= dmax; ++k) {
      double d = 0.0;
      int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[(pk + 1) * 32 + rk];
        d = a[s2][0] * ndu[rk * 32 + pk];
      }
      int j1 = rk >= -1 ? 1 : -rk;
      int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[(pk + 1) * 32 + rk + j];
        d += a[s2][j] * ndu[(rk + j) * 32 + pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[(pk + 1) * 32 + r];
        d += a[s2][k] * ndu[r * 32 + pk];
      }
      ders[k * w + r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= dmax; ++k) {
    for (int j = 0; j <= p; ++j) ders[k * w + j] *= factor;
    factor *= (p - k);
  }
}

std::vector<std::vector<double>> basis_derivatives(int i, double u, int p, int n, const std::vector<double>& U) {
  std::vector<double> flat(std::size_t(n + 1) * std::size_t(p + 1));
  basis_derivatives(i, u, p, n, U, flat.data());
  std::vector<std::vector<double>> ders(n + 1);
  for (int k = 0; k <= n; ++k) ders[k].assign(flat.begin() + k * (p + 1), flat.begin() + (k + 1) * (p + 1));
  return ders;
}

std::vector<double> open_uniform_knots(int degree, std::size_t count) {
  if (degree < 1) fail("degree must be at least 1, got ", degree);
  if (count < std::size_t(degree) + 1)
    fail("a curve of degree ", degree, " needs at least ", degree + 1, " control points, got ", count);
  std::vector<double> U;
  std::size_t spans = count - degree;
  for (int i = 0; i < degree; ++i) U.push_back(0.0);
  for (std::size_t i = 0; i <= spans; ++i) U.push_back(double(i) / double(spans));
  for (int i = 0; i < degree; ++i) U.push_back(1.0);
  return U;
}

std::vector<double> uniform_knots(int degree, std::size_t count) {
  if (degree < 1) fail("degree must be at least 1, got ", degree);
  if (count < std::size_t(degree) + 1)
    fail("a curve of degree ", degree, " needs at least ", degree + 1, " control points, got ", count);
  std::vector<double> U(count + degree + 1);
  for (std::size_t i = 0; i < U.size(); ++i) U[i] = double(i);
  return U;
}

}  // namespace wedge
