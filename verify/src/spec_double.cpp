#include "rayspace/verify/spec_double.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayspace::verify {
namespace {

constexpr double kInfD = std::numeric_limits<double>::infinity();
// The relative error of the double arithmetic that computes the bounds (a rounding or two), taken
// generously: every bound is widened by it on top of the device's ULPs.
constexpr double kBoundSlack = 0x1p-50;

// A ULP of 24 significant bits at |x| (0 at 0, where no rounding moves a result).
double Ulp24(double x) {
  const double a = std::fabs(x);
  if (a == 0.0 || std::isinf(a)) return 0.0;
  int e;
  std::frexp(a, &e);  // a in [2^(e-1), 2^e)
  return std::ldexp(1.0, e - 1 - 23);
}

SpecDouble MakeD(double v, double lo, double hi) {
  if (std::isnan(v) || std::isnan(lo) || std::isnan(hi)) return SpecDouble::Unbounded(v);
  SpecDouble r{};
  r.v = v;
  r.lo = lo;
  r.hi = hi;
  r.any = false;
  return r;
}

// The values within `ulps` ULPs of 24 bits of some exact value in [x_lo, x_hi], where x_lo and x_hi
// carry at most a double rounding or two.
SpecDouble WidenedD(double v, double x_lo, double x_hi, double ulps) {
  const auto out = [ulps](double x, double dir) {
    if (std::isinf(x)) return x;
    const double m = std::fabs(x) * (1.0 + kBoundSlack);
    return std::nextafter(x + dir * (ulps * Ulp24(m) + std::fabs(x) * kBoundSlack), dir * kInfD);
  };
  return MakeD(v, out(x_lo, -1.0), out(x_hi, 1.0));
}

template <typename F>
SpecDouble FromCorners(double v, const SpecDouble& a, const SpecDouble& b, double ulps, F op) {
  const double c[4] = {op(a.lo, b.lo), op(a.lo, b.hi), op(a.hi, b.lo), op(a.hi, b.hi)};
  for (double x : c)
    if (std::isnan(x)) return SpecDouble::Unbounded(v);
  return WidenedD(v, *std::min_element(c, c + 4), *std::max_element(c, c + 4), ulps);
}

void AmbiguousD() { ++CurrentSpecTrace().ambiguous; }

// 1 always true, 0 always false, -1 either.
template <typename Definite>
bool DecideD(const SpecDouble& a, const SpecDouble& b, bool nominal, Definite definite) {
  if (a.any || b.any || definite(a, b) < 0) AmbiguousD();
  return nominal;
}

}  // namespace

SpecDouble::SpecDouble(double x) : v(x), lo(x), hi(x), any(std::isnan(x)) {}

SpecDouble SpecDouble::Unbounded(double nominal) {
  SpecDouble r{};
  r.v = nominal;
  r.lo = -kInfD;
  r.hi = kInfD;
  r.any = true;
  return r;
}

bool SpecDouble::Allows(double actual) const { return any || (!std::isnan(actual) && lo <= actual && actual <= hi); }

SpecDouble operator+(SpecDouble a, SpecDouble b) {
  const double v = a.v + b.v;
  if (a.any || b.any) return SpecDouble::Unbounded(v);
  // Monotone in each operand: the corners are the extremes.
  return WidenedD(v, a.lo + b.lo, a.hi + b.hi, 1.0);
}

SpecDouble operator-(SpecDouble a) {
  SpecDouble r = a;
  r.v = -a.v;
  r.lo = -a.hi;
  r.hi = -a.lo;
  return r;
}

SpecDouble operator-(SpecDouble a, SpecDouble b) {
  SpecDouble r = a + (-b);
  r.v = a.v - b.v;
  return r;
}

SpecDouble operator*(SpecDouble a, SpecDouble b) {
  const double v = a.v * b.v;
  if (a.any || b.any) return SpecDouble::Unbounded(v);
  return FromCorners(v, a, b, 1.0, [](double x, double y) { return x * y; });
}

SpecDouble operator/(SpecDouble a, SpecDouble b) {
  const double v = a.v / b.v;
  if (a.any || b.any || std::isinf(a.lo) || std::isinf(a.hi)) return SpecDouble::Unbounded(v);
  // Single precision's bound holds for divisors of magnitude in [2^-126, 2^126] only.
  const bool positive = b.lo >= 0x1p-126 && b.hi <= 0x1p126, negative = b.hi <= -0x1p-126 && b.lo >= -0x1p126;
  if (!positive && !negative) return SpecDouble::Unbounded(v);
  return FromCorners(v, a, b, 2.5, [](double x, double y) { return x / y; });
}

SpecDouble Square(SpecDouble x) {
  const double v = x.v * x.v;
  if (x.any) return SpecDouble::Unbounded(v);
  const double l = x.lo * x.lo, h = x.hi * x.hi;
  const double lo = x.lo <= 0.0 && x.hi >= 0.0 ? 0.0 : std::min(l, h);
  SpecDouble r = WidenedD(v, lo, std::max(l, h), 1.0);
  r.lo = std::max(r.lo, 0.0);  // a value times itself is never negative
  return r;
}

