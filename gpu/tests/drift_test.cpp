// The element functions that must agree bit for bit between GLSL and C++ (the cone-sphere test, the
// watertight ray-triangle test, the hash keys, the cone build) are written twice: once in
// gpu/shaders/*.glsl, once in emu/. These tests feed both many random and extreme inputs through their
// real passes and demand equal bits, so the two cannot drift apart unseen; a planted fault in each
// kernel shows the comparison can fail.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/gpu/passes.h"

namespace rayspace {
namespace {

using Rng = std::mt19937;

std::unique_ptr<gpu_backend::VulkanPasses> MakeGpu(const gpu_backend::Faults& faults = {}) {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  const vk::Status st = gpu_backend::VulkanPasses::Create(-1, faults, gpu);
  INFO("Vulkan: " << st.message);
  REQUIRE(st);  // the build has Vulkan and the bootstrap installs lavapipe
  return gpu;
}

// A float spread over many binades: sign, exponent in [lo, hi], random mantissa.
float Wide(Rng& rng, int lo, int hi) {
  std::uniform_int_distribution<int> e(lo, hi);
  std::uniform_real_distribution<float> m(1.0f, 2.0f);
  return (rng() & 1 ? -1.0f : 1.0f) * std::ldexp(m(rng), e(rng));
}

glm::vec3 UnitDir(Rng& rng) {
  std::normal_distribution<float> n;
  glm::vec3 d(n(rng), n(rng), n(rng));
  if (rng() % 8 == 0) d = glm::vec3(1.0f, std::ldexp(n(rng), -20), std::ldexp(n(rng), -20));  // near an axis
  return emu::Normalize(d);
}

layout::Ray MakeRay(Rng& rng, float scale, std::uint32_t id) {
  layout::Ray r{};
  const glm::vec3 o(Wide(rng, -4, 4) * scale, Wide(rng, -4, 4) * scale, Wide(rng, -4, 4) * scale);
  r.origin_tmin = glm::vec4(o, rng() % 4 == 0 ? std::ldexp(1.0f, -10) : 0.0f);
  r.direction_tmax = glm::vec4(UnitDir(rng), rng() % 3 == 0 ? std::ldexp(1.0f, 3) * scale : std::numeric_limits<float>::infinity());
  r.info = glm::uvec4(id, 0xFFFFFFFFu, rng() % 3, rng() % 5);
  return r;
}

// Leaves of 1..12 random rays around a few centres (realistic cones), plus extreme hand-made nodes.
std::vector<layout::ConeNode> Nodes(Rng& rng, std::size_t count) {
  std::vector<layout::Ray> rays;
  std::vector<std::uint32_t> order, first{0};
  while (first.size() <= count) {
    const std::uint32_t n = 1 + rng() % 12;
    const float scale = std::ldexp(1.0f, static_cast<int>(rng() % 9) - 4);
    for (std::uint32_t j = 0; j < n; ++j) {
      order.push_back(static_cast<std::uint32_t>(rays.size()));
      rays.push_back(MakeRay(rng, scale, static_cast<std::uint32_t>(rays.size())));
    }
    first.push_back(static_cast<std::uint32_t>(order.size()));
  }
  std::vector<layout::ConeNode> nodes = emu::PassBuildLeaves({.rays = rays, .order = order, .first = first});
  layout::ConeNode full{};
  full.sphere = glm::vec4(1.0f, 2.0f, 3.0f, 4.0f);
  full.cone = glm::vec4(0.0f, 0.0f, 1.0f, -1.0f);
  nodes.push_back(full);
  layout::ConeNode thin{};  // a zero-radius, near-zero-angle cone
  thin.sphere = glm::vec4(0.0f, 0.0f, 0.0f, 0.0f);
  thin.cone = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
  thin.extra = glm::vec4(std::ldexp(1.0f, -126), 1.0f, 0.0f, 0.0f);
  nodes.push_back(thin);
  layout::ConeNode denormal = thin;  // denormal radius and sine
  denormal.sphere.w = std::ldexp(1.0f, -140);
  denormal.extra.x = std::ldexp(1.0f, -135);
  nodes.push_back(denormal);
  return nodes;
}

std::vector<glm::vec4> Spheres(Rng& rng, std::size_t count) {
  std::vector<glm::vec4> s(count);
  for (glm::vec4& x : s) {
    const float scale = std::ldexp(1.0f, static_cast<int>(rng() % 13) - 6);
    const int kind = static_cast<int>(rng() % 6);
    const float r = kind == 0 ? 0.0f : kind == 1 ? std::ldexp(1.0f, -140) : std::fabs(Wide(rng, -8, 2)) * scale;
    x = glm::vec4(Wide(rng, -3, 3) * scale, Wide(rng, -3, 3) * scale, Wide(rng, -3, 3) * scale, r);
  }
  return s;
}

struct TopCase {
  std::vector<layout::ConeNode> top;
  std::vector<glm::vec4> spheres;
  SceneBuffers scene;
  explicit TopCase(std::uint32_t seed) {
    Rng rng(seed);
    top = Nodes(rng, 300);
    spheres = Spheres(rng, 340);
    scene.triangles.resize(spheres.size());  // the top level reads the triangle count and, unmasked, nothing else
    scene.info.resize(spheres.size());
  }
  emu::call::TraverseTop Call(float eps) const {
    return {.top = top, .t0 = 0, .t1 = static_cast<std::uint32_t>(top.size()), .b0 = 0,
            .b1 = static_cast<std::uint32_t>(spheres.size()), .tri_spheres = spheres, .scene = &scene, .object_mask = {}, .eps = eps};
  }
};

std::size_t CountDiffering(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t d = a.size() != b.size() ? a.size() + b.size() : 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d += a[i] != b[i];
  return d;
}

TEST_CASE("drift: traverse.comp's cone-sphere test equals cone::Test on random and extreme nodes and spheres") {
  const TopCase tc(11);
  auto gpu = MakeGpu();
  for (const float eps : {0.0f, std::ldexp(1.0f, -20), 0.25f}) {
    CAPTURE(eps);
    const emu::call::TraverseTop call = tc.Call(eps);
    const emu::PairSlots expect = emu::PassTraverseTop(call);
    emu::PairSlots got;
    const vk::Status st = gpu->Run(call, got);
    INFO(st.message);
    REQUIRE(st);
    CHECK(CountDiffering(expect.flags, got.flags) == 0);
    CHECK(expect.values == got.values);
    // Both answers occur often: the comparison can tell a wrong test from a right one.
    const std::size_t met = std::count(expect.flags.begin(), expect.flags.end(), 1);
    CHECK(met > expect.flags.size() / 20);
    CHECK(met < expect.flags.size() - expect.flags.size() / 20);
  }
}

TEST_CASE("drift: a planted fault in traverse.comp's top level is seen by the cone-sphere comparison") {
  const TopCase tc(11);
  auto gpu = MakeGpu({{"traverse", 1}});  // the top level ignores the triangle sphere's radius
  const emu::call::TraverseTop call = tc.Call(0.0f);
  emu::PairSlots got;
  REQUIRE(gpu->Run(call, got));
  CHECK(CountDiffering(emu::PassTraverseTop(call).flags, got.flags) > 0);
}

// Rays from a grid of origins against triangles of a closed, shared-edge fan and random triangles:
// every (ray, triangle) pair is one final test.
struct IntersectCase {
  std::vector<layout::Ray> rays;
  std::vector<std::uint32_t> order, first1, pairs;
  SceneBuffers scene;
  explicit IntersectCase(std::uint32_t seed) {
    Rng rng(seed);
    for (std::uint32_t i = 0; i < 160; ++i) {
      layout::Ray r = MakeRay(rng, 1.0f, i);
      if (i % 4 == 0) {  // aimed at the fan's shared vertex and edges
        const glm::vec3 o(std::ldexp(static_cast<float>(i % 7), -2), std::ldexp(static_cast<float>(i % 5), -2), -2.0f);
        r.origin_tmin = glm::vec4(o, 0.0f);
        r.direction_tmax = glm::vec4(emu::Normalize(glm::vec3(0.0f, 0.0f, 0.0f) - o), std::numeric_limits<float>::infinity());
      }
      rays.push_back(r);
      order.push_back(i);
      first1.push_back(i);
    }
    first1.push_back(static_cast<std::uint32_t>(rays.size()));
    for (int k = 0; k < 8; ++k) {  // a fan around the origin in z = 0: edges and the apex shared
      const float a0 = static_cast<float>(k) * 0.785398f, a1 = static_cast<float>(k + 1) * 0.785398f;
      scene.triangles.push_back({glm::vec4(0.0f), glm::vec4(std::cos(a0), std::sin(a0), 0.0f, 0.0f),
                                 glm::vec4(std::cos(a1), std::sin(a1), 0.0f, 0.0f)});
    }
    for (int k = 0; k < 120; ++k) {
      const glm::vec3 c(Wide(rng, -3, 3), Wide(rng, -3, 3), Wide(rng, -3, 3));
      auto v = [&] { return glm::vec4(c + glm::vec3(Wide(rng, -4, 1), Wide(rng, -4, 1), Wide(rng, -4, 1)), 0.0f); };
      scene.triangles.push_back({v(), v(), v()});
    }
    for (std::uint32_t n = 0; n < rays.size(); ++n)
      for (std::uint32_t k = 0; k < scene.triangles.size(); ++k) pairs.push_back((n << layout::kPairTriangleBits) | k);
  }
};

TEST_CASE("drift: intersect.comp's watertight test equals the emulator's on random, shared-edge and finite-range rays") {
  const IntersectCase ic(23);
  for (const bool shadow : {false, true}) {
    CAPTURE(shadow);
    std::vector<std::uint64_t> eh(ic.rays.size(), emu::kMissPacked), gh = eh;
    std::vector<std::uint32_t> eo(ic.rays.size(), 0), go = eo, gt;
    emu::call::Intersect call{.pairs = ic.pairs, .first1 = ic.first1, .order = ic.order, .rays = ic.rays, .scene = &ic.scene};
    emu::call::Intersect gcall = call;
    call.hits = shadow ? nullptr : &eh;
    call.occluded = shadow ? &eo : nullptr;
    gcall.hits = shadow ? nullptr : &gh;
    gcall.occluded = shadow ? &go : nullptr;
    const std::vector<std::uint32_t> et = emu::PassIntersect(call);
    auto gpu = MakeGpu();
    const vk::Status st = gpu->Run(gcall, gt);
    INFO(st.message);
    REQUIRE(st);
    CHECK(gt == et);
    if (shadow) {
      CHECK(go == eo);
      CHECK(std::count(eo.begin(), eo.end(), 1u) > 20);
    } else {
      CHECK(gh == eh);  // distances and primitive ids, bit for bit
      CHECK(std::count(eh.begin(), eh.end(), emu::kMissPacked) < static_cast<std::ptrdiff_t>(eh.size()) - 20);
    }
  }
}

TEST_CASE("drift: a planted fault in intersect.comp's range check is seen by the ray-triangle comparison") {
  const IntersectCase ic(23);
  std::vector<std::uint64_t> eh(ic.rays.size(), emu::kMissPacked), gh = eh;
  std::vector<std::uint32_t> gt;
  emu::call::Intersect call{.pairs = ic.pairs, .first1 = ic.first1, .order = ic.order, .rays = ic.rays, .scene = &ic.scene,
                            .hits = &eh};
  emu::PassIntersect(call);
  call.hits = &gh;
  auto gpu = MakeGpu({{"intersect", 1}});  // tmin and tmax swapped
  REQUIRE(gpu->Run(call, gt));
  CHECK(gh != eh);
}

TEST_CASE("drift: hash.comp's keys equal the emulator's for every ray kind and extreme directions") {
  Rng rng(5);
  std::vector<layout::Ray> rays;
  for (std::uint32_t i = 0; i < 5000; ++i) rays.push_back(MakeRay(rng, 2.0f, i));
  for (const glm::vec3 d : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, -1, 0)}) {
    layout::Ray r = MakeRay(rng, 1.0f, static_cast<std::uint32_t>(rays.size()));
    r.direction_tmax = glm::vec4(d, 1.0f);
    rays.push_back(r);
  }
  SceneBuffers scene;
  scene.lo = glm::vec3(-40.0f);
  scene.hi = glm::vec3(40.0f);
  auto gpu = MakeGpu();
  auto faulty = MakeGpu({{"hash", 1}});  // the azimuth cell from the wrong coordinate pair
  for (const std::uint32_t quad : {0u, 64u}) {
    CAPTURE(quad);
    const emu::call::Hash call{.rays = rays, .scene = &scene, .quadtree_width = quad, .quadtree_depth = quad ? 6 : 0};
    const std::vector<std::uint32_t> expect = emu::PassHash(call);
    std::vector<std::uint32_t> got, planted;
    REQUIRE(gpu->Run(call, got));
    CHECK(got == expect);
    REQUIRE(faulty->Run(call, planted));
    if (!quad) CHECK(planted != expect);
  }
}

