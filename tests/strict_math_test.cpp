// The software division and square root of `--strict-math` (rayspace/strict_math.h, compiled into the
// kernels as well) against the host's IEEE operations, which round to nearest even: equal bits for
// random and boundary operands, denormals, overflow and every special value.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <random>

#include "rayspace/strict_math.h"

using rayspace::layout::DivRN;
using rayspace::layout::SqrtRN;

namespace {

bool SameBits(float expected, float actual) {
  if (std::isnan(expected)) return std::isnan(actual);
  return std::bit_cast<std::uint32_t>(expected) == std::bit_cast<std::uint32_t>(actual);
}

float FromBits(std::uint32_t u) { return std::bit_cast<float>(u); }

// Operands that stress the rounding: every exponent (denormals and the largest included), significands
// near a power of two or with runs of ones, and both signs.
float Operand(std::mt19937& rng) {
  const std::uint32_t kind = rng() % 4;
  std::uint32_t m = rng() & 0x7FFFFFu;
  if (kind == 1) m = 0x7FFFFFu ^ (rng() & 0xFu);
  if (kind == 2) m = rng() & 0xFu;
  const std::uint32_t e = kind == 3 ? (rng() % 2 ? 0u : 254u - rng() % 4) : rng() % 255;
  return FromBits((rng() & 0x80000000u) | (e << 23) | m);
}

}  // namespace

TEST_CASE("strict math: DivRN equals IEEE division bit for bit") {
  std::mt19937 rng(17);
  std::size_t wrong = 0, first = 0;
  float fa = 0, fb = 0;
  for (std::size_t i = 0; i < 3000000; ++i) {
    const float a = i % 2 ? Operand(rng) : FromBits(rng()), b = i % 3 ? Operand(rng) : FromBits(rng());
    if (!SameBits(a / b, DivRN(a, b)) && wrong++ == 0) first = i, fa = a, fb = b;
  }
  INFO("first wrong quotient at " << first << ": " << fa << " / " << fb << " = " << fa / fb << ", got " << DivRN(fa, fb));
  CHECK(wrong == 0);
}

TEST_CASE("strict math: DivRN's special values, gradual underflow and overflow") {
  const float inf = INFINITY, den = FromBits(1u), max = FromBits(0x7F7FFFFFu), tiny = FromBits(0x00800000u);
  const float cases[][2] = {{1, 0},   {-1, 0},     {0, 0},     {0, -5},   {inf, 2},  {inf, inf}, {3, inf},
                            {-3, inf}, {NAN, 1},   {1, NAN},   {max, 0.5f}, {max, -0.25f}, {den, 2}, {den, 0.5f},
                            {den, 3},  {tiny, 3},  {tiny, 1e30f}, {1, max}, {1, 3}, {2, 3}, {1e-30f, 1e10f},
                            {3 * den, 2}, {5 * den, 4}, {7 * den, 8}, {1, 1}, {-7, 7}, {6, 4}};
  for (const auto& c : cases) {
    INFO(c[0] << " / " << c[1]);
    CHECK(SameBits(c[0] / c[1], DivRN(c[0], c[1])));
  }
}

TEST_CASE("strict math: SqrtRN equals IEEE square root bit for bit") {
  std::mt19937 rng(23);
  std::size_t wrong = 0;
  float fx = 0;
  for (std::size_t i = 0; i < 3000000; ++i) {
    const float x = i % 2 ? std::fabs(Operand(rng)) : FromBits(rng());
    if (!SameBits(std::sqrt(x), SqrtRN(x)) && wrong++ == 0) fx = x;
  }
  // Every denormal and the first and last 2^16 significands of every binade.
  for (std::uint32_t e = 0; e < 255; ++e)
    for (std::uint32_t m = 0; m < 0x10000u; ++m)
      for (std::uint32_t mm : {m, 0x7FFFFFu - m}) {
        const float x = FromBits((e << 23) | mm);
        if (!SameBits(std::sqrt(x), SqrtRN(x)) && wrong++ == 0) fx = x;
      }
  INFO("first wrong root: sqrt(" << fx << ") = " << std::sqrt(fx) << ", got " << SqrtRN(fx));
  CHECK(wrong == 0);
  for (float x : {0.0f, -0.0f, -1.0f, INFINITY, -INFINITY, NAN, FromBits(1u), 4.0f, 2.0f})
    CHECK(SameBits(std::sqrt(x), SqrtRN(x)));
}
