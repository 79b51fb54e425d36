// Known answers for ray generation (thesis eqs. 3.1-3.7).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {
using Fixture = test::ShadingFixture;
}  // namespace

// One surface through a raygen pass of the given kind.
template <SparseRays (*Pass)(const call::Raygen&)>
SparseRays RaygenOne(std::uint32_t kind, const Fixture& f, const layout::Surface& s) {
  const std::vector<layout::Surface> surfaces{s};
  return Pass({.kind = kind, .frame = f.fc, .surfaces = surfaces, .scene = &f.b});
}
SparseRays RaygenShadow(const Fixture& f, const layout::Surface& s) { return RaygenOne<PassRaygenShadow>(layout::kRayShadow, f, s); }
SparseRays RaygenReflection(const Fixture& f, const layout::Surface& s) {
  return RaygenOne<PassRaygenReflection>(layout::kRayReflection, f, s);
}
SparseRays RaygenRefraction(const Fixture& f, const layout::Surface& s) {
  return RaygenOne<PassRaygenRefraction>(layout::kRayRefraction, f, s);
}

TEST_CASE("raygen: shadow rays start at the light and stop just short of the surface") {
  LightDesc light;
  light.position = {0, 4, 0};
  Fixture f(test::Diffuse("m", glm::vec3(0.5f)), light);
  const auto rays = RaygenShadow(f, {f.Surface({0, 0, 3}, {0, 1, 0}, {0, -1, 0})});
  REQUIRE(rays.flags.size() == 1);
  REQUIRE(rays.flags[0] == 1);
  const layout::Ray& r = rays.rays[0];
  CHECK(Xyz(r.origin_tmin) == glm::vec3(0, 4, 0));               // eq. 3.1
  CHECK(r.direction_tmax.y == doctest::Approx(-0.8f));           // eq. 3.2: (p - l) / |p - l| = (0,-4,3)/5
  CHECK(r.direction_tmax.z == doctest::Approx(0.6f));
  CHECK(r.direction_tmax.w == 5.0f * kShadowTmaxFactor);
  CHECK(r.info.z == layout::kRayShadow);
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

TEST_CASE("raygen: a slot without a surface (a background pixel) gets no ray of any kind") {
  LightDesc light;
  light.position = {0, 4, 0};
  MaterialDesc glass = test::Diffuse("m", glm::vec3(0.5f));
  glass.reflectivity = 0.5f;  // every kind of ray, had the slot a surface
  glass.transparency = 0.5f;
  glass.ior = 1.5f;
  Fixture f(glass, light);
  layout::Surface none = f.Surface({0, 0, 3}, {0, 1, 0}, {0, -1, 0});
  none.position.w = 0.0f;  // what surfaces writes for a pixel no triangle covers
  for (const SparseRays& rays : {RaygenShadow(f, none), RaygenReflection(f, none), RaygenRefraction(f, none)}) {
    REQUIRE(rays.flags.size() == 1);
    CHECK(rays.flags[0] == 0u);
    CHECK(Xyz(rays.rays[0].direction_tmax) == glm::vec3(0.0f));
  }
}

// The kernels and the passes spawn no ray along a degenerate direction (zero length, or NaN): the
// reflection of a zero incoming direction is zero, a NaN incoming direction reflects and refracts
// into NaN. The material would spawn one along any other direction.
TEST_CASE("raygen: a zero or NaN direction spawns no reflection or refraction ray") {
  MaterialDesc m = test::Diffuse("glass mirror", glm::vec3(0.1f));
  m.reflectivity = 0.5f;
  m.transparency = 0.5f;
  m.ior = 1.5f;
  Fixture f(m);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto zero = RaygenReflection(f, {f.Surface({0, 0, 0}, {0, 1, 0}, {0, 0, 0})});
  CHECK(zero.flags[0] == 0u);
  for (const SparseRays& rays : {RaygenReflection(f, {f.Surface({0, 0, 0}, {0, 1, 0}, {nan, -1, 0})}),
                                 RaygenRefraction(f, {f.Surface({0, 0, 0}, {0, 1, 0}, {nan, -1, 0})})})
    CHECK(rays.flags[0] == 0u);
  // The same surface with a proper incoming direction spawns both.
  CHECK(RaygenReflection(f, {f.Surface({0, 0, 0}, {0, 1, 0}, {0, -1, 0})}).flags[0] == 1u);
  CHECK(RaygenRefraction(f, {f.Surface({0, 0, 0}, {0, 1, 0}, {0, -1, 0})}).flags[0] == 1u);
}
