// Hard cases of rays against triangles and bounding spheres, beyond hard_cases_test.cpp: grazing
// rays along edges and through vertices, slivers, subnormal and axis-aligned directions, empty
// intervals, origins on a surface, and spheres of radius 0 and 2^60. The expected answer comes from
// the geometry and the exact oracle; every tracer (exhaustive, hierarchy flat and with the object
// tree, Embree) must give it, and where the exact decision is fragile they must at least agree
// among the emulator's tracers bit for bit and never produce NaN.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hard_tracers.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/exact_cone.h"
#include "test_util.h"

using namespace rayspace;
using test::AddTriangle;
using test::ExpectEveryTracer;
using test::HardTracers;
using test::OneScene;
using test::Ray;

namespace {

// The exact closest hit of each ray: the lowest id at the exactly smallest distance, with the float t
// the watertight test computes for it (the emulator's tracers must return those bits).
std::vector<std::uint64_t> ExactExpected(const SceneBuffers& buf, const std::vector<layout::Ray>& rays) {
  std::vector<std::uint64_t> out;
  for (const layout::Ray& r : rays) {
    const std::vector<std::uint32_t> exact = refs::ExactClosest(r, buf);
    if (exact.empty()) {
      out.push_back(emu::kMissPacked);
      continue;
    }
    const layout::Triangle& t = buf.triangles[exact.front()];
    float th = 0;
    REQUIRE(emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax)), emu::Xyz(t.v0),
                                     emu::Xyz(t.v1), emu::Xyz(t.v2), r.origin_tmin.w, r.direction_tmax.w, th));
    out.push_back(emu::PackHit(th, exact.front()));
  }
  return out;
}

// Where the exact answer is fragile the emulator's tracers must still agree bit for bit (one test,
// one answer) and return finite distances.
void ExpectEmulatorAgrees(const SceneBuffers& buf, const std::vector<layout::Ray>& rays) {
  HardTracers tracers(buf);
  std::vector<std::uint64_t> first;
  for (std::size_t k = 0; k < tracers.all.size(); ++k) {
    CAPTURE(tracers.names[k]);
    std::vector<std::uint64_t> hits;
    tracers.all[k]->Closest(rays, hits);
    for (std::uint64_t h : hits)
      if (h != emu::kMissPacked) CHECK(std::isfinite(emu::HitT(h)));
    if (k == 0) first = hits;
    CHECK(hits == first);
  }
}

Scene Cube() {
  const glm::vec3 p[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  const int faces[6][4] = {{4, 5, 6, 7}, {1, 0, 3, 2}, {5, 1, 2, 6}, {0, 4, 7, 3}, {7, 6, 2, 3}, {0, 1, 5, 4}};
  Scene s = OneScene();
  for (const auto& f : faces) {
    AddTriangle(s, p[f[0]], p[f[1]], p[f[2]]);
    AddTriangle(s, p[f[0]], p[f[2]], p[f[3]]);
  }
  return s;
}

}  // namespace

TEST_CASE("hard case: rays through a closed mesh's vertices and edges never slip through") {
  // Watertightness: every ray from outside toward a cube's vertex or edge point meets the cube.
  const SceneBuffers buf = FlattenScene(Cube());
  std::vector<layout::Ray> rays;
  for (glm::vec3 target : {glm::vec3(1, 1, 1), glm::vec3(-1, 1, 1), glm::vec3(1, 0, 1), glm::vec3(0, -1, 1), glm::vec3(0.25f, 0.25f, 1)})
    for (glm::vec3 from : {glm::vec3(3, 2, 5), glm::vec3(-2, 3, 4), glm::vec3(0.5f, -3, 6)}) rays.push_back(Ray(from, target - from, 0.0f, INFINITY));
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  for (std::uint64_t e : expected) REQUIRE(e != emu::kMissPacked);
  ExpectEveryTracer(buf, rays, expected, false);
  // Embree computes t per triangle its own way, so at a vertex it may take any of the exact ties.
  auto embree = refs::MakeEmbreeTracer(buf, 1);
  std::vector<std::uint64_t> hits;
  embree->Closest(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    CAPTURE(i);
    const std::vector<std::uint32_t> ties = refs::ExactClosest(rays[i], buf);
    CHECK(std::find(ties.begin(), ties.end(), emu::HitPrim(hits[i])) != ties.end());
  }
}

