// Device outputs checked where a backend returns them (emu/output_checks.h): for each kind of index
// and count, a valid output passes and one bad element is refused naming the call, the backend, the
// buffer and that element.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/output_checks.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

const OutputSource kFrom{"testdev", "pass.L1.shadow.b0"};

// Four triangles and two materials: all the indices below range over these.
SceneBuffers SmallScene() {
  SceneBuffers s;
  s.triangles.resize(4);
  s.info.resize(4);
  s.materials.resize(2);
  s.lights.resize(1);
  return s;
}

std::uint32_t Pair(std::uint32_t node, std::uint32_t tri) { return node << layout::kPairTriangleBits | tri; }

template <typename C, typename R>
std::string Refusal(const C& c, const R* r) {
  try {
    CheckOutputs(c, r, kFrom);
  } catch (const DeviceOutputError& e) {
    return e.what();
  }
  return "accepted";
}

template <typename C, typename R>
void Refused(const C& c, const R* r, const std::string& buffer_and_element, const std::string& why) {
  const std::string what = Refusal(c, r);
  INFO(what);
  CHECK(what.find(std::string(C::kName) + " (pass.L1.shadow.b0) from the testdev backend: output '" + buffer_and_element) == 0);
  CHECK(what.find(why) != std::string::npos);
}

}  // namespace

TEST_CASE("output checks: surfaces name a pixel, triangle and material in range") {
  const SceneBuffers scene = SmallScene();
  layout::FrameConstants fc{};
  fc.dims = glm::uvec4(2, 1, 0, 0);
  const std::vector<glm::vec4> px(2);
  const std::vector<std::uint32_t> prim(2, layout::kNoPrim);
  const call::SurfacesFromGBuffer c{.frame = fc, .width = 2, .height = 1, .position = px, .normal = px, .prim = prim, .scene = &scene};
  std::vector<layout::Surface> out(2);
  out[0].info = glm::uvec4(3, 0, 1, 0);  // triangle 3, pixel 0, material 1: the last of each
  out[1].info = glm::uvec4(layout::kNoPrim, 1, 99, 0);  // an empty slot's material is never read
  CHECK(Refusal(c, &out) == "accepted");
  out[0].info.z = 2;  // a wrong material id
  Refused(c, &out, "surfaces' element 0", "names material 2, out of range [0, 2)");
  out[0].info = glm::uvec4(4, 0, 0, 0);
  Refused(c, &out, "surfaces' element 0", "names triangle 4");
  out[0].info = glm::uvec4(0, 2, 0, 0);
  Refused(c, &out, "surfaces' element 0", "names pixel 2");
  out.pop_back();
  Refused(c, &out, "surfaces' holds 1 elements, expected 2", "");
}

TEST_CASE("output checks: chunks cover the keys, orders index them") {
  const std::vector<std::uint32_t> keys = {5, 5, 7, 9, 9};
  Chunks ch{.key = {5, 7, 9}, .base = {0, 2, 3}, .size = {2, 1, 2}};
  CHECK(Refusal(call::Compress{.keys = keys}, &ch) == "accepted");
  ch.size[2] = 1;  // the last chunk loses its last ray
  Refused(call::Compress{.keys = keys}, &ch, "chunk_size' element 2", "ends chunks holding 4 rays, not the 5 keys");
  ch.size = {2, 1, 3};  // the last chunk reaches past the end
  Refused(call::Compress{.keys = keys}, &ch, "chunk_base' element 2", "beyond the 5 rays");

  const std::vector<std::uint32_t> key = {5, 7, 9}, base = {0, 2, 3}, size = {2, 1, 2}, order = {0, 1, 2};
  const call::Decompress d{.chunk_key = key, .chunk_base = base, .chunk_size = size, .chunk_order = order};
  std::vector<std::uint32_t> rays = {0, 1, 2, 3, 4};
  CHECK(Refusal(d, &rays) == "accepted");
  rays[3] = 5;
  Refused(d, &rays, "ray_order' element 3", "is 5, out of range [0, 5)");
  std::vector<std::uint32_t> chunk_order = {2, 0, 3};
  Refused(call::SortChunks{.chunk_key = key}, &chunk_order, "chunk_order' element 2", "is 3, out of range [0, 3)");
}

TEST_CASE("output checks: a leaf and a parent count the rays below them") {
  const std::vector<layout::Ray> rays(3);
  const std::vector<std::uint32_t> order = {0, 1, 2}, first = {0, 2, 3};
  const call::BuildLeaves c{.rays = rays, .order = order, .first = first};
  std::vector<layout::ConeNode> nodes(2);
  nodes[0].extra.y = 2.0f, nodes[1].extra.y = 1.0f;
  CHECK(Refusal(c, &nodes) == "accepted");
  nodes[0].extra.y = 1.0f;  // a leaf drops its last ray
  Refused(c, &nodes, "nodes' element 0", "counts 1 rays below, expected 2");
  nodes[0].extra.y = 2.0f;
  const std::vector<std::uint32_t> parent_first = {0, 2};
  const call::BuildParents p{.below = nodes, .first = parent_first};
  std::vector<layout::ConeNode> parent(1);
  parent[0].extra.y = 3.0f;
  CHECK(Refusal(p, &parent) == "accepted");
  parent[0].extra.y = 2.0f;  // a parent leaves out its last child
  Refused(p, &parent, "nodes' element 0", "counts 2 rays below, expected 3");
}

