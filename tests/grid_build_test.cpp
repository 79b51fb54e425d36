// The grids' build as passes (grid.count, grid.emit, the sort by cell, grid.cells; what `diff` runs
// on both backends) against the host build the render path runs (grid::Build): the same arrays bit
// for bit on random soups with point and area lights, the eye's 2D and 3D grids, culling and margins
// on and off, at 1 and 2 threads; a regular grid's spans by a known answer; an unstable sort by cell
// (a planted fault of the kind a GPU sort makes) is caught.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/grid/tracer.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"
#include "test_util.h"
#include "tl_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

SceneBuffers Soup(std::uint32_t triangles, std::uint32_t seed, std::mt19937& rng) {
  SceneBuffers b;
  b.triangles = test::TlSoup(triangles, seed);
  b.lo = glm::vec3(INFINITY);
  b.hi = -b.lo;
  for (const layout::Triangle& t : b.triangles)
    for (const glm::vec4& v : {t.v0, t.v1, t.v2}) b.lo = glm::min(b.lo, Xyz(v)), b.hi = glm::max(b.hi, Xyz(v));
  std::uniform_real_distribution<float> u(-0.6f, 0.6f);
  std::uint32_t slot = 0;
  const auto light = [&](std::uint32_t shape, glm::vec4 position) {
    layout::Light l{};
    l.position = position;
    l.axis_u = glm::vec4(0.05f, 0.0f, 0.01f, 2.0f);
    l.axis_v = glm::vec4(0.0f, 0.04f, 0.02f, 2.0f);
    l.attenuation = glm::vec4(1, 0, 0, 0.125f);
    l.sampling = glm::uvec4(shape, shape == layout::kLightPoint ? 1u : 4u, slot, 2u);
    slot += l.sampling.y;
    b.lights.push_back(l);
  };
  light(layout::kLightPoint, glm::vec4(u(rng), 1.1f, u(rng), 1.0f));
  light(layout::kLightSphere, glm::vec4(u(rng), u(rng), u(rng), 0.07f));
  light(layout::kLightRect, glm::vec4(u(rng), u(rng), u(rng), 1.0f));
  light(layout::kLightPoint, glm::vec4(u(rng), u(rng), u(rng), 1.0f));  // inside the soup: triangles through it
  return b;
}

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// "" when the two builds agree bit for bit, else the first array that differs.
std::string Differs(const GridArrays& a, const GridArrays& b) {
  if (!SameBits(a.first, b.first)) return "first";
  if (!SameBits(a.triangles, b.triangles)) return "triangles";
  if (!SameBits(a.boxes, b.boxes)) return "boxes";
  if (!SameBits(a.min_dist, b.min_dist)) return "min_dist";
  if (!SameBits(a.light_grids, b.light_grids) || !SameBits(a.origins, b.origins)) return "light_grids/origins";
  if (!SameBits(a.volume, b.volume) || !SameBits(a.volume_dims, b.volume_dims) || !SameBits(a.slices, b.slices)) return "volume/slices";
  if (a.eye != b.eye || a.secondary != b.secondary) return "eye/secondary";
  if (a.perspective_cells != b.perspective_cells || a.perspective_refs != b.perspective_refs || a.regular_cells != b.regular_cells ||
      a.regular_refs != b.regular_refs || a.volume_cells != b.volume_cells || a.volume_refs != b.volume_refs)
    return "counters";
  return "";
}

