// Known answers for the hash pass (docs/hierarchy.md, "Hash keys"): the key layout, hand-computed keys,
// and Roger et al.'s quadtree keys.
#include <doctest/doctest.h>

#include <cmath>

#include "rayspace/emu/hierarchy.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

// The scene box is [-1, 1] x [-1, 1] x [0, 2] (two quads).
SceneBuffers BoxScene() {
  Scene s;
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  test::AddQuad(s, "low", {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
  test::AddQuad(s, "high", {-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2});
  return FlattenScene(s);
}

layout::Ray ShadowRay(std::uint32_t light, glm::vec3 d, std::uint32_t pixel = 0) {
  layout::Ray r = test::MakeRay({0, 0, 1}, d);
  r.info = glm::uvec4(pixel, layout::kNoPrim, layout::kRayShadow, light);
  return r;
}

layout::Ray SecondaryRay(glm::vec3 o, glm::vec3 d, std::uint32_t pixel = 0) {
  layout::Ray r = test::MakeRay(o, d);
  r.info.x = pixel;
  return r;
}

std::vector<std::uint32_t> Keys(const std::vector<layout::Ray>& rays, const SceneBuffers& b) {
  return PassHash({.rays = rays, .scene = &b, .hash = {}});
}

}  // namespace

TEST_CASE("hash: shadow keys hold the light in the high bits, and opposite directions differ") {
  const SceneBuffers b = BoxScene();
  const glm::vec3 dirs[] = {{0, 0, 1},  {1, 0, 0},   {0, 1, 0},  {1, 1, 0},   {-1, 2, 0.5f},
                            {3, -1, 2}, {0.2f, 0.1f, -1}, {-1, -1, -1}, {0.5f, -0.25f, 0.125f}};
  std::vector<layout::Ray> rays;
  for (std::uint32_t light = 0; light < 4; ++light)
    for (const glm::vec3& d : dirs) {
      rays.push_back(ShadowRay(light, d));
      rays.push_back(ShadowRay(light, -d));
    }
  const auto keys = Keys(rays, b);
  for (std::size_t i = 0; i < rays.size(); i += 2) {
    INFO("ray " << i << " light " << rays[i].info.w);
    CHECK((keys[i] >> 28) == rays[i].info.w);  // 4 light bits above 14 + 14 direction bits
    CHECK((keys[i + 1] >> 28) == rays[i].info.w);
    CHECK(keys[i] != keys[i + 1]);
  }
  // Lights past the 4 bits share the last value.
  CHECK((Keys({ShadowRay(20, {0, 0, 1})}, b)[0] >> 28) == 15u);
}

TEST_CASE("hash: hand-computed keys") {
  const SceneBuffers b = BoxScene();
  // Shadow, light 2, along +z: cos(theta) = 1 -> polar cell 2^14 - 1 (clamped), azimuth cell 0;
  // interleaved polar-over-azimuth bits: 10 repeated 14 times = 0xAAAAAAA, light 2 above: 0x2AAAAAAA.
  // Shadow, light 1, along (1,1,0): cos(theta) = 0 -> polar cell 2^13 (bit 13); the pseudo-angle of
  // 45 degrees is 0.5 of 4 -> azimuth cell 2^14 / 8 = 2^11. Polar bit 13 lands on key bit 27, azimuth
  // bit 11 on key bit 22: 0x08400000, light 1 above: 0x18400000.
  // Reflection from the box's far corner along +z: origin cells (63, 63, 63) interleaved = 2^18 - 1
  // above 14 direction bits; direction polar 127 over azimuth 0 = 0x2AAA: 0xFFFFEAAA.
  // Reflection from the box's centre along (1,1,0): origin cells (32, 32, 32) -> top 3 of 18 bits set
  // = 0x38000 << 14 = 0xE0000000; direction polar 64 (bit 6 -> key bit 13), azimuth 16 (bit 4 -> key
  // bit 8): 0x2100.
  // Reflection from the box's near corner along -z: everything 0.
  const std::vector<layout::Ray> rays = {ShadowRay(2, {0, 0, 1}), ShadowRay(1, {1, 1, 0}),
                                      SecondaryRay({1, 1, 2}, {0, 0, 1}), SecondaryRay({0, 0, 1}, {1, 1, 0}),
                                      SecondaryRay({-1, -1, 0}, {0, 0, -1})};
  const auto keys = Keys(rays, b);
  CHECK(keys[0] == 0x2AAAAAAAu);
  CHECK(keys[1] == 0x18400000u);
  CHECK(keys[2] == 0xFFFFEAAAu);
  CHECK(keys[3] == 0xE0002100u);
  CHECK(keys[4] == 0u);
}

TEST_CASE("hash: polar-first keys as the thesis prints them (--hash-order polar-first, --hash-bits)") {
  const SceneBuffers b = BoxScene();
  HashConfig h;
  h.order = layout::kHashOrderPolarFirst;
  h.polar_bits = h.azimuth_bits = 8;
  // Shadow, light 2, along +z: polar cell 2^8 - 1 (clamped) above azimuth cell 0: 0xFF00, light 2
  // above the 16 direction bits: 0x2FF00.
  // Shadow, light 1, along (1,1,0): polar cell 2^7 (cos 0 -> 0.5), azimuth 2^8 / 8 = 32: 0x8020,
  // light 1 above: 0x18020.
  // Reflection from the box's centre along (1,1,0): origin 0xE0000000 as interleaved (origin cells do
  // not change); direction polar 64 above azimuth 16 with 7 bits each: 64 << 7 | 16 = 0x2010.
  const std::vector<layout::Ray> rays = {ShadowRay(2, {0, 0, 1}), ShadowRay(1, {1, 1, 0}),
                                         SecondaryRay({0, 0, 1}, {1, 1, 0})};
  const auto keys = PassHash({.rays = rays, .scene = &b, .hash = h});
  CHECK(keys[0] == 0x2FF00u);
  CHECK(keys[1] == 0x18020u);
  CHECK(keys[2] == 0xE0002010u);
  // The widest direction part: 14 + 14 bits, light above: polar 2^13 << 14 | 2^11.
  h.polar_bits = h.azimuth_bits = 14;
  CHECK(PassHash({.rays = rays, .scene = &b, .hash = h})[1] == ((1u << 28) | (1u << 27) | (1u << 11)));
}

TEST_CASE("hash: the quadtree key of pixel (x, y) is its Morton code with the light above it") {
  const SceneBuffers b = BoxScene();
  const std::uint32_t width = 8;
  const int depth = 3;
  std::vector<layout::Ray> rays;
  for (std::uint32_t y = 0; y < 8; ++y)
    for (std::uint32_t x = 0; x < 8; ++x) {
      rays.push_back(ShadowRay(2, {0, 0, 1}, y * width + x));
      rays.push_back(SecondaryRay({0, 0, 1}, {0, 0, 1}, y * width + x));
    }
  const auto keys = PassHash({.rays = rays, .scene = &b, .hash = {}, .quadtree_width = width, .quadtree_depth = depth});
  for (std::uint32_t y = 0; y < 8; ++y)
    for (std::uint32_t x = 0; x < 8; ++x) {
      std::uint32_t morton = 0;  // bit b of x -> bit 2b, bit b of y -> bit 2b + 1
      for (int bit = 0; bit < depth; ++bit) morton |= ((x >> bit) & 1u) << (2 * bit) | ((y >> bit) & 1u) << (2 * bit + 1);
      const std::size_t i = 2 * (y * width + x);
      INFO("pixel " << x << "," << y);
      CHECK(keys[i] == (2u << (2 * depth) | morton));  // shadow: light 2 above 2 x depth bits
      CHECK(keys[i + 1] == morton);                    // other rays: light 0
    }
  // By hand: x = 5 = 101b, y = 3 = 011b -> y/x bit pairs 01 10 11 = 27; light 2 << 6 = 128.
  CHECK(keys[2 * (3 * width + 5)] == 155u);
  CHECK(keys[2 * (3 * width + 5) + 1] == 27u);
}
