// --objects tree against flat (emu/object_tree_top.h): the same hits and frame digest, and every pair
// the flat levels keep kept by the tree's too, on the bundled scenes and random configurations; the
// object tree's node tests counted, and its top level testing fewer triangles where objects are many.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <random>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;

namespace {

struct Run {
  std::vector<std::vector<std::uint32_t>> pairs;  // level by level, block by block
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

// "" when every pair list of `flat` is contained in the matching list of `tree`.
std::string Contained(const Run& flat, const Run& tree) {
  if (flat.pairs.size() != tree.pairs.size()) return "the number of compacted levels";
  for (std::size_t i = 0; i < flat.pairs.size(); ++i) {
    std::vector<std::uint32_t> a = flat.pairs[i], b = tree.pairs[i];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (!std::includes(b.begin(), b.end(), a.begin(), a.end())) return "a pair of compacted level " + std::to_string(i);
  }
  return "";
}

std::uint64_t Sum(const std::vector<emu::BatchStats>& st, std::uint64_t emu::BatchStats::*field) {
  std::uint64_t n = 0;
  for (const emu::BatchStats& b : st) n += b.*field;
  return n;
}

}  // namespace

TEST_CASE("objects tree: the same digest as flat and every flat pair among its own, on random configurations") {
  std::vector<std::pair<std::string, int>> scenes = {{"cornell-mirrors.json", 48}, {"office.json", 32}};
  if (test::HaveData()) scenes.push_back({"sponza.json", 32});
  std::mt19937 rng(16);
  for (const auto& [file, size] : scenes) {
    const Scene s = test::LoadBundled(file);
    for (int run = 0; run < 4; ++run) {
      emu::HierarchyConfig cfg;
      cfg.algorithm = std::array{emu::Algorithm::kCrsh, emu::Algorithm::kCrsh, emu::Algorithm::kRah, emu::Algorithm::kRahQuadtree}[rng() % 4];
      cfg.subdivision = std::array{4, 8, 16}[rng() % 3];
      cfg.depth = cfg.algorithm == emu::Algorithm::kRahQuadtree ? 3 + static_cast<int>(rng() % 3) : 2 + static_cast<int>(rng() % 2);
      cfg.fused = rng() % 2 == 0;
      // Small batches on the small scenes: subtrees straddle batches and are skipped by range.
      cfg.max_batch_triangles = file == "sponza.json" ? (1u << 14) : std::array{5u, 64u, 1u << 14}[rng() % 3];
      cfg.object_tree_options.big_fraction = std::array{0.1f, 0.25f, 0.6f}[rng() % 3];
      cfg.object_tree_options.leaf_triangles = std::array{1u, 4u, 16u}[rng() % 3];
      const int threads = 1 + static_cast<int>(rng() % 2);
      INFO(file << " run " << run << ": algorithm " << static_cast<int>(cfg.algorithm) << ", subdivision " << cfg.subdivision
                << ", depth " << cfg.depth << ", fused " << cfg.fused << ", batch triangles " << cfg.max_batch_triangles
                << ", big " << cfg.object_tree_options.big_fraction << ", leaf " << cfg.object_tree_options.leaf_triangles
                << ", threads " << threads);
      SetThreadCount(threads);
      const Run flat = RunObjects(s, size, cfg, false), tree = RunObjects(s, size, cfg, true);
      SetThreadCount(0);
      REQUIRE(!flat.pairs.empty());
      CHECK(flat.digest == tree.digest);
      CHECK(Contained(flat, tree) == "");
      CHECK(Sum(tree.stats, &emu::BatchStats::object_tree_tests) > 0);
      CHECK(Sum(tree.stats, &emu::BatchStats::object_sphere_tests) == 0);  // the roots replace the object spheres
      CHECK(Sum(flat.stats, &emu::BatchStats::object_tree_tests) == 0);
    }
  }
}

TEST_CASE("objects tree: the same run twice and at other thread counts gives the same pairs and counts") {
  const Scene s = test::LoadBundled("office.json");
  emu::HierarchyConfig cfg;
  SetThreadCount(1);
  const Run a = RunObjects(s, 40, cfg, true);
  SetThreadCount(2);
  const Run b = RunObjects(s, 40, cfg, true);
  SetThreadCount(0);
  CHECK(a.pairs == b.pairs);
  CHECK(a.digest == b.digest);
  CHECK(Sum(a.stats, &emu::BatchStats::object_tree_tests) == Sum(b.stats, &emu::BatchStats::object_tree_tests));
}

TEST_CASE("objects tree: Sponza's top level tests a fraction of the triangles flat tests") {
  if (!test::HaveData()) {
    MESSAGE("no scene data; skipping");
    return;
  }
  const Scene s = test::LoadBundled("sponza.json");
  emu::HierarchyConfig cfg;
  cfg.fused = true;
  const Run flat = RunObjects(s, 64, cfg, false), tree = RunObjects(s, 64, cfg, true);
  std::uint64_t top_flat = 0, top_tree = 0;
  for (const emu::BatchStats& b : flat.stats) top_flat += b.levels.back().intersections;
  for (const emu::BatchStats& b : tree.stats) top_tree += b.levels.back().intersections + b.object_tree_tests;
  MESSAGE("Sponza 64x64 top level: flat " << top_flat << " tests, tree " << top_tree << " (triangles and object nodes)");
  CHECK(top_tree * 3 < top_flat);  // 1:4 here, about 1:14 at 256x256
  CHECK(flat.digest == tree.digest);
}
