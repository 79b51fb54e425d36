// Hierarchy build: leaf nodes hold their rays, parents hold their children.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

glm::dvec3 RandomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  glm::dvec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

// A random direction at angle <= alpha from axis.
glm::dvec3 InCone(std::mt19937& rng, glm::dvec3 axis, double alpha) {
  std::uniform_real_distribution<double> u(0, 1);
  const double a = alpha * u(rng);
  glm::dvec3 p = glm::cross(axis, RandomUnit(rng));
  p = glm::normalize(p);
  return glm::normalize(axis * std::cos(a) + p * std::sin(a));
}

double Angle(glm::dvec3 a, glm::dvec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }
double HalfAngle(const layout::ConeNode& n) { return std::atan2(static_cast<double>(n.extra.x), static_cast<double>(n.cone.w)); }

}  // namespace

TEST_CASE("cone: leaf nodes hold their rays and parents hold their children (randomized, in double)") {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1), spread(0, 1);
  int full = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Children: leaves over 8 rays with origins in a small cloud and directions in a random cone,
    // including near-identical, antiparallel and wide configurations.
    const int mode = trial % 4;
    std::vector<layout::ConeNode> kids;
    const glm::dvec3 base_axis = RandomUnit(rng);
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 axis = mode == 2 && k % 2 ? -base_axis : (mode == 3 ? RandomUnit(rng) : InCone(rng, base_axis, 0.2));
      const double alpha = mode == 0 ? 1e-4 * spread(rng) : 0.5 * spread(rng);
      const glm::dvec3 centre(u(rng) * 10, u(rng) * 10, u(rng) * 10);
      std::vector<layout::Ray> rays(8);
      for (auto& r : rays) {
        r.origin_tmin = glm::vec4(glm::vec3(centre + glm::dvec3(u(rng), u(rng), u(rng)) * 0.1), 0);
        r.direction_tmax = glm::vec4(glm::vec3(InCone(rng, axis, alpha)), 1);
      }
      const layout::ConeNode leaf = cone::LeafNode(8, [&](std::uint32_t j) -> const layout::Ray& { return rays[j]; });
      for (const auto& r : rays) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(r.direction_tmax));
        if (!cone::IsFull(leaf)) CHECK(Angle(glm::dvec3(leaf.cone), d) <= HalfAngle(leaf));
        CHECK(glm::length(glm::dvec3(r.origin_tmin) - glm::dvec3(leaf.sphere)) <= leaf.sphere.w);
      }
      kids.push_back(leaf);
    }
    const layout::ConeNode parent = cone::ParentNode(kids.data(), static_cast<std::uint32_t>(kids.size()));
    if (cone::IsFull(parent)) {
      ++full;
    } else {
      for (const auto& k : kids) {
        INFO("trial " << trial);
        CHECK(Angle(glm::dvec3(parent.cone), glm::dvec3(k.cone)) + HalfAngle(k) <= HalfAngle(parent));
      }
    }
    for (const auto& k : kids)
      CHECK(glm::length(glm::dvec3(k.sphere) - glm::dvec3(parent.sphere)) + k.sphere.w <= parent.sphere.w);
  }
  CHECK(full > 0);     // antiparallel children really produce the whole sphere
  CHECK(full < 2000);  // and most parents stay proper cones
}

namespace {

// Half-angle bounds without trigonometry in the code under test: atan2 of the node's (sin, cos).
constexpr double kTwoPow17 = 1.0 / (1 << 17), kTwoPow18 = 1.0 / (1 << 18);

layout::Ray RayFrom(glm::vec3 o, glm::vec3 d) {
  layout::Ray r{};
  r.origin_tmin = glm::vec4(o, 0.0f);
  r.direction_tmax = glm::vec4(d, 1.0f);
  return r;
}

std::vector<layout::ConeNode> Leaves(const std::vector<layout::Ray>& rays, const std::vector<std::uint32_t>& order,
                                  const std::vector<std::uint32_t>& first) {
  return PassBuildLeaves({.rays = rays, .order = order, .first = first});
}

}  // namespace