// The emulator's passes, with the sort by cell replaced by an unstable one (ties in reverse order).
class UnstableSort final : public HierarchyPasses {
 public:
  std::string Name() const override { return "emu-unstable-sort"; }
#define RS_FORWARD(C) \
  call::C::Result C(const call::C& c) override { return EmuHierarchyPasses().C(c); }
  RS_FORWARD(Hash) RS_FORWARD(Compress) RS_FORWARD(Decompress) RS_FORWARD(BuildLeaves) RS_FORWARD(BuildParents)
  RS_FORWARD(ObjectMask) RS_FORWARD(TraverseTop) RS_FORWARD(TraverseLevel) RS_FORWARD(Reduce) RS_FORWARD(TraverseTopCompacted)
  RS_FORWARD(TraverseLevelCompacted) RS_FORWARD(Intersect) RS_FORWARD(TreeRoots) RS_FORWARD(TreeExpand) RS_FORWARD(TreeTest)
  RS_FORWARD(TreeStep) RS_FORWARD(IntersectTree) RS_FORWARD(TlLists) RS_FORWARD(TlHeads) RS_FORWARD(TlCells) RS_FORWARD(TlTrace)
  RS_FORWARD(GridCount) RS_FORWARD(GridEmit) RS_FORWARD(GridCells) RS_FORWARD(GridTrace)
#undef RS_FORWARD
  std::vector<std::uint32_t> SortChunks(const call::SortChunks& c) override {
    std::vector<std::uint32_t> order(c.chunk_key.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return c.chunk_key[x] != c.chunk_key[y] ? c.chunk_key[x] < c.chunk_key[y] : x > y;
    });
    return order;
  }
};

}  // namespace

TEST_CASE("grid build: the passes give the host build's arrays, bit for bit, on random grids and soups") {
  rayspace::test::TestSettings settings;
  std::mt19937 rng(20261127);
  for (int round = 0; round < 14; ++round) {
    CAPTURE(round);
    const std::uint32_t triangles = std::uniform_int_distribution<std::uint32_t>(1, 2400)(rng);
    const SceneBuffers b = Soup(triangles, 100 + round, rng);
    grid::Options o;
    o.cells = std::uniform_int_distribution<std::uint32_t>(1, 48)(rng);
    o.regular = std::uniform_int_distribution<std::uint32_t>(1, 30)(rng);
    o.area_cells = std::uniform_int_distribution<std::uint32_t>(1, 24)(rng);
    o.area_depth = std::uniform_int_distribution<std::uint32_t>(1, 6)(rng);
    o.area_near = std::uniform_int_distribution<std::uint32_t>(1, 8)(rng);
    o.closed = rng() % 2 == 0;
    o.margins = rng() % 4 != 0;
    o.secondary_perspective = rng() % 2 == 0;
    o.area_perspective = rng() % 5 != 0;
    const glm::vec3 eye(0.1f, 0.2f, -2.0f);
    const std::uint32_t eye_cells = std::uniform_int_distribution<std::uint32_t>(1, 9)(rng);
    const bool with_eye = rng() % 2 == 0;
    CAPTURE(triangles);
    CAPTURE(o.cells);
    CAPTURE(o.regular);
    CAPTURE(o.area_cells);
    CAPTURE(o.area_depth);
    CAPTURE(o.closed);
    CAPTURE(o.margins);
    const int threads = 1 + round % 2;
    settings->threads = threads;
    const GridArrays host = grid::Build(b, o, with_eye ? &eye : nullptr, eye_cells, &eye);
    const GridArrays passes = BuildWithPasses(b, grid::Plan(b, o, with_eye ? &eye : nullptr, eye_cells, &eye), EmuHierarchyPasses());
    settings->threads = 0;
    REQUIRE(host.triangles.size() > 0);
    CHECK(Differs(host, passes) == "");
  }
}

