// Area lights (docs/area-lights.md): the sampler's known answers, the shapes' geometry, the slot
// layout of the shadow rays and the shading of the samples.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/light_sample.h"
#include "rayspace/emu/passes.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {
using Fixture = test::ShadingFixture;

LightDesc AreaLight(LightShape shape, int samples) {
  LightDesc l;
  l.shape = shape;
  l.position = {0, 4, 0};
  l.samples = samples;
  l.size = {2.0f, 1.0f};
  l.radius = 0.5f;
  return l;
}

// The kernels' light as FlattenScene makes it.
layout::Light Flat(const LightDesc& l) {
  Fixture f(test::Diffuse("m", glm::vec3(0.5f)), l);
  return f.b.lights[0];
}
}  // namespace

TEST_CASE("area lights: the unit circle polynomial is within 4e-7 of cos and sin everywhere") {
  double worst = 0;
  for (int i = 0; i <= 100000; ++i) {
    const float b = static_cast<float>(i) / 100000.0f;
    const glm::vec2 cs = layout::UnitCircle(b);
    const double a = 2.0 * std::numbers::pi * static_cast<double>(b);
    worst = std::max({worst, std::fabs(cs.x - std::cos(a)), std::fabs(cs.y - std::sin(a))});
  }
  CHECK(worst < 4e-7);
  // The quadrants: the axes are hit exactly.
  CHECK(layout::UnitCircle(0.0f) == glm::vec2(1.0f, 0.0f));
  CHECK(layout::UnitCircle(0.25f) == glm::vec2(-0.0f, 1.0f));
  CHECK(layout::UnitCircle(0.5f) == glm::vec2(-1.0f, -0.0f));
}

TEST_CASE("area lights: each sample lies in its own stratum, and the jitter depends on the point") {
  const std::uint32_t cols = 4, rows = 2;
  std::set<float> firsts;
  for (std::uint32_t key = 0; key < 2000; ++key) {
    for (std::uint32_t k = 0; k < cols * rows; ++k) {
      const glm::vec2 ab = layout::StratifiedPoint(key, 3, k, cols, 0.25f, 0.5f);
      INFO("key " << key << " sample " << k << " at " << ab.x << ", " << ab.y);
      CHECK(ab.x >= static_cast<float>(k % cols) / cols);
      CHECK(ab.x <= static_cast<float>(k % cols + 1) / cols);
      CHECK(ab.y >= static_cast<float>(k / cols) / rows);
      CHECK(ab.y <= static_cast<float>(k / cols + 1) / rows);
    }
    firsts.insert(layout::StratifiedPoint(key, 3, 0, cols, 0.25f, 0.5f).x);
  }
  CHECK(firsts.size() > 1900);  // 2,000 points draw (nearly) 2,000 different jitters
  // Another light at the same point draws other points.
  CHECK(layout::StratifiedPoint(7, 0, 0, cols, 0.25f, 0.5f) != layout::StratifiedPoint(7, 1, 0, cols, 0.25f, 0.5f));
}

TEST_CASE("area lights: stratification splits every point's samples evenly over the halves of the shape") {
  // 8 samples: a rect's 4 columns put 4 samples on each side of its centre line, a disk's 4 angular
  // strata 4 on each side of its first axis, for every shading point; uniform random samples would not.
  const layout::Light rect = Flat(AreaLight(LightShape::kRect, 8)), disk = Flat(AreaLight(LightShape::kDisk, 8));
  REQUIRE(rect.sampling.w == 4u);
  REQUIRE(disk.sampling.w == 2u);
  for (std::uint32_t key = 0; key < 500; ++key) {
    int rect_left = 0, disk_upper = 0;
    for (std::uint32_t k = 0; k < 8; ++k) {
      const glm::vec3 p = LightSamplePoint<float>(rect, 0, key, k), q = LightSamplePoint<float>(disk, 0, key, k);
      rect_left += Dot(p - Xyz(rect.position), Xyz(rect.axis_u)) <= 0.0f;
      disk_upper += Dot(q - Xyz(disk.position), Xyz(disk.axis_v)) >= 0.0f;
    }
    CHECK(rect_left == 4);
    CHECK(disk_upper == 4);
  }
}