TEST_CASE("build.leaves: a leaf over one ray, two parallel rays, two antiparallel rays") {
  // Rays: 0 from (1,2,3) along (0,3,4) (not unit); 1, 2 from (0,0,0) and (2,0,0) along +z; 3, 4 from
  // the origin along +z and -z; 5, 6 from the origin along +x and +y.
  const std::vector<layout::Ray> rays = {RayFrom({1, 2, 3}, {0, 3, 4}), RayFrom({0, 0, 0}, {0, 0, 1}),
                                      RayFrom({2, 0, 0}, {0, 0, 1}), RayFrom({0, 0, 0}, {0, 0, 1}),
                                      RayFrom({0, 0, 0}, {0, 0, -1}), RayFrom({0, 0, 0}, {2, 0, 0}),
                                      RayFrom({0, 0, 0}, {0, 2, 0})};
  // Leaves in a different order than the rays, through `order`.
  const std::vector<std::uint32_t> order = {3, 4, 0, 2, 1, 5, 6}, first = {0, 2, 3, 5, 7};
  const auto n = Leaves(rays, order, first);
  REQUIRE(n.size() == 4);

  // One ray: the sphere is its origin (radius only the tiny absolute floor), the cone its unit
  // direction (0, 0.6, 0.8) with a half-angle of the finishing margin alone (2^-18 rad).
  const layout::ConeNode& one = n[1];
  CHECK(glm::vec3(one.sphere) == glm::vec3(1, 2, 3));
  CHECK(one.sphere.w > 0.0f);
  CHECK(one.sphere.w < 1e-30f);
  CHECK(one.cone.x == 0.0f);
  CHECK(one.cone.y == doctest::Approx(0.6).epsilon(1e-6));
  CHECK(one.cone.z == doctest::Approx(0.8).epsilon(1e-6));
  CHECK(HalfAngle(one) > 0.0);
  CHECK(HalfAngle(one) <= kTwoPow17);
  CHECK(one.extra.y == 1.0f);  // rays below

  // Two parallel rays 2 apart: centre half way, radius 1 (plus margins), the common direction.
  const layout::ConeNode& two = n[2];
  CHECK(glm::vec3(two.sphere) == glm::vec3(1, 0, 0));
  CHECK(two.sphere.w >= 1.0f);
  CHECK(two.sphere.w <= 1.0 + 2 * kTwoPow18);  // the 2^-18 margin, rounded up
  CHECK(glm::vec3(two.cone) == glm::vec3(0, 0, 1));
  CHECK(HalfAngle(two) <= 4 * kTwoPow18);  // a few angle margins (2^-18 rad each)
  CHECK(two.extra.y == 2.0f);

  // Two antiparallel rays: every direction, the full sphere.
  CHECK(cone::IsFull(n[0]));
  CHECK(n[0].cone.w == -1.0f);
  CHECK(n[0].extra.y == 2.0f);

  // Two perpendicular rays (+x, +y): the axis bisects them, (1, 1, 0) / sqrt 2, at 45 degrees.
  const layout::ConeNode& right = n[3];
  const double r = 1.0 / std::sqrt(2.0), quarter = std::atan(1.0);
  CHECK(right.cone.x == doctest::Approx(r).epsilon(1e-5));
  CHECK(right.cone.y == doctest::Approx(r).epsilon(1e-5));
  CHECK(right.cone.z == 0.0f);
  CHECK(HalfAngle(right) >= quarter);
  CHECK(HalfAngle(right) <= quarter + 1e-5);
  CHECK(right.extra.y == 2.0f);
}

