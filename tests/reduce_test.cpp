// Stream reduction of traversal slots: hierarchical (Roger et al.) and scan-based.
#include <doctest/doctest.h>

#include <random>

#include "rayspace/emu/hierarchy.h"

using namespace rayspace;
using namespace rayspace::emu;

TEST_CASE("reduction: hierarchical and scan-based give identical streams for every component size") {
  std::mt19937 rng(9);
  for (std::size_t n : {0u, 1u, 63u, 64u, 65u, 10007u}) {
    std::vector<std::uint8_t> flags(n);
    std::vector<std::uint32_t> values(n);
    for (std::size_t i = 0; i < n; ++i) {
      flags[i] = rng() % 4 == 0;
      values[i] = static_cast<std::uint32_t>(i * 2654435761u);
    }
    const auto scan = ReduceScan(flags, values);
    std::vector<std::uint32_t> expect;
    for (std::size_t i = 0; i < n; ++i)
      if (flags[i]) expect.push_back(values[i]);
    CHECK(scan == expect);
    for (int s : {1, 2, 7, 64, 1000}) CHECK(ReduceHierarchical(flags, values, s) == expect);
  }
}
