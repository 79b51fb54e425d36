// The intersect pass and the ray-triangle test it uses: watertightness, accurate distances, and
// known answers for the pass on hand-made pairs.
#include <doctest/doctest.h>

#include <algorithm>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;
using test::MakeRay;
using test::SphereScene;

TEST_CASE("intersect: rays through shared edges and vertices of a closed mesh are never lost") {
  // From inside a closed sphere every ray must hit. Aiming exactly at vertices and edge midpoints
  // puts the hit on shared edges, where a non-watertight test leaks.
  const Scene s = SphereScene(16, 9);
  const SceneBuffers b = FlattenScene(s);
  auto tracer = MakeDirectTracer(b, DirectMode::kExhaustive);
  std::vector<layout::Ray> rays;
  const glm::vec3 origins[3] = {{0, 0, 0}, {0.1f, -0.2f, 0.05f}, {-0.3f, 0.1f, 0.2f}};
  for (const glm::vec3& o : origins)
    for (const layout::Triangle& t : b.triangles) {
      const glm::vec3 v[3] = {Xyz(t.v0), Xyz(t.v1), Xyz(t.v2)};
      for (int k = 0; k < 3; ++k) {
        rays.push_back(MakeRay(o, v[k] - o));                       // through a vertex
        rays.push_back(MakeRay(o, (v[k] + v[(k + 1) % 3]) * 0.5f - o));  // through an edge
      }
    }
  std::vector<std::uint64_t> hits;
  tracer->Closest(rays, hits);
  std::size_t lost = 0;
  for (std::uint64_t h : hits) lost += h == kMissPacked;
  CHECK(lost == 0);
}

TEST_CASE("intersect: hit distance is accurate on long thin triangles") {
  // A sliver 10 units long and 0.01 wide (from Sponza). Woop's barycentric distance was 5e-5 off here;
  // the plane distance is within a few float roundings.
  const glm::vec3 v0(10.9132004f, -2.50748992f, 10.8992996f), v1(0.00724005979f, -2.50748992f, 10.8992996f),
      v2(0.00724005979f, -2.49748993f, 10.9153004f);
  const glm::vec3 o(0, 0, 14), d(0.7646977305412292f, -0.40520715713500977f, -0.5010433793067932f);
  float t = 0;
  REQUIRE(IntersectWatertight(SetupWatertight(o, d), v0, v1, v2, 0.0f, 1e30f, t));
  // Exact value (rational arithmetic): 6.187082996820349.
  CHECK(t == doctest::Approx(6.187082996820349).epsilon(1e-6));
}

