// Order-preserving compaction: the scan and scatter equal a sequential copy_if for every size around
// the scan's block boundaries and every schedule.
#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "rayspace/emu/passes.h"
#include "rayspace/contract.h"
#include "rayspace/parallel.h"
#include "rayspace/workgroup.h"
#include "test_util.h"

using namespace rayspace;

TEST_CASE("trim: exclusive scan and scatter keep input order") {
  rayspace::test::TestSettings settings;
  std::mt19937 rng(11);
  for (std::size_t n : {0u, 1u, 4095u, 4096u, 4097u, 12289u, 100000u}) {
    for (std::size_t chunk : {0u, 1u, 13u}) {
      settings->chunk = chunk;
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
}

namespace {


std::vector<std::uint32_t> RandomFlags(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> f(n);
  for (auto& x : f) x = rng() % 3 == 0 ? 1u : 0u;
  return f;
}

}  // namespace

TEST_CASE("trim: the workgroup mirror is bit-identical under every schedule, local size and subgroup size") {
  rayspace::test::TestSettings settings;
  const std::vector<std::uint32_t> flags = RandomFlags(3 * 4096 + 77, 5);
  std::vector<std::uint32_t> expect(flags.size());
  std::exclusive_scan(flags.begin(), flags.end(), expect.begin(), 0u);
  for (std::uint32_t local : {1u, 7u, 32u, 64u, 256u, 1024u})
    for (std::uint32_t sg : {1u, 8u, 32u})
      for (wg::Schedule s : {wg::Schedule{wg::Order::kForward, 0}, wg::Schedule{wg::Order::kReverse, 0},
                             wg::Schedule{wg::Order::kRandom, 3}, wg::Schedule{wg::Order::kRandom, 99}}) {
        INFO("local size " << local << " subgroup " << sg << " order " << static_cast<int>(s.order) << " seed " << s.seed);
        settings->local_size = local;
        settings->subgroup_size = sg;
        settings->schedule = s;
        std::uint32_t total = 0;
        CHECK(emu::ExclusiveScan(flags, &total, {"trim"}) == expect);  // checker on: a report throws
        CHECK(total == expect.back() + flags.back());
      }
}

TEST_CASE("trim: each planted workgroup fault is named by the checker, and the wrong offset by the result") {
  rayspace::test::TestSettings settings;
  const std::vector<std::uint32_t> flags = RandomFlags(2 * 4096 + 5, 9);
  struct Case {
    std::uint32_t fault;
    wg::ReportKind kind;
  };
  for (const Case& c : {Case{layout::kFaultDroppedBarrier, wg::ReportKind::kRace},
                        Case{layout::kFaultDivergentBarrier, wg::ReportKind::kDivergentBarrier},
                        Case{layout::kFaultSubgroup32, wg::ReportKind::kRace},
                        Case{layout::kFaultSharedOffByOne, wg::ReportKind::kUninitialisedRead}}) {
    INFO("fault " << c.fault);
    settings->emu_faults = {{"trim", c.fault}};
    try {
      emu::PassTrim({.kind = layout::kRayShadow, .rays = std::vector<layout::Ray>(flags.size()), .flags = flags});
      FAIL("the checker did not report the planted fault");
    } catch (const wg::CheckError& e) {
      const auto it = std::find_if(e.result.reports.begin(), e.result.reports.end(),
                                   [&](const wg::Report& r) { return r.kind == c.kind; });
      REQUIRE(it != e.result.reports.end());
      CHECK(it->dispatch == "trim.BlockSums");
      CHECK(it->array == (c.kind == wg::ReportKind::kDivergentBarrier ? "" : "wg_tile"));
      CHECK(it->inv_a != wg::kNoInvocation);
    }
  }
  // Not a shared-memory fault: the checker stays silent, the offsets are wrong.
  settings->emu_faults = {{"trim", layout::kFaultWorkgroupOffset}};
  const emu::Trimmed t = emu::PassTrim({.kind = layout::kRayShadow, .rays = std::vector<layout::Ray>(flags.size()), .flags = flags});
  std::vector<std::uint32_t> expect(flags.size());
  std::exclusive_scan(flags.begin(), flags.end(), expect.begin(), 0u);
  CHECK(t.offsets != expect);
}

TEST_CASE("trim: schedule variation exposes a dropped barrier even with the checker off") {
  // Unchecked, the racy mirror runs on: its result depends on the order invocations run in, which is
  // what varying the schedule is for.
  rayspace::test::TestSettings settings;
  settings->check = false;
  settings->emu_faults = {{"trim", layout::kFaultDroppedBarrier}};
  const std::vector<std::uint32_t> flags = RandomFlags(4096, 13);
  std::uint32_t fwd_total = 0, rev_total = 0;
  settings->schedule = {wg::Order::kForward, 0};
  const auto fwd = emu::ExclusiveScan(flags, &fwd_total, emu::KernelSite::Of("trim"));
  settings->schedule = {wg::Order::kReverse, 0};
  const auto rev = emu::ExclusiveScan(flags, &rev_total, emu::KernelSite::Of("trim"));
  CHECK(fwd != rev);
}
