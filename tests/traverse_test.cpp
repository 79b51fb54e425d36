// Traversal: the cone-sphere test and conservative traversal (no accepted pair is culled).
#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
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

TEST_CASE("traversal: every pair the final test accepts is a hierarchy candidate (cornell-mirrors)") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  for (Algorithm a : {Algorithm::kCrsh, Algorithm::kRah, Algorithm::kRahQuadtree}) {
    HierarchyConfig cfg;
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
