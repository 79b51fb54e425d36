// The worst-conformant device's arithmetic against the bounds Vulkan sets (docs/simulator.md,
// "Device models"), on random and hand-picked operands: each loose operation stays inside its bound
// and differs from the correctly rounded value where the bound leaves room; the exact ones (min and
// max of numbers) stay exact; the same operands give the same bits, other seeds other bits.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "../src/device_math.h"

namespace {

using rayspace::sim::DeviceMath;
using rayspace::sim::FloatOpKind;

std::uint64_t B(float x) { return std::bit_cast<std::uint32_t>(x); }
float F(std::uint64_t bits) { return std::bit_cast<float>(static_cast<std::uint32_t>(bits)); }
std::uint64_t B(double x) { return std::bit_cast<std::uint64_t>(x); }
double D(std::uint64_t bits) { return std::bit_cast<double>(bits); }

// The distance from `r` to the exact `q`, in ULP of float at q's magnitude.
double UlpsFrom(float r, double q) {
  const int e = std::max(std::ilogb(static_cast<float>(q)), -126);
  return std::fabs(static_cast<double>(r) - q) / std::ldexp(1.0, e - 23);
}

float Random(std::mt19937& rng) {
  std::uniform_real_distribution<float> m(1.0f, 2.0f);
  std::uniform_int_distribution<int> e(-40, 40);
  return std::ldexp(m(rng), e(rng)) * (rng() % 2 ? 1.0f : -1.0f);
}

}  // namespace

TEST_CASE("device math: +, - and * round toward zero, the other neighbour of an inexact result") {
  const DeviceMath m(1);
  // 1 + 1.5 * 2^-24: nearest is 1 + 2^-23, toward zero 1.
  CHECK(F(m.Binary(FloatOpKind::kAdd, 32, B(1.0f), B(1.5f * 0x1p-24f))) == 1.0f);
  CHECK(F(m.Binary(FloatOpKind::kSub, 32, B(-1.0f), B(1.5f * 0x1p-24f))) == -1.0f);
  CHECK(F(m.Binary(FloatOpKind::kAdd, 32, B(1.0f), B(2.0f))) == 3.0f);  // exact stays exact
  // An overflow of finite operands stays finite, as toward-zero rounding does.
  CHECK(F(m.Binary(FloatOpKind::kMul, 32, B(0x1p100f), B(0x1p100f))) == std::numeric_limits<float>::max());
  std::mt19937 rng(7);
  int moved = 0;
  for (int i = 0; i < 100000; ++i) {
    const float a = Random(rng), b = Random(rng);
    const double exact = static_cast<double>(a) * static_cast<double>(b);  // exact: 48 bits
    const float r = F(m.Binary(FloatOpKind::kMul, 32, B(a), B(b)));
    REQUIRE(std::fabs(static_cast<double>(r)) <= std::fabs(exact));
    REQUIRE(UlpsFrom(r, exact) < 1.0);
    moved += r != a * b;
  }
  CHECK(moved > 30000);  // about half the inexact products round the other way
}

TEST_CASE("device math: / within 2.5 ULP and never the correctly rounded quotient; inversesqrt within 2, sqrt as 1 / inversesqrt") {
  const DeviceMath m(3);
  std::mt19937 rng(11);
  for (int i = 0; i < 100000; ++i) {
    const float a = Random(rng), b = Random(rng);
    const double q = static_cast<double>(a) / static_cast<double>(b);
    const float r = F(m.Binary(FloatOpKind::kDiv, 32, B(a), B(b)));
    REQUIRE(UlpsFrom(r, q) <= 2.5);
    REQUIRE(r != a / b);
    const float x = std::fabs(a);
    const double is = 1.0 / std::sqrt(static_cast<double>(x));
    const float ri = F(m.Binary(FloatOpKind::kInverseSqrt, 32, B(x), B(x)));
    REQUIRE(UlpsFrom(ri, is) <= 2.0);
    REQUIRE(ri != static_cast<float>(is));
    // 1 / inversesqrt: a relative error of at most 2 ULP (2 x 2^-23), then a 2.5-ULP division.
    const double root = std::sqrt(static_cast<double>(x));
    REQUIRE(std::fabs(F(m.Binary(FloatOpKind::kSqrt, 32, B(x), B(x))) / root - 1) <= 4.51 * 0x1p-23);
  }
  CHECK(F(m.Binary(FloatOpKind::kSqrt, 32, B(0.0f), B(0.0f))) == 0.0f);
  CHECK(std::signbit(F(m.Binary(FloatOpKind::kSqrt, 32, B(-0.0f), B(-0.0f)))));
  CHECK(std::isinf(F(m.Binary(FloatOpKind::kSqrt, 32, B(INFINITY), B(INFINITY)))));
  CHECK(std::isnan(F(m.Binary(FloatOpKind::kSqrt, 32, B(-1.0f), B(-1.0f)))));
}

