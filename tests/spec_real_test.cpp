// Known answers for the relaxed device model's numbers (verify/spec_real.h): what Vulkan lets a
// device compute for one operation, the flushing of denormals, and the decisions a permitted
// rounding may flip.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_model.h"
#include "rayspace/verify/spec_real.h"

using rayspace::verify::ScopedSpecTrace;
using rayspace::verify::SpecReal;

namespace {

float Up(float x, int n = 1) {
  for (int i = 0; i < n; ++i) x = std::nextafter(x, INFINITY);
  return x;
}
float Down(float x, int n = 1) {
  for (int i = 0; i < n; ++i) x = std::nextafter(x, -INFINITY);
  return x;
}

}  // namespace

TEST_CASE("relaxed model: add and multiply give the exact value or a neighbour (RTE or RTZ)") {
  ScopedSpecTrace trace(false);
  const SpecReal s = SpecReal(1.0f) + SpecReal(0x1p-30f);  // not representable: 1 or the float above
  CHECK(s.v == 1.0f);
  CHECK(s.lo == 1.0f);
  CHECK(s.hi == Up(1.0f));
  const SpecReal p = SpecReal(3.0f) * SpecReal(5.0f);  // exact
  CHECK((p.lo == 15.0f && p.hi == 15.0f));
  const SpecReal d = SpecReal(1e30f) - SpecReal(1e30f);
  CHECK((d.lo == 0.0f && d.hi == 0.0f));
}

TEST_CASE("relaxed model: division within 2.5 ULP of the exact quotient, nothing outside") {
  ScopedSpecTrace trace(false);
  const SpecReal q = SpecReal(1.0f) / SpecReal(3.0f);
  // 1/3 lies in [0.25, 0.5): ULP 2^-25, and 1/3 = 0x3eaaaaaa + 2/3 ULP (IEEE rounds it to ...ab).
  // The floats within 2.5 ULP: 0x3eaaaaa9 .. 0x3eaaaaad.
  CHECK(q.v == std::bit_cast<float>(0x3eaaaaabu));
  CHECK(q.lo == std::bit_cast<float>(0x3eaaaaa9u));
  CHECK(q.hi == std::bit_cast<float>(0x3eaaaaadu));
  CHECK(q.Allows(Down(q.v, 2)));
  CHECK_FALSE(q.Allows(Down(q.v, 3)));
  CHECK(q.Allows(Up(q.v, 2)));
  CHECK_FALSE(q.Allows(Up(q.v, 3)));
  // A quotient past the largest float may come out as infinity or the largest float: no bound is
  // kept, and the exact value (infinity) is allowed.
  const SpecReal big = SpecReal(3e38f) / SpecReal(0.5f);
  CHECK(big.Allows(INFINITY));
  CHECK(big.Allows(big.v));
  // A divisor outside [2^-126, 2^126] carries no precision requirement.
  CHECK((SpecReal(1.0f) / SpecReal(0x1p127f)).any);
  CHECK((SpecReal(1.0f) / SpecReal(0.0f)).any);
}

TEST_CASE("relaxed model: sqrt inherited from 1 / inversesqrt") {
  ScopedSpecTrace trace(false);
  const SpecReal r = Sqrt(SpecReal(4.0f));
  CHECK(r.v == 2.0f);
  CHECK(r.lo < 2.0f);
  CHECK(r.hi > 2.0f);
  // inversesqrt(4) = 0.5 within 2 ULP (ULP 2^-24 there) and 1 / that within 2.5 ULP: about 6.5 ULP of
  // 2 below and 4.5 above, never 8.
  CHECK(r.Allows(Down(2.0f, 6)));
  CHECK_FALSE(r.Allows(Down(2.0f, 8)));
  CHECK(r.Allows(Up(2.0f, 4)));
  CHECK_FALSE(r.Allows(Up(2.0f, 6)));
  CHECK(Sqrt(SpecReal(0.0f)).lo == 0.0f);
  CHECK(Sqrt(SpecReal(-1.0f)).any);
}

