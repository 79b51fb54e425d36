// --objects tree (emu/object_tree_traverse.h): the joint descent gives flat's hits and frame digest
// on the bundled scenes over random configurations; its fused rounds equal its passes round by
// round; its counts add up; and each planted fault of the descent fails the check that guards it.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;

namespace {

struct Run {
  std::vector<std::vector<std::uint32_t>> pairs;  // per round: next cones, items, final cones, items
  std::vector<emu::BatchStats> stats;
  std::uint64_t digest = 0;
};

Run RunObjects(const Scene& s, int size, emu::HierarchyConfig cfg, bool tree) {
  Run r;
  cfg.object_tree = tree;
  cfg.pair_log = &r.pairs;
  test::HRun run = test::RunHierarchy(s, size, size, cfg);
  r.stats = run.stats;
  r.digest = run.frame.digest.Frame();
  return r;
}

std::uint64_t Sum(const std::vector<emu::BatchStats>& st, std::uint64_t emu::BatchStats::*field) {
  std::uint64_t n = 0;
  for (const emu::BatchStats& b : st) n += b.*field;
  return n;
}

// Every test counted once by its cone level and once by its object side.
bool CountsAddUp(const emu::BatchStats& b) {
  std::uint64_t by_cone = b.ray_level.intersections, by_object = b.object_triangles.intersections;
  for (const emu::LevelStats& l : b.levels) by_cone += l.intersections;
  for (const emu::LevelStats& l : b.object_levels) by_object += l.intersections;
  return by_cone == by_object && b.Total() == by_cone + b.final_tests;
}

emu::HierarchyConfig RandomConfig(std::mt19937& rng, bool big_scene) {
  emu::HierarchyConfig cfg;
  cfg.algorithm = std::array{emu::Algorithm::kCrsh, emu::Algorithm::kCrsh, emu::Algorithm::kRah, emu::Algorithm::kRahQuadtree}[rng() % 4];
  cfg.subdivision = std::array{4, 8, 16}[rng() % 3];
  cfg.depth = cfg.algorithm == emu::Algorithm::kRahQuadtree ? 3 + static_cast<int>(rng() % 3) : 1 + static_cast<int>(rng() % 3);
  cfg.fused = rng() % 2 == 0;
  // Small capacities split the top nodes into groups (the small scenes only: Sponza's would crawl).
  cfg.pair_capacity = big_scene ? std::size_t{1} << 24 : std::array<std::size_t, 3>{300, 5000, std::size_t{1} << 24}[rng() % 3];
  cfg.object_tree_options.big_fraction = std::array{0.1f, 0.25f, 0.6f}[rng() % 3];
  cfg.object_tree_options.leaf_triangles = std::array{1u, 4u, 16u}[rng() % 3];
  return cfg;
}

}  // namespace

TEST_CASE("objects tree: the same frame digest as flat, on the bundled scenes and random configurations") {
  rayspace::test::TestSettings settings;
  std::vector<std::pair<std::string, int>> scenes = {{"cornell-mirrors.json", 48}, {"office.json", 32}};
  if (test::HaveData()) scenes.push_back({"sponza.json", 32});
  std::mt19937 rng(16);
  for (const auto& [file, size] : scenes) {
    const Scene s = test::LoadBundled(file);
    for (int run = 0; run < 4; ++run) {
      const emu::HierarchyConfig cfg = RandomConfig(rng, file == "sponza.json");
      const int threads = 1 + static_cast<int>(rng() % 2);
      INFO(file << " run " << run << ": algorithm " << static_cast<int>(cfg.algorithm) << ", subdivision " << cfg.subdivision
                << ", depth " << cfg.depth << ", fused " << cfg.fused << ", pair capacity " << cfg.pair_capacity << ", big "
                << cfg.object_tree_options.big_fraction << ", leaf " << cfg.object_tree_options.leaf_triangles << ", threads " << threads);
      settings->threads = threads;
      const Run flat = RunObjects(s, size, cfg, false), tree = RunObjects(s, size, cfg, true);
      settings->threads = 0;
      CHECK(flat.digest == tree.digest);
      CHECK(Sum(tree.stats, &emu::BatchStats::tree_rounds) > 0);
      CHECK(Sum(tree.stats, &emu::BatchStats::object_sphere_tests) == 0);  // the roots take the object spheres' place
      CHECK(Sum(flat.stats, &emu::BatchStats::tree_rounds) == 0);
      for (const emu::BatchStats& b : tree.stats) CHECK(CountsAddUp(b));
    }
  }
}

TEST_CASE("objects tree: fused rounds give the passes' pairs and counts round by round, and a dropped survivor is seen") {
  rayspace::test::TestSettings settings;
  const Scene s = test::LoadBundled("office.json");
  std::mt19937 rng(7);
  for (int run = 0; run < 3; ++run) {
    emu::HierarchyConfig cfg = RandomConfig(rng, false);
    INFO("run " << run << ": algorithm " << static_cast<int>(cfg.algorithm) << ", subdivision " << cfg.subdivision << ", depth "
                << cfg.depth << ", pair capacity " << cfg.pair_capacity);
    cfg.fused = false;
    const Run passes = RunObjects(s, 40, cfg, true);
    cfg.fused = true;
    const Run fused = RunObjects(s, 40, cfg, true);
    REQUIRE(passes.pairs.size() > 4);
    CHECK(passes.pairs == fused.pairs);
    CHECK(passes.digest == fused.digest);
    REQUIRE(passes.stats.size() == fused.stats.size());
    for (std::size_t i = 0; i < passes.stats.size(); ++i) {
      CHECK(passes.stats[i].Total() == fused.stats[i].Total());
      CHECK(passes.stats[i].ray_level.hits == fused.stats[i].ray_level.hits);
      CHECK(passes.stats[i].object_triangles.hits == fused.stats[i].object_triangles.hits);
    }
    settings->tree_fault = static_cast<std::uint32_t>(emu::TreeFault::kDropBlockSurvivor);
    const Run faulty = RunObjects(s, 40, cfg, true);
    settings->tree_fault = static_cast<std::uint32_t>(emu::TreeFault::kNone);
    CHECK(faulty.pairs != passes.pairs);
  }
}

