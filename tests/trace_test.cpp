// The emulator's direct tracer: exhaustive == BVH, ignored primitives, tmin/tmax.
#include <doctest/doctest.h>

#include <random>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

using test::MakeRay;
using test::SphereScene;

TEST_CASE("direct tracer: BVH and exhaustive modes give identical answers") {
  const Scene s = SphereScene(40, 20);
  const SceneBuffers b = FlattenScene(s);
  auto ex = MakeDirectTracer(b, DirectMode::kExhaustive);
  auto bvh = MakeDirectTracer(b, DirectMode::kBvh);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  std::vector<layout::Ray> rays;
  for (int i = 0; i < 4000; ++i) {
    layout::Ray r = MakeRay({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, i % 7 == 0 ? static_cast<std::uint32_t>(i % b.triangles.size()) : layout::kNoPrim);
    if (i % 3 == 0) r.direction_tmax.w = 0.5f + (i % 5) * 0.3f;  // bounded rays too
    rays.push_back(r);
  }
  std::vector<std::uint64_t> h1, h2;
  ex->Closest(rays, h1);
  bvh->Closest(rays, h2);
  CHECK(h1 == h2);
  std::vector<std::uint32_t> o1, o2;
  ex->Occluded(rays, o1);
  bvh->Occluded(rays, o2);
  CHECK(o1 == o2);
  std::size_t hit = 0;
  for (auto h : h1) hit += h != kMissPacked;
  CHECK(hit > 1000);  // the comparison is not vacuous
}

TEST_CASE("direct tracer: ignores the primitive a ray leaves and honours tmin/tmax") {
  Scene s;
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  test::AddQuad(s, "a", {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
  test::AddQuad(s, "b", {-1, -1, -2}, {1, -1, -2}, {1, 1, -2}, {-1, 1, -2});
  const SceneBuffers b = FlattenScene(s);
  auto tr = MakeDirectTracer(b, DirectMode::kExhaustive);
  std::vector<std::uint64_t> h;
  tr->Closest({MakeRay({0.2f, 0.1f, 1}, {0, 0, -1})}, h);
  REQUIRE(h[0] != kMissPacked);
  CHECK(HitT(h[0]) == 1.0f);
  const std::uint32_t front = HitPrim(h[0]);
  tr->Closest({MakeRay({0.2f, 0.1f, 0}, {0, 0, -1}, front)}, h);  // leaving the front quad
  REQUIRE(h[0] != kMissPacked);
  CHECK(HitT(h[0]) == 2.0f);
  layout::Ray shortray = MakeRay({0.2f, 0.1f, 1}, {0, 0, -1});
  shortray.direction_tmax.w = 0.999f;
  std::vector<std::uint32_t> occ;
  tr->Occluded({shortray}, occ);
  CHECK(occ[0] == 0);
}
