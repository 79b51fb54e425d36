// The workgroup execution model (docs/workgroups.md): scans in shared memory and with subgroup
// operations against std::inclusive_scan under every schedule, and the checker's reports on planted
// faults (dropped barrier, divergent barrier, off-by-one, atomic against plain write).
#include <doctest/doctest.h>

#include <algorithm>
#include <malloc.h>

#include <numeric>
#include <random>

#include "rayspace/workgroup.h"
#include "test_settings.h"

using namespace rayspace;
using namespace rayspace::wg;

namespace {

std::vector<Schedule> AllSchedules() {
  std::vector<Schedule> s = {{Order::kForward, 0}, {Order::kReverse, 0}};
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) s.push_back({Order::kRandom, seed});
  return s;
}

std::vector<std::uint32_t> RandomInput(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> v(n);
  for (auto& x : v) x = rng();  // full 32-bit values: sums wrap, as uint does in GLSL
  return v;
}

std::vector<std::uint32_t> Expected(const std::vector<std::uint32_t>& in) {
  std::vector<std::uint32_t> out(in.size());
  std::inclusive_scan(in.begin(), in.end(), out.begin());
  return out;
}

// Adds the inclusive sums of the blocks before each block (second dispatch), after a serial exclusive
// scan of the block sums on the host.
void AddBlockOffsets(std::vector<std::uint32_t>& out, std::vector<std::uint32_t> sums, std::uint32_t L,
                     const DispatchOptions& o) {
  std::exclusive_scan(sums.begin(), sums.end(), sums.begin(), 0u);
  const auto n = static_cast<std::uint32_t>(out.size());
  const CheckResult r = Dispatch("scan.add", static_cast<std::uint32_t>(sums.size()), L, [&](Workgroup& w) {
    w.Phase([&](Inv& i) {
      if (i.global_id < n) out[i.global_id] += sums[i.workgroup_id];
    });
  }, o);
  CHECK(r.ok());
}

enum class Fault { kNone, kDropBarrier };

// Hillis-Steele inclusive scan of each block of L in shared memory, as the GLSL would be written:
//   tile[l] = v; barrier();
//   for (off = 1; off < L; off *= 2) { t = l >= off ? tile[l-off] : 0; barrier(); tile[l] += t; barrier(); }
// kDropBarrier omits the barrier between the read and the write: one phase `tile[l] += tile[l-off]`.
CheckResult HillisSteele(const std::vector<std::uint32_t>& in, std::vector<std::uint32_t>& out, std::uint32_t L,
                         const DispatchOptions& o, Fault fault) {
  const auto n = static_cast<std::uint32_t>(in.size());
  const std::uint32_t groups = (n + L - 1) / L;
  out.assign(n, 0);
  std::vector<std::uint32_t> sums(groups);
  CheckResult r = Dispatch("scan.hillis_steele", groups, L, [&](Workgroup& w) {
    auto& tile = w.Shared<std::uint32_t>(L, "tile");
    auto t = w.Private<std::uint32_t>();
    w.Phase([&](Inv& i) { tile[i.local_id] = i.global_id < n ? in[i.global_id] : 0u; });
    w.Barrier();
    for (std::uint32_t off = 1; off < L; off *= 2) {
      if (fault == Fault::kDropBarrier) {
        w.Phase([&](Inv& i) {
          if (i.local_id >= off) tile[i.local_id] += tile[i.local_id - off];
        });
      } else {
        w.Phase([&](Inv& i) { t[i] = i.local_id >= off ? static_cast<std::uint32_t>(tile[i.local_id - off]) : 0u; });
        w.Barrier();
        w.Phase([&](Inv& i) { tile[i.local_id] += t[i]; });
      }
      w.Barrier();
    }
    w.Phase([&](Inv& i) {
      if (i.global_id < n) out[i.global_id] = tile[i.local_id];
      if (i.local_id == L - 1) sums[i.workgroup_id] = tile[i.local_id];
    });
  }, o);
  AddBlockOffsets(out, sums, L, o);
  return r;
}

