#include "device_math.h"

#include <bit>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

namespace rayspace::sim {
namespace {

template <class F> F Flush(F x) { return std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(F(0), x) : x; }

float F32(std::uint64_t bits) { return Flush(std::bit_cast<float>(static_cast<std::uint32_t>(bits))); }
double F64(std::uint64_t bits) { return Flush(std::bit_cast<double>(bits)); }
std::uint64_t Bits(float x) { return std::bit_cast<std::uint32_t>(Flush(x)); }
std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(Flush(x)); }

// `r`, a correctly rounded result whose exact value is r + err, rounded toward zero instead.
float TowardZero(float r, float err) {
  if (std::isinf(r)) return std::nextafter(r, 0.0f);  // an overflow of finite operands
  return err != 0 && std::signbit(err) != std::signbit(r) ? std::nextafter(r, 0.0f) : r;
}

float AddTowardZero(float a, float b) {
  const float s = a + b;
  if (!std::isfinite(a) || !std::isfinite(b) || std::isnan(s)) return s;
  if (std::isinf(s)) return TowardZero(s, 0);
  // Knuth's TwoSum: the exact error of the rounded sum, itself a float.
  const float bp = s - a, ap = s - bp;
  return TowardZero(s, (a - ap) + (b - bp));
}

float MulTowardZero(float a, float b) {
  const double p = static_cast<double>(a) * static_cast<double>(b);  // exact: 48 significant bits
  const float r = static_cast<float>(p);
  if (std::isnan(p) || std::isinf(p)) return r;
  return std::fabs(static_cast<double>(r)) > std::fabs(p) ? std::nextafter(r, 0.0f) : r;
}

// k ULP away from zero (up) or toward it, stopping at the largest finite value.
float Step(float r, int k, bool up) {
  if (!std::isfinite(r) || r == 0) return r;
  for (int i = 0; i < k; ++i) {
    const float n = std::nextafter(r, up ? std::copysign(std::numeric_limits<float>::infinity(), r) : 0.0f);
    if (std::isinf(n) || n == 0) break;
    r = n;
  }
  return r;
}

// A double result carried at single precision: rounded toward zero to 24 significant bits.
double Single(double v) {
  if (!std::isfinite(v) || v == 0) return Flush(v);
  return Flush(std::bit_cast<double>(std::bit_cast<std::uint64_t>(v) & ~((std::uint64_t{1} << 29) - 1)));
}

// k ULP of 24 significant bits away from zero (up) or toward it.
double Step(double r, int k, bool up) {
  if (!std::isfinite(r) || r == 0) return r;
  for (int i = 0; i < k; ++i) {
    // Toward zero from a power of two the ULP below is half as large.
    const int e = std::ilogb(r) - 23 - (!up && std::fabs(r) == std::ldexp(1.0, std::ilogb(r)) ? 1 : 0);
    r += std::copysign(std::ldexp(1.0, e), r) * (up ? 1 : -1);
  }
  return r;
}

// |r - q| in ULP of `bits`-bit significands at q's magnitude (normal range).
double Ulps(double r, double q, int bits, int min_exponent) {
  const int e = std::max(std::ilogb(q), min_exponent);
  return std::fabs(r - q) / std::ldexp(1.0, e - (bits - 1));
}

// `rounded` (q correctly rounded, or toward zero) moved k ULP in the drawn direction, or the other
// way, or by one: the first that stays within `bound` ULP of q (at a power of two the ULP above is
// twice the one below, so a step up from a rounded-up result may leave the bound).
template <class F>
F Loose(F rounded, double q, int k, bool up, double bound) {
  if (!std::isfinite(rounded) || rounded == 0 || !std::isfinite(q)) return rounded;
  constexpr int bits = 24, min_exponent = std::is_same_v<F, float> ? -126 : -1022;
  for (const auto& [kk, uu] : {std::pair{k, up}, std::pair{k, !up}, std::pair{1, up}, std::pair{1, !up}}) {
    const F r = Step(rounded, kk, uu);
    if (r != rounded && Ulps(static_cast<double>(r), q, bits, min_exponent) <= bound) return r;
  }
  return rounded;
}

std::uint64_t Mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

std::uint64_t DeviceMath::Draw(FloatOpKind op, std::uint64_t a, std::uint64_t b) const {
  return Mix(seed_ ^ Mix(static_cast<std::uint64_t>(op) ^ Mix(a ^ Mix(b))));
}

std::uint64_t DeviceMath::Binary(FloatOpKind op, std::uint32_t width, std::uint64_t a_bits, std::uint64_t b_bits) const {
  // The draw decides only the loose division and roots: hashed for those alone.
  const bool loose = op == FloatOpKind::kDiv || op == FloatOpKind::kInverseSqrt;
  const std::uint64_t draw = loose ? Draw(op, a_bits, b_bits) : 0;
  const int k = 1 + static_cast<int>(draw & 1);
  const bool up = (draw >> 1) & 1;
  if (width == 32) {
    const float a = F32(a_bits), b = F32(b_bits);
    switch (op) {
      case FloatOpKind::kAdd: return Bits(toward_zero_ ? AddTowardZero(a, b) : a + b);
      case FloatOpKind::kSub: return Bits(toward_zero_ ? AddTowardZero(a, -b) : a - b);
      case FloatOpKind::kMul: return Bits(toward_zero_ ? MulTowardZero(a, b) : a * b);
      // The exact quotient and root, within 2^-52 relative in double: far inside the margins below.
      case FloatOpKind::kDiv: return Bits(Loose(a / b, static_cast<double>(a) / static_cast<double>(b), k, up, 2.4));
      case FloatOpKind::kInverseSqrt: {
        if (!(a > 0) || std::isinf(a)) return Bits(1.0f / std::sqrt(a));
        const double q = 1.0 / std::sqrt(static_cast<double>(a));
        return Bits(Loose(static_cast<float>(q), q, 1, up, 1.9));
      }
      case FloatOpKind::kSqrt:
        return Binary(FloatOpKind::kDiv, 32, Bits(1.0f), Binary(FloatOpKind::kInverseSqrt, 32, a_bits, a_bits));
      case FloatOpKind::kMin: return std::isnan(a) ? Bits(a) : std::isnan(b) ? Bits(b) : Bits(b < a ? b : a);
      case FloatOpKind::kMax: return std::isnan(a) ? Bits(a) : std::isnan(b) ? Bits(b) : Bits(b > a ? b : a);
      case FloatOpKind::kFused: break;
    }
    return Bits(a);
  }
  const double a = F64(a_bits), b = F64(b_bits);
  switch (op) {
    case FloatOpKind::kAdd: return Bits(Single(a + b));
    case FloatOpKind::kSub: return Bits(Single(a - b));
    case FloatOpKind::kMul: return Bits(Single(a * b));
    // Here the exact values are known to 2^-53, far inside single precision's ULP.
    case FloatOpKind::kDiv: return Bits(Loose(Single(a / b), a / b, k, up, 2.4));
    case FloatOpKind::kInverseSqrt: return Bits(Loose(Single(1.0 / std::sqrt(a)), 1.0 / std::sqrt(a), 1, up, 1.9));
    case FloatOpKind::kSqrt: return Binary(FloatOpKind::kDiv, 64, Bits(1.0), Binary(FloatOpKind::kInverseSqrt, 64, a_bits, a_bits));
    case FloatOpKind::kMin: return std::isnan(a) ? Bits(a) : std::isnan(b) ? Bits(b) : Bits(b < a ? b : a);
    case FloatOpKind::kMax: return std::isnan(a) ? Bits(a) : std::isnan(b) ? Bits(b) : Bits(b > a ? b : a);
    case FloatOpKind::kFused: break;
  }
  return Bits(a);
}

std::uint64_t DeviceMath::Fused(std::uint32_t width, std::uint64_t a, std::uint64_t b, std::uint64_t c) const {
  if (width == 32) return Bits(std::fma(F32(a), F32(b), F32(c)));
  return Bits(Single(std::fma(F64(a), F64(b), F64(c))));
}

std::uint64_t DeviceMath::FromDouble(std::uint32_t width, double v) const {
  if (width == 64) return Bits(Single(v));
  const float r = static_cast<float>(v);
  if (std::isnan(v) || std::isinf(v) || !toward_zero_) return Bits(r);
  return Bits(std::fabs(static_cast<double>(r)) > std::fabs(v) ? std::nextafter(r, 0.0f) : r);
}

std::uint64_t DeviceMath::FromInteger(std::uint32_t width, std::uint64_t magnitude, bool negative) const {
  // 24 significant bits, the rest cut: toward zero, in single precision for either width.
  if (!toward_zero_ && width == 32) return Bits(negative ? -static_cast<float>(magnitude) : static_cast<float>(magnitude));
  if (magnitude >> 24) {
    const int drop = 64 - std::countl_zero(magnitude) - 24;
    magnitude = magnitude >> drop << drop;
  }
  const double v = negative ? -static_cast<double>(magnitude) : static_cast<double>(magnitude);  // exact: 24 bits
  return width == 64 ? Bits(v) : Bits(static_cast<float>(v));
}

}  // namespace rayspace::sim
