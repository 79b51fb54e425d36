// The emulator's fused traversal (each level tests and compacts in one pass) against the passes the
// kernels run (traversal slots, then a stream reduction): the same pairs at every level of every
// block in the same order, the same final candidates, statistics and frame digest, on the bundled
// scenes and random configurations; and a planted difference the comparison must see.
#include <doctest/doctest.h>

#include <array>
#include <random>

#include "rayspace/emu/cone_cull.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;

namespace {

struct PathRun {
  std::vector<std::vector<std::uint32_t>> pairs;  // level by level, block by block
  std::vector<std::uint64_t> candidates;
  std::vector<emu::BatchStats> stats;
  std::uint64_t digest = 0;
};

PathRun RunPath(const Scene& s, int w, int h, emu::HierarchyConfig cfg, bool fused) {
  PathRun r;
  cfg.fused = fused;
  cfg.pair_log = &r.pairs;
  test::HRun run = test::RunHierarchy(s, w, h, cfg, &r.candidates);
  r.stats = run.stats;
  r.digest = run.frame.digest.Frame();
  return r;
}

// "" when the two runs agree everywhere, else what differs first.
std::string Compare(const PathRun& a, const PathRun& b) {
  if (a.pairs.size() != b.pairs.size()) return "the number of compacted levels";
  for (std::size_t i = 0; i < a.pairs.size(); ++i)
    if (a.pairs[i] != b.pairs[i]) return "the pairs of compacted level " + std::to_string(i);
  if (a.candidates != b.candidates) return "the final candidates";
  if (a.stats.size() != b.stats.size()) return "the batches";
  for (std::size_t i = 0; i < a.stats.size(); ++i) {
    const emu::BatchStats &x = a.stats[i], &y = b.stats[i];
    if (x.final_tests != y.final_tests || x.overflow_splits != y.overflow_splits || x.levels.size() != y.levels.size())
      return "the statistics of batch " + x.batch;
    for (std::size_t L = 0; L < x.levels.size(); ++L)
      if (x.levels[L].intersections != y.levels[L].intersections || x.levels[L].hits != y.levels[L].hits)
        return "the level statistics of batch " + x.batch;
  }
  return a.digest == b.digest ? "" : "the frame digest";
}

// Three random configurations per scene, each rendered by the passes and fused; the top level's group
// culling must have run in them, so that the equality covers it.
void CheckRandomConfigurations(const std::vector<std::pair<std::string, int>>& scenes, unsigned seed) {
  rayspace::test::TestSettings settings;
  std::uint64_t culled = 0;
  settings->culled_slots = &culled;
  std::mt19937 rng(seed);
  for (const auto& [file, size] : scenes) {
    const Scene s = test::LoadBundled(file);
    for (int run = 0; run < 3; ++run) {
      emu::HierarchyConfig cfg;
      cfg.algorithm = std::array{emu::Algorithm::kCrsh, emu::Algorithm::kCrsh, emu::Algorithm::kRah, emu::Algorithm::kRahQuadtree}[rng() % 4];
      cfg.subdivision = std::array{4, 8, 16}[rng() % 3];
      // Roger's quadtree: four children a node, one level per halving of the screen tile.
      cfg.depth = cfg.algorithm == emu::Algorithm::kRahQuadtree ? 3 + static_cast<int>(rng() % 3) : 2 + static_cast<int>(rng() % 2);
      cfg.reduction = rng() % 2 ? emu::Reduction::kScan : emu::Reduction::kHierarchical;
      cfg.pair_capacity = rng() % 2 ? (1u << 24) : 4096u + rng() % 4096u;  // small: batches split
      // Few triangles per batch: lane groups shorter than eight, blocks straddling nodes (on cornell's
      // 828 triangles; office's 36K in batches of 3 took 7 s, Sponza's 66K a minute). Office takes
      // batches of a few hundred, which straddle its objects.
      const std::uint32_t draw = rng() % 3;
      cfg.max_batch_triangles = file == "sponza.json"   ? (1u << 14)
                                : file == "office.json" ? std::array{509u, 1021u, 1u << 14}[draw]
                                                        : std::array{3u, 7u, 1u << 14}[draw];
      const int threads = 1 + static_cast<int>(rng() % 2);
      INFO(file << " run " << run << ": subdivision " << cfg.subdivision << ", depth " << cfg.depth << ", capacity "
                << cfg.pair_capacity << ", batch triangles " << cfg.max_batch_triangles << ", threads " << threads << ", algorithm " << static_cast<int>(cfg.algorithm));
      settings->threads = threads;
      const PathRun passes = RunPath(s, size, size, cfg, false), fused = RunPath(s, size, size, cfg, true);
      REQUIRE(!passes.pairs.empty());
      CHECK(Compare(passes, fused) == "");
    }
  }
  MESSAGE("top-level slots culled by group: " << culled);
  CHECK(culled > 0);
}

}  // namespace

TEST_CASE("fused path: the same pairs, statistics and digest as the passes, on random configurations") {
  CheckRandomConfigurations({{"cornell-mirrors.json", 48}, {"office.json", 16}}, 2026);
}

// The full test tier: the same on Sponza's 66K triangles (the default tier's case guards the claim).
TEST_CASE("fused path: the same pairs, statistics and digest as the passes, on random configurations on Sponza") {
  if (test::SkipWithoutData("sponza_dabrovic/sponza.obj")) return;
  CheckRandomConfigurations({{"sponza.json", 32}}, 2026);
}

// The passes and the fused path on a bundled scene at 32x32, the fused run with `plant` applied to
// its settings.
static std::string ComparePlanted(const std::string& file, void (*plant)(Settings&)) {
  const Scene s = test::LoadBundled(file);
  const PathRun passes = RunPath(s, 32, 32, {}, false);
  const ScopedSettings planted(plant);
  return Compare(passes, RunPath(s, 32, 32, {}, true));
}

TEST_CASE("fused path: a planted difference (the last survivor of every block dropped) is seen") {
  const auto plant = [](Settings& s) { s.fused_fault = true; };
  CHECK(ComparePlanted("cornell-mirrors.json", plant).rfind("the pairs of compacted level", 0) == 0);
}

TEST_CASE("fused path: a planted unsound group cull (a negative margin) is seen") {
  const auto plant = [](Settings& s) { s.cull_margin = -0.25; };
  CHECK(ComparePlanted("cornell-mirrors.json", plant).rfind("the pairs of compacted level", 0) == 0);
}

TEST_CASE("fused path: every instruction set of the lanes (scalar, AVX2, AVX-512F) gives the passes' pairs") {
  rayspace::test::TestSettings settings;
  for (const char* file : {"office.json", "cornell-mirrors.json"}) {
    const Scene s = test::LoadBundled(file);
    const PathRun passes = RunPath(s, 32, 32, {}, false);
    for (const emu::cone::Isa isa : {emu::cone::Isa::kScalar, emu::cone::Isa::kAvx2, emu::cone::Isa::kAvx512}) {
      if (!emu::cone::Runs(isa)) {
        MESSAGE("this CPU lacks " << emu::cone::IsaName(isa));
        continue;
      }
      CAPTURE(file);
      CAPTURE(emu::cone::IsaName(isa));
      settings->fused_isa = isa;
      const std::string diff = Compare(passes, RunPath(s, 32, 32, {}, true));
      CHECK(diff == "");
    }
  }
}
