// Double-double numbers that carry a proven bound on their error: the exact predicates' middle
// stage, between the interval filter and exact arithmetic (boolean_exact.cpp only).
//
// A DD is a real number known to lie within `err` of hi + lo, where (hi, lo) is a normalised
// double-double (|lo| <= ulp(hi) / 2) and err >= 0 (0: hi + lo is the number exactly). Sums and
// products are the error-free transformations (TwoSum, Dekker's TwoProduct) and the accurate
// double-word algorithms analysed by Joldes, Muller and Popescu ("Tight and rigorous error bounds
// for basic building blocks of double-word arithmetic", ACM TOMS 2017): a sum of two double-words
// is within 3u^2 / (1 - 4u) of the exact sum relative to it, a product (the variant below, which
// drops lo * lo) within 5u^2, u = 2^-53. The bounds here are taken larger (4u^2 and 8u^2 of the
// result's leading part), the bound's own arithmetic is rounded to nearest and then inflated by
// 2^-48 relative (far more than the few roundings it makes), and errors of the operands are
// carried through: for a product, |a| eb + |b| ea + ea eb.
//
// A sign is decided only when |hi + lo| certainly exceeds err; overflow (an infinity or NaN
// anywhere reaches hi) and products near underflow (where TwoProduct is no longer exact) leave it
// undecided (2), and the caller goes on to exact arithmetic. Needs round-to-nearest, and no
// contraction of a * b + c into a fused multiply-add (this file's users are compiled with
// -ffp-contract=off).
#pragma once
#include <cmath>
#include <limits>

// The operations are small and called in long expressions: inlined always (GCC would otherwise
// call out to each, which costs as much as the arithmetic).
#define WEDGE_DD_INLINE inline __attribute__((always_inline))

namespace wedge::boolean_detail {

struct DD {
  double hi = 0, lo = 0, err = 0;
  DD() = default;
  explicit DD(double x) : hi(x) {}
  DD(double h, double l, double e) : hi(h), lo(l), err(e) {}
};

namespace dd {

constexpr double kU2 = 0x1p-106;           // u^2
constexpr double kInflate = 1 + 0x1p-48;   // covers the rounding of an error bound's arithmetic
constexpr double kSubnormal = 0x1p-1074;   // the least positive double
constexpr double kLeast = 0x1p-900;        // a product's leading part below this: not exact

WEDGE_DD_INLINE void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

// |a| >= |b| or a == 0.
WEDGE_DD_INLINE void fast_two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  e = b - (s - a);
}

// Veltkamp's split: a = h + l, each of 26 bits or fewer (|a| < 2^996).
WEDGE_DD_INLINE void split(double a, double& h, double& l) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  h = c - (c - a);
  l = a - h;
}

// Dekker: p + e = a b exactly (no overflow, and a b far from underflow).
WEDGE_DD_INLINE void two_product(double a, double b, double& p, double& e) {
  p = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

}  // namespace dd

WEDGE_DD_INLINE DD operator-(const DD& a) { return DD(-a.hi, -a.lo, a.err); }

WEDGE_DD_INLINE DD operator+(const DD& a, const DD& b) {
  DD r;
  double sh, sl;
  dd::two_sum(a.hi, b.hi, sh, sl);
  if (a.lo == 0 && b.lo == 0) {
    // Two doubles: their sum is sh + sl exactly.
    r.hi = sh;
    r.lo = sl;
    r.err = a.err == 0 && b.err == 0 ? 0.0 : (a.err + b.err) * dd::kInflate;
  } else {
    double th, tl, vh, vl;
    dd::two_sum(a.lo, b.lo, th, tl);
    dd::fast_two_sum(sh, sl + th, vh, vl);
    dd::fast_two_sum(vh, tl + vl, r.hi, r.lo);
    // (A relative bound: a sum of exact operands that comes out 0 is 0. The least double covers
    // the bound's product where it underflows.)
    r.err = (a.err + b.err + 4 * dd::kU2 * std::abs(r.hi)) * dd::kInflate + (r.hi != 0 ? dd::kSubnormal : 0.0);
  }
  if (!std::isfinite(r.hi)) r.err = INFINITY;
  return r;
}

WEDGE_DD_INLINE DD operator-(const DD& a, const DD& b) { return a + (-b); }

WEDGE_DD_INLINE DD operator*(const DD& a, const DD& b) {
  DD r;
  double ph, pl;
  dd::two_product(a.hi, b.hi, ph, pl);
  if (a.lo == 0 && b.lo == 0 && a.err == 0 && b.err == 0) {
    // Two doubles: their product is ph + pl exactly (pl is ph's rounding error, so normalised).
    r.hi = ph;
    r.lo = pl;
  } else {
    dd::fast_two_sum(ph, pl + (a.hi * b.lo + a.lo * b.hi), r.hi, r.lo);
    r.err = (std::abs(a.hi) * b.err + std::abs(b.hi) * a.err + a.err * b.err + 8 * dd::kU2 * std::abs(ph)) * dd::kInflate;
  }
  // Dekker's product is exact only away from underflow (a product of two non-zero numbers that
  // underflowed to 0 is not zero) and where the split does not overflow (|a|, |b| < 2^995; an
  // overflow of the product itself reaches hi).
  const bool tiny = a.hi != 0 && b.hi != 0 &&
                    (!(std::abs(ph) >= dd::kLeast) || !(std::abs(a.hi) >= 0x1p-960) || !(std::abs(b.hi) >= 0x1p-960));
  const bool huge = !(std::abs(a.hi) < 0x1p995) || !(std::abs(b.hi) < 0x1p995);
  if (tiny || huge || !std::isfinite(r.hi)) r.err = INFINITY;
  return r;
}

// +1, -1 or 0 as the exact number's sign, or 2 where the bound does not decide it.
WEDGE_DD_INLINE int sign_of(const DD& x) {
  if (!std::isfinite(x.hi) || !(x.err < INFINITY)) return 2;
  if (x.hi == 0 && x.err == 0) return 0;
  // |hi + lo| >= |hi| (1 - u) > |hi| (1 - 2^-50) (rounded), and that must exceed err.
  if (std::abs(x.hi) * (1 - 0x1p-50) > x.err) return x.hi > 0 ? 1 : -1;
  return 2;
}

}  // namespace wedge::boolean_detail