// Subgroup inclusive scan, then each invocation adds the totals of the subgroups before its own:
//   uint s = subgroupInclusiveAdd(v);
//   if (gl_SubgroupInvocationID == kAssumed - 1) totals[l / kAssumed] = s; barrier();
//   for (k = 0; k < l / kAssumed; ++k) s += totals[k];
// `assumed` is the subgroup size the kernel was written for (gl_SubgroupSize in a correct kernel).
CheckResult SubgroupScan(const std::vector<std::uint32_t>& in, std::vector<std::uint32_t>& out, std::uint32_t L,
                         const DispatchOptions& o, std::uint32_t assumed) {
  const auto n = static_cast<std::uint32_t>(in.size());
  const std::uint32_t groups = (n + L - 1) / L;
  out.assign(n, 0);
  std::vector<std::uint32_t> sums(groups);
  CheckResult r = Dispatch("scan.subgroup", groups, L, [&](Workgroup& w) {
    auto& totals = w.Shared<std::uint32_t>(L / assumed, "totals");
    auto v = w.Private<std::uint32_t>();
    w.Phase([&](Inv& i) { v[i] = i.global_id < n ? in[i.global_id] : 0u; });
    auto s = w.SubgroupInclusiveAdd(v);
    w.Phase([&](Inv& i) {
      if (i.local_id % assumed == assumed - 1) totals[i.local_id / assumed] = s[i];
    });
    w.Barrier();
    w.Phase([&](Inv& i) {
      for (std::uint32_t k = 0; k < i.local_id / assumed; ++k) s[i] += totals[k];
      if (i.global_id < n) out[i.global_id] = s[i];
      if (i.local_id == L - 1) sums[i.workgroup_id] = s[i];
    });
  }, o);
  AddBlockOffsets(out, sums, L, o);
  return r;
}

}  // namespace

TEST_CASE("workgroup: Hillis-Steele scan in shared memory equals std::inclusive_scan under every schedule") {
  for (std::uint32_t L : {64u, 256u}) {
    for (std::size_t n : {1u, 7u, 256u, 1000u, 4097u}) {
      const auto in = RandomInput(n, static_cast<unsigned>(n));
      const auto expect = Expected(in);
      for (const Schedule& s : AllSchedules()) {
        std::vector<std::uint32_t> out;
        const CheckResult r = HillisSteele(in, out, L, {.schedule = s, .check = true}, Fault::kNone);
        INFO("L=" << L << " n=" << n << " order=" << static_cast<int>(s.order) << " seed=" << s.seed);
        CHECK_MESSAGE(r.ok(), r.Summary());
        CHECK(out == expect);
      }
    }
  }
}

TEST_CASE("workgroup: subgroup scan plus workgroup combine equals std::inclusive_scan under every schedule") {
  for (std::uint32_t sg : {8u, 32u}) {
    for (std::size_t n : {1u, 7u, 256u, 1000u, 4097u}) {
      const auto in = RandomInput(n, static_cast<unsigned>(n) + 1);
      const auto expect = Expected(in);
      for (const Schedule& s : AllSchedules()) {
        std::vector<std::uint32_t> out;
        const CheckResult r = SubgroupScan(in, out, 256, {.subgroup_size = sg, .schedule = s, .check = true}, sg);
        INFO("subgroup=" << sg << " n=" << n << " order=" << static_cast<int>(s.order) << " seed=" << s.seed);
        CHECK_MESSAGE(r.ok(), r.Summary());
        CHECK(out == expect);
      }
    }
  }
}

