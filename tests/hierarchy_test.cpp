// The ray-space hierarchy as a tracer: statistics identities and determinism. (The passes' own tests
// are in tests/<family>_test.cpp.)
#include <doctest/doctest.h>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;
using test::HRun;
using test::RunHierarchy;

namespace {

std::uint64_t Total(const std::vector<BatchStats>& v) {
  std::uint64_t t = 0;
  for (const auto& b : v) t += b.Total();
  return t;
}

// Hashes of the traced results (hits, occlusion) and the image, which every algorithm must share.
std::vector<std::uint64_t> Results(const FrameResult& f) {
  std::vector<std::uint64_t> out;
  for (const auto& e : f.digest.entries())
    if (e.pass.rfind("trace.", 0) == 0 || e.pass == "resolve" || e.pass.rfind("shade", 0) == 0) out.push_back(e.hash);
  return out;
}

}  // namespace

TEST_CASE("statistics: accounting identity, RAH top level, and all algorithms agree on every hit") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  HierarchyConfig cfg;
  cfg.algorithm = Algorithm::kRah;
  const HRun rah = RunHierarchy(s, 64, 64, cfg);
  for (const BatchStats& b : rah.stats) {
    std::uint64_t sum = b.final_tests;
    for (const auto& l : b.levels) sum += l.intersections;
    CHECK(sum == b.Total());
    // RAH tests every top node against every triangle: ceil(rays / 64) x triangles.
    CHECK(b.levels.back().intersections == (b.rays + 63) / 64 * b.triangles);
    for (const auto& l : b.levels) CHECK(l.hits <= l.intersections);
  }
  cfg.algorithm = Algorithm::kCrsh;
  const HRun crsh = RunHierarchy(s, 64, 64, cfg);
  CHECK(Total(crsh.stats) < Total(rah.stats));
  cfg.algorithm = Algorithm::kRahQuadtree;
  cfg.subdivision = 4;
  cfg.depth = 6;
  const HRun quad = RunHierarchy(s, 64, 64, cfg);
  // Same hits, shading and image as the direct tracer.
  const SceneBuffers b = FlattenScene(s);
  auto direct = MakeDirectTracer(b, DirectMode::kAuto);
  FrameOptions fo;
  fo.width = 64;
  fo.height = 64;
  const FrameResult ref = RenderFrame(s, b, *direct, fo);
  CHECK(Results(rah.frame) == Results(ref));
  CHECK(Results(crsh.frame) == Results(ref));
  CHECK(Results(quad.frame) == Results(ref));
  CHECK(crsh.frame.rgb == ref.rgb);
}

TEST_CASE("determinism: hierarchy digests across threads, reductions, component sizes and forced overflow") {
  rayspace::test::TestSettings settings;
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  HierarchyConfig cfg;
  const std::uint64_t ref = RunHierarchy(s, 64, 64, cfg).frame.digest.Frame();
  settings->threads = 1;
  CHECK(RunHierarchy(s, 64, 64, cfg).frame.digest.Frame() == ref);
  settings->threads = 2;
  settings->chunk = 3;
  CHECK(RunHierarchy(s, 64, 64, cfg).frame.digest.Frame() == ref);
  settings->chunk = 0;
  settings->threads = 0;
  for (int comp : {1, 5, 64, 4096}) {
    HierarchyConfig c = cfg;
    c.component_size = comp;
    CHECK(RunHierarchy(s, 64, 64, c).frame.digest.Frame() == ref);
  }
  HierarchyConfig scan = cfg;
  scan.reduction = Reduction::kScan;
  CHECK(RunHierarchy(s, 64, 64, scan).frame.digest.Frame() == ref);
  HierarchyConfig small = cfg;
  small.pair_capacity = 2000;
  small.max_batch_triangles = 100;
  const HRun over = RunHierarchy(s, 64, 64, small);
  std::uint64_t splits = 0;
  for (const auto& b : over.stats) splits += b.overflow_splits;
  CHECK(splits > 0);  // overflow really happened
  CHECK(over.frame.digest.Frame() == ref);
}

// --leaf-test ray-sphere on every hierarchy: the rays below the surviving leaves meet the triangle
// spheres first (as many sphere tests as the node test's ray-triangle tests), far fewer ray-triangle
// tests follow, and every hit, shading and pixel stays the same.
TEST_CASE("leaf test: ray-sphere cuts the ray-triangle tests per ray on cornell-mirrors, same hits, every algorithm") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  for (Algorithm algo : {Algorithm::kCrsh, Algorithm::kRah, Algorithm::kRahQuadtree}) {
    HierarchyConfig cfg;
    cfg.algorithm = algo;
    if (algo == Algorithm::kRahQuadtree) cfg.subdivision = 4, cfg.depth = 6;
    INFO("algorithm " << static_cast<int>(algo));
    const HRun node = RunHierarchy(s, 64, 64, cfg);
    cfg.leaf_test = layout::kLeafTestRaySphere;
    const HRun sphere = RunHierarchy(s, 64, 64, cfg);
    REQUIRE(node.stats.size() == sphere.stats.size());
    std::uint64_t node_finals = 0, sphere_finals = 0, leaf_tests = 0;
    for (std::size_t i = 0; i < node.stats.size(); ++i) {
      CHECK(node.stats[i].leaf_sphere_tests == 0);
      CHECK(sphere.stats[i].leaf_sphere_tests == node.stats[i].final_tests);
      CHECK(sphere.stats[i].final_tests <= sphere.stats[i].leaf_sphere_tests);
      node_finals += node.stats[i].final_tests, sphere_finals += sphere.stats[i].final_tests;
      leaf_tests += sphere.stats[i].leaf_sphere_tests;
    }
    CHECK(leaf_tests == node_finals);
    CHECK(sphere_finals * 2 < node_finals);
    CHECK(Results(sphere.frame) == Results(node.frame));
    CHECK(sphere.frame.rgb == node.frame.rgb);
    // The fused path's final tests run on lanes (IntersectLanes): the same counts and hits.
    cfg.fused = true;
    const HRun lanes = RunHierarchy(s, 64, 64, cfg);
    REQUIRE(lanes.stats.size() == sphere.stats.size());
    for (std::size_t i = 0; i < lanes.stats.size(); ++i) {
      CHECK(lanes.stats[i].final_tests == sphere.stats[i].final_tests);
      CHECK(lanes.stats[i].leaf_sphere_tests == sphere.stats[i].leaf_sphere_tests);
    }
    CHECK(Results(lanes.frame) == Results(node.frame));
  }
}

TEST_CASE("hierarchy: --levels auto, known answers (the fewest levels, at least 2, leaving at most 512 top nodes)") {
  CHECK(emu::AutoLevels(0, 8) == 2);
  CHECK(emu::AutoLevels(24 * 24, 8) == 2);
  CHECK(emu::AutoLevels(512 * 64, 8) == 2);        // 32,768 rays / 8^2 = 512 top nodes
  CHECK(emu::AutoLevels(512 * 64 + 1, 8) == 3);
  CHECK(emu::AutoLevels(256 * 256, 8) == 3);       // 128 top nodes
  CHECK(emu::AutoLevels(512 * 512, 8) == 3);       // 512
  CHECK(emu::AutoLevels(512 * 512 + 1, 8) == 4);
  CHECK(emu::AutoLevels(1024 * 1024, 8) == 4);     // 256
  CHECK(emu::AutoLevels(128 * 128, 4) == 3);       // 256; with 2 levels 1,024
  CHECK(emu::AutoLevels(std::uint64_t{1} << 40, 4) == 12);  // capped at --levels' maximum
}
