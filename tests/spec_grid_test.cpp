// grid.trace's relaxed device model of the perspective cells (verify/src/spec_grid.cpp), on the
// smallest grid where the answer follows by hand.
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_model.h"

namespace {

using namespace rayspace;

// A point light at the origin with a 2D perspective grid of 2 x 2 cells per face; its shadow ray
// along (3, 1, 0.5) falls in cell 3 of face +x at (u, v) = (1/3, 1/6), both quotients. Cell 3 lists
// one triangle, across the ray at x = 2, whose (u, v) rectangle starts at `u_min`.
struct GridCase {
  std::vector<std::uint32_t> first, cell_triangles = {0};
  std::vector<float> min_dist = std::vector<float>(24, 0.0f);
  std::vector<glm::vec4> boxes, origins = {glm::vec4(0, 0, 0, 1)};
  std::vector<glm::uvec4> light_grids = {glm::uvec4(0, 2, 0, 0)};
  std::vector<layout::Triangle> triangles;
  std::vector<layout::Ray> rays;
  emu::call::GridTrace call;
  explicit GridCase(float u_min) {
    for (std::uint32_t c = 0; c <= 24; ++c) first.push_back(c <= 3 ? 0u : 1u);
    boxes = {glm::vec4(u_min, 0, 1, 1)};
    layout::Triangle t{};
    t.v0 = glm::vec4(2, -1, -1, 1);
    t.v1 = glm::vec4(2, 3, -1, 1);
    t.v2 = glm::vec4(2, 0, 3, 1);
    triangles = {t};
    layout::Ray r{};
    r.origin_tmin = glm::vec4(0, 0, 0, 0);
    r.direction_tmax = glm::vec4(3, 1, 0.5f, 1);
    r.info = glm::uvec4(0, layout::kNoPrim, layout::kRayShadow, 0);
    rays = {r};
    call = {.first = first, .cell_triangles = cell_triangles, .min_dist = min_dist, .boxes = boxes, .light_grids = light_grids,
            .origins = origins, .triangles = triangles, .rays = rays, .shadow = 1};
  }
  verify::SpecVerdict Verdict(std::uint32_t occluded, std::uint32_t tests) const {
    const emu::GridWalks emulated = emu::PassGridTrace(call);
    emu::GridWalks device = emulated;
    device.occluded = {occluded};
    device.tests = {tests};
    return verify::ClassifyWithinSpec("grid.trace", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

}  // namespace

TEST_CASE("relaxed model: a perspective cell's ray may skip a triangle whose rectangle edge its (u, v) sits on, not another") {
  const float third = 1.0f / 3.0f;  // the ray's u as lavapipe divides
  const GridCase edge(third);
  const emu::GridWalks emulated = emu::PassGridTrace(edge.call);
  REQUIRE(emulated.occluded[0] == 1u);
  REQUIRE(emulated.steps[0] == 1u);
  REQUIRE(emulated.tests[0] == 1u);
  const verify::SpecVerdict skipped = edge.Verdict(0, 0);  // a u one ULP lower misses the rectangle
  CHECK(skipped.modelled);
  CHECK(skipped.within == 1);
  CHECK(skipped.beyond == 0);
  CHECK(edge.Verdict(0, 2).beyond == 1);  // two tests in a cell of one triangle

  const GridCase inside(0.0f);
  const verify::SpecVerdict dropped = inside.Verdict(0, 0);
  CHECK(dropped.beyond == 1);  // every device tests it and it surely hits
  CHECK(dropped.first_beyond.find("occluded[0]") != std::string::npos);
  CHECK(inside.Verdict(0, 1).beyond == 1);  // tested, surely hit, yet lit
}