TEST_CASE("drift: build.comp's leaves and parents equal the emulator's cone build") {
  Rng rng(17);
  std::vector<layout::Ray> rays;
  for (std::uint32_t i = 0; i < 4000; ++i) rays.push_back(MakeRay(rng, std::ldexp(1.0f, static_cast<int>(i % 11) - 5), i));
  std::vector<std::uint32_t> order(rays.size());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), rng);
  const std::vector<std::uint32_t> first = emu::FixedGroups(rays.size(), 7), up = emu::FixedGroups(first.size() - 1, 5);
  const emu::call::BuildLeaves leaves{.rays = rays, .order = order, .first = first};
  const std::vector<layout::ConeNode> expect = emu::PassBuildLeaves(leaves);
  auto gpu = MakeGpu();
  std::vector<layout::ConeNode> got, got_up;
  REQUIRE(gpu->Run(leaves, got));
  REQUIRE(got.size() == expect.size());
  CHECK(std::memcmp(got.data(), expect.data(), got.size() * sizeof(layout::ConeNode)) == 0);
  const emu::call::BuildParents parents{.below = expect, .first = up};
  const std::vector<layout::ConeNode> expect_up = emu::PassBuildParents(parents);
  REQUIRE(gpu->Run(parents, got_up));
  REQUIRE(got_up.size() == expect_up.size());
  CHECK(std::memcmp(got_up.data(), expect_up.data(), got_up.size() * sizeof(layout::ConeNode)) == 0);
  auto faulty = MakeGpu({{"build", 1}});  // the float containment checks of each step are skipped
  std::vector<layout::ConeNode> planted;
  REQUIRE(faulty->Run(leaves, planted));
  CHECK(std::memcmp(planted.data(), expect.data(), planted.size() * sizeof(layout::ConeNode)) != 0);
}

}  // namespace
}  // namespace rayspace