TEST_CASE("device math: double operations carry single precision") {
  const DeviceMath m(5);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(1.0, 2.0);
  for (int i = 0; i < 20000; ++i) {
    const double a = u(rng), b = u(rng);
    const double add = D(m.Binary(FloatOpKind::kAdd, 64, B(a), B(b))), div = D(m.Binary(FloatOpKind::kDiv, 64, B(a), B(b)));
    REQUIRE(std::fabs(add - (a + b)) <= std::ldexp(std::fabs(a + b), -23));
    REQUIRE(std::fabs(div - a / b) <= 3 * std::ldexp(std::fabs(a / b), -23));
    REQUIRE((std::bit_cast<std::uint64_t>(add) & ((1ull << 29) - 1)) == 0);  // 24 significant bits
  }
  CHECK(D(m.FromInteger(64, (1ull << 40) + 1, false)) == 0x1p40);
  CHECK(D(m.FromDouble(64, 1.0 + 0x1p-30)) == 1.0);
}

TEST_CASE("device math: conversions toward zero, min and max return a NaN operand, denormals flush") {
  const DeviceMath m(1);
  CHECK(F(m.FromInteger(32, (1u << 25) + 3, false)) == 0x1p25f + 2);  // nearest: + 4
  CHECK(F(m.FromInteger(32, (1u << 25) + 3, true)) == -(0x1p25f + 2));
  CHECK(F(m.FromDouble(32, 0.1)) < 0.1f);
  CHECK(F(m.FromDouble(32, 0.1)) == std::nextafter(0.1f, 0.0f));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(std::isnan(F(m.Binary(FloatOpKind::kMin, 32, B(1.0f), B(nan)))));
  CHECK(std::isnan(F(m.Binary(FloatOpKind::kMax, 32, B(nan), B(1.0f)))));
  CHECK(F(m.Binary(FloatOpKind::kMin, 32, B(1.0f), B(-2.0f))) == -2.0f);
  CHECK(F(m.Binary(FloatOpKind::kMax, 32, B(1.0f), B(-2.0f))) == 1.0f);
  const float tiny = 0x1p-140f;  // a denormal
  CHECK(m.Binary(FloatOpKind::kAdd, 32, B(tiny), B(0.0f)) == B(0.0f));
  CHECK(m.Binary(FloatOpKind::kMul, 32, B(-0x1p-70f), B(0x1p-70f)) == B(-0.0f));
  CHECK(F(m.Binary(FloatOpKind::kMax, 32, B(tiny), B(0.0f))) == 0.0f);
}

TEST_CASE("device math: the worst-nearest model rounds +, -, * and conversions to nearest, and the rest as the worst") {
  const DeviceMath m(1, false);
  CHECK(F(m.Binary(FloatOpKind::kAdd, 32, B(1.0f), B(1.5f * 0x1p-24f))) == 1.0f + 0x1p-23f);
  CHECK(F(m.FromInteger(32, (1u << 25) + 3, false)) == 0x1p25f + 4);
  CHECK(F(m.FromDouble(32, 0.1)) == 0.1f);
  CHECK(F(m.Binary(FloatOpKind::kDiv, 32, B(1.0f), B(3.0f))) != 1.0f / 3.0f);
}

TEST_CASE("device math: fused multiply-add rounds once") {
  const DeviceMath m(1);
  // (1 + 2^-12)^2 - 1 = 2^-11 + 2^-24: rounded after the multiply, the 2^-24 is lost.
  const float x = 1.0f + 0x1p-12f;
  CHECK(F(m.Fused(32, B(x), B(x), B(-1.0f))) == 0x1p-11f + 0x1p-24f);
  CHECK(x * x - 1.0f == 0x1p-11f);
}

TEST_CASE("device math: the same operands give the same bits; another seed other bits") {
  const DeviceMath a(1), b(1), c(2);
  std::mt19937 rng(17);
  int differ = 0;
  for (int i = 0; i < 1000; ++i) {
    const float x = Random(rng), y = Random(rng);
    REQUIRE(a.Binary(FloatOpKind::kDiv, 32, B(x), B(y)) == b.Binary(FloatOpKind::kDiv, 32, B(x), B(y)));
    differ += a.Binary(FloatOpKind::kDiv, 32, B(x), B(y)) != c.Binary(FloatOpKind::kDiv, 32, B(x), B(y));
  }
  CHECK(differ > 300);
}
