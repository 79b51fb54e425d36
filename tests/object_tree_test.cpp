// The object tree (rayspace/object_tree.h): a known answer, its invariants on random soups, procedural
// and real meshes, determinism, and the degenerate sets that must still end.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include <doctest/doctest.h>

#include "rayspace/emu/passes.h"
#include "rayspace/object_tree.h"
#include "rayspace/scene_buffers.h"
#include "test_util.h"

using rayspace::BuildObjectTree;
using rayspace::ObjectTree;
using rayspace::ObjectTreeNode;
using rayspace::ObjectTreeOptions;
using rayspace::layout::Triangle;

namespace {

Triangle Tri(glm::vec3 a, glm::vec3 b, glm::vec3 c) { return {glm::vec4(a, 0.0f), glm::vec4(b, 0.0f), glm::vec4(c, 0.0f)}; }

// A small triangle around p.
Triangle Small(glm::vec3 p, float s) { return Tri(p + glm::vec3(-s, -s, 0), p + glm::vec3(s, -s, 0), p + glm::vec3(0, s, s)); }

// The scene triangles below node n (its own and its descendants'), by walking the tree.
void Below(const ObjectTree& t, std::uint32_t n, std::vector<std::uint32_t>& out) {
  const ObjectTreeNode& node = t.nodes[n];
  out.insert(out.end(), t.triangles.begin() + node.first_tri, t.triangles.begin() + node.first_tri + node.tris);
  for (std::uint32_t c = 0; c < node.children; ++c) Below(t, node.first_child + c, out);
}

// Every invariant the header promises; returns the number of nodes checked.
std::size_t CheckInvariants(const ObjectTree& t, std::span<const Triangle> tris, std::span<const glm::uvec4> objects) {
  REQUIRE(t.roots.size() == objects.size());
  REQUIRE(t.depth.size() == t.nodes.size());
  std::vector<int> seen(tris.size(), 0);
  for (const std::uint32_t i : t.triangles) ++seen[i];
  CHECK(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }));  // each triangle exactly once
  for (std::size_t o = 0; o < objects.size(); ++o) {
    std::vector<std::uint32_t> below;
    Below(t, t.roots[o], below);
    std::sort(below.begin(), below.end());
    CHECK(below.size() == objects[o].y);
    CHECK((below.front() == objects[o].x && below.back() == objects[o].x + objects[o].y - 1));
  }
  for (std::uint32_t n = 0; n < t.nodes.size(); ++n) {
    const ObjectTreeNode& node = t.nodes[n];
    CHECK(node.tris + node.children > 0);
    for (std::uint32_t c = 0; c < node.children; ++c) CHECK(t.depth[node.first_child + c] == t.depth[n] + 1);
    std::vector<std::uint32_t> below;
    Below(t, n, below);
    for (const std::uint32_t i : below)  // every vertex inside, checked in long double
      for (const glm::vec4& v : {tris[i].v0, tris[i].v1, tris[i].v2}) {
        const long double dx = (long double)v.x - node.sphere.x, dy = (long double)v.y - node.sphere.y,
                          dz = (long double)v.z - node.sphere.z;
        if (std::sqrt(dx * dx + dy * dy + dz * dz) > (long double)node.sphere.w) FAIL_CHECK("node " << n << " misses triangle " << i);
      }
  }
  return t.nodes.size();
}

// With the triangles' spheres: every node's sphere holds the sphere of every triangle below it,
// checked in long double.
void CheckHoldsSpheres(const ObjectTree& t, std::span<const glm::vec4> spheres) {
  for (std::uint32_t n = 0; n < t.nodes.size(); ++n) {
    const glm::vec4 c = t.nodes[n].sphere;
    std::vector<std::uint32_t> below;
    Below(t, n, below);
    for (const std::uint32_t i : below) {
      const glm::vec4 s = spheres[i];
      const long double dx = (long double)s.x - c.x, dy = (long double)s.y - c.y, dz = (long double)s.z - c.z;
      if (std::sqrt(dx * dx + dy * dy + dz * dz) + s.w > (long double)c.w) FAIL_CHECK("node " << n << " misses the sphere of " << i);
    }
  }
}

std::vector<Triangle> RandomSoup(std::uint32_t seed, int n, float spread, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-spread, spread), s(0.0f, size);
  std::vector<Triangle> out;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 p(u(rng), u(rng), u(rng));
    out.push_back(Tri(p, p + glm::vec3(s(rng), s(rng), 0), p + glm::vec3(0, s(rng), s(rng))));
  }
  return out;
}

}  // namespace

