// The hard-case suite: named special configurations with their expected behaviour, judged by the
// exact oracles (refs/exact.h, refs/exact_cone.h) where an exact answer exists. Related cases live
// beside their concept: shared edges of a closed mesh and sliver distances in intersect_test.cpp, total
// internal reflection in raygen_test.cpp, NaN/inf and out-of-range transforms in
// scene_loader_test.cpp; the scale and permutation metamorphic tests are in metamorphic_test.cpp.
// The tracer-level cases hold the exhaustive direct tracer and the hierarchy, flat and with the
// object tree, to the same answer. More ray cases: hard_cases_rays_test.cpp; the interval ends and
// ties: hit_convention_test.cpp (docs/numerics.md, "The hard-case suite").
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/error.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/exact_cone.h"
#include "hard_tracers.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;
using test::HardTracers;

namespace {

layout::ConeNode Node(glm::vec3 c, float r, glm::vec3 axis, double half_angle) {
  layout::ConeNode n;
  n.sphere = glm::vec4(c, r);
  const glm::dvec3 a = glm::normalize(glm::dvec3(axis));
  n.cone = glm::vec4(glm::vec3(a), static_cast<float>(std::cos(half_angle)));
  n.extra = glm::vec4(static_cast<float>(std::sin(half_angle)), 1.0f, 0.0f, 0.0f);
  if (half_angle >= M_PI) n = cone::FullSphereCone(n);
  return n;
}

// The parent of two children must contain both exactly.
void CheckUnion(const layout::ConeNode& a, const layout::ConeNode& b) {
  const layout::ConeNode kids[2] = {a, b};
  const layout::ConeNode p = cone::ParentNode(kids, 2);
  std::string why;
  CHECK_MESSAGE(refs::ExactNodeContains(p, a, &why), why);
  CHECK_MESSAGE(refs::ExactNodeContains(p, b, &why), why);
}

// Over a grid of spheres around the node, the float test never rejects what the exact decision
// accepts; returns how many the exact decision accepted.
int CheckTestConservative(const layout::ConeNode& n, float extent) {
  int met = 0;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j)
      for (int k = -6; k <= 6; ++k)
        for (float r : {0.0f, extent * 0.05f}) {
          const glm::vec4 s(Xyz(n.sphere) + glm::vec3(i, j, k) * (extent / 6.0f), r);
          if (!refs::ExactNodeMeetsSphere(n, s)) continue;
          ++met;
          if (!cone::Test(n, s, 0.0f)) {
            FAIL_CHECK("the test rejects a sphere the exact decision accepts");
            return met;
          }
        }
  return met;
}

layout::Ray Ray(glm::vec3 o, glm::vec3 d, std::uint32_t ignore = layout::kNoPrim, float tmin = 0.0f, float tmax = INFINITY) {
  layout::Ray r{};
  r.origin_tmin = glm::vec4(o, tmin);
  r.direction_tmax = glm::vec4(d, tmax);
  r.info = glm::uvec4(0, ignore, layout::kRayReflection, 0);
  return r;
}

bool FloatHit(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  float t;
  return IntersectWatertight(SetupWatertight(o, d), a, b, c, 0.0f, INFINITY, t) && std::isfinite(t) && t > 0.0f;
}

}  // namespace

TEST_CASE("hard case: antiparallel cones unite into the full node, which contains both") {
  const layout::ConeNode a = Node({0, 0, 0}, 1, {0, 0, 1}, 0.1), b = Node({1, 0, 0}, 0.5f, {0, 0, -1}, 0.1);
  const layout::ConeNode kids[2] = {a, b};
  CHECK(cone::IsFull(cone::ParentNode(kids, 2)));
  CheckUnion(a, b);
  // Nearly antiparallel: not full, but still containing.
  CheckUnion(a, Node({1, 0, 0}, 0.5f, {1e-6f, 0, -1}, 0.1));
}

TEST_CASE("hard case: a ray along the cone's axis leaves the cone, against it makes it full") {
  const layout::ConeNode n = Node({0, 0, 0}, 0, {0, 0, 1}, 0.2);
  const layout::ConeNode along = cone::GrowNode(n, {0, 0, 1}, {0, 0, 1});
  CHECK(along.cone.w >= n.cone.w * (1.0f - 1e-5f));  // no widening beyond the margin
  CHECK(refs::ExactNodeContains(along, n));
  CHECK(refs::ExactNodeContainsRay(along, {0, 0, 1}, {0, 0, 1}));
  const layout::ConeNode against = cone::GrowNode(n, {0, 0, 1}, {0, 0, -1});
  CHECK(cone::IsFull(against));
  CHECK(refs::ExactNodeContainsRay(against, {0, 0, 1}, {0, 0, -1}));
}

