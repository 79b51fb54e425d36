// Hierarchy build: leaf nodes hold their rays, parents hold their children.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

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
double HalfAngle(const gpu::ConeNode& n) { return std::atan2(static_cast<double>(n.extra.x), static_cast<double>(n.cone.w)); }

}  // namespace

TEST_CASE("cone: leaf nodes hold their rays and parents hold their children (randomized, in double)") {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1), spread(0, 1);
  int full = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Children: leaves over 8 rays with origins in a small cloud and directions in a random cone,
    // including near-identical, antiparallel and wide configurations.
    const int mode = trial % 4;
    std::vector<gpu::ConeNode> kids;
    const glm::dvec3 base_axis = RandomUnit(rng);
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 axis = mode == 2 && k % 2 ? -base_axis : (mode == 3 ? RandomUnit(rng) : InCone(rng, base_axis, 0.2));
      const double alpha = mode == 0 ? 1e-4 * spread(rng) : 0.5 * spread(rng);
      const glm::dvec3 centre(u(rng) * 10, u(rng) * 10, u(rng) * 10);
      std::vector<gpu::Ray> rays(8);
      for (auto& r : rays) {
        r.origin_tmin = glm::vec4(glm::vec3(centre + glm::dvec3(u(rng), u(rng), u(rng)) * 0.1), 0);
        r.direction_tmax = glm::vec4(glm::vec3(InCone(rng, axis, alpha)), 1);
      }
      const gpu::ConeNode leaf = cone::LeafNode(8, [&](std::uint32_t j) -> const gpu::Ray& { return rays[j]; });
      for (const auto& r : rays) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(r.direction_tmax));
        if (!cone::IsFull(leaf)) CHECK(Angle(glm::dvec3(leaf.cone), d) <= HalfAngle(leaf));
        CHECK(glm::length(glm::dvec3(r.origin_tmin) - glm::dvec3(leaf.sphere)) <= leaf.sphere.w);
      }
      kids.push_back(leaf);
    }
    const gpu::ConeNode parent = cone::ParentNode(kids.data(), static_cast<std::uint32_t>(kids.size()));
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
