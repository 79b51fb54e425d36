// Known answers, worked out by hand, for the object-tree passes (tree.roots, tree.expand, tree.test,
// tree.step, intersect.tree; docs/object-tree.md), whose other tests compare them with flat
// traversal, with each other or between thread counts. No Vulkan; the fixture is small enough to
// follow on paper:
//
//   cone hierarchy (every node a hemisphere of directions around +z, apex at the origin):
//     level 2: node 0 over level-1 node 0;  level 1: node 0 over rays 0, 1;  level 0: rays 0, 1
//   object tree: one root (node 0, depth 0, sphere at the origin, radius 20), no child nodes, two
//     own triangles: entry 0 (scene triangle 5, sphere at z = 10) and entry 1 (scene triangle 7,
//     sphere at z = -10, behind every cone)
//
// A hemisphere is always the wider side (SplitCone), so a pair of a cone above level 0 refines the
// cone; a ray (level 0) refines the object node. The root's sphere holds every apex and entry 0's
// lies in front of it, so both pass every cone test; entry 1's is behind, so it fails every one.
#include <doctest/doctest.h>

#include <bit>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/object_tree_traverse.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

constexpr std::uint32_t kT = layout::kTreeItemTriangle;
constexpr std::uint32_t Cone(std::uint32_t level, std::uint32_t node) { return level << layout::kTreeLevelShift | node; }

struct Fixture {
  std::vector<layout::ConeNode> nodes;
  // Level starts: level 0 at 0 (2 rays), level 1 at 2, level 2 at 3, end 4.
  std::vector<std::uint32_t> base = {0, 2, 3, 4};
  // Per level its CSR child offsets: level 0's are 0, 1, 2; level 1's node 0 has level-0 children
  // [0, 2); level 2's node 0 has level-1 child [0, 1).
  std::vector<std::uint32_t> first = {0, 1, 2, 0, 2, 0, 1};
  std::vector<glm::vec4> spheres = {glm::vec4(0, 0, 0, 20)};
  std::vector<glm::uvec4> links = {glm::uvec4(0, 0, 0, 2)};  // no child nodes; own triangles [0, 2)
  std::vector<std::uint32_t> depth = {0}, roots = {0};
  std::vector<glm::vec4> tri_spheres = {glm::vec4(0, 0, 10, 1), glm::vec4(0, 0, -10, 1)};
  std::vector<std::uint32_t> triangles = {5, 7};

  Fixture() {
    layout::ConeNode hemisphere{};
    hemisphere.sphere = glm::vec4(0, 0, 0, 0);
    hemisphere.cone = glm::vec4(0, 0, 1, 0);  // cos(alpha) = 0, sin(alpha) = 1
    hemisphere.extra = glm::vec4(1, 1, 0, 0);
    nodes.assign(4, hemisphere);
    nodes[2].extra.y = nodes[3].extra.y = 2;  // rays below
  }
  ConeTreeView cones() const { return {nodes, base, first}; }
  ObjectTreeView tree() const { return {spheres, links, depth, roots, tri_spheres, triangles}; }
};

// Counts as worked out: cone tests and hits per level 0..2, node tests and hits at depth 0, triangle
// tests and hits.
TreeCounts Counts(std::vector<std::uint64_t> cone_tests, std::vector<std::uint64_t> cone_hits, std::uint64_t node_tests,
                  std::uint64_t node_hits, std::uint64_t tri_tests, std::uint64_t tri_hits) {
  TreeCounts k;
  k.cone_tests = std::move(cone_tests), k.cone_hits = std::move(cone_hits);
  k.node_tests = {node_tests}, k.node_hits = {node_hits};
  k.tri_tests = tri_tests, k.tri_hits = tri_hits;
  return k;
}

void CheckCounts(const TreeCounts& got, const TreeCounts& want) {
  CHECK(got.cone_tests == want.cone_tests);
  CHECK(got.cone_hits == want.cone_hits);
  CHECK(got.node_tests == want.node_tests);
  CHECK(got.node_hits == want.node_hits);
  CHECK(got.tri_tests == want.tri_tests);
  CHECK(got.tri_hits == want.tri_hits);
}

}  // namespace

TEST_CASE("tree.roots: known answer, the top node against the one root: one test at level 2 and depth 0, a hit that goes on") {
  const Fixture f;
  const TreeSlots s = PassTreeRoots({.cones = f.cones(), .tree = f.tree(), .level = 2, .t0 = 0, .t1 = 1, .eps = 0.0f});
  CHECK(s.flags == std::vector<std::uint8_t>{1});
  CHECK(s.pairs.cone == std::vector<std::uint32_t>{Cone(2, 0)});
  CHECK(s.pairs.item == std::vector<std::uint32_t>{0});
  // The statistics start at zero: exactly the one test and its hit.
  CheckCounts(s.counts, Counts({0, 0, 1}, {0, 0, 1}, 1, 1, 0, 0));
}

