// Known answers for the resolve pass: fixed-point accumulator -> 8-bit RGB with display gamma 2.
#include <doctest/doctest.h>

#include "rayspace/emu/passes.h"

using namespace rayspace;
using namespace rayspace::emu;

TEST_CASE("resolve: 0 -> 0, full scale -> 255, sqrt gamma, clamped above 1") {
  // Three pixels, nine channels.
  const std::uint64_t one = std::uint64_t{1} << 32;  // kAccumScale: colour 1.0
  const std::vector<std::uint64_t> accum = {
      0,                // 0 -> 0
      one,              // 1 -> 255
      one / 4,          // 1/4 -> sqrt = 1/2 -> 127.5 rounds to 128
      one / 16,         // 1/16 -> 1/4 -> 63.75 + 0.5 -> 64
      one / 16 * 9,     // 9/16 -> 3/4 -> 191.25 + 0.5 -> 191
      2 * one,          // 2 -> clamped to 1 -> 255
      1000 * one,       // far above 1 -> 255
      one / 64,         // 1/64 -> 1/8 -> 31.875 + 0.5 -> 32
      one - 1,          // just below 1 -> 255
  };
  const std::vector<std::uint8_t> rgb = PassResolve({.accum = accum});
  const std::vector<std::uint8_t> expect = {0, 255, 128, 64, 191, 255, 255, 32, 255};
  CHECK(rgb == expect);
}
