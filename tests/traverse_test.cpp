// Traversal: the cone-sphere test and conservative traversal (no accepted pair is culled), and
// traverse.compact's workgroup mirror against its lanes and against traverse + reduce.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <random>
#include <set>
#include <type_traits>

#include "rayspace/contract.h"
#include "rayspace/emu/backend.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/error.h"
#include "rayspace/refs/exact_cone.h"
#include "rayspace/workgroup.h"
#include "random_traversal.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;
using test::HRun;
using test::RunHierarchy;

TEST_CASE("cone test: wide cones, spheres behind the apex, the full sphere") {
  layout::ConeNode n = cone::FromRay({0, 0, 0}, {0, 0, 1});
  // A narrow cone misses a sphere beside and behind the apex but meets one around the apex.
  CHECK_FALSE(cone::Test(n, {5, 0, 1, 1}, 0));
  CHECK_FALSE(cone::Test(n, {0, 0, -5, 1}, 0));
  CHECK(cone::Test(n, {0, 0.5f, -0.5f, 1}, 0));
  CHECK(cone::Test(n, {0, 0.9f, 10, 1}, 0));
  // Half-angle 120 degrees: everything but a 60-degree cone behind the apex.
  n.cone.w = -0.5f;
  n.extra.x = std::sqrt(3.0f) / 2;
  CHECK(cone::Test(n, {5, 0, -1, 0.1f}, 0));        // 101 degrees off the axis: inside
  CHECK_FALSE(cone::Test(n, {0, 0.5f, -5, 0.1f}, 0));  // 174 degrees: outside, far from the surface
  CHECK(cone::Test(cone::FullSphereCone(n), {0, 0, -5, 0.1f}, 0));
}

TEST_CASE("traversal: every pair the final test accepts is a hierarchy candidate, flat and with the object tree (cornell-mirrors)") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  for (const bool tree : {false, true})
  for (Algorithm a : {Algorithm::kCrsh, Algorithm::kRah, Algorithm::kRahQuadtree}) {
    INFO("object tree " << tree << ", algorithm " << static_cast<int>(a));
    HierarchyConfig cfg;
    cfg.object_tree = tree;
    cfg.algorithm = a;
    cfg.depth = a == Algorithm::kRahQuadtree ? 5 : 2;
    cfg.subdivision = a == Algorithm::kRahQuadtree ? 4 : 8;
    std::vector<std::uint64_t> log;
    std::vector<std::vector<layout::Ray>> batches;
    // Re-run the frame with an observer to keep every batch's rays.
    const HRun r = RunHierarchy(s, 32, 32, cfg, &log);
    (void)r;
    // The log holds (ray, prim) per batch in batch order; rebuild the batches with the direct tracer.
    auto direct = MakeDirectTracer(b, DirectMode::kExhaustive);
    FrameOptions fo;
    fo.width = 32;
    fo.height = 32;
    RenderFrame(s, b, *direct, fo, [&](const Batch& batch) { batches.push_back(*batch.rays); });
    // Split the log at batch boundaries: ray indices restart per batch, so use the candidate count per
    // batch from the statistics.
    std::size_t at = 0, missing = 0, accepted = 0;
    REQUIRE(r.stats.size() == batches.size());
    for (std::size_t k = 0; k < batches.size(); ++k) {
      std::set<std::uint64_t> cand(log.begin() + at, log.begin() + at + r.stats[k].final_tests);
      at += r.stats[k].final_tests;
      const auto& rays = batches[k];
      for (std::uint32_t i = 0; i < rays.size(); ++i) {
        const WatertightRay wr = SetupWatertight(Xyz(rays[i].origin_tmin), Xyz(rays[i].direction_tmax));
        for (std::uint32_t p = 0; p < b.triangles.size(); ++p) {
          if (p == rays[i].info.y) continue;
          float t;
          if (!IntersectWatertight(wr, Xyz(b.triangles[p].v0), Xyz(b.triangles[p].v1), Xyz(b.triangles[p].v2),
                                   rays[i].origin_tmin.w, rays[i].direction_tmax.w, t))
            continue;
          ++accepted;
          missing += !cand.count((static_cast<std::uint64_t>(i) << 32) | p);
        }
      }
    }
    CHECK(at == log.size());
    CHECK(accepted > 1000);
    CHECK(missing == 0);
  }
}