TEST_CASE("hard case: a ray along a shared edge, in neither triangle's plane, is one answer and no NaN") {
  // The edge (1, 1, -1)-(1, 1, 1) of the cube: the ray runs along its line from outside.
  const SceneBuffers buf = FlattenScene(Cube());
  const std::vector<layout::Ray> rays = {Ray({1, 1, 5}, {0, 0, -1}, 0.0f, INFINITY), Ray({1, 1, -5}, {0, 0, 1}, 0.0f, INFINITY)};
  // Exactly the ray touches the cube only on that edge: no triangle's interior, so either answer
  // is defensible, but the edge's triangles are touched.
  for (const layout::Ray& r : rays) {
    int touched = 0;
    for (const layout::Triangle& t : buf.triangles) {
      const refs::Contact c = refs::ExactContact(r, t);
      CHECK(c != refs::Contact::kInterior);
      touched += c == refs::Contact::kBoundary;
    }
    CHECK(touched >= 2);
  }
  ExpectEmulatorAgrees(buf, rays);
}

TEST_CASE("hard case: a sliver triangle, 16 long and 2^-8 wide, is hit and missed as the exact test says") {
  // 16 units long, 2^-8 wide at its base.
  Scene s = OneScene();
  AddTriangle(s, {0, 0, 0}, {16, 0, 0}, {0, 0x1p-8f, 0});
  const SceneBuffers buf = FlattenScene(s);
  std::vector<layout::Ray> rays;
  for (float x : {0.001f, 1.0f, 8.0f})
    for (float y : {0x1p-10f, 0x1p-7f, -0x1p-10f}) rays.push_back(Ray({x, y, 1}, {0, 0, -1}, 0.0f, INFINITY));
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) hits += expected[i] != emu::kMissPacked;
  CHECK(hits == 3);  // only y = 2^-10 lies inside, at every x
  ExpectEveryTracer(buf, rays, expected);
}

TEST_CASE("hard case: subnormal and zero direction components give the exact answer") {
  Scene s = OneScene();
  AddTriangle(s, {-1, -1, 2}, {3, -1, 2}, {-1, 3, 2});
  const SceneBuffers buf = FlattenScene(s);
  const float sub = 1e-40f;
  REQUIRE(std::fpclassify(sub) == FP_SUBNORMAL);
  const std::vector<layout::Ray> rays = {Ray({0, 0, 0}, {sub, sub, 1}, 0.0f, INFINITY), Ray({0, 0, 0}, {0, -sub, 1}, 0.0f, INFINITY),
                                         Ray({0.5f, 0.5f, 0}, {0, 0, 1}, 0.0f, INFINITY), Ray({0, 0, 0}, {sub, 0, 0}, 0.0f, INFINITY),
                                         Ray({0, 0, 0}, {1, 1, sub}, 0.0f, INFINITY)};
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  CHECK(expected[0] == emu::PackHit(2.0f, 0));
  CHECK(expected[2] == emu::PackHit(2.0f, 0));
  CHECK(expected[3] == emu::kMissPacked);  // parallel to the plane
  ExpectEveryTracer(buf, rays, expected);
}

TEST_CASE("hard case: an empty or inverted interval hits nothing on every path") {
  Scene s = OneScene();
  AddTriangle(s, {-1, -1, 2}, {3, -1, 2}, {-1, 3, 2});
  const SceneBuffers buf = FlattenScene(s);
  const std::vector<layout::Ray> rays = {Ray({0, 0, 0}, {0, 0, 1}, 2.0f, 2.0f), Ray({0, 0, 0}, {0, 0, 1}, 3.0f, 1.0f),
                                         Ray({0, 0, 0}, {0, 0, 1}, 0.0f, 0.0f)};
  for (const layout::Ray& r : rays) CHECK_FALSE(refs::ExactHitDecision(r, buf.triangles[0]));
  ExpectEveryTracer(buf, rays, std::vector<std::uint64_t>(rays.size(), emu::kMissPacked));
}

