// grid.trace's render path (PassGridTraceLanes: each cell's triangles tested 8 or 16 at a time)
// against the pass that diff compares (PassGridTrace, ray by ray): the same hits, occlusion, steps and
// tests for every ray, hence the same statistics and frame digest, on the bundled scenes and random
// grid configurations, on every instruction set this CPU has; and a planted difference is seen.
#include <doctest/doctest.h>

#include <array>
#include <random>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/grid/tracer.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;

namespace {

struct GridRun {
  std::uint64_t digest = 0;
  std::vector<emu::GridBatchStats> stats;
  std::vector<std::uint8_t> rgb;
  std::vector<std::vector<std::uint64_t>> hits;
  std::vector<std::vector<std::uint32_t>> occluded;
  std::vector<std::uint64_t> eye_hits;  // the eye rays' batch (--primary grid)
};

GridRun Render(const Scene& s, const SceneBuffers& b, int size, emu::grid::Options o, bool primary, bool lanes) {
  o.lanes = lanes;
  const auto tracer = emu::MakeGridTracer(b, o);
  emu::FrameOptions fo;
  fo.width = fo.height = size;
  fo.trace_primary = primary;
  GridRun r;
  const emu::FrameResult f = emu::RenderFrame(s, b, *tracer, fo, [&](const emu::Batch& batch) {
    if (batch.hits) r.hits.push_back(*batch.hits);
    if (batch.kind == layout::kRayPrimary) r.eye_hits = *batch.hits;
    if (batch.occluded) r.occluded.push_back(*batch.occluded);
  });
  r.digest = f.digest.Frame();
  r.stats = tracer->Stats();
  r.rgb = f.rgb;
  return r;
}

// "" when the runs agree everywhere, else what differs first. The digest holds every batch's
// per-ray answers, steps and tests (grid_tracer.cpp); the rest names the difference.
std::string Compare(const GridRun& a, const GridRun& b) {
  if (a.hits != b.hits) return "closest hits";
  if (a.occluded != b.occluded) return "occlusion";
  if (a.stats.size() != b.stats.size()) return "the batches";
  for (std::size_t i = 0; i < a.stats.size(); ++i)
    if (a.stats[i].steps != b.stats[i].steps || a.stats[i].tests != b.stats[i].tests || a.stats[i].skipped_rays != b.stats[i].skipped_rays)
      return "the statistics of batch " + a.stats[i].name;
  if (a.rgb != b.rgb) return "the image";
  return a.digest == b.digest ? "" : "the frame digest";
}

emu::grid::Options RandomOptions(std::mt19937& rng) {
  emu::grid::Options o;
  o.cells = std::array{1u, 7u, 50u, 200u}[rng() % 4];
  o.regular = std::array{1u, 9u, 54u}[rng() % 3];
  o.closed = rng() % 4 == 0;
  o.area_cells = std::array{8u, 33u, 200u}[rng() % 3];
  o.area_depth = 1 + rng() % 4;
  o.area_near = std::array{1u, 8u}[rng() % 2];
  o.area_perspective = rng() % 3 != 0;
  o.secondary_perspective = rng() % 3 == 0;
  o.margins = rng() % 5 != 0;
  return o;
}

}  // namespace

// Three runs per scene (the default render's options, then two random), each walked by the pass and by
// the lanes.
static void CheckRandomConfigurations(const std::vector<std::pair<std::string, int>>& scenes) {
  rayspace::test::TestSettings settings;
  std::mt19937 rng(2027);
  std::size_t tested = 0;
  for (const auto& [file, size] : scenes) {
    const Scene s = test::LoadBundled(file);
    const SceneBuffers b = FlattenScene(s);
    for (int run = 0; run < 3; ++run) {
      // The first run is the default render's; the others random.
      const emu::grid::Options o = run == 0 ? emu::grid::Options{} : RandomOptions(rng);
      const bool primary = run != 1;
      const int threads = 1 + static_cast<int>(rng() % 2);
      INFO(file << " run " << run << ": cells " << o.cells << ", regular " << o.regular << ", closed " << o.closed << ", area " << o.area_cells
                << "x" << o.area_depth << " near " << o.area_near << (o.area_perspective ? "" : " (regular)") << ", secondary "
                << o.secondary_perspective << ", margins " << o.margins << ", primary " << primary << ", threads " << threads);
      settings->threads = threads;
      const GridRun pass = Render(s, b, size, o, primary, false), lanes = Render(s, b, size, o, primary, true);
      settings->threads = 0;
      REQUIRE(!pass.stats.empty());
      for (const emu::GridBatchStats& st : pass.stats) tested += st.tests;
      CHECK(Compare(pass, lanes) == "");
    }
  }
  MESSAGE("triangle tests compared: " << tested);
  CHECK(tested > 100000);  // enough triangle tests for the comparison to mean something
}