namespace {

// Two top nodes at the origin (radius 0.1, half-angle 30 degrees, along +z and -z) and four
// triangle spheres: 0 on the +z axis, 1 far behind the +z node's apex (on the -z axis), 2 further up
// the +z axis, 3 beside both cones. Triangles 0, 1 are object 0; triangles 2, 3 object 1.
struct TopFixture {
  SceneBuffers b;
  std::vector<layout::ConeNode> top;
  std::vector<glm::vec4> spheres = {{0, 0, 10, 0.5f}, {0, 0, -100, 1}, {0, 0, 20, 0.5f}, {20, 0, 1, 1}};
  TopFixture() {
    Scene s;
    s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
    test::AddQuad(s, "a", {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    test::AddQuad(s, "b", {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1});
    b = FlattenScene(s);
    for (float z : {1.0f, -1.0f}) {
      layout::ConeNode n;
      n.sphere = glm::vec4(0, 0, 0, 0.1f);
      n.cone = glm::vec4(0, 0, z, std::sqrt(3.0f) / 2);
      n.extra = glm::vec4(0.5f, 8, 0, 0);
      top.push_back(n);
    }
  }
  call::TraverseTop Call(std::uint32_t t0, std::uint32_t t1, std::uint32_t b0, std::uint32_t b1) const {
    return {.top = top, .t0 = t0, .t1 = t1, .b0 = b0, .b1 = b1, .tri_spheres = spheres, .scene = &b, .object_mask = {}, .eps = 0.0f};
  }
};

std::uint32_t Pair(std::uint32_t node, std::uint32_t tri) { return node << kPairTriangleBits | tri; }

}  // namespace

TEST_CASE("traverse.top: spheres on the cone's axis are flagged, spheres behind the apex or beside it are not") {
  const TopFixture f;
  const PairSlots s = PassTraverseTop(f.Call(0, 2, 0, 4));
  // Slot node * 4 + triangle.
  CHECK(s.flags == std::vector<std::uint8_t>{1, 0, 1, 0, /* -z node: */ 0, 1, 0, 0});
  CHECK(s.tested == std::vector<std::uint8_t>(8, 1));
  CHECK(s.values == std::vector<std::uint32_t>{Pair(0, 0), Pair(0, 1), Pair(0, 2), Pair(0, 3), Pair(1, 0), Pair(1, 1),
                                              Pair(1, 2), Pair(1, 3)});
  // A sub-block: node 1 against triangles 1, 2, with ids relative to t0 and b0.
  const PairSlots sub = PassTraverseTop(f.Call(1, 2, 1, 3));
  CHECK(sub.flags == std::vector<std::uint8_t>{1, 0});
  CHECK(sub.values == std::vector<std::uint32_t>{Pair(0, 0), Pair(0, 1)});
}

TEST_CASE("traverse.top: an object mask of 0 skips the test and records tested = 0") {
  const TopFixture f;
  // Top nodes x objects: the +z node may not meet object 1; the -z node may meet both.
  const std::vector<std::uint8_t> mask = {1, 0, 1, 1};
  call::TraverseTop c = f.Call(0, 2, 0, 4);
  c.object_mask = mask;
  const PairSlots s = PassTraverseTop(c);
  CHECK(s.tested == std::vector<std::uint8_t>{1, 1, 0, 0, 1, 1, 1, 1});
  CHECK(s.flags == std::vector<std::uint8_t>{1, 0, 0, 0, 0, 1, 0, 0});  // triangle 2 is no longer flagged
}

TEST_CASE("traverse.compact: the emulator's backend gives the survivors of the slots in slot order and the tests run") {
  const TopFixture f;
  const std::vector<std::uint8_t> mask = {1, 0, 1, 1};
  call::TraverseTopCompacted c;
  static_cast<call::TraverseTop&>(c) = f.Call(0, 2, 0, 4);
  c.object_mask = mask;
  const Compacted r = EmuHierarchyPasses().TraverseTopCompacted(c);
  CHECK(r.pairs == std::vector<std::uint32_t>{Pair(0, 0), Pair(1, 1)});  // the flagged slots 0 and 5
  CHECK(r.tested == 6u);
  const PairSlots s = PassTraverseTop(c);
  CHECK(r.pairs == ReduceScan(s.flags, s.values));

  // One level down: each surviving pair's node has two children, copies of the two top nodes.
  std::vector<layout::ConeNode> children = {f.top[0], f.top[1], f.top[1], f.top[0]};
  const std::vector<std::uint32_t> first = {0, 2, 4};
  call::TraverseLevelCompacted lc;
  static_cast<call::TraverseLevel&>(lc) = {.pairs = r.pairs, .nodes = children, .first = first, .base_up = 0, .base = 0,
                                           .children_max = 3, .b0 = 0, .tri_spheres = f.spheres, .eps = 0.0f};
  const Compacted lr = EmuHierarchyPasses().TraverseLevelCompacted(lc);
  const PairSlots ls = PassTraverseLevel(lc);
  CHECK(lr.pairs == ReduceScan(ls.flags, ls.values));
  CHECK(lr.pairs == std::vector<std::uint32_t>{Pair(0, 0), Pair(2, 1)});
  CHECK(lr.tested == 4u);
}

// ---- traverse.compact's workgroup mirror (emu/src/traverse_compact_wg.cpp) ---------------------------

namespace {



// The shared random calls (random_traversal.h): a top level whose calls choose the object mask, and
// a lower level.
struct RandomTop : test::TopCase {
  using test::TopCase::TopCase;
  call::TraverseTop Call(std::uint32_t t0, std::uint32_t t1, std::uint32_t b0, std::uint32_t b1, bool masked, float eps = 0) const {
    return Top(t0, t1, b0, b1, masked, eps);
  }
};
struct RandomLevel : test::LevelCase {
  using test::LevelCase::LevelCase;
  call::TraverseLevel Call(float eps = 0) const { return Level(eps); }
};

// traverse, then reduce: the result traverse.compact stands for.
template <typename C>
Compacted TwoPasses(const C& c) {
  PairSlots s;
  if constexpr (std::is_same_v<C, call::TraverseTop>)
    s = PassTraverseTop(c);
  else
    s = PassTraverseLevel(c);
  Compacted r;
  for (std::uint8_t t : s.tested) r.tested += t;
  const std::vector<std::uint32_t> pairs = ReduceScan(s.flags, s.values);
  r.pairs.assign(pairs.begin(), pairs.end());
  return r;
}

// The fused path's lanes and the workgroup mirror.
Compacted Lanes(const call::TraverseTop& c) { return PassTraverseTopCompacted(c); }
Compacted Lanes(const call::TraverseLevel& c) { return PassTraverseLevelCompacted(c); }
Compacted Mirror(const call::TraverseTop& c) { return TraverseTopCompactedWorkgroups(c); }
Compacted Mirror(const call::TraverseLevel& c) { return TraverseLevelCompactedWorkgroups(c); }

bool Same(const Compacted& a, const Compacted& b) { return a.pairs == b.pairs && a.tested == b.tested; }

// The mirror equals the lanes and the two passes (the checker on: a report throws); returns it.
template <typename C>
Compacted CheckMirror(const C& c) {
  const Compacted m = Mirror(c), lanes = Lanes(c);
  CHECK(m.tested == lanes.tested);
  CHECK(m.pairs == lanes.pairs);
  CHECK(Same(m, TwoPasses(c)));
  return m;
}

}  // namespace

TEST_CASE("traverse.compact mirror: random calls give the lanes' and traverse + reduce's result at every local size, "
          "subgroup size and schedule, the checker silent") {
  rayspace::test::TestSettings settings;
  // Rows of 170 triangles: one round a row from local size 32 on; rows of 1,300 (tc_wide): several
  // rounds of the top phase up to local size 128, the rows' nodes shuffled between rounds.
  const RandomTop tc(3, 150, 170, 6), tc_wide(4, 40, 1300, 5);
  const RandomLevel lc(5, 300, 2000, 8), lc_wide(6, 120, 600, 16);
  // Pairs in runs of one parent: subgroups that share their children (several chunks at 40 children).
  const RandomLevel lc_runs(7, 200, 1500, 8, false, 30), lc_runs_wide(8, 100, 400, 40, false, 30);
  for (std::uint32_t local : {32u, 64u, 128u, 256u, 12u})
    for (std::uint32_t sg : {8u, 32u})
      for (wg::Schedule s : {wg::Schedule{wg::Order::kForward, 0}, wg::Schedule{wg::Order::kReverse, 0},
                             wg::Schedule{wg::Order::kRandom, 17}}) {
        INFO("local size " << local << " subgroup " << sg << " order " << static_cast<int>(s.order));
        settings->local_size = local;
        settings->subgroup_size = sg;
        settings->schedule = s;
        const Compacted all = CheckMirror(tc.Call(0, 150, 0, 170, false));
        CHECK(all.tested == 150u * 170u);
        CHECK(all.pairs.size() > all.tested / 100);
        CHECK(all.pairs.size() < all.tested / 2);
        const Compacted culled = CheckMirror(tc.Call(0, 150, 0, 170, true));
        CHECK(culled.tested < all.tested);
        CheckMirror(tc.Call(17, 131, 33, 160, true, 0.05f));  // ids relative to t0 and b0, mask rows from t0
        CheckMirror(tc_wide.Call(0, 40, 0, 1300, true));
        CheckMirror(tc_wide.Call(3, 30, 100, 1250, false, 0.05f));
        const Compacted level = CheckMirror(lc.Call());
        CHECK(level.pairs.size() > 0u);
        CheckMirror(lc_wide.Call(0.05f));
        CheckMirror(lc_runs.Call());  // at local size 12: a full subgroup of 8 beside a partial one
        CheckMirror(lc_runs_wide.Call(0.05f));
      }
}

TEST_CASE("traverse.compact mirror: empty calls, calls shorter than a round and a lone slot") {
  rayspace::test::TestSettings settings;
  const RandomTop tc(9, 40, 50, 3);
  for (std::uint32_t local : {1u, 7u, 64u}) {
    INFO("local size " << local);
    settings->local_size = local;
    CHECK(Mirror(tc.Call(5, 5, 0, 50, false)).pairs.empty());
    CHECK(Mirror(tc.Call(0, 40, 7, 7, true)).tested == 0u);
    CheckMirror(tc.Call(3, 4, 10, 11, false));
    CheckMirror(tc.Call(0, 40, 0, 50, true));
    CheckMirror(RandomLevel(4, 30, 0, 4).Call());
    CheckMirror(RandomLevel(4, 30, 50, 0).Call());
  }
}

TEST_CASE("traverse.compact mirror: more blocks than its grid of kCompactStrideGroups workgroups, which stride over them") {
  rayspace::test::TestSettings settings;
  // The top level's blocks are its rows (Scatter strides over them); a level's are kCompactBlock
  // slots (Test and Scatter stride).
  constexpr std::uint32_t kRows = layout::kCompactStrideGroups + 20u;
  const RandomTop tc(15, kRows, 40, 3);
  const Compacted top = CheckMirror(tc.Call(0, kRows, 0, 40, true));
  CHECK(top.pairs.size() > kRows);  // survivors in rows past the grid's first pass
  CHECK((top.pairs.back() >> layout::kPairTriangleBits) >= layout::kCompactStrideGroups);
  const RandomLevel lc(16, 300, (layout::kCompactStrideGroups + 3u) * layout::kCompactBlock / 8u, 8);
  const Compacted level = CheckMirror(lc.Call());
  CHECK(std::uint64_t{lc.Call().pairs.size()} * 8u > std::uint64_t{layout::kCompactStrideGroups} * layout::kCompactBlock);
  CHECK(level.pairs.size() > 0u);
}

TEST_CASE("traverse.compact mirror: each planted fault changes the result, and the backend runs the mirror when asked") {
  rayspace::test::TestSettings settings;
  // Rows of two rounds and a part at the default local size (64 x kCompactCols triangles a round).
  constexpr std::uint32_t kRowTris = 2u * 64u * layout::kCompactCols + 100u;
  const RandomTop tc(11, 150, kRowTris, 6);
  const RandomLevel lc(12, 400, 3000, 8);
  const call::TraverseTopCompacted top{tc.Call(0, 150, 0, kRowTris, true)};
  const call::TraverseLevelCompacted level{lc.Call()};
  const Compacted top_lanes = Lanes(top), level_lanes = Lanes(level);
  CHECK_FALSE(RunsWorkgroupMirror("traverse.compact"));
  // Local size 64: more than one round a top-level row and a lower-level block, which fault 3 needs.
  for (std::uint32_t fault : {1u, 2u, 3u, 4u}) {
    INFO("traverse.compact:" << fault << "@emu");
    settings->emu_faults = {{"traverse.compact", fault}};
    CHECK(RunsWorkgroupMirror("traverse.compact"));
    CHECK_FALSE(Same(EmuHierarchyPasses().TraverseTopCompacted(top), top_lanes));
    CHECK_FALSE(Same(EmuHierarchyPasses().TraverseLevelCompacted(level), level_lanes));
  }
  // Fault 6 is in the levels' shared children: pairs in runs of one parent, some subgroups straddling two.
  const RandomLevel runs(14, 300, 2000, 8, false, 12);
  settings->emu_faults = {};
  const Compacted runs_lanes = Lanes(call::TraverseLevelCompacted{runs.Call()});
  settings->emu_faults = {{"traverse.compact", 6u}};
  CHECK_FALSE(Same(EmuHierarchyPasses().TraverseLevelCompacted(call::TraverseLevelCompacted{runs.Call()}), runs_lanes));
  // Fault 7 is in the top level's object words: 6 objects over rows of 1,124 triangles, so some
  // invocations' 8 triangles straddle two objects.
  settings->emu_faults = {{"traverse.compact", 7u}};
  CHECK_FALSE(Same(EmuHierarchyPasses().TraverseTopCompacted(top), top_lanes));
  settings->emu_faults = {};
  CHECK_FALSE(RunsWorkgroupMirror("traverse.compact"));
  settings->workgroup_model = true;
  CHECK(RunsWorkgroupMirror("traverse.compact"));
  // The mirror without a fault: the lanes' result.
  CHECK(Same(EmuHierarchyPasses().TraverseTopCompacted(top), top_lanes));
  CHECK(Same(EmuHierarchyPasses().TraverseLevelCompacted(level), level_lanes));
  CHECK(Same(EmuHierarchyPasses().TraverseLevelCompacted(call::TraverseLevelCompacted{runs.Call()}), runs_lanes));
}

TEST_CASE("traverse.compact mirror: a dropped barrier in its workgroup scan is named by the checker") {
  // The phase-A scan is WorkgroupInclusiveAdd with the pass's fault, as in the kernel.
  rayspace::test::TestSettings settings;
  const RandomTop tc(13, 60, 100, 2);
  settings->emu_faults = {{"traverse.compact", layout::kFaultDroppedBarrier}};
  try {
    Mirror(tc.Call(0, 60, 0, 100, false));
    FAIL("the checker did not report the dropped barrier");
  } catch (const wg::CheckError& e) {
    REQUIRE_FALSE(e.result.reports.empty());
    CHECK(e.result.reports.front().dispatch == "traverse.compact.Test");
    CHECK(e.result.reports.front().array == "wg_tile");
    CHECK(e.result.Count(wg::ReportKind::kRace) > 0u);
  }
}

TEST_CASE("cone: the test as printed (eq. 3.16) rejects what the exact geometry and the conservative test keep") {
  // Worked by hand. Apex C at the origin, d = 0, axis z, cos alpha = sin alpha = h = float(sqrt(1/2))
  // (an exact pi/4 as the angle of (h, h)); sphere P = (224, 3, 215), r = 0x40cc19ef = 6.3781657...
  // Exactly: |C - H| = 215, |P - H| = sqrt(50185) = 224.0200884, so the distance from P to the cone
  // is (224.0200884 - 215) / sqrt(2) = 6.3781657 - 5.8e-8 < r: they meet, and the conservative test
  // (margins for its rounding) keeps the pair. Printed, in float: tan = h / h = 1 exactly; r / h =
  // 9.0200886 rounds down to 9.0200882, and 215 + that rounds down again to 224.0200806; |P - H|
  // rounds up to 224.0200958, above the left side: rejected, a hit lost to rounding alone.
  const float h = std::sqrt(0.5f);
  layout::ConeNode n{};
  n.sphere = glm::vec4(0.0f);
  n.cone = glm::vec4(0.0f, 0.0f, 1.0f, h);
  n.extra.x = h;
  const glm::vec4 sphere(224.0f, 3.0f, 215.0f, std::bit_cast<float>(0x40cc19efu));
  CHECK(refs::ExactNodeMeetsSphere(n, sphere));
  CHECK(emu::cone::Test(n, sphere, 0.0f));
  CHECK_FALSE(emu::cone::PrintedTest(n, sphere));
  CHECK_FALSE(emu::cone::TestBy(layout::kConeTestPrinted, n, sphere, 0.0f));
  CHECK(emu::cone::TestBy(layout::kConeTestConservative, n, sphere, 0.0f));
  // The next float of radius is enough: 215 + (r' / h) rounds to 224.0200958 = |P - H|.
  CHECK(emu::cone::PrintedTest(n, glm::vec4(glm::vec3(sphere), std::bit_cast<float>(0x40cc19f0u))));
  // eq. 3.16 assumes alpha < pi/2; past it (cos alpha = -0.5) and for a full cone (cos = -1) dividing
  // by cos alpha would make the left side negative and reject everything: the printed test keeps them,
  // as the conservative test keeps full cones.
  n.cone.w = -0.5f;
  n.extra.x = 0.8660254f;
  CHECK(emu::cone::PrintedTest(n, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)));
  CHECK(emu::cone::PrintedTest(emu::cone::FullSphereCone(n), glm::vec4(100.0f, 0.0f, -50.0f, 0.0f)));
  // A narrow cone and a sphere on its axis ahead: kept.
  n.cone.w = 0.99f;
  n.extra.x = 0.14106736f;
  CHECK(emu::cone::PrintedTest(n, glm::vec4(0.0f, 0.0f, 10.0f, 0.5f)));
  // The same sphere behind the apex: |C - H| makes the printed test a double cone that keeps it
  // (10 x 0.1425 + 0.5 / 0.99 = 1.93 >= 0); without the absolute value (printed-signed) the left side
  // is -1.425 + 0.505 < 0 and it is rejected, as the exact geometry says.
  const glm::vec4 behind(0.0f, 0.0f, -10.0f, 0.5f);
  CHECK_FALSE(refs::ExactNodeMeetsSphere(n, behind));
  CHECK(emu::cone::PrintedTest(n, behind));
  CHECK(emu::cone::TestBy(layout::kConeTestPrinted, n, behind, 0.0f));
  CHECK_FALSE(emu::cone::PrintedSignedTest(n, behind, 0.0f));
  CHECK_FALSE(emu::cone::TestBy(layout::kConeTestPrintedSigned, n, behind, 0.0f));
  CHECK(emu::cone::PrintedSignedTest(n, glm::vec4(0.0f, 0.0f, 10.0f, 0.5f), 0.0f));
  // The traversal's eps widens the sphere: a sphere 1 off a zero-angle cone's axis needs r + eps >= 1.
  n.cone.w = 1.0f;
  n.extra.x = 0.0f;
  CHECK_FALSE(emu::cone::PrintedTest(n, glm::vec4(1.0f, 0.0f, 5.0f, 0.5f), 0.25f));
  CHECK(emu::cone::PrintedTest(n, glm::vec4(1.0f, 0.0f, 5.0f, 0.5f), 0.5f));
}

TEST_CASE("traverse: cone_test printed runs eq. 3.16 in every traversal pass, the fused lanes' fallback and the "
          "workgroup mirror alike") {
  rayspace::test::TestSettings settings;
  const RandomTop tc(3, 150, 170, 6);
  const RandomLevel lc(5, 300, 2000, 8);
  const auto printed = [](const layout::ConeNode& n, glm::vec4 s, float eps) { return emu::cone::PrintedTest(n, s, eps); };
  for (bool mask : {false, true}) {
    call::TraverseTop top = tc.Call(0, 150, 0, 170, mask, 0.05f);
    const Compacted conservative = CheckMirror(top);
    top.cone_test = layout::kConeTestPrinted;
    const Compacted p = CheckMirror(top);  // mirror = fused = traverse.top + reduce
    CHECK(Same(p, TraverseTopCompactedWith(printed, top)));
    CHECK(p.tested == conservative.tested);  // the same slots are tested, other pairs survive
    CHECK(p.pairs != conservative.pairs);
  }
  call::TraverseLevel level = lc.Call(0.05f);
  const Compacted conservative = CheckMirror(level);
  level.cone_test = layout::kConeTestPrinted;
  const Compacted p = CheckMirror(level);
  CHECK(Same(p, TraverseLevelCompactedWith(printed, level)));
  CHECK(p.pairs != conservative.pairs);
  // The object mask too.
  const call::TraverseTop any = tc.Call(0, 150, 0, 170, false, 0.05f);
  call::ObjectMask om{.top = any.top, .object_spheres = any.tri_spheres.subspan(0, 40), .eps = 0.05f};
  const std::vector<std::uint8_t> mask_conservative = PassObjectMask(om);
  om.cone_test = layout::kConeTestPrinted;
  CHECK(PassObjectMask(om) == ObjectMaskWith(printed, om));
  CHECK(PassObjectMask(om) != mask_conservative);
  // printed-signed, in the same passes: its own pairs.
  const auto signed_test = [](const layout::ConeNode& n, glm::vec4 s, float eps) { return emu::cone::PrintedSignedTest(n, s, eps); };
  call::TraverseTop top_signed = tc.Call(0, 150, 0, 170, false, 0.05f);
  top_signed.cone_test = layout::kConeTestPrintedSigned;
  const Compacted ps = CheckMirror(top_signed);
  CHECK(Same(ps, TraverseTopCompactedWith(signed_test, top_signed)));
  level.cone_test = layout::kConeTestPrintedSigned;
  const Compacted ls = CheckMirror(level);
  CHECK(Same(ls, TraverseLevelCompactedWith(signed_test, level)));
  CHECK(ls.pairs != p.pairs);
  om.cone_test = layout::kConeTestPrintedSigned;
  CHECK(PassObjectMask(om) == ObjectMaskWith(signed_test, om));
  // An unknown test is refused with the call's name.
  om.cone_test = 3;
  CHECK_THROWS_WITH_AS(CheckInputs(om), doctest::Contains("traverse.objects: cone_test 3"), InputError);
}

TEST_CASE("hierarchy: --cone-test printed changes what a real frame's traversal keeps, on both emulated paths") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  HierarchyConfig cfg;
  const HRun conservative = RunHierarchy(s, 64, 64, cfg);
  cfg.cone_test = layout::kConeTestPrinted;
  const HRun printed = RunHierarchy(s, 64, 64, cfg);
  cfg.fused = true;
  const HRun printed_fused = RunHierarchy(s, 64, 64, cfg);
  REQUIRE(printed.stats.size() == conservative.stats.size());
  REQUIRE(printed_fused.stats.size() == printed.stats.size());
  bool differs = false;
  for (std::size_t b = 0; b < printed.stats.size(); ++b) {
    CHECK(printed.stats[b].rays == conservative.stats[b].rays);
    for (std::size_t l = 0; l < printed.stats[b].levels.size(); ++l) {
      differs = differs || printed.stats[b].levels[l].hits != conservative.stats[b].levels[l].hits;
      CHECK(printed_fused.stats[b].levels[l].hits == printed.stats[b].levels[l].hits);
      CHECK(printed_fused.stats[b].levels[l].intersections == printed.stats[b].levels[l].intersections);
    }
  }
  CHECK(differs);
  CHECK(printed_fused.frame.digest.Frame() == printed.frame.digest.Frame());
}