TEST_CASE("hard case: an origin on the surface with tmin 0 does not hit that surface at t = 0") {
  // The origin is the triangle's vertex or a point inside it; leaving along the normal or into it,
  // the surface lies at t = 0, outside (0, tmax). A second triangle behind is the only hit.
  Scene s = OneScene();
  AddTriangle(s, {-1, -1, 0}, {3, -1, 0}, {-1, 3, 0});
  AddTriangle(s, {-5, -5, -4}, {5, -5, -4}, {0, 5, -4});
  const SceneBuffers buf = FlattenScene(s);
  const std::vector<layout::Ray> rays = {Ray({0, 0, 0}, {0, 0, 1}, 0.0f, INFINITY), Ray({0, 0, 0}, {0, 0, -1}, 0.0f, INFINITY),
                                         Ray({-1, -1, 0}, {0.1f, 0.2f, -1}, 0.0f, INFINITY)};
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  CHECK(expected[0] == emu::kMissPacked);
  CHECK(expected[1] == emu::PackHit(4.0f, 1));
  CHECK(emu::HitPrim(expected[2]) == 1u);
  ExpectEveryTracer(buf, rays, expected);
}

TEST_CASE("hard case: a triangle 2^40 away and one 2^-12 across are hit at finite t") {
  // Embree (sse4.2, robust) misses the far triangle at 2^50; the emulator's tracers are tested at
  // 2^60 with the scaled cases in hard_cases_test.cpp.
  Scene s = OneScene();
  const float far = 0x1p40f, small = 0x1p-12f;
  AddTriangle(s, {-far, -far, far}, {far * 3, -far, far}, {-far, far * 3, far});
  AddTriangle(s, {-small, -small, 1}, {small * 3, -small, 1}, {-small, small * 3, 1});
  const SceneBuffers buf = FlattenScene(s);
  const std::vector<layout::Ray> rays = {Ray({0, 0, 0}, {0, 0, 1}, 0.0f, INFINITY), Ray({0, 0, 2}, {0, 0, 1}, 0.0f, INFINITY)};
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  CHECK(expected[0] == emu::PackHit(1.0f, 1));
  CHECK(expected[1] == emu::PackHit(far - 2.0f, 0));
  ExpectEveryTracer(buf, rays, expected);
}

TEST_CASE("hard case: a ray just above and parallel to a triangle's plane misses on every path") {
  Scene s = OneScene();
  AddTriangle(s, {-1, -1, 0}, {3, -1, 0}, {-1, 3, 0});
  const SceneBuffers buf = FlattenScene(s);
  const std::vector<layout::Ray> rays = {Ray({-5, 0, 0x1p-20f}, {1, 0, 0}, 0.0f, INFINITY), Ray({-5, 0, 0x1p-126f}, {1, 0.5f, 0}, 0.0f, INFINITY),
                                         Ray({-5, 0, 1e-40f}, {1, 0, 0}, 0.0f, INFINITY)};
  for (const layout::Ray& r : rays) CHECK_FALSE(refs::ExactHitDecision(r, buf.triangles[0]));
  ExpectEveryTracer(buf, rays, std::vector<std::uint64_t>(rays.size(), emu::kMissPacked));
}