TEST_CASE("tree.expand: known answer, a cone above level 0 offers its children, a ray the node's children and triangles") {
  const Fixture f;
  const std::vector<std::uint32_t> cone = {Cone(2, 0), Cone(1, 0), Cone(0, 1)}, item = {0, 0, 0};
  // Level 2's node has 1 child, level 1's has 2 rays; a ray against the root: 0 child nodes + 2 triangles.
  CHECK(PassTreeExpand({.cones = f.cones(), .tree = f.tree(), .pair_cone = cone, .pair_item = item}) ==
        std::vector<std::uint32_t>{1, 2, 2});
}

TEST_CASE("tree.test and tree.step: known answer, candidates in slot order, survivors split into going on and final") {
  const Fixture f;
  // Pair 0 (level-1 node, root) refines the cone: rays 0 and 1 against the root, both hit, both go on.
  // Pair 1 (ray 1, root) refines the root: entry 0 hits and is final (a ray with a triangle), entry 1 misses.
  const std::vector<std::uint32_t> cone = {Cone(1, 0), Cone(0, 1)}, item = {0, 0}, offsets = {0, 2};
  const TreeSlots s =
      PassTreeTest({.cones = f.cones(), .tree = f.tree(), .pair_cone = cone, .pair_item = item, .offsets = offsets, .slots = 4, .eps = 0.0f});
  CHECK(s.flags == std::vector<std::uint8_t>{1, 1, 2, 0});
  CHECK(s.pairs.cone == std::vector<std::uint32_t>{Cone(0, 0), Cone(0, 1), Cone(0, 1), Cone(0, 1)});
  CHECK(s.pairs.item == std::vector<std::uint32_t>{0, 0, kT | 0, kT | 1});
  // Four tests, all of level-0 cones: two against the root (depth 0, both hit), two against triangles (one hit).
  const TreeCounts want = Counts({4, 0, 0}, {3, 0, 0}, 2, 2, 2, 1);
  CheckCounts(s.counts, want);

  const TreeRound r = PassTreeStep({.cones = f.cones(), .tree = f.tree(), .pair_cone = cone, .pair_item = item, .eps = 0.0f});
  CHECK(r.next.cone == std::vector<std::uint32_t>{Cone(0, 0), Cone(0, 1)});
  CHECK(r.next.item == std::vector<std::uint32_t>{0, 0});
  CHECK(r.final.cone == std::vector<std::uint32_t>{Cone(0, 1)});
  CHECK(r.final.item == std::vector<std::uint32_t>{kT | 0});
  CheckCounts(r.counts, want);
}

TEST_CASE("intersect.tree: known answer, a level-1 pair tests its node's rays, a level-0 pair its one ray") {
  const Fixture f;
  // Scene triangle 5 lies in the plane z = 10 over x, y in [-2, 2]; triangle 7 is never tested here.
  SceneBuffers scene;
  scene.triangles.resize(8);
  scene.triangles[5] = {glm::vec4(-2, -2, 10, 1), glm::vec4(2, -2, 10, 1), glm::vec4(0, 2, 10, 1)};
  scene.info.resize(8);
  // Ray 0 from the origin along +z meets it at t = 10; ray 1 starts at x = 100 and misses.
  std::vector<layout::Ray> rays(2);
  rays[0].origin_tmin = glm::vec4(0, 0, 0, 0), rays[0].direction_tmax = glm::vec4(0, 0, 1, 100);
  rays[1].origin_tmin = glm::vec4(100, 0, 0, 0), rays[1].direction_tmax = glm::vec4(0, 0, 1, 100);
  for (layout::Ray& r : rays) r.info.y = layout::kNoPrim;
  // Sorted order: ray 1 first, then ray 0; level-1 node 0 holds sorted rays [0, 2).
  const std::vector<std::uint32_t> order = {1, 0}, first1 = {0, 2};
  const std::vector<std::uint32_t> cone = {Cone(1, 0), Cone(0, 0)}, item = {kT | 0, kT | 0};
  std::vector<std::uint64_t> hits(2, ~std::uint64_t{0});
  const std::vector<std::uint32_t> tests = PassIntersectTree({.pair_cone = cone, .pair_item = item, .first1 = first1,
                                                              .tree_triangles = f.triangles, .order = order, .rays = rays,
                                                              .scene = &scene, .hits = &hits, .occluded = nullptr});
  CHECK(tests == std::vector<std::uint32_t>{2, 1});  // the level-1 node's two rays; sorted ray 0 alone
  const std::uint64_t at10 = std::uint64_t{std::bit_cast<std::uint32_t>(10.0f)} << 32 | 5;
  CHECK(hits == std::vector<std::uint64_t>{at10, ~std::uint64_t{0}});
}