TEST_CASE("object tree: one big triangle stays at the root, one small triangle per octant becomes a leaf each") {
  std::vector<Triangle> tris;
  for (int k = 0; k < 8; ++k)  // octant k: bit 0 x, bit 1 y, bit 2 z above the centre
    tris.push_back(Small(glm::vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1) * 4.0f, 0.125f));
  tris.push_back(Tri({-4, -4, 0}, {4, -4, 0}, {0, 4, 0}));
  const std::vector<glm::uvec4> objects{{0, 9, 0, 0}};
  const ObjectTree t = BuildObjectTree(tris, objects);
  CheckInvariants(t, tris, objects);
  REQUIRE(t.nodes.size() == 9);
  const ObjectTreeNode& root = t.nodes[0];
  CHECK(root.tris == 1);
  CHECK(t.triangles[root.first_tri] == 8);
  CHECK(root.children == 8);
  // The box is [-4.125, 4.125] x [-4.125, 3.875 + 0.25] x [-4, 4.125]: its centre, by hand.
  CHECK(root.sphere.x == 0.0f);
  CHECK(root.sphere.y == 0.0f);
  CHECK(root.sphere.z == 0.0625f);
  for (std::uint32_t k = 0; k < 8; ++k) {
    const ObjectTreeNode& leaf = t.nodes[root.first_child + k];
    CHECK(leaf.children == 0);
    REQUIRE(leaf.tris == 1);
    CHECK(t.triangles[leaf.first_tri] == k);
    // A leaf of one triangle: centred at its box's centre (p + (0, 0, s/2)), radius its farthest
    // vertex, (-s, -s, -s/2) from there: 1.5 s, rounded outward by a hair.
    const glm::vec3 p = glm::vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1) * 4.0f;
    CHECK(glm::vec3(leaf.sphere) == p + glm::vec3(0, 0, 0.0625f));
    CHECK(leaf.sphere.w >= 0.1875f);
    CHECK(leaf.sphere.w < 0.1875f * 1.0001f);
  }
}

TEST_CASE("object tree: random soups keep every invariant, and the build is deterministic") {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    CAPTURE(seed);
    const std::vector<Triangle> tris = RandomSoup(seed, 3000, 100.0f, seed % 2 ? 2.0f : 60.0f);
    const std::vector<glm::uvec4> objects{{0, 1000, 0, 0}, {1000, 1500, 0, 0}, {2500, 500, 0, 0}};
    const ObjectTree a = BuildObjectTree(tris, objects), b = BuildObjectTree(tris, objects);
    CHECK(CheckInvariants(a, tris, objects) > objects.size());
    REQUIRE(a.nodes.size() == b.nodes.size());
    CHECK(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(ObjectTreeNode)) == 0);
    CHECK(a.triangles == b.triangles);
    // An object's nodes are contiguous, starting at its root.
    for (std::size_t o = 0; o + 1 < objects.size(); ++o) CHECK(a.roots[o] < a.roots[o + 1]);
    // With the triangles' spheres (what --objects tree builds): they are held too.
    const std::vector<glm::vec4> spheres = rayspace::emu::PassTriangleSpheres(tris);
    const ObjectTree s = BuildObjectTree(tris, objects, {}, spheres);
    CheckInvariants(s, tris, objects);
    CheckHoldsSpheres(s, spheres);
  }
}

TEST_CASE("object tree: the options move triangles between nodes and leaves") {
  const std::vector<Triangle> tris = RandomSoup(9, 500, 50.0f, 5.0f);
  const std::vector<glm::uvec4> objects{{0, 500, 0, 0}};
  const ObjectTree one_leaf = BuildObjectTree(tris, objects, {0.25f, 1000});
  CHECK(one_leaf.nodes.size() == 1);
  CHECK(one_leaf.nodes[0].tris == 500);
  const ObjectTree no_big = BuildObjectTree(tris, objects, {1e9f, 1});
  CheckInvariants(no_big, tris, objects);
  for (const ObjectTreeNode& n : no_big.nodes) CHECK((n.tris == 0 || n.children == 0));  // only leaves own triangles
  const ObjectTree all_big = BuildObjectTree(tris, objects, {1e-9f, 1});
  CHECK(all_big.nodes.size() == 1);  // every triangle is big against the root
}

TEST_CASE("object tree: coincident and zero-area triangles end in a leaf") {
  std::vector<Triangle> same(100, Tri({1, 2, 3}, {2, 2, 3}, {1, 3, 3}));
  const std::vector<glm::uvec4> objects{{0, 100, 0, 0}};
  const ObjectTree t = BuildObjectTree(same, objects, {1e9f, 1});
  CheckInvariants(t, same, objects);
  CHECK(t.nodes.size() == 1);
  std::vector<Triangle> points(50, Tri({5, 5, 5}, {5, 5, 5}, {5, 5, 5}));
  const ObjectTree p = BuildObjectTree(points, std::vector<glm::uvec4>{{0, 50, 0, 0}});
  CHECK(p.nodes.size() == 1);
  CHECK(p.nodes[0].sphere.w > 0.0f);  // rounded outward even for a point
}

TEST_CASE("object tree: the bundled scenes' objects keep every invariant") {
  if (rayspace::test::SkipWithoutData("sponza_dabrovic/sponza.obj")) return;
  for (const char* file : {"cornell-mirrors.json", "office.json", "sponza.json", "dragon-closeup.json"}) {
    CAPTURE(file);
    const rayspace::SceneBuffers b = rayspace::FlattenScene(rayspace::test::LoadBundled(file));
    const ObjectTree t = BuildObjectTree(b.triangles, b.objects);
    CHECK(CheckInvariants(t, b.triangles, b.objects) > b.objects.size());
    std::size_t leaves = 0;
    for (const ObjectTreeNode& n : t.nodes) leaves += n.children == 0 ? 1 : 0;
    MESSAGE(std::string(file) << ": " << b.triangles.size() << " triangles, " << t.nodes.size() << " nodes, " << leaves << " leaves, depth "
                 << *std::max_element(t.depth.begin(), t.depth.end()));
  }
}