TEST_CASE("hard case: zero-radius spheres and nodes") {
  const layout::ConeNode ray = Node({1, 2, 3}, 0, {1, 1, 0}, 0.0);  // a single ray
  CHECK(cone::Test(ray, glm::vec4(1, 2, 3, 0), 0.0f));           // its own origin
  CHECK(refs::ExactNodeMeetsSphere(ray, glm::vec4(1, 2, 3, 0)));
  CHECK(CheckTestConservative(ray, 4.0f) > 0);
  CheckUnion(ray, Node({1, 2, 3}, 0, {1, 1, 1e-7f}, 0.0));
}

TEST_CASE("hard case: half-angles near 0, near pi/2 and at or beyond pi") {
  for (double alpha : {1e-7, 1e-3, M_PI / 2 - 1e-7, M_PI / 2, M_PI / 2 + 1e-7, M_PI - 1e-6, M_PI, 4.0}) {
    CAPTURE(alpha);
    const layout::ConeNode n = Node({0.5f, -1, 2}, 0.25f, {0.3f, -0.4f, 0.5f}, alpha);
    CHECK(CheckTestConservative(n, 3.0f) > 0);
    CheckUnion(n, Node({0.5f, -1, 2.5f}, 0.1f, {-0.3f, 0.4f, 0.5f}, alpha / 2));
    const layout::ConeNode g = cone::GrowNode(n, {1, 1, 1}, glm::normalize(glm::vec3(-0.3f, 0.4f, -0.5f)));
    CHECK(refs::ExactNodeContains(g, n));
  }
}

TEST_CASE("hard case: degenerate triangles never hit and never produce NaN") {
  const glm::vec3 o(0.25f, 0.25f, 1), d(0, 0, -1);
  struct Tri {
    const char* what;
    glm::vec3 a, b, c;
  } tris[] = {{"zero area (all equal)", {0.25f, 0.25f, 0}, {0.25f, 0.25f, 0}, {0.25f, 0.25f, 0}},
              {"collinear", {0, 0, 0}, {0.5f, 0.5f, 0}, {1, 1, 0}},
              {"repeated vertex", {0, 0, 0}, {1, 0, 0}, {1, 0, 0}}};
  for (const Tri& t : tris) {
    CAPTURE(t.what);
    float th = -1.0f;
    const bool hit = IntersectWatertight(SetupWatertight(o, d), t.a, t.b, t.c, 0.0f, INFINITY, th);
    CHECK_FALSE(hit);
    CHECK_FALSE(refs::ExactRobustInteriorHit(o, d, t.a, t.b, t.c, 0x1p-16f));
  }
}

TEST_CASE("hard case: grazing rays in a triangle's plane are misses, not NaN hits") {
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK_FALSE(FloatHit({-1, 0.25f, 0}, {1, 0, 0}, a, b, c));
  CHECK_FALSE(FloatHit({0.25f, 0.25f, 0}, {1, 1, 0}, a, b, c));  // starting inside the triangle
  CHECK_FALSE(refs::ExactRobustInteriorHit({-1, 0.25f, 0}, {1, 0, 0}, a, b, c, 0x1p-16f));
}

TEST_CASE("hard case: secondary rays do not hit their own surface or its coplanar neighbour") {
  // A floor made of two triangles; rays leave a point on the shared edge region of triangle 0.
  Scene s;
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  test::AddQuad(s, "floor", {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1});
  const SceneBuffers buf = FlattenScene(s);
  HardTracers tracers(buf);
  const float eps = static_cast<float>(glm::length(buf.hi - buf.lo) * kRayEpsilonRelative);
  std::vector<layout::Ray> rays;
  for (float x : {-0.5f, 0.0f, 0.3f, 0.999f})
    for (glm::vec3 d : {glm::vec3(0, 1, 0), glm::vec3(1, 1e-3f, 0), glm::vec3(-1, 1e-6f, 1), glm::vec3(0, 1e-7f, 1)}) {
      layout::Ray r = Ray({x, 0, x}, glm::normalize(d), 0, eps);  // on the diagonal edge shared by both
      r.info.z = layout::kRayReflection;
      rays.push_back(r);
    }
  for (std::size_t k = 0; k < tracers.all.size(); ++k) {
    CAPTURE(tracers.names[k]);
    std::vector<std::uint64_t> hits;
    tracers.all[k]->Closest(rays, hits);
    REQUIRE(hits.size() == rays.size());
    for (std::size_t i = 0; i < hits.size(); ++i) CHECK_MESSAGE(hits[i] == kMissPacked, "ray " << i);
  }
}