TEST_CASE("workgroup: a scan with its barrier dropped is reported as a race and its result depends on the schedule") {
  const auto in = RandomInput(512, 3);
  const auto expect = Expected(in);
  bool some_wrong = false, some_right = false;
  for (const Schedule& s : AllSchedules()) {
    std::vector<std::uint32_t> out;
    const CheckResult r = HillisSteele(in, out, 256, {.schedule = s, .check = true}, Fault::kDropBarrier);
    CHECK(r.Count(ReportKind::kRace) > 0);
    CHECK(r.Count(ReportKind::kRace) == r.reports.size());
    (out == expect ? some_right : some_wrong) = true;
    if (s.order == Order::kForward) {
      // Invocation 2 reads tile[1] after invocation 1 wrote it, in the interval after the first barrier
      // (invocation 0 touches nothing: local_id >= 1 is false).
      REQUIRE(!r.reports.empty());
      const Report& first = r.reports.front();
      CHECK(first.dispatch == "scan.hillis_steele");
      CHECK(first.workgroup == 0);
      CHECK(first.array == "tile");
      CHECK(first.word == 1);
      CHECK(first.inv_a == 1);
      CHECK(first.inv_b == 2);
      CHECK(first.interval == 1);
      CHECK(first.phase == 1);
      CHECK(first.message.find("tile[1]") != std::string::npos);
    }
  }
  CHECK(some_wrong);  // forward: each invocation sees its neighbour's updated value
  CHECK(some_right);  // reverse: each reads before the neighbour writes, which happens to be correct
  // With checking off the same run reports nothing.
  std::vector<std::uint32_t> out;
  CHECK(HillisSteele(in, out, 256, {.check = false}, Fault::kDropBarrier).ok());
}

TEST_CASE("workgroup: a barrier inside if (local_id < 10) is reported divergent") {
  const CheckResult r = Dispatch("divergent", 2, 64, [&](Workgroup& w) {
    w.Phase([&](Inv& i) {
      if (i.local_id < 10) w.Barrier();
    });
  }, {.check = true});
  REQUIRE(r.reports.size() == 2);  // one per workgroup
  for (std::uint32_t g = 0; g < 2; ++g) {
    CHECK(r.reports[g].kind == ReportKind::kDivergentBarrier);
    CHECK(r.reports[g].workgroup == g);
    CHECK(r.reports[g].inv_a == 0);   // reached it
    CHECK(r.reports[g].inv_b == 10);  // did not
  }
  // Reached by every invocation inside a phase: not divergent, but the phase must be split there.
  const CheckResult u = Dispatch("uniform", 1, 64, [&](Workgroup& w) { w.Phase([&](Inv&) { w.Barrier(); }); },
                                 {.check = true});
  CHECK(u.Count(ReportKind::kBarrierInPhase) == 1);
  CHECK(u.Count(ReportKind::kDivergentBarrier) == 0);
  try {
    Dispatch("divergent", 1, 64, [&](Workgroup& w) {
      w.Phase([&](Inv& i) {
        if (i.local_id < 10) w.Barrier();
      });
    }, {.check = true, .throw_on_report = true});
    FAIL("no CheckError");
  } catch (const CheckError& e) {  // the exception carries the reports, and its message the first
    REQUIRE(e.result.reports.size() == 1);
    CHECK(std::string(e.what()).find(e.result.reports.front().message) != std::string::npos);
  }
}

TEST_CASE("workgroup: reading tile[i+1] past what was written is an uninitialised read or out of bounds") {
  const std::uint32_t L = 32;
  for (std::uint32_t count : {L + 1, L}) {
    std::vector<std::uint32_t> out(L);
    const CheckResult r = Dispatch("off_by_one", 1, L, [&](Workgroup& w) {
      auto& tile = w.Shared<std::uint32_t>(count, "tile");
      w.Phase([&](Inv& i) { tile[i.local_id] = i.local_id; });
      w.Barrier();
      w.Phase([&](Inv& i) { out[i.local_id] = tile[i.local_id + 1]; });
    }, {.check = true});
    REQUIRE(r.reports.size() == 1);
    CHECK(r.reports[0].kind == (count == L + 1 ? ReportKind::kUninitialisedRead : ReportKind::kOutOfBounds));
    CHECK(r.reports[0].word == L);
    CHECK(r.reports[0].inv_a == L - 1);
    CHECK(out[L - 1] == 0xa5a5a5a5u);  // poison
    CHECK(out[L - 2] == L - 1);
  }
}