SpecDouble Sqrt(SpecDouble x) {
  const double v = std::sqrt(x.v);
  if (x.any || !(x.lo >= 0.0) || std::isinf(x.hi)) return SpecDouble::Unbounded(v);
  if (x.hi == 0.0) return MakeD(v, 0.0, 0.0);
  // inversesqrt within 2 ULP at both ends (decreasing), then 1 / r within 2.5 ULP.
  const SpecDouble r_hi_end = WidenedD(0.0, 1.0 / std::sqrt(x.hi), 1.0 / std::sqrt(x.hi), 2.0);
  const double r_lo = r_hi_end.lo;  // the least inverse root: of the greatest x
  const double hi = WidenedD(0.0, 1.0 / r_lo, 1.0 / r_lo, 2.5).hi;
  double lo = 0.0;
  if (x.lo > 0.0) {
    const double r_hi = WidenedD(0.0, 1.0 / std::sqrt(x.lo), 1.0 / std::sqrt(x.lo), 2.0).hi;
    lo = std::max(0.0, WidenedD(0.0, 1.0 / r_hi, 1.0 / r_hi, 2.5).lo);
  }
  return MakeD(v, lo, hi);
}

SpecDouble Floor(SpecDouble x) {
  SpecDouble r = x;
  r.v = std::floor(x.v);
  if (x.any) return r;
  r.lo = std::floor(x.lo);
  r.hi = std::floor(x.hi);
  return r;
}

SpecDouble Lesser(SpecDouble x, SpecDouble b) {
  const double v = b.v < x.v ? b.v : x.v;
  if (x.any || b.any) return SpecDouble::Unbounded(v);
  return MakeD(v, std::min(x.lo, b.lo), std::min(x.hi, b.hi));
}

SpecDouble Greater(SpecDouble x, SpecDouble b) {
  const double v = b.v > x.v ? b.v : x.v;
  if (x.any || b.any) return SpecDouble::Unbounded(v);
  return MakeD(v, std::max(x.lo, b.lo), std::max(x.hi, b.hi));
}

SpecDouble ClampOf(SpecDouble x, double lo, double hi) {
  // Bounded whatever x is: an unbounded x may end anywhere in [lo, hi].
  SpecDouble r{};
  r.v = std::isnan(x.v) ? lo : std::clamp(x.v, lo, hi);
  r.lo = x.any ? lo : std::clamp(x.lo, lo, hi);
  r.hi = x.any ? hi : std::clamp(x.hi, lo, hi);
  r.any = false;
  return r;
}

SpecDouble Widen(SpecReal x) {
  if (x.any) return SpecDouble::Unbounded(x.v);
  return MakeD(x.v, x.lo, x.hi);
}

SpecReal ToFloat(SpecDouble x) {
  const float v = static_cast<float>(x.v);
  if (x.any) return SpecReal::Unbounded(v);
  // The float at or below lo, the float at or above hi: every rounding of a value between.
  float lo = static_cast<float>(x.lo), hi = static_cast<float>(x.hi);
  if (static_cast<double>(lo) > x.lo) lo = std::nextafter(lo, -std::numeric_limits<float>::infinity());
  if (static_cast<double>(hi) < x.hi) hi = std::nextafter(hi, std::numeric_limits<float>::infinity());
  return SpecReal::Between(v, lo, hi);
}

bool operator<(SpecDouble a, SpecDouble b) {
  return DecideD(a, b, a.v < b.v, [](const SpecDouble& x, const SpecDouble& y) { return x.hi < y.lo ? 1 : (x.lo >= y.hi ? 0 : -1); });
}
bool operator<=(SpecDouble a, SpecDouble b) {
  return DecideD(a, b, a.v <= b.v, [](const SpecDouble& x, const SpecDouble& y) { return x.hi <= y.lo ? 1 : (x.lo > y.hi ? 0 : -1); });
}
bool operator>(SpecDouble a, SpecDouble b) { return b < a; }
bool operator>=(SpecDouble a, SpecDouble b) { return b <= a; }
bool operator==(SpecDouble a, SpecDouble b) {
  return DecideD(a, b, a.v == b.v, [](const SpecDouble& x, const SpecDouble& y) {
    if (x.lo == x.hi && y.lo == y.hi && x.lo == y.lo) return 1;
    return (x.hi < y.lo || y.hi < x.lo) ? 0 : -1;
  });
}
bool operator!=(SpecDouble a, SpecDouble b) { return !(a == b); }

IndexRange CellIndex(SpecDouble x) {
  // Clamped to [0, n - 1] before the conversion, so both ends are integers in range.
  return {static_cast<std::uint32_t>(x.lo), static_cast<std::uint32_t>(x.hi)};
}

IndexRange SliceOf(SpecDouble r, const float* b, std::uint32_t depth) {
  IndexRange k{};
  for (std::uint32_t j = 1; j < depth; ++j) {
    const double bj = static_cast<double>(b[j]);
    if (r.any || r.lo <= bj) ++k.hi;
    if (!r.any && r.hi <= bj) ++k.lo;
  }
  return k;
}

}  // namespace rayspace::verify