TEST_CASE("build.parents: a parent over two identical children is the child, widened by the margins only") {
  // A child around (1,2,3) with radius 0.5 and a 30-degree cone over 4 rays, about +z and about a unit
  // axis whose float components do not square to exactly 1.
  for (const glm::vec3 axis : {glm::vec3(0, 0, 1), glm::vec3(0, 0.6f, 0.8f)}) {
    layout::ConeNode child;
    child.sphere = glm::vec4(1, 2, 3, 0.5f);
    child.cone = glm::vec4(axis, std::sqrt(3.0f) / 2);
    child.extra = glm::vec4(0.5f, 4, 0, 0);
    const std::vector<layout::ConeNode> below = {child, child, child};
    const std::vector<std::uint32_t> first = {0, 2, 3};  // a parent over two children, one over one
    const auto p = PassBuildParents({.below = below, .first = first});
    REQUIRE(p.size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
      INFO("axis " << axis.y << " parent " << i << " half-angle excess " << HalfAngle(p[i]) - HalfAngle(child));
      CHECK(glm::vec3(p[i].sphere) == glm::vec3(child.sphere));
      CHECK(p[i].sphere.w >= child.sphere.w);
      CHECK(p[i].sphere.w <= 0.5 * (1.0 + kTwoPow18) + 1e-7);  // one radius margin (2^-18 relative)
      for (int k = 0; k < 3; ++k) CHECK(p[i].cone[k] == doctest::Approx(axis[k]).epsilon(1e-7));
      CHECK(HalfAngle(p[i]) >= HalfAngle(child));
      CHECK(HalfAngle(p[i]) <= HalfAngle(child) + kTwoPow17);  // one angle margin (2^-18 rad)
    }
    CHECK(p[0].extra.y == 8.0f);  // the counts add up
    CHECK(p[1].extra.y == 4.0f);
  }
}

TEST_CASE("cone: the radius floor survives a device that flushes denormals") {
#if defined(__SSE2__)
  // FTZ and DAZ on this thread: denormal results and operands become zero, as on a GPU whose kernels
  // do not (or cannot) declare DenormPreserve. A leaf of one ray has radius 0, so its finished radius
  // is the floor alone, which must stay a positive normal float.
  const unsigned csr = _mm_getcsr();
  _mm_setcsr(csr | 0x8040u);
  layout::ConeNode n = cone::FromRay(glm::vec3(1, 2, 3), glm::vec3(0, 0, 1));
  cone::Finish(n);
  _mm_setcsr(csr);
  CHECK(std::fpclassify(n.sphere.w) == FP_NORMAL);
  CHECK(n.sphere.w >= 0x1p-122f);
  CHECK(n.sphere.w < 0x1p-121f);
#endif
}

// --child-merge: 8 one-point children evenly spaced on a line. Each step of the sequential fold adds
// half the distance to the next child (0.5, 1.25, 2.125, ... 6.0078125 = 6 + 2^-7 spacings, where 3.5
// would do); the pairwise tree's radius only grows per level (0.5, 1.5, 3.5), exactly. After the checks and margins both parents hold every child, the pairwise one
// within its margins of 3.5.
TEST_CASE("build: pairwise child merge gives radius 3.5 where the sequential fold gives about 6 (8 points on a line)") {
  std::vector<layout::ConeNode> kids;
  for (int k = 0; k < 8; ++k) kids.push_back(cone::FromRay(glm::vec3(static_cast<float>(k), 0, 0), glm::vec3(0, 0, 1)));
  layout::ConeNode sequential = kids[0];
  for (std::size_t k = 1; k < kids.size(); ++k) sequential = cone::Union(sequential, kids[k]);
  CHECK(sequential.sphere.w == 6.0078125f);
  const layout::ConeNode pairwise = cone::PairwiseUnion(kids.data(), 8);
  CHECK(pairwise.sphere.w == 3.5f);
  CHECK(glm::vec3(pairwise.sphere) == glm::vec3(3.5f, 0, 0));
  CHECK(pairwise.extra.y == 8.0f);  // the children's rays, summed
  // Counts that are no power of two: 5 children give ((0 u 1) u (2 u 3)) u 4.
  const layout::ConeNode five = cone::PairwiseUnion(kids.data(), 5);
  CHECK(five.sphere.w == cone::Union(cone::Union(cone::Union(kids[0], kids[1]), cone::Union(kids[2], kids[3])), kids[4]).sphere.w);
  for (std::uint32_t merge : {layout::kChildMergeSequential, layout::kChildMergePairwise}) {
    const layout::ConeNode parent = cone::ParentNode(kids.data(), 8, merge);
    INFO("merge " << merge);
    for (const auto& k : kids) CHECK(glm::length(glm::dvec3(k.sphere) - glm::dvec3(parent.sphere)) <= parent.sphere.w);
    const float radius = merge == layout::kChildMergePairwise ? 3.5f : 6.0078125f;
    CHECK(parent.sphere.w >= radius);
    CHECK(parent.sphere.w < radius * 1.0001f);
  }
}