TEST_CASE("workgroup: subgroup operations on a known input give the hand-computed answers") {
  const std::uint32_t L = 16;  // two subgroups of 8
  std::vector<std::uint32_t> add(L), incl(L), excl(L), bc(L), bcf(L), shuf(L), elect(L), ballot(L);
  const CheckResult r = Dispatch("subgroup.ops", 1, L, [&](Workgroup& w) {
    auto x = w.Private<std::uint32_t>();
    auto src = w.Private<std::uint32_t>();
    auto pred = w.Private<bool>();
    w.Phase([&](Inv& i) {
      x[i] = i.local_id + 1;
      src[i] = (i.lane + 1) % 8;
      pred[i] = i.local_id % 3 == 0;
    });
    const auto a = w.SubgroupAdd(x), in = w.SubgroupInclusiveAdd(x), ex = w.SubgroupExclusiveAdd(x);
    const auto b = w.SubgroupBroadcast(x, 3), f = w.SubgroupBroadcastFirst(x), sh = w.SubgroupShuffle(x, src);
    const auto e = w.SubgroupElect();
    const auto bal = w.SubgroupBallot(pred);
    w.Phase([&](Inv& i) {
      const std::uint32_t l = i.local_id;
      add[l] = a[i], incl[l] = in[i], excl[l] = ex[i], bc[l] = b[i], bcf[l] = f[i], shuf[l] = sh[i];
      elect[l] = e[i];
      ballot[l] = bal[i].x;
      CHECK(bal[i].y == 0u);
    });
  }, {.subgroup_size = 8, .check = true});
  CHECK(r.ok());
  using V = std::vector<std::uint32_t>;
  CHECK(add == V{36, 36, 36, 36, 36, 36, 36, 36, 100, 100, 100, 100, 100, 100, 100, 100});
  CHECK(incl == V{1, 3, 6, 10, 15, 21, 28, 36, 9, 19, 30, 42, 55, 69, 84, 100});
  CHECK(excl == V{0, 1, 3, 6, 10, 15, 21, 28, 0, 9, 19, 30, 42, 55, 69, 84});
  CHECK(bc == V{4, 4, 4, 4, 4, 4, 4, 4, 12, 12, 12, 12, 12, 12, 12, 12});
  CHECK(bcf == V{1, 1, 1, 1, 1, 1, 1, 1, 9, 9, 9, 9, 9, 9, 9, 9});
  CHECK(shuf == V{2, 3, 4, 5, 6, 7, 8, 1, 10, 11, 12, 13, 14, 15, 16, 9});
  CHECK(elect == V{1, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0});
  // local ids 0, 3, 6 -> lanes 0, 3, 6; local ids 9, 12, 15 -> lanes 1, 4, 7.
  CHECK(ballot == V{0x49, 0x49, 0x49, 0x49, 0x49, 0x49, 0x49, 0x49, 0x92, 0x92, 0x92, 0x92, 0x92, 0x92, 0x92, 0x92});
}

