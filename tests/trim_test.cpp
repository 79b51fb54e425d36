// Order-preserving compaction: the scan and scatter equal a sequential copy_if for every size around
// the scan's block boundaries and every schedule.
#include <doctest/doctest.h>

#include <numeric>
#include <random>

#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

using namespace rayspace;

TEST_CASE("trim: exclusive scan and scatter keep input order") {
  std::mt19937 rng(11);
  for (std::size_t n : {0u, 1u, 4095u, 4096u, 4097u, 12289u, 100000u}) {
    for (std::size_t chunk : {0u, 1u, 13u}) {
      SetChunkSize(chunk);
      emu::SparseRays s;
      s.rays.resize(n);
      s.flags.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        s.flags[i] = rng() % 3 == 0 ? 1u : 0u;
        s.rays[i].info.w = static_cast<std::uint32_t>(i);
      }
      std::uint32_t total = 0;
      const auto scan = emu::ExclusiveScan(s.flags, &total);
      std::vector<std::uint32_t> expect(n);
      std::exclusive_scan(s.flags.begin(), s.flags.end(), expect.begin(), 0u);
      CHECK(scan == expect);
      const emu::Trimmed t = emu::PassTrim({.kind = layout::kRayShadow, .rays = s.rays, .flags = s.flags});
      std::vector<std::uint32_t> kept, got;
      for (std::size_t i = 0; i < n; ++i)
        if (s.flags[i]) kept.push_back(static_cast<std::uint32_t>(i));
      for (const auto& r : t.rays) got.push_back(r.info.w);
      INFO("n " << n << " chunk " << chunk);
      CHECK(total == kept.size());
      CHECK(got == kept);
    }
  }
  SetChunkSize(0);
}