TEST_CASE("hard case: a shadow ray toward a light lying on a surface is not blocked by that surface") {
  Scene s;
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  test::AddQuad(s, "floor", {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1});
  const SceneBuffers buf = FlattenScene(s);
  HardTracers tracers(buf);
  // The light sits on the floor at the origin; shadow rays run from it to floor points, inside the
  // floor's plane, and stop just short of the surface point (kShadowTmaxFactor).
  std::vector<layout::Ray> rays;
  for (glm::vec3 p : {glm::vec3(0.5f, 0, 0.5f), glm::vec3(-0.9f, 0, 0.1f), glm::vec3(0.2f, 0, -0.7f)}) {
    layout::Ray r = Ray({0, 0, 0}, p, 1, 0.0f, kShadowTmaxFactor);
    r.info.z = layout::kRayShadow;
    rays.push_back(r);
  }
  for (std::size_t k = 0; k < tracers.all.size(); ++k) {
    CAPTURE(tracers.names[k]);
    std::vector<std::uint32_t> occluded;
    tracers.all[k]->Occluded(rays, occluded);
    REQUIRE(occluded.size() == rays.size());
    for (std::uint32_t o : occluded) CHECK(o == 0u);
  }
}

TEST_CASE("hard case: coordinates scaled by 2^60 and 2^-60 keep the ray-triangle and cone answers") {
  for (float k : {0x1p60f, 0x1p-60f, 1.0f}) {
    CAPTURE(k);
    const glm::vec3 a = glm::vec3(0, 0, 0) * k, b = glm::vec3(1, 0, 0) * k, c = glm::vec3(0, 1, 0) * k;
    CHECK(FloatHit(glm::vec3(0.25f, 0.25f, 1) * k, {0, 0, -1}, a, b, c));
    CHECK(FloatHit(glm::vec3(0.5f, 0, 1) * k, {0, 0, -1}, a, b, c));  // the edge: inclusive
    CHECK_FALSE(FloatHit(glm::vec3(0.75f, 0.75f, 1) * k, {0, 0, -1}, a, b, c));
    float t = 0;
    REQUIRE(IntersectWatertight(SetupWatertight(glm::vec3(0.25f, 0.25f, 1) * k, {0, 0, -1}), a, b, c, 0.0f, INFINITY, t));
    CHECK(t == k);  // exact: the plane equation scales by powers of two
    const layout::ConeNode n = Node(glm::vec3(1, 2, 3) * k, 0.5f * k, {1, -1, 2}, 0.3);
    CHECK(CheckTestConservative(n, 4.0f * k) > 0);
    CheckUnion(n, Node(glm::vec3(1, 2, 4) * k, 0.25f * k, {-1, -1, 2}, 0.2));
  }
}

TEST_CASE("hard case: denormal coordinates and radii are computed, not lost") {
  const float tiny = 1e-40f;  // a denormal
  REQUIRE(std::fpclassify(tiny) == FP_SUBNORMAL);
  const layout::ConeNode a = Node({tiny, 0, 0}, tiny, {0, 0, 1}, 0.1), b = Node({0, tiny, -tiny}, 0, {0, 1, 1}, 0.0);
  CheckUnion(a, b);
  const layout::ConeNode g = cone::GrowNode(a, {0, 0, 3 * tiny}, {0, 0, 1});
  CHECK(refs::ExactNodeContains(g, a));
  CHECK(refs::ExactNodeContainsRay(g, {0, 0, 3 * tiny}, {0, 0, 1}));
  CHECK(cone::Test(a, glm::vec4(0, 0, 1, 0), 0.0f));
}

TEST_CASE("hard case: NaN and infinite coordinates are rejected at load, naming the input") {
  test::TempDir dir;
  for (const char* bad : {"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                          "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n"}) {
    CAPTURE(bad);
    const auto path = dir.Write("bad.obj", bad);
    try {
      (void)LoadMesh(path);
      FAIL_CHECK("loaded a mesh with a non-finite coordinate");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find("bad.obj") != std::string::npos);
    }
  }
}