TEST_CASE("relaxed model: an integer converts to either neighbouring float") {
  ScopedSpecTrace trace(false);
  const SpecReal f = SpecReal::FromInteger(42949707u);  // between the floats 42949704 and 42949708
  CHECK(f.v == 42949708.0f);
  CHECK(f.Allows(42949704.0f));
  CHECK(f.Allows(42949708.0f));
  CHECK_FALSE(f.Allows(42949712.0f));
  const SpecReal exact = SpecReal::FromInteger(1u << 20);
  CHECK((exact.lo == exact.hi && exact.v == 1048576.0f));
}

TEST_CASE("relaxed model: denormals may be flushed only on a flushing device") {
  const SpecReal a(0x1p-70f), b(0x1p-70f);
  {
    ScopedSpecTrace trace(false);
    const SpecReal p = a * b;  // 2^-140, a denormal
    CHECK(p.lo == 0x1p-140f);
    CHECK_FALSE(p.Allows(0.0f));
  }
  {
    ScopedSpecTrace trace(true);
    const SpecReal p = a * b;
    CHECK(p.Allows(0.0f));
    CHECK(p.Allows(0x1p-140f));
    CHECK(SpecReal(0x1p-144f).Allows(0.0f));  // a denormal input may be read as zero
    CHECK_FALSE(SpecReal(0x1p-126f).Allows(0.0f));
  }
}

TEST_CASE("relaxed model: a decision the permitted rounding can flip is counted, a sure one is not") {
  ScopedSpecTrace trace(false);
  const SpecReal third = SpecReal(1.0f) / SpecReal(3.0f);
  CHECK(trace.trace().ambiguous == 0);
  const bool sure = third < SpecReal(0.5f);
  CHECK(sure);
  CHECK(trace.trace().ambiguous == 0);
  (void)(third * SpecReal(3.0f) < SpecReal(1.0f));  // 1/3 * 3 may round either side of 1
  CHECK(trace.trace().ambiguous == 1);
}

TEST_CASE("relaxed model: the exact evaluation always lies inside the permitted interval") {
  ScopedSpecTrace trace(true);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-100.0f, 100.0f);
  for (int i = 0; i < 20000; ++i) {
    const SpecReal a(u(rng)), b(u(rng)), c(u(rng));
    for (const SpecReal& r : {a + b * c, (a - b) / c, Sqrt(Abs(a) * Abs(b)) + c, Min(a, b) / (c * c + SpecReal(1.0f))}) {
      if (r.any) continue;
      REQUIRE(r.lo <= r.v);
      REQUIRE(r.v <= r.hi);
    }
  }
}

TEST_CASE("relaxed model: resolve bytes a device may produce, and one it may not") {
  using rayspace::verify::BufferSet;
  using rayspace::verify::ClassifyWithinSpec;
  // Channel values whose gamma-corrected byte sits at a rounding boundary (x * 255 + 0.5 within a few
  // ULP of an integer) may come out one lower or higher on a device; one in the middle may not.
  // c = (k - 0.5)^2 / 255^2 puts sqrt(c) * 255 + 0.5 on the integer k.
  const std::uint64_t one = std::uint64_t{1} << 32;
  const double k = 100.0;
  const std::uint64_t boundary = static_cast<std::uint64_t>(std::ldexp((k - 0.5) * (k - 0.5) / (255.0 * 255.0), 32));
  BufferSet in, expected, actual;
  in.Put("accum", std::vector<std::uint64_t>{boundary, one / 9});  // 1/9 -> 1/3 -> 85.5: far from the boundary
  expected.Put("rgb", std::vector<std::uint8_t>{static_cast<std::uint8_t>(k) , 85});
  SUBCASE("one lower at the boundary: within") {
    actual.Put("rgb", std::vector<std::uint8_t>{static_cast<std::uint8_t>(k - 1), 85});
    const auto v = ClassifyWithinSpec("resolve", in, expected, actual);
    CHECK(v.modelled);
    CHECK(v.within == 1);
    CHECK(v.beyond == 0);
  }
  SUBCASE("one higher in the middle of a byte: beyond") {
    actual.Put("rgb", std::vector<std::uint8_t>{static_cast<std::uint8_t>(k), 86});
    const auto v = ClassifyWithinSpec("resolve", in, expected, actual);
    CHECK(v.beyond == 1);
    CHECK(v.first_beyond.find("rgb[1]") != std::string::npos);
  }
  SUBCASE("a pass without a model is not classified") {
    CHECK_FALSE(ClassifyWithinSpec("sort", in, expected, actual).modelled);
  }
}