TEST_CASE("grid lanes: the pass's walks, statistics and digest on the bundled scenes and random configurations") {
  CheckRandomConfigurations({{"cornell-mirrors.json", 40}, {"cornell-soft.json", 24}, {"office.json", 32}});
}

// The full test tier: the same on the data scenes (the default tier's case guards the claim).
TEST_CASE("grid lanes: the pass's walks, statistics and digest on the data scenes and random configurations") {
  if (test::SkipWithoutData("sponza_dabrovic/sponza.obj")) return;
  CheckRandomConfigurations({{"sponza.json", 24}, {"sponza-soft.json", 16}, {"conference.json", 24}});
}

TEST_CASE("grid lanes: every instruction set (AVX2, AVX-512F) walks as the pass, shadow rays and eye rays") {
  const Scene s = test::LoadBundled("cornell-soft.json");
  const SceneBuffers b = FlattenScene(s);
  emu::grid::Options o;
  o.cells = 20;
  const GridRun pass = Render(s, b, 32, o, true, false);
  for (const emu::cone::Isa isa : {emu::cone::Isa::kAvx2, emu::cone::Isa::kAvx512}) {
    if (!emu::cone::Runs(isa)) {
      MESSAGE("this CPU lacks " << emu::cone::IsaName(isa));
      continue;
    }
    CAPTURE(emu::cone::IsaName(isa));
    const emu::GridLanes lanes = emu::PrepareGridLanes(b.triangles, isa);
    REQUIRE(lanes.isa == isa);
    // The tracer prepares the best ISA; here each batch's rays go through the chosen one directly.
    const auto tracer = emu::MakeGridTracer(b, o);
    emu::FrameOptions fo;
    fo.width = fo.height = 32;
    fo.trace_primary = true;
    std::size_t batches = 0, differing = 0;
    emu::RenderFrame(s, b, *tracer, fo, [&](const emu::Batch& batch) {
      const emu::GridArrays& g = tracer->Grids();
      const emu::call::GridTrace c{.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes,
                                   .light_grids = g.light_grids, .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims,
                                   .slices = g.slices, .triangles = b.triangles, .rays = *batch.rays, .shadow = batch.occluded ? 1u : 0u,
                                   .eye = g.eye, .secondary = g.secondary};
      const emu::GridWalks x = emu::PassGridTrace(c), y = emu::PassGridTraceLanes(c, lanes);
      ++batches;
      differing += x.hits != y.hits || x.occluded != y.occluded || x.steps != y.steps || x.tests != y.tests;
    });
    CHECK(batches >= 3);  // eye rays, shadow rays, reflections
    CHECK(differing == 0);
  }
  CHECK(pass.digest != 0);
}

TEST_CASE("grid lanes: a planted difference (the last lane of every full lane group dropped) is seen, in shadow and in eye rays") {
  rayspace::test::TestSettings settings;
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  emu::grid::Options o;
  o.cells = 1;    // long cell lists: full lane groups
  o.regular = 1;  // reflection rays test every triangle of the one cell
  for (const bool primary : {false, true}) {
    CAPTURE(primary);
    const GridRun pass = Render(s, b, 32, o, primary, false);
    settings->grid_lanes_fault = true;
    const GridRun faulty = Render(s, b, 32, o, primary, true);
    settings->grid_lanes_fault = false;
    CHECK(Compare(pass, faulty) != "");
    // The eye rays go through the tiled order alone: their batch differs too.
    if (primary) CHECK(pass.eye_hits != faulty.eye_hits);
    CHECK(Compare(pass, Render(s, b, 32, o, primary, true)) == "");
  }
}
