// The emulator's intersection test and direct tracer: watertightness, exhaustive == BVH.
#include <doctest/doctest.h>

#include <random>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/procedural.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

gpu::Ray MakeRay(glm::vec3 o, glm::vec3 d, std::uint32_t ignore = gpu::kNoPrim) {
  gpu::Ray r{};
  r.origin_tmin = glm::vec4(o, 0.0f);
  r.direction_tmax = glm::vec4(d, std::numeric_limits<float>::infinity());
  r.info = glm::uvec4(0, ignore, gpu::kRayReflection, 0);
  return r;
}

Scene SphereScene(int segments, int rings) {
  Scene s;
  s.camera.eye = {0, 0, 5};
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  MeshData m = GenerateSphere(1.0f, segments, rings, "sphere");
  Object o;
  o.name = "sphere";
  o.positions = m.submeshes[0].positions;
  o.normals = m.submeshes[0].normals;
  o.material.assign(o.TriangleCount(), 0);
  s.objects.push_back(o);
  return s;
}

}  // namespace

TEST_CASE("intersect: rays through shared edges and vertices of a closed mesh are never lost") {
  // From inside a closed sphere every ray must hit. Aiming exactly at vertices and edge midpoints
  // puts the hit on shared edges, where a non-watertight test leaks.
  const Scene s = SphereScene(16, 9);
  const SceneBuffers b = FlattenScene(s);
  auto tracer = MakeDirectTracer(b, DirectMode::kExhaustive);
  std::vector<gpu::Ray> rays;
  const glm::vec3 origins[3] = {{0, 0, 0}, {0.1f, -0.2f, 0.05f}, {-0.3f, 0.1f, 0.2f}};
  for (const glm::vec3& o : origins)
    for (const gpu::Triangle& t : b.triangles) {
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

TEST_CASE("direct tracer: BVH and exhaustive modes give identical answers") {
  const Scene s = SphereScene(40, 20);
  const SceneBuffers b = FlattenScene(s);
  auto ex = MakeDirectTracer(b, DirectMode::kExhaustive);
  auto bvh = MakeDirectTracer(b, DirectMode::kBvh);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  std::vector<gpu::Ray> rays;
  for (int i = 0; i < 4000; ++i) {
    gpu::Ray r = MakeRay({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, i % 7 == 0 ? static_cast<std::uint32_t>(i % b.triangles.size()) : gpu::kNoPrim);
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
  gpu::Ray shortray = MakeRay({0.2f, 0.1f, 1}, {0, 0, -1});
  shortray.direction_tmax.w = 0.999f;
  std::vector<std::uint32_t> occ;
  tr->Occluded({shortray}, occ);
  CHECK(occ[0] == 0);
}
