// Known answers for the shading points of a generation: from ray hits (surfaces.hits) and from the
// G-buffer (surfaces). Expected values are worked out by hand from the scene below.
#include <doctest/doctest.h>

#include <cmath>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

// One triangle (0,0,0), (3,0,0), (0,3,0) in the plane z = 0 with a different normal at each vertex,
// material 1 of 2, seen by a 90-degree camera at (0,0,5) looking down -z.
const glm::vec3 kV[3] = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}};
const glm::vec3 kN[3] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {0, 0.6f, 0.8f}};

Scene TriangleScene() {
  Scene s;
  s.camera.eye = {0, 0, 5};
  s.camera.target = {0, 0, 0};
  s.camera.fov_y_deg = 90.0f;
  s.materials.push_back(test::Diffuse("first", glm::vec3(0.5f)));
  s.materials.push_back(test::Diffuse("second", glm::vec3(0.25f)));
  Object o;
  o.name = "tri";
  o.positions = {kV[0], kV[1], kV[2]};
  o.normals = {kN[0], kN[1], kN[2]};
  o.material = {1};
  s.objects.push_back(o);
  return s;
}

layout::Ray RayAt(glm::vec3 o, glm::vec3 d, std::uint32_t pixel) {
  layout::Ray r = test::MakeRay(o, d);
  r.info.x = pixel;
  r.weight = glm::vec4(0.5f, 0.25f, 0.125f, 0.0f);
  return r;
}

void CheckNear(glm::vec3 got, glm::vec3 expect) {
  for (int k = 0; k < 3; ++k) CHECK(got[k] == doctest::Approx(expect[k]).epsilon(1e-6));
}

}  // namespace

TEST_CASE("surfaces.hits: position o + t d, normals interpolated to the vertex normals, misses keep the pixel") {
  const Scene scene = TriangleScene();
  const SceneBuffers b = FlattenScene(scene);
  std::vector<layout::Ray> rays;
  std::vector<std::uint64_t> hits;
  // 0: down a non-unit direction onto the centroid (1,1,0): t = 2.5 along (0,0,-2) from z = 5.
  rays.push_back(RayAt({1, 1, 5}, {0, 0, -2}, 7));
  hits.push_back(PackHit(2.5f, 0));
  // 1-3: straight down onto each vertex from one unit above it.
  for (std::uint32_t k = 0; k < 3; ++k) {
    rays.push_back(RayAt(kV[k] + glm::vec3(0, 0, 1), {0, 0, -1}, 10 + k));
    hits.push_back(PackHit(1.0f, 0));
  }
  // 4: a miss.
  rays.push_back(RayAt({9, 9, 5}, {0, 0, -1}, 9));
  hits.push_back(kMissPacked);

  const auto s = PassSurfacesFromHits({.rays = rays, .hits = hits, .scene = &b});
  REQUIRE(s.size() == rays.size());

  CHECK(s[0].position == glm::vec4(1, 1, 0, 1));  // (1,1,5) + 2.5 (0,0,-2), exact in float
  CHECK(s[0].incoming == glm::vec4(0, 0, -1, 0));
  CHECK(s[0].weight == rays[0].weight);
  CHECK(s[0].info == glm::uvec4(0, 7, 1, 0));  // primitive, pixel, material
  // The centroid weighs the three vertex normals equally.
  CheckNear(glm::vec3(s[0].normal), glm::normalize(kN[0] + kN[1] + kN[2]));
  CHECK(s[0].normal.w == 0.0f);

  for (std::uint32_t k = 0; k < 3; ++k) {
    INFO("vertex " << k);
    CHECK(s[1 + k].position == glm::vec4(kV[k], 1));
    CheckNear(glm::vec3(s[1 + k].normal), kN[k]);
    CHECK(s[1 + k].info == glm::uvec4(0, 10 + k, 1, 0));
  }

  CHECK(s[4].position == glm::vec4(0));  // w 0: an empty slot
  CHECK(s[4].info == glm::uvec4(layout::kNoPrim, 9, 0, 0));
}

TEST_CASE("surfaces: a 2x1 G-buffer with one covered pixel") {
  const Scene scene = TriangleScene();
  const SceneBuffers b = FlattenScene(scene);
  const layout::FrameConstants fc = MakeFrameConstants(scene, b, 2, 1);
  // Pixel 0 is empty (whatever the other attachments hold); pixel 1 sees the triangle at (1,1,0).
  const std::vector<glm::vec4> position = {{7, 7, 7, 0}, {1, 1, 0, 1}};
  const std::vector<glm::vec4> normal = {{0, 1, 0, 0}, {0, 0, 1, 0.25f}};  // w: transparency
  const std::vector<std::uint32_t> prim = {layout::kNoPrim, 0};
  const auto s = PassSurfacesFromGBuffer(
      {.frame = fc, .width = 2, .height = 1, .position = position, .normal = normal, .prim = prim, .scene = &b});
  REQUIRE(s.size() == 2);

  CHECK(s[0].position == glm::vec4(0));
  CHECK(s[0].info == glm::uvec4(layout::kNoPrim, 0, 0, 0));

  CHECK(s[1].position == glm::vec4(1, 1, 0, 1));
  CHECK(s[1].normal == glm::vec4(0, 0, 1, 0));
  CHECK(s[1].weight == glm::vec4(1, 1, 1, 0));
  CHECK(s[1].info == glm::uvec4(0, 1, 1, 0));  // primitive, pixel, material
  // tan(45 deg) = 1 vertically and 2 horizontally (2:1 image): the centre of pixel 1 is half way to the
  // right edge, at 1 unit right per unit forward, so the camera ray's direction is (1, 0, -1) / sqrt 2.
  const float r = 1.0f / std::sqrt(2.0f);
  CheckNear(glm::vec3(s[1].incoming), {r, 0, -r});
  CHECK(s[1].incoming.w == 0.0f);
}