TEST_CASE("workgroup: subgroup min and max over a partial last subgroup") {
  const std::uint32_t L = 13;  // subgroups of 8 and 5
  std::vector<float> lo(L), hi(L);
  const CheckResult r = Dispatch("subgroup.reduce", 1, L, [&](Workgroup& w) {
    auto x = w.Private<float>();
    w.Phase([&](Inv& i) { x[i] = static_cast<float>((i.local_id * 5u) % 13u) - 6.0f; });  // a permutation of -6 .. 6
    const auto mn = w.SubgroupReduce(x, [](float a, float b) { return std::min(a, b); });
    const auto mx = w.SubgroupReduce(x, [](float a, float b) { return std::max(a, b); });
    w.Phase([&](Inv& i) { lo[i.local_id] = mn[i], hi[i.local_id] = mx[i]; });
  }, {.subgroup_size = 8, .check = true});
  CHECK(r.ok());
  // Local ids 0..7 hold -6, -1, 4, -4, 1, 6, -2, 3; ids 8..12 hold -5, 0, 5, -3, 2.
  using V = std::vector<float>;
  CHECK(lo == V{-6, -6, -6, -6, -6, -6, -6, -6, -5, -5, -5, -5, -5});
  CHECK(hi == V{6, 6, 6, 6, 6, 6, 6, 6, 5, 5, 5, 5, 5});
}

TEST_CASE("workgroup: ballot bit order is lane k in bit k % 32 of component k / 32") {
  glm::uvec4 seen(0);
  const CheckResult r = Dispatch("subgroup.ballot", 1, 128, [&](Workgroup& w) {
    auto pred = w.Private<bool>();
    w.Phase([&](Inv& i) { pred[i] = i.local_id == 33 || i.local_id == 70 || i.local_id == 127; });
    const auto b = w.SubgroupBallot(pred);
    w.Phase([&](Inv& i) {
      if (i.local_id == 5) seen = b[i];
    });
  }, {.subgroup_size = 128});
  CHECK(r.ok());
  CHECK(seen == glm::uvec4(0u, 1u << 1, 1u << 6, 1u << 31));
}

TEST_CASE("workgroup: a partial last subgroup and a broadcast from a lane it lacks") {
  std::vector<std::uint32_t> add(12);
  const CheckResult r = Dispatch("subgroup.partial", 1, 12, [&](Workgroup& w) {
    auto x = w.Private<std::uint32_t>();
    w.Phase([&](Inv& i) { x[i] = i.local_id; });
    const auto a = w.SubgroupAdd(x);
    w.Phase([&](Inv& i) { add[i.local_id] = a[i]; });
    w.SubgroupBroadcast(x, 6);  // lanes 8..11 form subgroup 1: lane 6 does not exist there
  }, {.subgroup_size = 8});
  CHECK(add == std::vector<std::uint32_t>{28, 28, 28, 28, 28, 28, 28, 28, 38, 38, 38, 38});
  REQUIRE(r.reports.size() == 1);
  CHECK(r.reports[0].kind == ReportKind::kInvalidLane);
  CHECK(r.reports[0].inv_a == 8);
}

TEST_CASE("workgroup: a kernel written for subgroup size 32 is wrong at size 8 and right at 32") {
  const auto in = RandomInput(1024, 11);
  const auto expect = Expected(in);
  std::vector<std::uint32_t> out;
  SubgroupScan(in, out, 256, {.subgroup_size = 8, .check = true}, 32);
  CHECK(out != expect);
  const CheckResult r = SubgroupScan(in, out, 256, {.subgroup_size = 32, .check = true}, 32);
  CHECK(r.ok());
  CHECK(out == expect);
}