namespace {
// A node at the origin about +z with a half-angle of 0.1 rad, and the smallest radius of a sphere at
// (1, 0, 5) that the float test accepts, found by bisection over the floats: there the decision is one
// rounding away from the other answer. Radius 2 is accepted with room to spare.
struct BoundaryCase {
  rayspace::layout::ConeNode node{};
  float radius = 0.0f;
};
BoundaryCase Boundary() {
  BoundaryCase b;
  b.node.sphere = glm::vec4(0, 0, 0, 0.001f);
  b.node.cone = glm::vec4(0, 0, 1, std::cos(0.1f));
  b.node.extra = glm::vec4(std::sin(0.1f), 1, 0, 0);
  auto accepts = [&](float r) { return rayspace::emu::cone::Test(b.node, glm::vec4(1, 0, 5, r), 0.0f); };
  std::uint32_t lo = std::bit_cast<std::uint32_t>(0.0f), hi = std::bit_cast<std::uint32_t>(2.0f);
  REQUIRE(!accepts(0.0f));
  REQUIRE(accepts(2.0f));
  while (hi - lo > 1) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    (accepts(std::bit_cast<float>(mid)) ? hi : lo) = mid;
  }
  b.radius = std::bit_cast<float>(hi);
  return b;
}
}  // namespace

TEST_CASE("relaxed model: a cone-sphere test on its boundary may flip, one far from it may not") {
  using namespace rayspace;
  using rayspace::verify::BufferSet;
  using rayspace::verify::ClassifyWithinSpec;
  const BoundaryCase b = Boundary();
  const layout::ConeNode n = b.node;
  emu::call::ObjectMask c;
  const std::vector<layout::ConeNode> top = {n};
  const std::vector<glm::vec4> spheres = {glm::vec4(1, 0, 5, b.radius), glm::vec4(1, 0, 5, 2.0f)};
  c.top = top;
  c.object_spheres = spheres;
  const BufferSet in = rayspace::verify::EncodeCall(c);
  BufferSet expected, actual;
  expected.Put("mask", std::vector<std::uint8_t>{1, 1});
  actual.Put("mask", std::vector<std::uint8_t>{0, 1});
  const auto boundary = ClassifyWithinSpec("traverse.objects", in, expected, actual);
  CHECK(boundary.within == 1);
  CHECK(boundary.beyond == 0);
  actual.Put("mask", std::vector<std::uint8_t>{1, 0});
  const auto far = ClassifyWithinSpec("traverse.objects", in, expected, actual);
  CHECK(far.beyond == 1);
}