TEST_CASE("hard case: a zero-radius sphere on the cone's axis and a 2^60 sphere around the apex are met") {
  const glm::vec3 apex(1, 2, 3);
  layout::ConeNode n;
  n.sphere = glm::vec4(apex, 0.0f);  // a single ray's node: radius 0
  n.cone = glm::vec4(0, 0, 1, 1.0f);  // half-angle 0
  n.extra = glm::vec4(0, 1, 0, 0);
  for (const glm::vec4 s : {glm::vec4(1, 2, 10, 0), glm::vec4(0, 0, 0, 0x1p60f), glm::vec4(1e17f, -1e17f, 0, 0x1p60f)}) {
    CAPTURE(s.w);
    CHECK(refs::ExactNodeMeetsSphere(n, s));
    CHECK(emu::cone::Test(n, s, 0.0f));
  }
  // Behind the apex, or beside the axis, a zero-radius sphere is not met (exactly), and the float
  // test, conservative, must accept at least what the exact one does.
  for (const glm::vec4 s : {glm::vec4(1, 2, -10, 0), glm::vec4(1.5f, 2, 10, 0)}) {
    CHECK_FALSE(refs::ExactNodeMeetsSphere(n, s));
    if (refs::ExactNodeMeetsSphere(n, s)) CHECK(emu::cone::Test(n, s, 0.0f));
  }
}

TEST_CASE("hard case: rays from inside a closed mesh toward its vertices and edges hit exactly once, at the exact distance") {
  const SceneBuffers buf = FlattenScene(Cube());
  std::vector<layout::Ray> rays;
  for (glm::vec3 d : {glm::vec3(1, 1, 1), glm::vec3(-1, 1, -1), glm::vec3(1, 0, 1), glm::vec3(0, -1, 1), glm::vec3(1, 0, 0)})
    rays.push_back(Ray({0, 0, 0}, d, 0.0f, INFINITY));
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  CHECK(emu::HitT(expected[0]) == 1.0f);
  CHECK(emu::HitT(expected[4]) == 1.0f);
  ExpectEveryTracer(buf, rays, expected, false);
}

TEST_CASE("hard case: rays parallel to an edge, inside and outside the triangle by a little, keep the exact answer") {
  // Directions in the plane x = const are parallel to the edge along y; the rays cross near it.
  Scene s = OneScene();
  AddTriangle(s, {0, -1, 0}, {0, 1, 0}, {2, 0, 0});
  const SceneBuffers buf = FlattenScene(s);
  std::vector<layout::Ray> rays;
  for (float x : {0x1p-12f, -0x1p-12f, 0x1p-6f})
    for (glm::vec3 d : {glm::vec3(0, 0.5f, -1), glm::vec3(0, -1, -1), glm::vec3(0, 0, -1)}) rays.push_back(Ray({x, 0, 1}, d, 0.0f, INFINITY));
  const std::vector<std::uint64_t> expected = ExactExpected(buf, rays);
  int hits = 0;
  for (std::uint64_t e : expected) hits += e != emu::kMissPacked;
  CHECK(hits == 4);  // x > 0 lies inside, except toward y = -1, the vertex (0, -1) where the width is 0
  ExpectEveryTracer(buf, rays, expected);
}

TEST_CASE("hard case: rays with NaN or infinite directions hit nothing and shadow nothing") {
  const SceneBuffers buf = FlattenScene(Cube());
  const float nan = std::nanf(""), inf = INFINITY;
  const std::vector<layout::Ray> rays = {Ray({0, 0, 5}, {nan, 0, -1}, 0.0f, INFINITY), Ray({0, 0, 5}, {0, 0, -inf}, 0.0f, INFINITY),
                                         Ray({0, 0, 5}, {0, 0, -1}, nan, INFINITY), Ray({0, 0, 5}, {0, 0, -1}, 0.0f, nan)};
  // The watertight test itself refuses every triangle: its comparisons with NaN are false.
  for (const layout::Ray& r : rays)
    for (const layout::Triangle& t : buf.triangles) {
      float th = 0;
      CHECK_FALSE(emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax)), emu::Xyz(t.v0),
                                           emu::Xyz(t.v1), emu::Xyz(t.v2), r.origin_tmin.w, r.direction_tmax.w, th));
    }
  ExpectEveryTracer(buf, rays, std::vector<std::uint64_t>(rays.size(), emu::kMissPacked), false);
}