TEST_CASE("workgroup: atomicAdd from every invocation gives the exact total under every schedule") {
  const std::uint32_t L = 256, groups = 40;
  for (const Schedule& s : AllSchedules()) {
    std::uint32_t global32 = 0;
    std::uint64_t global64 = 0;
    std::vector<std::uint32_t> per_group(groups), min_or(2 * groups);
    const CheckResult r = Dispatch("atomics", groups, L, [&](Workgroup& w) {
      auto& acc = w.Shared<std::uint32_t>(3, "acc");
      w.Phase([&](Inv& i) {
        if (i.local_id == 0) acc[0] = 0, acc[1] = 0xffffffffu, acc[2] = 0;
      });
      w.Barrier();
      w.Phase([&](Inv& i) {
        AtomicAdd(acc[0], i.local_id + 1);
        AtomicMin(acc[1], (i.local_id * 7919u) % 1000u + 5u);
        AtomicOr(acc[2], 1u << (i.local_id % 32));
        AtomicAdd(global32, i.global_id);
        AtomicAdd(global64, std::uint64_t{i.global_id} << 20);
      });
      w.Barrier();
      w.Phase([&](Inv& i) {
        if (i.local_id == 0) per_group[i.workgroup_id] = acc[0], min_or[2 * i.workgroup_id] = acc[1],
                             min_or[2 * i.workgroup_id + 1] = acc[2];
      });
    }, {.schedule = s, .check = true});
    CHECK_MESSAGE(r.ok(), r.Summary());
    std::uint32_t min = 0xffffffffu;
    for (std::uint32_t l = 0; l < L; ++l) min = std::min(min, (l * 7919u) % 1000u + 5u);
    for (std::uint32_t g = 0; g < groups; ++g) {
      CHECK(per_group[g] == L * (L + 1) / 2);
      CHECK(min_or[2 * g] == min);
      CHECK(min_or[2 * g + 1] == 0xffffffffu);
    }
    const std::uint64_t n = std::uint64_t{L} * groups;
    CHECK(global32 == static_cast<std::uint32_t>(n * (n - 1) / 2));
    CHECK(global64 == (n * (n - 1) / 2) << 20);
  }
}

TEST_CASE("workgroup: atomics on one word do not race, an atomic and a plain write do, and old values follow the schedule") {
  rayspace::test::TestSettings settings;
  auto run = [](bool plain_write, Schedule s, std::vector<std::uint32_t>* slots) {
    return Dispatch("atomics.race", 1, 16, [&](Workgroup& w) {
      auto& c = w.Shared<std::uint32_t>(1, "counter");
      w.Phase([&](Inv& i) {
        if (i.local_id == 0) c[0] = 0;
      });
      w.Barrier();
      w.Phase([&](Inv& i) {
        if (plain_write && i.local_id == 5) {
          c[0] = 100;
        } else {
          const std::uint32_t old = AtomicAdd(c[0], 1u);
          if (slots) (*slots)[i.local_id] = old;
        }
      });
    }, {.schedule = s, .check = true});
  };
  CHECK(run(false, {}, nullptr).ok());
  const CheckResult r = run(true, {}, nullptr);
  REQUIRE(r.reports.size() == 1);
  CHECK(r.reports[0].kind == ReportKind::kRace);
  CHECK(r.reports[0].word == 0);
  CHECK(r.reports[0].inv_a == 0);  // atomic, forward order: invocation 0 first
  CHECK(r.reports[0].inv_b == 5);  // the plain write
  // The returned old values (slot allocation) depend on the order; the total does not.
  std::vector<std::uint32_t> fwd(16), rev(16);
  run(false, {Order::kForward, 0}, &fwd);
  run(false, {Order::kReverse, 0}, &rev);
  CHECK(fwd[0] == 0);
  CHECK(rev[0] == 15);
  // The global setting applies when the dispatch does not override it.
  settings->schedule = {Order::kReverse, 0};
  std::vector<std::uint32_t> global(16);
  run(false, GetSchedule(), &global);
  settings->schedule = {};
  CHECK(global == rev);
}

TEST_CASE("workgroup: a dispatch frees its workgroups' shared arrays") {
  // Each workgroup declares 64 KiB of shared memory; 2,000 of them would hold 128 MiB if the arrays
  // outlived their workgroup (they are owned through their untyped base).
  const auto in_use = [] { return mallinfo2().uordblks + mallinfo2().hblkhd; };
  const std::size_t before = in_use();
  Dispatch("alloc", 2000, 1, [&](Workgroup& w) {
    auto& big = w.Shared<std::uint64_t>(8192, "big");
    w.Phase([&](Inv&) { big[0] = 1; });
  }, {.check = false});
  CHECK(in_use() < before + (16u << 20));
}