TEST_CASE("objects tree: the same pairs and counts at one and two threads") {
  rayspace::test::TestSettings settings;
  const Scene s = test::LoadBundled("office.json");
  emu::HierarchyConfig cfg;
  cfg.fused = true;
  settings->threads = 1;
  const Run a = RunObjects(s, 40, cfg, true);
  settings->threads = 2;
  const Run b = RunObjects(s, 40, cfg, true);
  settings->threads = 0;
  CHECK(a.pairs == b.pairs);
  CHECK(a.digest == b.digest);
  CHECK(Sum(a.stats, &emu::BatchStats::final_tests) == Sum(b.stats, &emu::BatchStats::final_tests));
}

TEST_CASE("objects tree: a descent that skips an object node's last child, or a leaf's rays after its first, loses hits") {
  rayspace::test::TestSettings settings;
  const Scene s = test::LoadBundled("office.json");
  emu::HierarchyConfig cfg;
  const Run flat = RunObjects(s, 32, cfg, false);
  for (const emu::TreeFault f : {emu::TreeFault::kDropLastChild, emu::TreeFault::kFirstRayOnly}) {
    CAPTURE(static_cast<int>(f));
    settings->tree_fault = static_cast<std::uint32_t>(f);
    const Run faulty = RunObjects(s, 32, cfg, true);
    settings->tree_fault = static_cast<std::uint32_t>(emu::TreeFault::kNone);
    CHECK(faulty.digest != flat.digest);
  }
}

TEST_CASE("objects tree: the side refined is the cone where its cross-section at the node is wider than the node") {
  // Apex at the origin (radius 0), half-angle 45 degrees: the cross-section's radius at distance d is d.
  layout::ConeNode n{};
  n.sphere = glm::vec4(0, 0, 0, 0);
  n.cone = glm::vec4(0, 0, 1, std::sqrt(0.5f));
  n.extra = glm::vec4(std::sqrt(0.5f), 8, 0, 0);
  CHECK(emu::SplitCone(n, glm::vec4(0, 0, 10, 5)));    // 10 wide, node 5: refine the cone
  CHECK(!emu::SplitCone(n, glm::vec4(0, 0, 10, 20)));  // node 20: refine the node
  CHECK(!emu::SplitCone(n, glm::vec4(6, 0, 8, 10.5f)));  // distance 10 (3-4-5), node 10.5
  CHECK(emu::SplitCone(n, glm::vec4(6, 0, 8, 9.5f)));
  n.sphere.w = 30;  // the apex sphere alone is wider than the node
  CHECK(emu::SplitCone(n, glm::vec4(0, 0, 10, 20)));
  n.sphere.w = 0;
  n.cone.w = 0.0f, n.extra.x = 1.0f;  // a hemisphere
  CHECK(emu::SplitCone(n, glm::vec4(0, 0, 10, 1000)));
  n.cone.w = -1.0f, n.extra.x = 0.0f;  // the full sphere
  CHECK(emu::SplitCone(n, glm::vec4(0, 0, 10, 1000)));
}

TEST_CASE("objects auto: a batch takes the tree exactly when its leaves spread at least the threshold or an object is big, and the digest is flat's") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  emu::HierarchyConfig cfg;
  cfg.fused = true;
  const Run flat = RunObjects(s, 48, cfg, false);
  // Between the least and the most spread batch, so that both kinds occur.
  double lo = 1.0, hi = 0.0;
  for (const emu::BatchStats& b : flat.stats) lo = std::min(lo, b.leaf_spread), hi = std::max(hi, b.leaf_spread);
  REQUIRE(lo < hi);
  const float threshold = static_cast<float>((lo + hi) / 2);
  cfg.auto_tree_spread = threshold;
  const Run automatic = RunObjects(s, 48, cfg, false);
  std::size_t trees = 0;
  for (const emu::BatchStats& b : automatic.stats) {
    CAPTURE(b.batch);
    CAPTURE(b.leaf_spread);
    CHECK(b.object_tree == (b.leaf_spread >= threshold));
    CHECK((b.tree_rounds > 0) == b.object_tree);
    trees += b.object_tree;
  }
  CHECK(trees > 0);
  CHECK(trees < automatic.stats.size());
  CHECK(automatic.digest == flat.digest);
  REQUIRE(flat.stats.size() == automatic.stats.size());
  for (std::size_t i = 0; i < flat.stats.size(); ++i) {
    CHECK(flat.stats[i].leaf_spread == automatic.stats[i].leaf_spread);  // the same hierarchy, whichever descent
    CHECK(flat.stats[i].leaf_spread > 0.0);
    CHECK(flat.stats[i].leaf_spread <= 1.0);
  }
  // An object of at least auto_tree_triangles sends every batch to the tree (cornell-mirrors' room
  // and ball have a few hundred triangles each).
  cfg.auto_tree_triangles = 100;
  for (const emu::BatchStats& b : RunObjects(s, 48, cfg, false).stats) CHECK(b.object_tree);
  cfg.auto_tree_triangles = 100000;
  for (const emu::BatchStats& b : RunObjects(s, 48, cfg, false).stats) CHECK(b.object_tree == (b.leaf_spread >= threshold));
}
