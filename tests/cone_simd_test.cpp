// The eight-lane cone-sphere test (emu/cone_simd.h) against the scalar cone::Test, lane by lane, on
// random nodes and spheres and on the special values the scalar test handles: NaN and infinite
// coordinates, a sphere at the apex, full and wide cones, denormal and huge scales.
#include <doctest/doctest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/cone_simd.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

float Pick(std::mt19937& rng, float scale) {
  static const float kSpecial[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), INFINITY, -INFINITY,
                                   0x1p-140f, 0x1p62f, std::numeric_limits<float>::max()};
  if (rng() % 16 == 0) return kSpecial[rng() % 10];
  return std::uniform_real_distribution<float>(-scale, scale)(rng);
}

layout::ConeNode RandomNode(std::mt19937& rng, float scale) {
  layout::ConeNode n{};
  n.sphere = glm::vec4(Pick(rng, scale), Pick(rng, scale), Pick(rng, scale), std::fabs(Pick(rng, scale * 0.1f)));
  const glm::vec3 axis = Normalize(glm::vec3(Pick(rng, 1), Pick(rng, 1), Pick(rng, 1)));
  const float angle = std::uniform_real_distribution<float>(0.0f, 3.3f)(rng);  // past pi: a full node
  n.cone = glm::vec4(axis, std::cos(angle));
  n.extra = glm::vec4(std::sin(angle), 1, 0, 0);
  if (rng() % 8 == 0) n.cone.w = -1.0f;  // full
  return n;
}

}  // namespace

TEST_CASE("cone simd: eight lanes give the scalar test's answer on every lane") {
  if (!cone::HaveSimdTest()) {
    MESSAGE("no AVX2 on this CPU: the fused path runs the scalar test");
    return;
  }
  std::mt19937 rng(99);
  std::size_t lanes = 0, accepted = 0;
  for (int iter = 0; iter < 200000; ++iter) {
    const float scale = std::array{1.0f, 1e-30f, 1e30f, 1000.0f}[rng() % 4];
    const layout::ConeNode n = RandomNode(rng, scale);
    const float eps = rng() % 4 == 0 ? 0.0f : std::fabs(Pick(rng, scale * 1e-6f));
    cone::SphereLanes s;
    glm::vec4 spheres[8];
    for (int i = 0; i < 8; ++i) {
      spheres[i] = glm::vec4(Pick(rng, scale), Pick(rng, scale), Pick(rng, scale), std::fabs(Pick(rng, scale * 0.2f)));
      if (rng() % 32 == 0) spheres[i] = glm::vec4(glm::vec3(n.sphere), 0.0f);  // at the apex
      s.x[i] = spheres[i].x;
      s.y[i] = spheres[i].y;
      s.z[i] = spheres[i].z;
      s.r[i] = spheres[i].w;
    }
    const std::uint32_t bits = cone::TestEight(n, s, eps);
    for (int i = 0; i < 8; ++i) {
      const bool scalar = cone::Test(n, spheres[i], eps);
      ++lanes;
      accepted += scalar;
      if (((bits >> i) & 1u) != static_cast<std::uint32_t>(scalar)) {
        FAIL("lane " << i << " differs: node (" << n.sphere.x << ", " << n.sphere.y << ", " << n.sphere.z << ", " << n.sphere.w
                     << ") cone (" << n.cone.x << ", " << n.cone.y << ", " << n.cone.z << ", " << n.cone.w << ", " << n.extra.x
                     << ") sphere (" << spheres[i].x << ", " << spheres[i].y << ", " << spheres[i].z << ", " << spheres[i].w
                     << ") eps " << eps << ": scalar " << scalar);
      }
    }
  }
  // Both answers occur often enough for the comparison to mean something.
  CHECK(accepted > lanes / 10);
  CHECK(accepted < lanes * 9 / 10);
}

TEST_CASE("cone simd: on the boundary found by bisection, every lane still agrees") {
  if (!cone::HaveSimdTest()) return;
  // For random nodes and sphere centres, the smallest radius the scalar test accepts, found by
  // bisection over the floats; lanes just below, on and above it. A lane computing any step
  // differently (another slack, another order) moves its boundary and disagrees there.
  std::mt19937 rng(7);
  std::size_t compared = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    layout::ConeNode n = RandomNode(rng, 100.0f);
    n.sphere = glm::vec4(Pick(rng, 10.0f), Pick(rng, 10.0f), Pick(rng, 10.0f), 0.5f);
    const glm::vec3 c(std::uniform_real_distribution<float>(-100, 100)(rng), std::uniform_real_distribution<float>(-100, 100)(rng),
                      std::uniform_real_distribution<float>(-100, 100)(rng));
    if (!std::isfinite(n.sphere.x + n.sphere.y + n.sphere.z) || cone::IsFull(n)) continue;
    auto accepts = [&](float r) { return cone::Test(n, glm::vec4(c, r), 0.0f); };
    if (accepts(0.0f) || !accepts(1000.0f)) continue;
    std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1000.0f);
    while (hi - lo > 1) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      (accepts(std::bit_cast<float>(mid)) ? hi : lo) = mid;
    }
    cone::SphereLanes s;
    for (int i = 0; i < 8; ++i) {
      s.x[i] = c.x;
      s.y[i] = c.y;
      s.z[i] = c.z;
      s.r[i] = std::bit_cast<float>(hi - 4 + static_cast<std::uint32_t>(i));
    }
    const std::uint32_t bits = cone::TestEight(n, s, 0.0f);
    for (int i = 0; i < 8; ++i) {
      ++compared;
      REQUIRE(((bits >> i) & 1u) == static_cast<std::uint32_t>(accepts(s.r[i])));
    }
  }
  CHECK(compared > 8000);
}
