// Known answers for ray generation (thesis eqs. 3.1-3.7) and shading (eq. 3.19).
#include <doctest/doctest.h>

#include <cmath>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

struct Fixture {
  Scene scene;
  SceneBuffers b;
  gpu::FrameConstants fc{};
  explicit Fixture(MaterialDesc m, LightDesc light = {}) {
    scene.camera.eye = {0, 3, 3};
    scene.camera.target = {0, 0, 0};
    scene.materials.push_back(m);
    scene.lights.push_back(light);
    test::AddQuad(scene, "floor", {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1});
    b = FlattenScene(scene);
    fc = MakeFrameConstants(scene, b, 8, 8);
  }
  gpu::Surface Surface(glm::vec3 p, glm::vec3 n, glm::vec3 incoming) const {
    gpu::Surface s{};
    s.position = glm::vec4(p, 1);
    s.normal = glm::vec4(n, 0);
    s.incoming = glm::vec4(incoming, 0);
    s.weight = glm::vec4(1, 1, 1, 0);
    s.info = glm::uvec4(0, 0, 0, 0);
    return s;
  }
};

}  // namespace

// One surface through a raygen pass of the given kind.
template <SparseRays (*Pass)(const call::Raygen&)>
SparseRays RaygenOne(std::uint32_t kind, const Fixture& f, const gpu::Surface& s) {
  const std::vector<gpu::Surface> surfaces{s};
  return Pass({.kind = kind, .frame = f.fc, .surfaces = surfaces, .scene = &f.b});
}
SparseRays RaygenShadow(const Fixture& f, const gpu::Surface& s) { return RaygenOne<PassRaygenShadow>(gpu::kRayShadow, f, s); }
SparseRays RaygenReflection(const Fixture& f, const gpu::Surface& s) {
  return RaygenOne<PassRaygenReflection>(gpu::kRayReflection, f, s);
}
SparseRays RaygenRefraction(const Fixture& f, const gpu::Surface& s) {
  return RaygenOne<PassRaygenRefraction>(gpu::kRayRefraction, f, s);
}

TEST_CASE("raygen: shadow rays start at the light and stop just short of the surface") {
  LightDesc light;
  light.position = {0, 4, 0};
  Fixture f(test::Diffuse("m", glm::vec3(0.5f)), light);
  const auto rays = RaygenShadow(f, {f.Surface({0, 0, 3}, {0, 1, 0}, {0, -1, 0})});
  REQUIRE(rays.flags.size() == 1);
  REQUIRE(rays.flags[0] == 1);
  const gpu::Ray& r = rays.rays[0];
  CHECK(Xyz(r.origin_tmin) == glm::vec3(0, 4, 0));               // eq. 3.1
  CHECK(r.direction_tmax.y == doctest::Approx(-0.8f));           // eq. 3.2: (p - l) / |p - l| = (0,-4,3)/5
  CHECK(r.direction_tmax.z == doctest::Approx(0.6f));
  CHECK(r.direction_tmax.w == 5.0f * kShadowTmaxFactor);
  CHECK(r.info.z == gpu::kRayShadow);
  CHECK(r.info.y == 0);  // ignores the surface's own triangle
}

TEST_CASE("raygen: reflection mirrors the incident direction about the normal") {
  MaterialDesc m = test::Diffuse("mirror", glm::vec3(0.1f));
  m.reflectivity = 0.5f;
  Fixture f(m);
  const float s = 1.0f / std::sqrt(2.0f);
  const auto rays = RaygenReflection(f, {f.Surface({0, 0, 0}, {0, 1, 0}, {s, -s, 0})});
  REQUIRE(rays.flags[0] == 1);
  CHECK(rays.rays[0].direction_tmax.x == doctest::Approx(s));
  CHECK(rays.rays[0].direction_tmax.y == doctest::Approx(s));
  CHECK(rays.rays[0].direction_tmax.z == 0.0f);
  CHECK(rays.rays[0].weight.x == doctest::Approx(0.5f));
  // The formula does not depend on the normal's sign.
  const auto flipped = RaygenReflection(f, {f.Surface({0, 0, 0}, {0, -1, 0}, {s, -s, 0})});
  CHECK(Xyz(flipped.rays[0].direction_tmax) == Xyz(rays.rays[0].direction_tmax));
  // Non-reflective materials spawn nothing.
  Fixture g(test::Diffuse("matte", glm::vec3(0.5f)));
  CHECK(RaygenReflection(g, {g.Surface({0, 0, 0}, {0, 1, 0}, {s, -s, 0})}).flags[0] == 0);
}

TEST_CASE("raygen: refraction follows Snell's law and stops at total internal reflection") {
  MaterialDesc m = test::Diffuse("glass", glm::vec3(0.0f));
  m.transparency = 0.9f;
  m.ior = 1.5f;
  Fixture f(m);
  for (float deg : {0.0f, 20.0f, 45.0f, 70.0f}) {
    const float a = deg * 3.14159265f / 180.0f;
    const glm::vec3 i(std::sin(a), -std::cos(a), 0);
    // Entering (the ray meets the normal's front side).
    auto in = RaygenRefraction(f, {f.Surface({0, 0, 0}, {0, 1, 0}, i)});
    REQUIRE(in.flags[0] == 1);
    const glm::vec3 d = glm::normalize(Xyz(in.rays[0].direction_tmax));
    CHECK(d.y < 0);
    CHECK(std::fabs(d.x) == doctest::Approx(std::sin(a) / 1.5f).epsilon(1e-5));
    CHECK(glm::length(Xyz(in.rays[0].direction_tmax)) == doctest::Approx(1.0f).epsilon(1e-5));
    // Leaving: sin t = 1.5 sin i, total internal reflection past asin(1/1.5) = 41.8 degrees.
    auto out = RaygenRefraction(f, {f.Surface({0, 0, 0}, {0, -1, 0}, i)});
    if (deg < 41.0f) {
      REQUIRE(out.flags[0] == 1);
      const glm::vec3 e = glm::normalize(Xyz(out.rays[0].direction_tmax));
      CHECK(std::fabs(e.x) == doctest::Approx(std::sin(a) * 1.5f).epsilon(1e-5));
    } else {
      CHECK(out.flags[0] == 0);
    }
  }
}

TEST_CASE("IntPow is exact repeated squaring") {
  CHECK(IntPow(0.5f, 0) == 1.0f);
  CHECK(IntPow(0.5f, 1) == 0.5f);
  CHECK(IntPow(0.5f, 10) == 1.0f / 1024.0f);
  CHECK(IntPow(3.0f, 5) == 243.0f);
  CHECK(IntPow(0.9f, 64) == doctest::Approx(std::pow(0.9, 64)).epsilon(1e-5));
}

namespace {

// Shades one surface with one light and returns the pixel's colour from the fixed-point accumulator.
glm::vec3 ShadeOne(const Fixture& f, const gpu::Surface& s, bool occluded) {
  std::vector<std::uint64_t> accum(3 * 64, 0);
  const std::vector<gpu::Surface> surfaces{s};
  const std::vector<std::uint32_t> flags{1u}, offsets{0u}, occ{occluded ? 1u : 0u};
  PassShade({.frame = f.fc, .surfaces = surfaces, .shadow_flags = flags, .shadow_offsets = offsets, .occluded = occ,
             .accum = &accum, .scene = &f.b});
  return glm::vec3(accum[0], accum[1], accum[2]) / gpu::kAccumScale;
}

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
