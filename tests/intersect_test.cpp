// The intersect pass and the ray-triangle test it uses: watertightness, accurate distances.
#include <doctest/doctest.h>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/hierarchy.h"
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