TEST_CASE("relaxed model: the fused traversal's list may gain or lose a pair whose test may flip, in slot order only") {
  using namespace rayspace;
  using rayspace::verify::BufferSet;
  using rayspace::verify::ClassifyWithinSpec;
  // One parent with one child node; two pairs, triangle 0's sphere on the test's boundary and
  // triangle 1's accepted with room to spare.
  const BoundaryCase b = Boundary();
  const layout::ConeNode n = b.node;
  const std::vector<layout::ConeNode> nodes = {n};
  const std::vector<std::uint32_t> pairs = {0u, 1u}, first = {0u, 1u};
  const std::vector<glm::vec4> spheres = {glm::vec4(1, 0, 5, b.radius), glm::vec4(1, 0, 5, 2.0f)};
  emu::call::TraverseLevel c;
  c.pairs = pairs;
  c.nodes = nodes;
  c.first = first;
  c.children_max = 1;
  c.tri_spheres = spheres;
  const BufferSet in = rayspace::verify::EncodeCall(c);
  const auto verdict = [&](std::vector<std::uint32_t> device, std::uint64_t tested = 2) {
    BufferSet expected, actual;
    expected.Put("pairs", std::vector<std::uint32_t>{0u, 1u});  // child 0 with triangles 0 and 1, both kept
    expected.Put("tested", std::vector<std::uint64_t>{2});
    actual.Put("pairs", device);
    actual.Put("tested", std::vector<std::uint64_t>{tested});
    return ClassifyWithinSpec("traverse.compact.level", in, expected, actual);
  };
  const auto boundary = verdict({1u});  // the boundary pair dropped: a conformant device may
  CHECK(boundary.modelled);
  CHECK(boundary.within == 1);
  CHECK(boundary.beyond == 0);
  const auto far = verdict({0u});  // the far pair dropped: none may
  CHECK(far.beyond == 1);
  CHECK(far.first_beyond.find("dropped") != std::string::npos);
  CHECK(verdict({1u, 0u}).beyond >= 1);         // out of slot order
  CHECK(verdict({0u, 1u, 7u}).beyond == 1);     // a pair no slot gives
  CHECK(verdict({0u, 1u}, 3).beyond == 1);      // the tests run are counted exactly
  CHECK(verdict({0u, 1u}).AllWithin());         // equal lists: nothing beyond
}

namespace {
// The object-tree descent's smallest call: one level-1 cone node (the boundary case's) over one ray,
// and an object tree whose root (at (1, 0, 5), radius 1000: the object side is refined, with room to
// spare) has two children, the boundary sphere and the far one (radius 2).
struct TreeCase {
  BoundaryCase b = Boundary();
  std::vector<rayspace::layout::ConeNode> cone_nodes;
  std::vector<std::uint32_t> cone_base = {0, 1, 2}, cone_first = {0, 1, 0, 1};
  std::vector<glm::vec4> spheres;
  std::vector<glm::uvec4> links = {glm::uvec4(1, 2, 0, 0), glm::uvec4(0), glm::uvec4(0)};
  std::vector<std::uint32_t> depth = {0, 1, 1}, roots = {0}, children = {1, 2}, none;
  std::vector<glm::vec4> tri_spheres;
  std::uint32_t cone = 1u << rayspace::layout::kTreeLevelShift;  // level 1, node 0
  TreeCase() {
    rayspace::layout::ConeNode ray = b.node;
    cone_nodes = {ray, b.node};
    spheres = {glm::vec4(1, 0, 5, 1000), glm::vec4(1, 0, 5, b.radius), glm::vec4(1, 0, 5, 2)};
  }
  rayspace::emu::ConeTreeView Cones() const { return {cone_nodes, cone_base, cone_first}; }
  rayspace::emu::ObjectTreeView Tree(const std::vector<std::uint32_t>& tree_roots) const {
    return {spheres, links, depth, tree_roots, tri_spheres, none};
  }
};
}  // namespace