TEST_CASE("output checks: traversal pairs stay in their block, among the node's children, with the pair's triangle") {
  const SceneBuffers scene = SmallScene();
  const std::vector<layout::ConeNode> top(2);
  const std::vector<glm::vec4> spheres(4);
  const call::TraverseTop t{.top = top, .t0 = 0, .t1 = 2, .b0 = 1, .b1 = 4, .tri_spheres = spheres, .scene = &scene};
  PairSlots s{.flags = std::vector<std::uint8_t>(6, 0), .values = std::vector<std::uint32_t>(6, 0xFFFFFFFFu),
              .tested = std::vector<std::uint8_t>(6, 1)};
  s.flags[5] = 1, s.values[5] = Pair(1, 2);  // unflagged slots' values are never read
  CHECK(Refusal(t, &s) == "accepted");
  s.values[5] = Pair(1, 3);
  Refused(t, &s, "values' element 5", "outside the block's 2 nodes x 3 triangles");

  // Level: pair (node 1, triangle 2) of the level above; node 1's children are 2 and 3 below.
  const std::vector<layout::ConeNode> below(4);
  const std::vector<std::uint32_t> pairs = {Pair(1, 2)}, first = {0, 2, 4};
  const call::TraverseLevel l{.pairs = pairs, .nodes = below, .first = first, .base_up = 0, .base = 0, .children_max = 2,
                              .b0 = 0, .tri_spheres = spheres};
  PairSlots ls{.flags = {1, 1}, .values = {Pair(2, 2), Pair(3, 2)}, .tested = {2}};
  CHECK(Refusal(l, &ls) == "accepted");
  ls.values[1] = Pair(1, 2);  // a child of another node
  Refused(l, &ls, "values' element 1", "not a child of pair 0's node (children [2, 4))");
  ls.values[1] = Pair(3, 1);  // another triangle
  Refused(l, &ls, "values' element 1", "with its triangle");
  ls.values[1] = Pair(3, 2), ls.tested[0] = 1;
  Refused(l, &ls, "tested' element 0", "counts 1 children, but the pair's node has 2");

  Compacted cp{.pairs = {Pair(0, 0), Pair(2, 0)}, .tested = 6};
  Refused(call::TraverseTopCompacted{t}, &cp, "pairs' element 1", "outside the block's 2 nodes x 3 triangles");
  cp.pairs = {Pair(0, 0)}, cp.tested = 7;
  Refused(call::TraverseTopCompacted{t}, &cp, "tested' element 0", "more than the block's 6 slots");

  const std::vector<std::uint8_t> flags = {0, 1, 1};
  const std::vector<std::uint32_t> values = {Pair(9, 9), Pair(0, 1), Pair(1, 0)};
  const call::Reduce r{.flags = flags, .values = values};
  std::vector<std::uint32_t> out = {Pair(0, 1), Pair(1, 0)};
  CHECK(Refusal(r, &out) == "accepted");
  out[1] = Pair(9, 9);  // an unflagged slot's value
  Refused(r, &out, "pairs' element 1", "the value of no flagged slot");
}

TEST_CASE("output checks: final tests count the node's rays, hits name triangles, occlusion is a flag") {
  const SceneBuffers scene = SmallScene();
  const std::vector<layout::Ray> rays(3);
  const std::vector<std::uint32_t> pairs = {Pair(0, 3), Pair(1, 0)}, first1 = {0, 2, 3}, order = {0, 1, 2};
  std::vector<std::uint64_t> hits(3, ~std::uint64_t{0});
  call::Intersect c{.pairs = pairs, .first1 = first1, .base1 = 0, .b0 = 0, .order = order, .rays = rays, .scene = &scene, .hits = &hits};
  std::vector<std::uint32_t> tests = {2, 1};
  hits[1] = std::uint64_t{0x3f800000} << 32 | 3;
  CHECK(Refusal(c, &tests) == "accepted");
  tests[0] = 1;  // a node's last ray never tested
  Refused(c, &tests, "tests' element 0", "counts 1 tests, but the pair's node holds 2 rays");
  tests[0] = 2, hits[2] = std::uint64_t{0x3f800000} << 32 | 4;
  Refused(c, &tests, "hits' element 2", "names triangle 4, out of range [0, 4)");
  std::vector<std::uint32_t> occluded = {0, 2, 1};
  c.hits = nullptr, c.occluded = &occluded;
  Refused(c, &tests, "occluded' element 1", "is 2, out of range [0, 2)");
}

TEST_CASE("output checks: a G-buffer's primitive ids and sizes") {
  const SceneBuffers scene = SmallScene();
  layout::FrameConstants fc{};
  fc.dims = glm::uvec4(2, 1, 0, 0);
  const call::Raster c{.frame = fc, .scene = &scene};
  GBuffer g{.width = 2, .height = 1, .diffuse = std::vector<glm::vec4>(2), .specular = std::vector<glm::vec4>(2),
            .position = std::vector<glm::vec4>(2), .normal = std::vector<glm::vec4>(2), .prim = {layout::kNoPrim, 3},
            .depth = std::vector<float>(2)};
  CHECK(Refusal(c, &g) == "accepted");
  g.prim[0] = 7;
  Refused(c, &g, "prim' element 0", "names triangle 7");
}
