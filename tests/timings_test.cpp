// --timings' rows: the thesis's phases, every other pass by name, and the two remainders no pass
// covers, adding up to the frame's time (rayspace/frame/timings.h).
#include <doctest/doctest.h>

#include <numeric>
#include <string>
#include <vector>

#include "rayspace/frame/timings.h"

using rayspace::app::NamedShare;
using rayspace::app::Phase;
using rayspace::app::Phases;
using rayspace::emu::PassRecord;

namespace {

double Ms(const std::vector<Phase>& rows, const std::string& name) {
  for (const Phase& p : rows)
    if (p.name == name) return p.ms;
  FAIL("no row ", name);
  return -1;
}

double Sum(const std::vector<Phase>& rows) {
  return std::accumulate(rows.begin(), rows.end(), 0.0, [](double s, const Phase& p) { return s + p.ms; });
}

PassRecord Ran(const std::string& name, double ms, bool in_trace = false) { return {name, true, {}, ms, 1, in_trace}; }

}  // namespace

TEST_CASE("timings: a hierarchy frame's rows add up to the frame, the remainders named") {
  const std::vector<PassRecord> passes = {Ran("prep", 10),
                                          Ran("raster", 20),
                                          Ran("raygen.shadow.b0", 3),
                                          Ran("hash.shadow.b0", 5, true),
                                          Ran("build.shadow.b0", 2, true),
                                          Ran("tree.gather.shadow.b0", 1, true),
                                          Ran("trace.shadow.b0", 12),
                                          {"trace.reflection", false, "max_depth is 0", 0, 0, false},
                                          Ran("shade.b0", 2),
                                          Ran("resolve", 1)};
  const std::vector<Phase> rows = Phases(passes, 60, 6);
  CHECK(rows[0].name == "ray_creation");
  CHECK(Ms(rows, "ray_creation") == 3);
  CHECK(Ms(rows, "ray_compression") == 5);  // hash: the thesis's compression phase
  CHECK(Ms(rows, "hierarchy_creation") == 2);
  CHECK(Ms(rows, "prep") == 10);
  CHECK(Ms(rows, "raster") == 20);
  CHECK(Ms(rows, "shade") == 2);
  CHECK(Ms(rows, "resolve") == 1);
  CHECK(Ms(rows, "tree.gather") == 1);                // a tracer's pass of no phase, by its name
  CHECK(Ms(rows, "tracer_outside_its_passes") == 4);  // 12 - (5 + 2 + 1)
  CHECK(Ms(rows, "oracle") == 6);
  CHECK(Ms(rows, "frame_outside_passes") == 6);  // 60 - (10 + 20 + 3 + 12 + 2 + 1) - 6
  CHECK(Sum(rows) == doctest::Approx(60));
  CHECK(NamedShare(rows, 60) == doctest::Approx(1.0 - 10.0 / 60.0));
  for (const Phase& p : rows) CHECK(p.name != "other");
}

TEST_CASE("timings: a tracer without passes of its own counts its trace as final tests") {
  const std::vector<PassRecord> passes = {Ran("prep", 1), Ran("raster", 2), Ran("trace.shadow.b0", 30), Ran("resolve", 1)};
  const std::vector<Phase> rows = Phases(passes, 40, 0);
  CHECK(Ms(rows, "final_intersection_tests") == 30);
  for (const Phase& p : rows) CHECK(p.name != "tracer_outside_its_passes");
  CHECK(Ms(rows, "frame_outside_passes") == 6);
  CHECK(Sum(rows) == doctest::Approx(40));
}