TEST_CASE("relaxed model: the object-tree descent may keep or drop a candidate whose test may flip, and counts it") {
  using namespace rayspace;
  using rayspace::verify::BufferSet;
  using rayspace::verify::ClassifyWithinSpec;
  const TreeCase tc;
  const std::vector<std::uint32_t> pair_cone = {tc.cone}, pair_item = {0u}, offsets = {0u};
  SUBCASE("tree.roots and tree.test: a flag per candidate") {
    emu::call::TreeRoots roots{.cones = tc.Cones(), .tree = tc.Tree(tc.children), .level = 1, .t0 = 0, .t1 = 1, .eps = 0.0f};
    emu::call::TreeTest test{.cones = tc.Cones(), .tree = tc.Tree(tc.roots), .pair_cone = pair_cone, .pair_item = pair_item,
                             .offsets = offsets, .slots = 2, .eps = 0.0f};
    for (const auto& [method, in, emulated] :
         {std::tuple{"tree.roots", verify::EncodeCall(roots), emu::PassTreeRoots(roots)},
          std::tuple{"tree.test", verify::EncodeCall(test), emu::PassTreeTest(test)}}) {
      CAPTURE(method);
      REQUIRE(emulated.flags == std::vector<std::uint8_t>{1, 1});  // both candidates kept, to go on
      const BufferSet expected = verify::EncodeOutputs(test, &emulated);  // roots' buffers are test's
      const auto verdict = [&](std::vector<std::uint8_t> flags, int hits_lost) {
        emu::TreeSlots device = emulated;
        device.flags = flags;
        device.counts.cone_hits[1] -= hits_lost;
        device.counts.node_hits[1] -= hits_lost;
        return ClassifyWithinSpec(method, in, expected, verify::EncodeOutputs(test, &device));
      };
      const auto boundary = verdict({0, 1}, 1);  // the boundary candidate dropped: a conformant device may
      CHECK(boundary.modelled);
      CHECK(boundary.within == 1);
      CHECK(boundary.beyond == 0);
      const auto far = verdict({1, 0}, 1);  // the far one dropped: none may
      CHECK(far.beyond >= 1);
      CHECK(far.first_beyond.find("flags[1]") != std::string::npos);
      CHECK(verdict({0, 1}, 0).beyond == 1);  // the counts not the device's own flags'
      CHECK(verdict({2, 1}, 0).beyond == 1);  // a node candidate is never final
      CHECK(verdict({1, 1}, 0).AllWithin());
      emu::TreeSlots moved = emulated;
      std::swap(moved.pairs.item[0], moved.pairs.item[1]);
      CHECK(ClassifyWithinSpec(method, in, expected, verify::EncodeOutputs(test, &moved)).beyond == 1);  // candidates are integers
    }
  }
  SUBCASE("tree.step: the kept candidates in slot order") {
    emu::call::TreeStep step{.cones = tc.Cones(), .tree = tc.Tree(tc.roots), .pair_cone = pair_cone, .pair_item = pair_item, .eps = 0.0f};
    const BufferSet in = verify::EncodeCall(step);
    const emu::TreeRound emulated = emu::PassTreeStep(step);
    REQUIRE(emulated.next.item == std::vector<std::uint32_t>{1u, 2u});
    const BufferSet expected = verify::EncodeOutputs(step, &emulated);
    const auto verdict = [&](std::vector<std::uint32_t> items, int hits_lost) {
      emu::TreeRound device = emulated;
      device.next.item = items;
      device.next.cone.assign(items.size(), tc.cone);
      device.counts.cone_hits[1] -= hits_lost;
      device.counts.node_hits[1] -= hits_lost;
      return ClassifyWithinSpec("tree.step", in, expected, verify::EncodeOutputs(step, &device));
    };
    const auto boundary = verdict({2u}, 1);
    CHECK(boundary.modelled);
    CHECK(boundary.within == 1);
    CHECK(boundary.beyond == 0);
    const auto far = verdict({1u}, 1);  // the far candidate dropped
    CHECK(far.beyond >= 1);
    CHECK(far.first_beyond.find("dropped") != std::string::npos);
    CHECK(verdict({2u}, 0).beyond == 1);          // counts
    CHECK(verdict({2u, 1u}, 0).beyond >= 1);      // out of slot order
    CHECK(verdict({1u, 2u, 2u}, -1).beyond >= 1);  // a candidate twice
    CHECK(verdict({1u, 2u}, 0).AllWithin());
  }
  SUBCASE("tree.expand: a pair refined on the side no device doubts has one count") {
    emu::call::TreeExpand expand{.cones = tc.Cones(), .tree = tc.Tree(tc.roots), .pair_cone = pair_cone, .pair_item = pair_item};
    BufferSet expected, actual;
    expected.Put("counts", std::vector<std::uint32_t>{2u});
    actual.Put("counts", std::vector<std::uint32_t>{1u});
    const auto v = ClassifyWithinSpec("tree.expand", verify::EncodeCall(expand), expected, actual);
    CHECK(v.modelled);
    CHECK(v.beyond == 1);
  }
}
