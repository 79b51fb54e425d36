// The multi-lane cone-sphere test (emu/cone_simd.h), on every instruction set this CPU runs, against
// the scalar cone::Test, item by item: one node against many spheres and many nodes against one
// sphere, on random inputs and on the special values the scalar test handles (NaN and infinite
// coordinates, a sphere at the apex, full and wide cones, denormal and huge scales), and on the
// boundary radius of random configurations.
#include <doctest/doctest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

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


const cone::Isa kVector[] = {cone::Isa::kAvx2, cone::Isa::kAvx512};

glm::vec4 RandomSphere(std::mt19937& rng, float scale, const layout::ConeNode& n) {
  if (rng() % 32 == 0) return glm::vec4(glm::vec3(n.sphere), 0.0f);  // at the apex
  return glm::vec4(Pick(rng, scale), Pick(rng, scale), Pick(rng, scale), std::fabs(Pick(rng, scale * 0.2f)));
}

// Which of items [i0, i1) the call wrote, as a bit per item, from the values it wrote (item i
// writes 7 + (i << 3)); also checks they come in item order.
std::vector<bool> Written(const std::uint32_t* out, std::size_t count, std::uint32_t i0, std::uint32_t i1) {
  std::vector<bool> bits(i1 - i0, false);
  std::uint32_t last = 0;
  for (std::size_t j = 0; j < count; ++j) {
    const std::uint32_t i = (out[j] - 7u) >> 3;
    REQUIRE((out[j] - 7u) % 8u == 0u);
    REQUIRE(i >= i0);
    REQUIRE(i < i1);
    REQUIRE((j == 0 || i > last));
    bits[i - i0] = true;
    last = i;
  }
  return bits;
}

std::string Describe(const layout::ConeNode& n, glm::vec4 s, float eps) {
  std::ostringstream o;
  o << std::hexfloat << "node (" << n.sphere.x << ", " << n.sphere.y << ", " << n.sphere.z << ", " << n.sphere.w << ") cone ("
    << n.cone.x << ", " << n.cone.y << ", " << n.cone.z << ", " << n.cone.w << ", " << n.extra.x << ") sphere (" << s.x << ", "
    << s.y << ", " << s.z << ", " << s.w << ") eps " << eps;
  return o.str();
}

}  // namespace

TEST_CASE("cone simd: one node against many spheres, every lane the scalar test's answer") {
  std::mt19937 rng(99);
  for (const cone::Isa isa : kVector) {
    if (!cone::Runs(isa)) {
      MESSAGE("this CPU lacks " << cone::IsaName(isa));
      continue;
    }
    CAPTURE(cone::IsaName(isa));
    std::size_t items = 0, accepted = 0;
    for (int iter = 0; iter < 40000; ++iter) {
      const float scale = std::array{1.0f, 1e-30f, 1e30f, 1000.0f}[rng() % 4];
      const layout::ConeNode n = RandomNode(rng, scale);
      const float eps = rng() % 4 == 0 ? 0.0f : std::fabs(Pick(rng, scale * 1e-6f));
      std::vector<glm::vec4> spheres(40);
      for (auto& sp : spheres) sp = RandomSphere(rng, scale, n);
      const cone::SphereArrays arrays = cone::ToArrays(spheres);
      // A run that starts and ends inside lane groups.
      const std::uint32_t i0 = rng() % 9, i1 = i0 + 1 + rng() % (40 - i0);
      std::uint32_t out[40 + cone::kLanePad];
      const std::vector<bool> got = Written(out, cone::TestSpheres(isa, n, arrays, i0, i1, eps, 7u, 3, out), i0, i1);
      for (std::uint32_t i = i0; i < i1; ++i) {
        const bool scalar = cone::Test(n, spheres[i], eps);
        ++items;
        accepted += scalar;
        if (got[i - i0] != scalar) FAIL("sphere " << i << " differs: " << Describe(n, spheres[i], eps) << ": scalar " << scalar);
      }
    }
    // Both answers occur often enough for the comparison to mean something.
    CHECK(accepted > items / 10);
    CHECK(accepted < items * 9 / 10);
  }
}