TEST_CASE("area lights: samples lie on their shape, and average to its centre") {
  for (const LightShape shape : {LightShape::kRect, LightShape::kDisk, LightShape::kSphere}) {
    LightDesc d = AreaLight(shape, 8);
    d.normal = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    const layout::Light l = Flat(d);
    const glm::dvec3 c(d.position), n(d.normal);
    glm::dvec3 sum(0);
    const int keys = 4000;
    for (std::uint32_t key = 0; key < keys; ++key)
      for (std::uint32_t k = 0; k < 8; ++k) {
        const glm::dvec3 v = glm::dvec3(LightSamplePoint<float>(l, 0, key, k)) - c;
        sum += v;
        INFO("shape " << static_cast<int>(shape) << " key " << key << " sample " << k);
        if (shape == LightShape::kSphere) {
          CHECK(std::fabs(glm::length(v) - d.radius) < 1e-5);
          continue;
        }
        CHECK(std::fabs(glm::dot(v, n)) < 1e-5);  // in the shape's plane
        const glm::dvec3 u = glm::normalize(glm::dvec3(Xyz(l.axis_u))), w = glm::normalize(glm::dvec3(Xyz(l.axis_v)));
        if (shape == LightShape::kRect) {
          CHECK(std::fabs(glm::dot(v, u)) <= d.size.x / 2 + 1e-5);
          CHECK(std::fabs(glm::dot(v, w)) <= d.size.y / 2 + 1e-5);
        } else {
          CHECK(glm::length(v) <= d.radius + 1e-5);
        }
      }
    const glm::dvec3 mean = sum / (8.0 * keys);
    CHECK(glm::length(mean) < 0.01);
  }
}

TEST_CASE("area lights: a point light's one sample is its position, untouched") {
  LightDesc d;
  d.position = {0.1f, 3.7f, -2.3f};
  const layout::Light l = Flat(d);
  CHECK(l.sampling.y == 1u);
  CHECK(l.attenuation.w == 1.0f);
  for (std::uint32_t key : {0u, 1u, 12345u}) CHECK(LightSamplePoint<float>(l, 0, key, 0) == d.position);
}

TEST_CASE("area lights: shadow rays of a surface fill its slots light by light, sample by sample") {
  Scene scene;
  scene.camera.eye = {0, 3, 3};
  scene.camera.target = {0, 0, 0};
  scene.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  LightDesc point;
  point.position = {1, 5, 0};
  scene.lights = {AreaLight(LightShape::kRect, 8), point, AreaLight(LightShape::kSphere, 3)};
  test::AddQuad(scene, "floor", {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1});
  const SceneBuffers b = FlattenScene(scene);
  REQUIRE(ShadowSlots(b.lights) == 12u);
  CHECK(b.lights[1].sampling.z == 8u);
  CHECK(b.lights[2].sampling.z == 9u);
  const layout::FrameConstants fc = MakeFrameConstants(scene, b, 8, 8);
  Fixture f(test::Diffuse("m", glm::vec3(0.5f)));
  std::vector<layout::Surface> surfaces{f.Surface({0, 0, 0}, {0, 1, 0}, {0, -1, 0}), f.Surface({0.5f, 0, 0}, {0, 1, 0}, {0, -1, 0})};
  surfaces[1].info = glm::uvec4(1, 9, 0, 0);
  const SparseRays rays = PassRaygenShadow({.kind = layout::kRayShadow, .frame = fc, .surfaces = surfaces, .scene = &b});
  REQUIRE(rays.rays.size() == 24u);
  for (std::size_t s = 0; s < 2; ++s)
    for (std::size_t j = 0; j < 12; ++j) {
      const layout::Ray& r = rays.rays[s * 12 + j];
      const std::uint32_t light = j < 8 ? 0u : (j == 8 ? 1u : 2u);
      INFO("surface " << s << " slot " << j);
      REQUIRE(rays.flags[s * 12 + j] == 1u);
      CHECK(r.info.w == light);
      CHECK(r.info.x == surfaces[s].info.y);
      // The ray runs from its sample to just short of the surface.
      const glm::vec3 o = Xyz(r.origin_tmin), end = o + Xyz(r.direction_tmax) * (r.direction_tmax.w / kShadowTmaxFactor);
      CHECK(glm::length(end - Xyz(surfaces[s].position)) < 1e-5f);
      if (light == 1) CHECK(o == point.position);
      if (light == 0) CHECK(o.y == doctest::Approx(4.0f));  // the rect faces down at y = 4
    }
  // The two surfaces draw different points of the rect.
  CHECK(Xyz(rays.rays[0].origin_tmin) != Xyz(rays.rays[12].origin_tmin));
}


TEST_CASE("area lights: a small light shades as the point at its centre, and each sample carries 1/N") {
  LightDesc point;
  point.position = {0, 4, 0};
  LightDesc small = AreaLight(LightShape::kDisk, 8);
  small.radius = 1e-3f;
  const Fixture fp(test::Diffuse("m", glm::vec3(0.5f)), point), fa(test::Diffuse("m", glm::vec3(0.5f)), small);
  const layout::Surface s = fp.Surface({0, 0, 0}, {0, 1, 0}, glm::normalize(glm::vec3(0, -1, -1)));
  const glm::vec3 cp = fp.Shade(s, {0u});
  const glm::vec3 ca = fa.Shade(s, std::vector<std::uint32_t>(8, 0u));
  CHECK(cp.x > 0.0f);
  CHECK(ca.x == doctest::Approx(cp.x).epsilon(1e-5));
  // Three samples in shadow: five eighths of the light.
  const glm::vec3 partial = fa.Shade(s, {0u, 1u, 0u, 1u, 0u, 0u, 1u, 0u});
  CHECK(partial.x == doctest::Approx(cp.x * 5.0 / 8.0).epsilon(1e-5));
}
