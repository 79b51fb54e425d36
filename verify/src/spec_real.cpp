#include "rayspace/verify/spec_real.h"

#include "rayspace/emu/intersect.h"

#include <algorithm>
#include <cfloat>
#include <limits>

namespace rayspace::verify {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kMinNormal = 0x1p-126;
// Relative error of the double computations below (a quotient or a square root rounded once or
// twice), taken generously: bounds are widened by it before they are rounded to float.
constexpr double kDoubleSlack = 0x1p-50;

thread_local SpecTrace tls_default;
thread_local SpecTrace* tls_current = nullptr;

// The largest float <= s + err, where err is the exact rounding error of the double s.
float DownF(double s, double err = 0.0) {
  if (std::isnan(s)) return NAN;
  if (std::isinf(s)) return static_cast<float>(s);
  float f = static_cast<float>(s);
  // f - s is exact: f is s rounded to float, so they are within a float ulp of each other.
  if (std::isinf(f) || static_cast<double>(f) - s > err) f = std::nextafter(f, -kInf);
  return f;
}

// The smallest float >= s + err.
float UpF(double s, double err = 0.0) {
  if (std::isnan(s)) return NAN;
  if (std::isinf(s)) return static_cast<float>(s);
  float f = static_cast<float>(s);
  if (std::isinf(f) || static_cast<double>(f) - s < err) f = std::nextafter(f, kInf);
  return f;
}

// x + y = s + err exactly (Knuth's TwoSum in double).
double TwoSum(double x, double y, double& err) {
  const double s = x + y;
  const double b = s - x;
  err = (x - (s - b)) + (y - b);
  return s;
}

// Any denormal the interval holds may be read or written as zero on a flushing device.
SpecReal Flushed(SpecReal r) {
  if (r.any || !CurrentSpecTrace().flush_denormals) return r;
  if (r.lo < kMinNormal && r.hi > -kMinNormal) {
    r.lo = std::min(r.lo, 0.0f);
    r.hi = std::max(r.hi, 0.0f);
  }
  return r;
}

SpecReal Make(float v, float lo, float hi) {
  SpecReal r{};
  r.v = v;
  r.lo = lo;
  r.hi = hi;
  if (std::isnan(v) || std::isnan(lo) || std::isnan(hi)) return SpecReal::Unbounded(v);
  return Flushed(r);
}

// The floats within `ulps` spec ULPs of some exact value in [x_lo, x_hi] (doubles carrying at most
// kDoubleSlack relative error).
void WithinUlps(double x_lo, double x_hi, double ulps, float& lo, float& hi) {
  const double m_lo = std::fabs(x_lo) * (1.0 + kDoubleSlack), m_hi = std::fabs(x_hi) * (1.0 + kDoubleSlack);
  lo = UpF(x_lo - std::fabs(x_lo) * kDoubleSlack - ulps * UlpOf(m_lo));
  hi = DownF(x_hi + std::fabs(x_hi) * kDoubleSlack + ulps * UlpOf(m_hi));
}

void Ambiguous() { ++CurrentSpecTrace().ambiguous; }

template <typename Definite, typename Nominal>
bool Decide(const SpecReal& a, const SpecReal& b, Definite definite, Nominal nominal) {
  const bool n = nominal(a.v, b.v);
  if (a.any || b.any) {
    Ambiguous();
    return n;
  }
  const int d = definite(a, b);  // 1 always true, 0 always false, -1 either
  if (d < 0) Ambiguous();
  return n;
}

}  // namespace

SpecTrace& CurrentSpecTrace() { return tls_current ? *tls_current : tls_default; }

ScopedSpecTrace::ScopedSpecTrace(bool flush_denormals) : outer_(tls_current) {
  trace_.flush_denormals = flush_denormals;
  tls_current = &trace_;
}
ScopedSpecTrace::~ScopedSpecTrace() { tls_current = outer_; }

double UlpOf(double x) {
  const double a = std::fabs(x);
  if (!(a >= kMinNormal)) return 0x1p-149;
  if (std::isinf(a)) return std::ldexp(1.0, 104);
  int e;
  std::frexp(a, &e);  // a in [2^(e-1), 2^e)
  return std::ldexp(1.0, e - 1 - 23);
}

SpecReal::SpecReal(float x) : v(x), lo(x), hi(x), any(false) {
  if (std::isnan(x)) any = true;
  else *this = Flushed(*this);
}

