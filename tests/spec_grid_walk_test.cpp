// The relaxed device model of a ray's walk through the regular grid (verify/src/spec_grid_walk.cpp),
// on a grid of 4 x 4 x 4 unit cells where the cells a ray crosses follow by hand.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_model.h"

namespace {

using namespace rayspace;

// One reflection ray from (0.5, 0.5, 0.5) along `dir`, and one triangle: the wall x = 2.5 (hit at
// t = 2 by both rays below), listed in cell (cx, cy, 0) only, so what decides the answer is which
// cells a walk visits.
struct WalkCase {
  std::vector<std::uint32_t> first, cell_triangles = {0};
  std::vector<glm::vec4> volume = {glm::vec4(0.0f), glm::vec4(1.0f), glm::vec4(1.0f), glm::vec4(4.0f)};
  std::vector<glm::uvec4> volume_dims = {glm::uvec4(4, 4, 4, 0)};
  std::vector<layout::Triangle> triangles;
  std::vector<layout::Ray> rays;
  emu::call::GridTrace call;
  WalkCase(glm::vec3 dir, std::uint32_t cx, std::uint32_t cy) {
    const std::uint32_t listed = cy * 4 + cx;
    for (std::uint32_t c = 0; c <= 64; ++c) first.push_back(c <= listed ? 0u : 1u);
    layout::Triangle t{};
    t.v0 = glm::vec4(2.5f, -8.0f, -8.0f, 1.0f);
    t.v1 = glm::vec4(2.5f, 8.0f, -8.0f, 1.0f);
    t.v2 = glm::vec4(2.5f, 0.0f, 8.0f, 1.0f);
    triangles = {t};
    layout::Ray r{};
    r.origin_tmin = glm::vec4(0.5f, 0.5f, 0.5f, 0.0f);
    r.direction_tmax = glm::vec4(dir, 100.0f);
    r.info = glm::uvec4(0, layout::kNoPrim, layout::kRayReflection, 0);
    rays = {r};
    call = {.first = first, .cell_triangles = cell_triangles, .volume = volume, .volume_dims = volume_dims, .triangles = triangles,
            .rays = rays};
  }
  emu::GridWalks Emulated() const { return emu::PassGridTrace(call); }
  verify::SpecVerdict Verdict(std::uint64_t hit, std::uint32_t steps, std::uint32_t tests) const {
    const emu::GridWalks emulated = Emulated();
    emu::GridWalks device = emulated;
    device.hits = {hit};
    device.steps = {steps};
    device.tests = {tests};
    return verify::ClassifyWithinSpec("grid.trace", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

}  // namespace

TEST_CASE("relaxed model: a regular-grid walk tests a wall whose hit lies inside a cell every walk crosses") {
  // Along (1, 0.15, 0.1) the ray stays in row 0 until x = 3.83: cells x = 0, 1, 2, 3 of row 0, then
  // (3, 1); the wall's hit at t = 2, (2.5, 0.8, 0.7), is well inside cell (2, 0, 0).
  const WalkCase c(glm::vec3(1.0f, 0.15f, 0.1f), 2, 0);
  const emu::GridWalks e = c.Emulated();
  REQUIRE(e.hits[0] != emu::kMissPacked);
  REQUIRE(emu::HitT(e.hits[0]) == 2.0f);
  REQUIRE(e.steps[0] == 3u);
  REQUIRE(e.tests[0] == 1u);
  const verify::SpecVerdict missed = c.Verdict(emu::kMissPacked, 5, 1);
  CHECK(missed.modelled);
  CHECK(missed.beyond == 1);  // every device crosses (2, 0, 0) and the wall surely hits there
  CHECK(c.Verdict(e.hits[0], 3, 0).beyond == 1);    // a hit without a test
  CHECK(c.Verdict(e.hits[0], 40, 1).beyond == 1);   // more steps than any walk has
  CHECK(c.Verdict(e.hits[0], 4, 1).within == 1);    // one cell more before stopping: the exit's rounding
}

TEST_CASE("relaxed model: where two crossings tie a regular-grid walk may take either cell, and miss a triangle listed in one") {
  // Along (1, 1, 0.1) the ray leaves cell (0, 0) through its corner at t = 0.5: lavapipe steps along
  // x first (a tie keeps the lower axis) and meets the wall's listing in (1, 0); a device whose
  // crossings round apart may step along y into (0, 1) and never see it.
  const WalkCase c(glm::vec3(1.0f, 1.0f, 0.1f), 1, 0);
  const emu::GridWalks e = c.Emulated();
  REQUIRE(e.hits[0] != emu::kMissPacked);
  REQUIRE(e.steps[0] == 5u);  // (0,0), (1,0) where the wall is met, (1,1), (2,1), (2,2) past its hit
  // Without the wall a walk crosses seven cells to x = 4 by either corner, every time.
  const verify::SpecVerdict other_way = c.Verdict(emu::kMissPacked, 7, 0);
  CHECK(other_way.modelled);
  CHECK(other_way.within == 1);
  CHECK(other_way.beyond == 0);
  CHECK(c.Verdict(emu::kMissPacked, 5, 0).beyond == 1);  // a walk without a hit goes to the end
}