TEST_CASE("cone simd: many nodes against one sphere, every lane the scalar test's answer") {
  std::mt19937 rng(5);
  for (const cone::Isa isa : kVector) {
    if (!cone::Runs(isa)) continue;
    CAPTURE(cone::IsaName(isa));
    std::size_t items = 0, accepted = 0;
    for (int iter = 0; iter < 40000; ++iter) {
      const float scale = std::array{1.0f, 1e-30f, 1e30f, 1000.0f}[rng() % 4];
      std::vector<layout::ConeNode> nodes(24);
      for (auto& n : nodes) n = RandomNode(rng, scale);
      const glm::vec4 sphere = RandomSphere(rng, scale, nodes[rng() % nodes.size()]);
      const float eps = rng() % 4 == 0 ? 0.0f : std::fabs(Pick(rng, scale * 1e-6f));
      const cone::NodeArrays arrays = cone::ToArrays(nodes);
      const std::uint32_t k0 = rng() % 9, k1 = k0 + 1 + rng() % (24 - k0);
      std::uint32_t out[24 + cone::kLanePad];
      const std::vector<bool> got = Written(out, cone::TestNodes(isa, arrays, sphere, k0, k1, eps, 7u, 3, out), k0, k1);
      for (std::uint32_t k = k0; k < k1; ++k) {
        const bool scalar = cone::Test(nodes[k], sphere, eps);
        ++items;
        accepted += scalar;
        if (got[k - k0] != scalar) FAIL("node " << k << " differs: " << Describe(nodes[k], sphere, eps) << ": scalar " << scalar);
      }
    }
    CHECK(accepted > items / 10);
    CHECK(accepted < items * 9 / 10);
  }
}

TEST_CASE("cone simd: on the boundary found by bisection, every lane still agrees") {
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
    std::vector<glm::vec4> spheres(16);
    for (std::uint32_t i = 0; i < 16; ++i) spheres[i] = glm::vec4(c, std::bit_cast<float>(hi - 8 + i));
    const cone::SphereArrays arrays = cone::ToArrays(spheres);
    for (const cone::Isa isa : kVector) {
      if (!cone::Runs(isa)) continue;
      std::uint32_t out[16 + cone::kLanePad];
      const std::vector<bool> got = Written(out, cone::TestSpheres(isa, n, arrays, 0, 16, 0.0f, 7u, 3, out), 0, 16);
      for (std::uint32_t i = 0; i < 16; ++i) {
        ++compared;
        REQUIRE(got[i] == accepts(spheres[i].w));
      }
    }
  }
  CHECK(compared > 16000);
}

TEST_CASE("cone simd: a level's pairs (two per test where each has at most eight children) give the scalar loop's output") {
  std::mt19937 rng(31);
  for (const cone::Isa isa : kVector) {
    if (!cone::Runs(isa)) continue;
    CAPTURE(cone::IsaName(isa));
    for (int iter = 0; iter < 3000; ++iter) {
      const float scale = std::array{1.0f, 1e-30f, 1e30f, 1000.0f}[rng() % 4];
      // Parents with 0 to 12 children: pairs of at most eight share a test, larger ones run alone.
      std::vector<std::uint32_t> first{0};
      while (first.size() < 12) first.push_back(first.back() + (rng() % 6 == 0 ? 9 + rng() % 4 : rng() % 9));
      std::vector<layout::ConeNode> nodes(first.back());
      for (auto& n : nodes) n = RandomNode(rng, scale);
      std::vector<glm::vec4> spheres(20);
      for (auto& s : spheres) s = RandomSphere(rng, scale, nodes.empty() ? RandomNode(rng, scale) : nodes[rng() % nodes.size()]);
      const std::uint32_t base_up = 1, base = rng() % 3;  // ids relative to a level's first node
      std::vector<std::uint32_t> pairs(1 + rng() % 24);
      for (auto& p : pairs) p = ((1 + rng() % 10 - base_up) << layout::kPairTriangleBits) | (rng() % 20);
      const float eps = rng() % 4 == 0 ? 0.0f : std::fabs(Pick(rng, scale * 1e-6f));
      const cone::NodeArrays arrays = cone::ToArrays(nodes);
      const cone::PairLevel lv{pairs, first, base_up, base, spheres.data()};
      std::vector<std::uint32_t> out(nodes.size() * pairs.size() + cone::kLanePad), expect(out.size());
      std::uint64_t tested = 0, expect_tested = 0;
      const std::size_t p0 = rng() % 2, n = cone::TestPairs(isa, arrays, lv, p0, pairs.size(), eps, out.data(), tested);
      const std::size_t m = cone::TestPairs(cone::Isa::kScalar, arrays, lv, p0, pairs.size(), eps, expect.data(), expect_tested);
      REQUIRE(tested == expect_tested);
      REQUIRE(n == m);
      for (std::size_t i = 0; i < n; ++i) REQUIRE(out[i] == expect[i]);
    }
  }
}
