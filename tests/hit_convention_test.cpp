// The hit convention (docs/numerics.md, "The hit convention"), held on every path: a triangle counts
// when tmin < t < tmax, ends excluded; among triangles at the same distance the lowest primitive id
// wins. Every tracer (exhaustive, hierarchy flat and with the object tree, Embree) and the exact
// decision must agree; the expected answers come from the geometry and the exact oracle.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hard_tracers.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/refs/exact.h"
#include "test_util.h"

using namespace rayspace;
using test::HardTracers;
using test::Ray;
using test::AddTriangle;
using test::OneScene;
using test::ExpectEveryTracer;

TEST_CASE("hard case: a triangle exactly at t = tmin or t = tmax is not hit, one float inside it is, on every path") {
  // The plane z = 2 meets the ray from the origin along +z at t = 2 exactly, in float and exactly.
  Scene s = OneScene();
  AddTriangle(s, {-1, -1, 2}, {3, -1, 2}, {-1, 3, 2});
  const SceneBuffers buf = FlattenScene(s);
  const layout::Triangle& tri = buf.triangles[0];
  auto rays_around = [](float t) {
    return std::vector<layout::Ray>{
        Ray({0, 0, 0}, {0, 0, 1}, 0.0f, t),                             // t = tmax: excluded
        Ray({0, 0, 0}, {0, 0, 1}, 0.0f, std::nextafter(t, INFINITY)),   // one float beyond: a hit
        Ray({0, 0, 0}, {0, 0, 1}, t, INFINITY),                         // t = tmin: excluded
        Ray({0, 0, 0}, {0, 0, 1}, std::nextafter(t, 0.0f), INFINITY)};  // one float before: a hit
  };
  const bool hit[4] = {false, true, false, true};
  const std::vector<layout::Ray> at_two = rays_around(2.0f);
  for (std::size_t i = 0; i < at_two.size(); ++i) {
    CAPTURE(i);
    CHECK(refs::ExactHitDecision(at_two[i], tri) == hit[i]);
    CHECK(refs::ExactHitDecision(at_two[i], tri, false) == hit[i]);
    float t = 0;
    CHECK(emu::IntersectWatertight(emu::SetupWatertight(glm::vec3(0, 0, 0), glm::vec3(0, 0, 1)), emu::Xyz(tri.v0), emu::Xyz(tri.v1), emu::Xyz(tri.v2),
                                   at_two[i].origin_tmin.w, at_two[i].direction_tmax.w, t) == hit[i]);
  }
  // Each tracer at the ends of the t it computes itself (Embree's need not be 2 exactly).
  HardTracers tracers(buf, true);
  for (std::size_t k = 0; k < tracers.all.size(); ++k) {
    CAPTURE(tracers.names[k]);
    std::vector<std::uint64_t> open_hit;
    tracers.all[k]->Closest({Ray({0, 0, 0}, {0, 0, 1}, 0.0f, INFINITY)}, open_hit);
    REQUIRE(open_hit[0] != emu::kMissPacked);
    const float t = emu::HitT(open_hit[0]);
    if (tracers.names[k] != "embree") CHECK(t == 2.0f);
    const std::vector<layout::Ray> rays = rays_around(t);
    std::vector<layout::Ray> shadow = rays;
    for (layout::Ray& r : shadow) r.info.z = layout::kRayShadow;
    std::vector<std::uint64_t> hits;
    std::vector<std::uint32_t> occluded;
    tracers.all[k]->Closest(rays, hits);
    tracers.all[k]->Occluded(shadow, occluded);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      CAPTURE(i);
      CHECK(hits[i] == (hit[i] ? emu::PackHit(t, 0) : emu::kMissPacked));
      CHECK(occluded[i] == (hit[i] ? 1u : 0u));
    }
  }
}

TEST_CASE("hard case: triangles at exactly the same distance go to the lowest primitive id, on every path") {
  // A cube seen along its diagonal: the ray meets the corner shared by six of its triangles, and a
  // second ray meets the middle of a face's diagonal, shared by that face's two triangles. Built
  // twice, with the triangles in opposite orders, so the winner is the lowest id, not a position.
  const glm::vec3 p[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  const int faces[6][4] = {{4, 5, 6, 7}, {1, 0, 3, 2}, {5, 1, 2, 6}, {0, 4, 7, 3}, {7, 6, 2, 3}, {0, 1, 5, 4}};
  for (const bool reversed : {false, true}) {
    CAPTURE(reversed);
    std::vector<std::array<glm::vec3, 3>> tris;
    for (const auto& f : faces) {
      tris.push_back({p[f[0]], p[f[1]], p[f[2]]});
      tris.push_back({p[f[0]], p[f[2]], p[f[3]]});
    }
    if (reversed) std::reverse(tris.begin(), tris.end());
    Scene s = OneScene();
    for (const auto& t : tris) AddTriangle(s, t[0], t[1], t[2]);
    const SceneBuffers buf = FlattenScene(s);
    const std::vector<layout::Ray> rays = {Ray({3, 3, 3}, {-1, -1, -1}, 0.0f, INFINITY),  // the corner (1, 1, 1) at t = 2
                                           Ray({2, -2, 3}, {-2, 2, -2}, 0.0f, INFINITY)}; // (0, 0, 1) on the +z diagonal at t = 1
    std::vector<std::uint64_t> expected;
    for (const layout::Ray& r : rays) {
      const std::vector<std::uint32_t> exact = refs::ExactClosest(r, buf);
      REQUIRE(exact.size() >= 2);  // a true tie
      expected.push_back(emu::PackHit(&r == &rays[0] ? 2.0f : 1.0f, *std::min_element(exact.begin(), exact.end())));
    }
    ExpectEveryTracer(buf, rays, expected);
  }
}
