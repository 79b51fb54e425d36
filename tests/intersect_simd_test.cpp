// The final tests eight rays at a time (emu/intersect_simd.h) against PassIntersect, the scalar
// watertight test the kernels mirror: the same closest hits (distance bits and primitive) and the
// same occlusion for every ray, the same test counts, on rays aimed at triangles' vertices, edge
// midpoints and interiors (the watertight boundary), axis-aligned and degenerate directions, tiny
// and huge scales, degenerate triangles, NaN and infinite coordinates, and rays that leave a triangle
// of the batch.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/intersect_simd.h"
#include "test_settings.h"

using namespace rayspace;

namespace {

struct Case {
  SceneBuffers scene;
  std::vector<layout::Ray> rays;
  std::vector<std::uint32_t> order, first1, pairs;
};

glm::vec3 RandomPoint(std::mt19937& rng, float scale) {
  std::uniform_real_distribution<float> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

// A point of triangle t that stresses the test: a vertex, an edge midpoint or an interior point.
glm::vec3 Target(std::mt19937& rng, const layout::Triangle& t) {
  const glm::vec3 a = emu::Xyz(t.v0), b = emu::Xyz(t.v1), c = emu::Xyz(t.v2);
  switch (rng() % 4) {
    case 0: return std::array{a, b, c}[rng() % 3];
    case 1: return (a + b) * 0.5f;
    case 2: return (b + c) * 0.5f;
    default: {
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      const float x = u(rng), y = u(rng) * (1.0f - x);
      return a + (b - a) * x + (c - a) * y;
    }
  }
}

layout::Triangle RandomTriangle(std::mt19937& rng, float scale) {
  const glm::vec3 a = RandomPoint(rng, scale), b = rng() % 16 == 0 ? a : RandomPoint(rng, scale);  // some degenerate
  const glm::vec3 c = rng() % 16 == 0 ? (a + b) * 0.5f : RandomPoint(rng, scale);
  layout::Triangle t{glm::vec4(a, 0), glm::vec4(b, 0), glm::vec4(c, 0)};
  if (rng() % 32 == 0) t.v1[rng() % 3] = std::array{NAN, INFINITY, -INFINITY}[rng() % 3];  // GLSL's max rule on NaN
  return t;
}

layout::Ray RandomRay(std::mt19937& rng, const Case& k, float scale) {
  const std::uint32_t T = static_cast<std::uint32_t>(k.scene.triangles.size());
  glm::vec3 o = RandomPoint(rng, 2.0f * scale);
  if (rng() % 64 == 0) o[rng() % 3] = NAN;
  glm::vec3 d = Target(rng, k.scene.triangles[rng() % T]) - o;
  if (rng() % 8 == 0) d[rng() % 3] = 0.0f;                    // axis-aligned components
  if (rng() % 64 == 0) d = glm::vec3(0.0f);                  // no direction at all
  const float tmin = rng() % 2 ? 0.0f : 1e-3f, tmax = rng() % 4 == 0 ? 0.5f : INFINITY;
  const std::uint32_t leaves = rng() % 8 == 0 ? rng() % T : ~0u;  // the surface the ray leaves
  return {glm::vec4(o, tmin), glm::vec4(d, tmax), glm::uvec4(0, leaves, 0, 0), glm::vec4(1)};
}

Case RandomCase(std::mt19937& rng) {
  Case k;
  const float scale = std::array{1.0f, 1e-12f, 1e12f, 300.0f}[rng() % 4];
  const std::uint32_t T = 1 + rng() % 40;
  for (std::uint32_t t = 0; t < T; ++t) k.scene.triangles.push_back(RandomTriangle(rng, scale));
  // Leaves of 1 to 20 rays (most below 8, as in a frame, some spanning several lane groups).
  k.first1.push_back(0);
  while (k.first1.size() < 40) k.first1.push_back(k.first1.back() + 1 + rng() % (rng() % 4 == 0 ? 20 : 8));
  const std::uint32_t R = k.first1.back();
  for (std::uint32_t r = 0; r < R; ++r) k.rays.push_back(RandomRay(rng, k, scale));
  k.order.resize(R);
  std::iota(k.order.begin(), k.order.end(), 0u);
  std::shuffle(k.order.begin(), k.order.end(), rng);
  // Pairs in a frame's order: the children of a parent (1 to 4 adjacent nodes) per triangle, so
  // that consecutive pairs of one triangle with adjacent rays form runs, broken where a child failed.
  const std::uint32_t nodes = static_cast<std::uint32_t>(k.first1.size() - 1);
  for (std::uint32_t p0 = 0, p1; p0 < nodes; p0 = p1) {
    p1 = std::min(nodes, p0 + 1 + static_cast<std::uint32_t>(rng() % 4));
    for (std::uint32_t t = 0; t < T; ++t)
      if (rng() % 3 == 0)
        for (std::uint32_t n = p0; n < p1; ++n)
          if (rng() % 3 != 0) k.pairs.push_back((n << layout::kPairTriangleBits) | t);
  }
  return k;
}

struct Outcome {
  std::uint64_t tests = 0;  // the per-pair tests summed: all the lanes return
  std::vector<std::uint32_t> occluded;
  std::vector<std::uint64_t> hits;
};

Outcome Run(const Case& k, bool lanes, bool shadow) {
  Outcome o;
  o.hits.assign(k.rays.size(), emu::kMissPacked);
  o.occluded.assign(k.rays.size(), 0u);
  const emu::call::Intersect c{.pairs = k.pairs, .first1 = k.first1, .base1 = 0, .b0 = 0, .order = k.order, .rays = k.rays,
                          .scene = &k.scene, .hits = shadow ? nullptr : &o.hits, .occluded = shadow ? &o.occluded : nullptr};
  if (lanes) {
    o.tests = emu::IntersectLanes(c, emu::ToWatertightArrays(k.rays, k.order));
  } else {
    for (const std::uint32_t t : emu::PassIntersect(c)) o.tests += t;
  }
  return o;
}

}  // namespace

TEST_CASE("intersect simd: many rays at a time give the scalar test's hits, occlusion and counts, on every instruction set") {
  rayspace::test::TestSettings settings;
  for (const emu::cone::Isa isa : {emu::cone::Isa::kAvx2, emu::cone::Isa::kAvx512}) {
    if (!emu::cone::Runs(isa)) {
      MESSAGE("this CPU lacks " << emu::cone::IsaName(isa));
      continue;
    }
    CAPTURE(emu::cone::IsaName(isa));
    settings->intersect_isa = isa;
    std::mt19937 rng(4242);
    std::size_t rays = 0, hit = 0;
    for (int iter = 0; iter < 3000; ++iter) {
      const Case k = RandomCase(rng);
      const bool shadow = iter % 2 == 1;
      const Outcome scalar = Run(k, false, shadow), lanes = Run(k, true, shadow);
      REQUIRE(lanes.tests == scalar.tests);
      for (std::size_t r = 0; r < k.rays.size(); ++r) {
        ++rays;
        hit += shadow ? scalar.occluded[r] : scalar.hits[r] != emu::kMissPacked;
        if (lanes.hits[r] != scalar.hits[r] || lanes.occluded[r] != scalar.occluded[r])
          FAIL("ray " << r << " of case " << iter << (shadow ? " (shadow)" : "") << ": scalar hit " << scalar.hits[r] << " occluded "
                      << scalar.occluded[r] << ", lanes " << lanes.hits[r] << " / " << lanes.occluded[r]);
      }
    }
    settings->intersect_isa = emu::cone::BestIsa();
    // Both outcomes occur often enough for the comparison to mean something.
    CHECK(hit > rays / 10);
    CHECK(hit < rays * 9 / 10);
  }
}

TEST_CASE("intersect simd: the scalar fallback is PassIntersect") {
  rayspace::test::TestSettings settings;
  std::mt19937 rng(17);
  const Case k = RandomCase(rng);
  settings->intersect_isa = emu::cone::Isa::kScalar;
  const Outcome off = Run(k, true, false);
  settings->intersect_isa = emu::cone::BestIsa();
  CHECK(off.hits == Run(k, false, false).hits);
}