SpecReal SpecReal::FromInteger(std::uint64_t n) {
  // Exact in double below 2^53; a conversion rounds in the device's mode, so either neighbour.
  const double x = static_cast<double>(n);
  return Make(static_cast<float>(n), DownF(x), UpF(x));
}

SpecReal SpecReal::Between(float v, float lo, float hi) { return Make(v, lo, hi); }

SpecReal SpecReal::Unbounded(float nominal) {
  SpecReal r{};
  r.v = nominal;
  r.lo = -kInf;
  r.hi = kInf;
  r.any = true;
  return r;
}

bool SpecReal::Allows(float actual) const {
  if (any) return true;
  if (std::isnan(actual)) return false;
  return lo <= actual && actual <= hi;
}

SpecReal operator+(SpecReal a, SpecReal b) {
  if (a.any || b.any) return SpecReal::Unbounded(a.v + b.v);
  double el, eh;
  const double sl = TwoSum(a.lo, b.lo, el), sh = TwoSum(a.hi, b.hi, eh);
  return Make(a.v + b.v, DownF(sl, std::isfinite(sl) ? el : 0.0), UpF(sh, std::isfinite(sh) ? eh : 0.0));
}

SpecReal operator-(SpecReal a) {
  SpecReal r = a;
  r.v = -a.v;
  r.lo = -a.hi;
  r.hi = -a.lo;
  return r;
}

SpecReal operator-(SpecReal a, SpecReal b) {
  SpecReal r = a + (-b);
  r.v = a.v - b.v;  // the same bits as a + (-b), written as the kernels do
  return r;
}

SpecReal Square(SpecReal x) {
  if (x.any) return SpecReal::Unbounded(x.v * x.v);
  // One value times itself: never negative, whichever value of [lo, hi] the device holds.
  const double l = double(x.lo) * x.lo, h = double(x.hi) * x.hi;
  const double lo = x.lo <= 0.0f && x.hi >= 0.0f ? 0.0 : std::min(l, h);
  return Make(x.v * x.v, DownF(lo), UpF(std::max(l, h)));
}

SpecReal Lesser(SpecReal x, SpecReal b) {
  const float v = b.v < x.v ? b.v : x.v;
  if (x.any || b.any) return SpecReal::Unbounded(v);
  return Make(v, std::min(x.lo, b.lo), std::min(x.hi, b.hi));
}

SpecReal Greater(SpecReal x, SpecReal b) {
  const float v = b.v > x.v ? b.v : x.v;
  if (x.any || b.any) return SpecReal::Unbounded(v);
  return Make(v, std::max(x.lo, b.lo), std::max(x.hi, b.hi));
}

SpecReal operator*(SpecReal a, SpecReal b) {
  if (a.any || b.any) return SpecReal::Unbounded(a.v * b.v);
  // Products of floats are exact in double.
  const double p[4] = {double(a.lo) * b.lo, double(a.lo) * b.hi, double(a.hi) * b.lo, double(a.hi) * b.hi};
  for (double x : p)
    if (std::isnan(x)) return SpecReal::Unbounded(a.v * b.v);
  return Make(a.v * b.v, DownF(*std::min_element(p, p + 4)), UpF(*std::max_element(p, p + 4)));
}

SpecReal operator/(SpecReal a, SpecReal b) {
  const float v = a.v / b.v;
  if (a.any || b.any || std::isinf(a.lo) || std::isinf(a.hi)) return SpecReal::Unbounded(v);
  // 2.5 ULP only for divisors of magnitude in [2^-126, 2^126]: a divisor interval that reaches out
  // of that range (or across zero) gets no bound.
  const bool positive = b.lo >= 0x1p-126f && b.hi <= 0x1p126f;
  const bool negative = b.hi <= -0x1p-126f && b.lo >= -0x1p126f;
  if (!positive && !negative) return SpecReal::Unbounded(v);
  const double q[4] = {double(a.lo) / b.lo, double(a.lo) / b.hi, double(a.hi) / b.lo, double(a.hi) / b.hi};
  for (double x : q)
    if (std::fabs(x) > double(FLT_MAX)) return SpecReal::Unbounded(v);  // 2.5 ULP of an overflow: infinity too
  float lo, hi;
  WithinUlps(*std::min_element(q, q + 4), *std::max_element(q, q + 4), 2.5, lo, hi);
  return Make(v, lo, hi);
}

