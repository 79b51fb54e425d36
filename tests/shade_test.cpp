// Known answers for shading (eq. 3.19) and its integer power.
#include <doctest/doctest.h>

#include <cmath>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {
using Fixture = test::ShadingFixture;
}  // namespace

TEST_CASE("IntPow is exact repeated squaring") {
  CHECK(IntPow(0.5f, 0) == 1.0f);
  CHECK(IntPow(0.5f, 1) == 0.5f);
  CHECK(IntPow(0.5f, 10) == 1.0f / 1024.0f);
  CHECK(IntPow(3.0f, 5) == 243.0f);
  CHECK(IntPow(0.9f, 64) == doctest::Approx(std::pow(0.9, 64)).epsilon(1e-5));
}

namespace {

// Shades one surface with one light and returns the pixel's colour.
glm::vec3 ShadeOne(const Fixture& f, const layout::Surface& s, bool occluded) { return f.Shade(s, {occluded ? 1u : 0u}); }

}  // namespace

TEST_CASE("shade: Lambert term with attenuation (eq. 3.19)") {
  LightDesc light;
  light.position = {0, 2, 0};
  light.color = {1, 0.5f, 0.25f};
  light.intensity = 2.0f;
  light.attenuation = {1, 0, 1};  // 1 / (1 + d^2) = 1/5 at d = 2
  Fixture f(test::Diffuse("m", glm::vec3(0.5f)), light);
  const glm::vec3 c = ShadeOne(f, f.Surface({0, 0, 0}, {0, 1, 0}, glm::normalize(glm::vec3(0, -1, -1))), false);
  CHECK(c.x == doctest::Approx(0.5 * 1.0 * 2.0 / 5.0).epsilon(1e-6));
  CHECK(c.y == doctest::Approx(0.5 * 0.5 * 2.0 / 5.0).epsilon(1e-6));
  CHECK(c.z == doctest::Approx(0.5 * 0.25 * 2.0 / 5.0).epsilon(1e-6));
  // At 60 degrees from the normal the diffuse factor is cos 60 = 1/2 (distance still 2).
  LightDesc tilted = light;
  tilted.position = {std::sqrt(3.0f), 1, 0};
  Fixture g(test::Diffuse("m", glm::vec3(0.5f)), tilted);
  const glm::vec3 d = ShadeOne(g, g.Surface({0, 0, 0}, {0, 1, 0}, glm::normalize(glm::vec3(0, -1, -1))), false);
  CHECK(d.x == doctest::Approx(0.5 * 0.5 * 2.0 / 5.0).epsilon(1e-5));
}

TEST_CASE("shade: Phong specular, shadows and back-facing lights") {
  LightDesc light;
  light.position = {0, 1, 0};
  light.attenuation = {1, 0, 0};
  MaterialDesc m = test::Diffuse("shiny", glm::vec3(0.0f));
  m.specular = glm::vec3(0.25f);
  m.shininess = 8;
  Fixture f(m, light);
  // Viewer straight above: halfway vector = normal, specular factor 1.
  CHECK(ShadeOne(f, f.Surface({0, 0, 0}, {0, 1, 0}, {0, -1, 0}), false).x == doctest::Approx(0.25f));
  // Off the mirror direction the highlight falls off as cos^8 of the halfway angle.
  const glm::vec3 view = glm::normalize(glm::vec3(1, -1, 0));
  const glm::vec3 h = glm::normalize(glm::vec3(0, 1, 0) - view);
  CHECK(ShadeOne(f, f.Surface({0, 0, 0}, {0, 1, 0}, view), false).x == doctest::Approx(0.25 * std::pow(h.y, 8)).epsilon(1e-5));
  // In shadow: nothing.
  CHECK(ShadeOne(f, f.Surface({0, 0, 0}, {0, 1, 0}, {0, -1, 0}), true) == glm::vec3(0));
  // Light behind the lit side (two-sided surface seen from below, light above): nothing.
  CHECK(ShadeOne(f, f.Surface({0, 0, 0}, {0, 1, 0}, {0, 1, 0}), false) == glm::vec3(0));
}

// Two surfaces and two lights: slot s x lights + l holds surface s's ray to light l. Only surface 1's
// ray to light 1 is unoccluded, so only that pair may light anything.
TEST_CASE("shade: two surfaces and two lights read each light's own shadow slot") {
  LightDesc near_light, far_light;
  near_light.position = {0, 2, 0};
  near_light.attenuation = {1, 0, 1};  // 1 / (1 + 4) at d = 2
  far_light.position = {0, 4, 0};
  far_light.attenuation = {1, 0, 1};   // 1 / (1 + 16) at d = 4
  Fixture f(test::Diffuse("m", glm::vec3(0.5f)), near_light);
  f.scene.lights.push_back(far_light);
  f.b = FlattenScene(f.scene);
  const glm::vec3 view = glm::normalize(glm::vec3(0, -1, -1));
  std::vector<layout::Surface> surfaces{f.Surface({0, 0, 0}, {0, 1, 0}, view), f.Surface({0, 0, 0}, {0, 1, 0}, view)};
  surfaces[1].info.y = 1;  // pixel 1
  // Dense shadow rays 0..3 in slot order; occluded: all but slot 3 (surface 1, light 1).
  const std::vector<std::uint32_t> flags{1, 1, 1, 1}, offsets{0, 1, 2, 3}, occ{1, 1, 1, 0};
  std::vector<std::uint64_t> accum(3 * 64, 0);
  PassShade({.frame = f.fc, .surfaces = surfaces, .shadow_flags = flags, .shadow_offsets = offsets, .occluded = occ,
             .accum = &accum, .scene = &f.b});
  CHECK(accum[0] == 0);  // pixel 0: both its rays occluded
  // Pixel 1: the far light only, straight above: kd 0.5 x cos 0 x 1/17.
  CHECK(accum[3] / double(layout::kAccumScale) == doctest::Approx(0.5 / 17.0).epsilon(1e-5));
}
