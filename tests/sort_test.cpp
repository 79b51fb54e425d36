// Ray sorting: compress, radix sort of chunk keys and decompress.
#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/workgroup.h"
#include "test_settings.h"

using namespace rayspace;
using namespace rayspace::emu;

TEST_CASE("sort: compress, radix sort and decompress equal a stable sort by key") {
  std::mt19937 rng(5);
  for (std::size_t n : {1u, 2u, 100u, 5000u, 70000u}) {
    std::vector<std::uint32_t> keys(n);
    // Runs of equal keys (what compression exploits) and keys using every byte.
    for (std::size_t i = 0; i < n;) {
      const std::uint32_t k = rng() % 7 == 0 ? rng() : rng() % 97;
      for (std::size_t r = 1 + rng() % 5; r > 0 && i < n; --r) keys[i++] = k;
    }
    const Chunks c = PassCompress({.keys = keys});
    const std::vector<std::uint32_t> sorted = PassSortChunks({.chunk_key = c.key});
    const std::vector<std::uint32_t> order =
        PassDecompress({.chunk_key = c.key, .chunk_base = c.base, .chunk_size = c.size, .chunk_order = sorted});
    std::vector<std::uint32_t> expect(n);
    std::iota(expect.begin(), expect.end(), 0u);
    std::stable_sort(expect.begin(), expect.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    INFO("n = " << n);
    CHECK(order == expect);
    CHECK(c.key.size() <= n);
  }
}

TEST_CASE("sort: the radix mirror is a stable sort at every local size and schedule, the checker silent") {
  rayspace::test::TestSettings settings;
  std::mt19937 rng(17);
  std::vector<std::uint32_t> keys(3 * 4096 + 333);
  for (auto& k : keys) k = rng() % 5 == 0 ? rng() : rng() % 300;  // many equal digits: stability matters
  std::vector<std::uint32_t> expect(keys.size());
  std::iota(expect.begin(), expect.end(), 0u);
  std::stable_sort(expect.begin(), expect.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  // 4 blocks: the bin scan takes a workgroup per bin at local sizes 1 and 7, and packs 2, 16, 64 and
  // 128 bins into a workgroup at 12, 64, 256 and 1024 (layout::SortBinsPerGroup).
  for (std::uint32_t local : {1u, 7u, 12u, 64u, 256u, 1024u})
    for (wg::Schedule s : {wg::Schedule{wg::Order::kForward, 0}, wg::Schedule{wg::Order::kReverse, 0},
                           wg::Schedule{wg::Order::kRandom, 21}}) {
      INFO("local size " << local << " order " << static_cast<int>(s.order));
      settings->local_size = local;
      settings->schedule = s;
      CHECK(PassSortChunks({.chunk_key = keys}) == expect);  // checker on: a report throws
    }
}

TEST_CASE("sort: the fused path's host radix sort gives the kernel mirror's permutation") {
  std::mt19937 rng(23);
  for (std::size_t n : {0u, 1u, 2u, 1000u, 70000u}) {
    // Ties everywhere (stability), keys equal in whole digits (skipped passes), keys using every bit.
    std::vector<std::uint32_t> keys(n);
    for (auto& k : keys) k = rng() % 3 == 0 ? rng() : rng() % 3 == 0 ? (rng() % 8) << 22 : rng() % 500;
    INFO("n = " << n);
    CHECK(SortChunksHost({.chunk_key = keys}) == PassSortChunks({.chunk_key = keys}));
  }
}