TEST_CASE("grid build: --grid-regular-cells picks the count along the longest side whose grid is closest") {
  // A cube: n^3; 54^3 = 157,464 is 2,536 from 160,000, 55^3 = 166,375 is 6,375 from it.
  CHECK(grid::RegularLongestFor({1.0, 1.0, 1.0}, 160000) == 54u);
  // A 2:1:1 box: n x ceil(n/2)^2; 16 x 8 x 8 = 1,024 is 24 from 1,000, 15 x 8 x 8 = 960 is 40.
  CHECK(grid::RegularLongestFor({2.0, 1.0, 1.0}, 1000) == 16u);
  // A tie: on the 2:1:1 box 3 x 2 x 2 = 12 and 4 x 2 x 2 = 16 are both 2 from 14: the lower count wins.
  CHECK(grid::RegularLongestFor({2.0, 1.0, 1.0}, 14) == 3u);
  CHECK(grid::RegularLongestFor({1.0, 1.0, 1.0}, 1) == 1u);
  CHECK(grid::RegularLongestFor({1.0, 1.0, 1.0}, std::uint64_t{1} << 40) == grid::kRegularLongestMax);
  // The build uses it: a unit cube scene's grid of about 160,000 cells is 54 x 54 x 54.
  SceneBuffers b;
  b.triangles = {test::MakeTriangle({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 1.0f})};
  b.lo = glm::vec3(0.0f);
  b.hi = glm::vec3(1.0f);
  grid::Options o;
  o.regular = 7;  // replaced by the cell count's choice
  o.regular_cells = 160000;
  CHECK(grid::Plan(b, o, nullptr, 0, nullptr).arrays.volume_dims[0] == glm::uvec4(54u, 54u, 54u, 0u));
}

TEST_CASE("grid build: a regular grid's spans and references by a known answer") {
  SceneBuffers b;
  b.triangles = {test::MakeTriangle({0.5f, 0.5f, 0.5f}, {2.5f, 0.5f, 0.5f}, {0.5f, 1.5f, 3.5f}),
                 test::MakeTriangle({3.25f, 3.25f, 3.25f}, {3.75f, 3.25f, 3.25f}, {3.25f, 3.75f, 3.75f})};
  layout::GridBuildGrid g{};
  g.centre = glm::vec4(0.0f);  // the grid's lo
  g.cell = glm::vec4(1.0f, 1.0f, 1.0f, 0.0f);
  g.shape = glm::uvec4(layout::kGridKindRegular, 4u, 4u, 4u);
  const grid::GridDescriptor d = grid::Describe(g);
  const GridCounts counts = PassGridCount({.triangles = b.triangles, .grid = d.params, .shape = d.shape});
  // Without margins: x 0..2, y 0..1, z 0..3, and one cell, (3, 3, 3).
  REQUIRE(counts.counts == std::vector<std::uint32_t>{24u, 1u});
  CHECK(counts.spans[0] == glm::uvec4(0u | 2u << 16, 0u | 1u << 16, 0u | 3u << 16, 1u));
  CHECK(counts.spans[6] == glm::uvec4(3u | 3u << 16, 3u | 3u << 16, 3u | 3u << 16, 1u));
  CHECK(counts.dist.empty());
  const GridRefs refs = PassGridEmit({.grid = d.params, .shape = d.shape, .counts = counts.counts, .spans = counts.spans});
  CHECK(refs.offsets == std::vector<std::uint32_t>{0u, 24u});
  // Slices, rows, columns: the first references (0,0,0), (1,0,0), (2,0,0), (0,1,0); the last (3,3,3) = 63.
  CHECK(refs.cells[0] == 0u);
  CHECK(refs.cells[1] == 1u);
  CHECK(refs.cells[3] == 4u);
  CHECK(refs.cells[6] == 16u);
  CHECK(refs.cells[24] == 63u);
  CHECK(refs.triangles[24] == 1u);
}

TEST_CASE("grid build: an unstable sort by cell (planted) breaks the lists' ascending order, and the comparison sees it") {
  std::mt19937 rng(7);
  const SceneBuffers b = Soup(900, 3, rng);
  grid::Options o;
  o.cells = 12;
  o.regular = 6;
  const GridArrays host = grid::Build(b, o);
  UnstableSort unstable;
  const GridArrays planted = BuildWithPasses(b, grid::Plan(b, o), unstable);
  CHECK(Differs(host, planted) == "triangles");
  CHECK(Differs(host, BuildWithPasses(b, grid::Plan(b, o), EmuHierarchyPasses())) == "");
}