SpecReal Sqrt(SpecReal x) {
  const float v = std::sqrt(x.v);
  if (x.any || !(x.lo >= 0.0f) || std::isinf(x.hi)) return SpecReal::Unbounded(v);
  if (x.hi == 0.0f) return Make(v, 0.0f, 0.0f);  // sqrt(+-0) = +-0
  // inversesqrt within 2 ULP at both ends (monotone decreasing), then 1 / r within 2.5 ULP.
  float r_lo, r_hi, unused;
  const double e_hi = 1.0 / std::sqrt(double(x.hi));
  WithinUlps(e_hi, e_hi, 2.0, r_lo, unused);
  if (x.lo > 0.0f) {
    const double e_lo = 1.0 / std::sqrt(double(x.lo));
    WithinUlps(e_lo, e_lo, 2.0, unused, r_hi);
  } else {
    r_hi = kInf;  // inversesqrt(0) = inf, and sqrt(0) = 0
  }
  float lo = 0.0f, hi, ignore;
  WithinUlps(1.0 / double(r_lo), 1.0 / double(r_lo), 2.5, ignore, hi);
  if (!std::isinf(r_hi)) WithinUlps(1.0 / double(r_hi), 1.0 / double(r_hi), 2.5, lo, ignore);
  return Make(v, lo, hi);
}

SpecReal Abs(SpecReal x) {
  SpecReal r = x;
  r.v = std::fabs(x.v);
  if (x.any) return r;
  if (x.lo >= 0.0f) return r;
  if (x.hi <= 0.0f) {
    r.lo = -x.hi;
    r.hi = -x.lo;
    return r;
  }
  r.lo = 0.0f;
  r.hi = std::max(-x.lo, x.hi);
  return r;
}

// GLSL min/max on lavapipe return the first operand when the second is NaN (emu Min/Max); the bounds
// follow the same selection for every pair of permitted operands.
SpecReal Min(SpecReal a, SpecReal b) {
  SpecReal r{};
  r.v = std::isnan(b.v) ? a.v : (a.v < b.v ? a.v : b.v);
  if (a.any || b.any) return SpecReal::Unbounded(r.v);
  r.lo = std::min(a.lo, b.lo);
  r.hi = std::min(a.hi, b.hi);
  return r;
}

SpecReal Max(SpecReal a, SpecReal b) {
  SpecReal r{};
  r.v = std::isnan(b.v) ? a.v : (a.v > b.v ? a.v : b.v);
  if (a.any || b.any) return SpecReal::Unbounded(r.v);
  r.lo = std::max(a.lo, b.lo);
  r.hi = std::max(a.hi, b.hi);
  return r;
}

SpecReal Clamp(SpecReal x, SpecReal lo, SpecReal hi) { return Min(Max(x, lo), hi); }

SpecReal NextAfter(SpecReal x, float toward) {
  SpecReal r = x;
  r.v = std::nextafter(x.v, toward);
  if (x.any) return r;
  r.lo = std::nextafter(x.lo, toward);
  r.hi = std::nextafter(x.hi, toward);
  return Flushed(r);
}

SpecReal InversePowerOfTwo(SpecReal m) { return SpecReal(emu::InversePowerOfTwo(m.v)); }

bool operator<(SpecReal a, SpecReal b) {
  return Decide(a, b, [](const SpecReal& x, const SpecReal& y) { return x.hi < y.lo ? 1 : (x.lo >= y.hi ? 0 : -1); },
                [](float x, float y) { return x < y; });
}
bool operator<=(SpecReal a, SpecReal b) {
  return Decide(a, b, [](const SpecReal& x, const SpecReal& y) { return x.hi <= y.lo ? 1 : (x.lo > y.hi ? 0 : -1); },
                [](float x, float y) { return x <= y; });
}
bool operator>(SpecReal a, SpecReal b) { return b < a; }
bool operator>=(SpecReal a, SpecReal b) { return b <= a; }
bool operator==(SpecReal a, SpecReal b) {
  return Decide(
      a, b,
      [](const SpecReal& x, const SpecReal& y) {
        if (x.lo == x.hi && y.lo == y.hi && x.lo == y.lo) return 1;
        return (x.hi < y.lo || y.hi < x.lo) ? 0 : -1;
      },
      [](float x, float y) { return x == y; });
}
bool operator!=(SpecReal a, SpecReal b) { return !(a == b); }

}  // namespace rayspace::verify