namespace {

// Two unit quads facing +z: "near" at z = 0 (triangles 0, 1) and "far" at z = -2 (triangles 2, 3). The
// point (0.2, 0.1) lies in triangle 0 (below the diagonal y = x) and, behind it, in triangle 2.
struct TwoQuads {
  SceneBuffers b;
  std::vector<layout::Ray> rays;
  TwoQuads() {
    Scene s;
    s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
    test::AddQuad(s, "near", {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    test::AddQuad(s, "far", {-1, -1, -2}, {1, -1, -2}, {1, 1, -2}, {-1, 1, -2});
    b = FlattenScene(s);
    rays.push_back(MakeRay({0.2f, 0.1f, 1}, {0, 0, -1}));     // 0: triangle 0 at t = 1, triangle 2 at t = 3
    rays.push_back(MakeRay({0.2f, 0.1f, 1}, {0, 0, -1}, 0));  // 1: the same, leaving triangle 0
    rays.push_back(MakeRay({5, 5, 1}, {0, 0, -1}));           // 2: beside both quads
    rays.push_back(MakeRay({0.2f, 0.1f, 1}, {0, 0, -1}));     // 3: stops at t = 0.5, before both
    rays[3].direction_tmax.w = 0.5f;
  }
};

std::uint32_t Pair(std::uint32_t node, std::uint32_t tri) { return node << kPairTriangleBits | tri; }

}  // namespace

TEST_CASE("intersect: one pass over hand-made pairs (tests per pair, closest hit, occlusion, the surface left)") {
  const TwoQuads q;
  // Level-1 nodes over the rays through `order`: node 0 holds rays 2, 0, 1 and node 1 holds ray 3.
  const std::vector<std::uint32_t> order = {2, 0, 1, 3}, first1 = {0, 3, 4};
  for (bool reversed : {false, true}) {
    std::vector<std::uint32_t> pairs = {Pair(0, 0), Pair(0, 2), Pair(1, 2), Pair(1, 0)};
    if (reversed) std::reverse(pairs.begin(), pairs.end());
    INFO("pairs reversed: " << reversed);
    std::vector<std::uint64_t> hits(4, kMissPacked);
    const auto tests =
        PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = q.rays, .scene = &q.b, .hits = &hits});
    // A pair tests every ray below its node.
    const std::vector<std::uint32_t> expect_tests = reversed ? std::vector<std::uint32_t>{1, 1, 3, 3}
                                                             : std::vector<std::uint32_t>{3, 3, 1, 1};
    CHECK(tests == expect_tests);
    CHECK(hits[0] == PackHit(1.0f, 0));  // the nearer of triangles 0 (t = 1) and 2 (t = 3)
    CHECK(hits[1] == PackHit(3.0f, 2));  // leaves triangle 0: only triangle 2
    CHECK(hits[2] == kMissPacked);
    CHECK(hits[3] == kMissPacked);

    std::vector<std::uint32_t> occluded(4, 0);
    PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = q.rays, .scene = &q.b, .occluded = &occluded});
    CHECK(occluded == std::vector<std::uint32_t>{1, 1, 0, 0});
  }
  // Only the pair with triangle 0: the ray leaving it hits nothing.
  std::vector<std::uint64_t> hits(4, kMissPacked);
  const std::vector<std::uint32_t> pairs = {Pair(0, 0)};
  PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = q.rays, .scene = &q.b, .hits = &hits});
  CHECK(hits[0] == PackHit(1.0f, 0));
  CHECK(hits[1] == kMissPacked);
  // Node and triangle ids are relative to base1 and b0: with node 0 over ray 3 and node 1 over rays
  // 2, 0, 1, the pair (0, 0) with base1 = 1 and b0 = 2 is node 1 against triangle 2.
  std::vector<std::uint32_t> occluded(4, 0);
  const std::vector<std::uint32_t> rel = {Pair(0, 0)}, order2 = {3, 2, 0, 1}, first2 = {0, 1, 4};
  const auto tests = PassIntersect({.pairs = rel, .first1 = first2, .base1 = 1, .b0 = 2, .order = order2, .rays = q.rays,
                                    .scene = &q.b, .occluded = &occluded});
  CHECK(tests == std::vector<std::uint32_t>{3});
  CHECK(occluded == std::vector<std::uint32_t>{1, 1, 0, 0});
}

