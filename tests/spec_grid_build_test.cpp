// grid.count's relaxed device model (verify/src/spec_grid_build.cpp) and the double arithmetic it
// runs on (verify::SpecDouble): known answers where the permitted values follow by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_double.h"
#include "rayspace/verify/spec_model.h"

namespace {

using namespace rayspace;
using verify::SpecDouble;

// A regular grid of 4 x 4 x 4 unit cells from the origin, no margins, one triangle whose x extent
// is [1, 2.5]: x / 1 rounds within 2.5 ULP of 24 bits, so its first column is 0 or 1 on some device
// (1 exactly, or just below), its last surely 2; y and z ([0.5, 1.5], [0.5, 0.5]) are certain.
struct RegularCase {
  std::vector<layout::Triangle> triangles;
  emu::grid::GridDescriptor desc{};
  emu::call::GridCount call;
  RegularCase() {
    layout::Triangle t{};
    t.v0 = glm::vec4(1.0f, 0.5f, 0.5f, 1.0f);
    t.v1 = glm::vec4(2.5f, 0.5f, 0.5f, 1.0f);
    t.v2 = glm::vec4(2.0f, 1.5f, 0.5f, 1.0f);
    triangles = {t};
    layout::GridBuildGrid g{};
    g.centre = glm::vec4(0.0f);
    g.cell = glm::vec4(1.0f, 1.0f, 1.0f, 0.0f);
    g.shape = glm::uvec4(layout::kGridKindRegular, 4, 4, 4);
    g.flags = glm::uvec4(0u);
    desc = emu::grid::Describe(g);
    call = {.triangles = triangles, .grid = desc.params, .shape = desc.shape};
  }
  // The device's words: columns [i0, i1], rows [0, 1], slice 0, and `count` references.
  verify::SpecVerdict Verdict(std::uint32_t i0, std::uint32_t i1, std::uint32_t count) const {
    const emu::GridCounts emulated = emu::PassGridCount(call);
    emu::GridCounts device = emulated;
    device.spans[0] = glm::uvec4(i0 | i1 << 16, 0u | 1u << 16, 0u, 1u);
    device.counts[0] = count;
    return verify::ClassifyWithinSpec("grid.count", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

}  // namespace

TEST_CASE("SpecDouble: + within a ULP of 24 bits, / within 2.5, sqrt and conversions to float either way") {
  const SpecDouble s = SpecDouble(1.0) + SpecDouble(0x1p-30);
  CHECK(s.v == 1.0 + 0x1p-30);
  CHECK(s.Allows(1.0));               // 24 bits, toward zero
  CHECK(s.Allows(1.0 + 0x1p-23));     // one ULP above
  CHECK_FALSE(s.Allows(1.0 + 0x1p-21));
  CHECK_FALSE(s.Allows(1.0 - 0x1p-21));

  const SpecDouble q = SpecDouble(1.0) / SpecDouble(3.0);  // 1/3 in [2^-2, 2^-1): a ULP is 2^-25
  CHECK(q.Allows(1.0 / 3.0 + 2.0 * 0x1p-25));
  CHECK(q.Allows(1.0 / 3.0 - 2.0 * 0x1p-25));
  CHECK_FALSE(q.Allows(1.0 / 3.0 + 3.0 * 0x1p-25));
  CHECK(SpecDouble::Unbounded(0.0).Allows(1e300));
  CHECK((SpecDouble(1.0) / SpecDouble(0.0)).any);  // no bound for a divisor at zero

  const SpecDouble r = verify::Sqrt(SpecDouble(4.0));
  CHECK(r.Allows(2.0));
  CHECK_FALSE(r.Allows(2.0 * (1.0 + 0x1p-18)));
  CHECK(r.lo >= 0.0);

  const verify::SpecReal f = verify::ToFloat(SpecDouble(1.0 + 0x1p-30));  // between two floats
  CHECK(f.Allows(1.0f));
  CHECK(f.Allows(std::nextafter(1.0f, 2.0f)));
  CHECK_FALSE(f.Allows(std::nextafter(std::nextafter(1.0f, 2.0f), 2.0f)));

  verify::ScopedSpecTrace trace(true);
  CHECK(s > SpecDouble(1.0));  // lavapipe's answer, which a device may not share
  CHECK(trace.trace().ambiguous == 1);
  CHECK(SpecDouble(2.0) > SpecDouble(1.0));
  CHECK(trace.trace().ambiguous == 1);
}

TEST_CASE("relaxed model: grid.count's first column may move where x / cell rounds across a cell boundary, the last may not") {
  const RegularCase c;
  const emu::GridCounts emulated = emu::PassGridCount(c.call);
  REQUIRE(emulated.spans[0] == glm::uvec4(1u | 2u << 16, 0u | 1u << 16, 0u, 1u));
  REQUIRE(emulated.counts[0] == 4u);
  const verify::SpecVerdict moved = c.Verdict(0, 2, 6);  // a quotient just below 1: column 0 too
  CHECK(moved.modelled);
  CHECK(moved.within == 1);
  CHECK(moved.beyond == 0);
  CHECK(c.Verdict(1, 1, 2).beyond == 1);  // the last column lost: 2.5 / 1 is surely in column 2
  CHECK(c.Verdict(0, 2, 4).beyond == 1);  // a count that is not its spans' cells
  const verify::SpecVerdict short_count = c.Verdict(1, 2, 3);
  CHECK(short_count.beyond == 1);
  CHECK(short_count.first_beyond.find("counts[0]") != std::string::npos);
}