// The range is open at both ends: a triangle before tmin (or at it) is not hit, however near. Rays
// spawned on a surface rely on it, and a test that ignored tmin would still pass every ray above
// whose tmin is 0.
TEST_CASE("intersect: tmin excludes the triangles before it, one pass over hand-made pairs") {
  const TwoQuads q;
  std::vector<layout::Ray> rays(4, MakeRay({0.2f, 0.1f, 1}, {0, 0, -1}));  // triangle 0 at t = 1, triangle 2 at t = 3
  rays[0].origin_tmin.w = 1.5f;                                          // past the near quad: the far one
  rays[1].origin_tmin.w = 1.0f;                                          // exactly at the near quad: the far one
  rays[2].origin_tmin.w = 3.5f;                                          // past both: a miss
  rays[3].origin_tmin.w = 0.5f;                                          // before both: the near one
  const std::vector<std::uint32_t> order = {0, 1, 2, 3}, first1 = {0, 4}, pairs = {Pair(0, 0), Pair(0, 2)};
  std::vector<std::uint64_t> hits(4, kMissPacked);
  PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = rays, .scene = &q.b, .hits = &hits});
  CHECK(hits == std::vector<std::uint64_t>{PackHit(3.0f, 2), PackHit(3.0f, 2), kMissPacked, PackHit(1.0f, 0)});
  // Shadow rays between tmin 1.5 and tmax 2.5 meet neither quad; from tmin 0.5 they meet the near one.
  for (layout::Ray& r : rays) r.direction_tmax.w = 2.5f;
  std::vector<std::uint32_t> occluded(4, 0);
  PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = rays, .scene = &q.b, .occluded = &occluded});
  CHECK(occluded == std::vector<std::uint32_t>{0, 0, 0, 1});
  // The direct tracer, the brute-force reference, agrees.
  auto direct = MakeDirectTracer(q.b, DirectMode::kExhaustive);
  std::vector<std::uint32_t> direct_occluded;
  direct->Occluded(rays, direct_occluded);
  CHECK(direct_occluded == occluded);
}

// --leaf-test ray-sphere: a ray that misses the triangle's sphere is culled before its ray-triangle
// test, while rays that hit the triangle at its vertex and at a glancing angle near it are kept (the
// sphere test is conservative): the pair counts the two, with the same hits as the node test.
TEST_CASE("intersect: the leaf sphere test culls a ray beside the sphere and keeps grazing rays that hit") {
  const TwoQuads q;
  const std::vector<glm::vec4> spheres = PassTriangleSpheres(q.b.triangles);
  const layout::Triangle& t = q.b.triangles[0];
  const glm::vec3 v1 = Xyz(t.v1), centroid = (Xyz(t.v0) + Xyz(t.v1) + Xyz(t.v2)) / 3.0f;
  const glm::vec3 near_vertex = v1 * 0.98f + centroid * 0.02f;
  std::vector<layout::Ray> rays = {MakeRay({5, 5, 1}, {0, 0, -1}),                         // beside the sphere
                                   MakeRay(v1 + glm::vec3(0, 0, 1), {0, 0, -1}),            // onto the vertex
                                   MakeRay(near_vertex + glm::vec3(-1000, 0, 1), {1000, 0, -1})};  // glancing
  float th = 0.0f;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const layout::Ray& r = rays[i];
    const bool hit = IntersectWatertight(SetupWatertight(Xyz(r.origin_tmin), Xyz(r.direction_tmax)), Xyz(t.v0), Xyz(t.v1), Xyz(t.v2),
                                         r.origin_tmin.w, r.direction_tmax.w, th);
    INFO("ray " << i);
    CHECK(hit == (i != 0));
    CHECK(cone::RayMayMeetSphere(r, spheres[0], 0.0f) == (i != 0));
  }
  const std::vector<std::uint32_t> order = {0, 1, 2}, first1 = {0, 3}, pairs = {Pair(0, 0)};
  std::vector<std::uint64_t> node_hits(3, kMissPacked), sphere_hits(3, kMissPacked);
  const auto node_tests = PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = rays, .scene = &q.b, .hits = &node_hits});
  const auto sphere_tests = PassIntersect({.pairs = pairs, .first1 = first1, .order = order, .rays = rays, .scene = &q.b,
                                           .hits = &sphere_hits, .leaf_test = layout::kLeafTestRaySphere, .tri_spheres = spheres});
  CHECK(node_tests == std::vector<std::uint32_t>{3});
  CHECK(sphere_tests == std::vector<std::uint32_t>{2});
  CHECK(sphere_hits == node_hits);
  CHECK(sphere_hits[0] == kMissPacked);
  CHECK(sphere_hits[1] != kMissPacked);
  CHECK(sphere_hits[2] != kMissPacked);
}
