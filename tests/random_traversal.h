// Random traversal calls for the tests of traverse and traverse.compact (tests/traverse_test.cpp
// and gpu/tests/traverse_compact_test.cpp): cone nodes built from random ray bundles, random
// spheres, top-level and lower-level calls.
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::test {

using Rng = std::mt19937;

inline glm::vec3 RandomDir(Rng& rng) {
  std::normal_distribution<float> n;
  return emu::Normalize(glm::vec3(n(rng), n(rng), n(rng)));
}

// Cone-sphere nodes over 1..8 rays each, the rays of a node leaving a small box in similar directions
// (narrow cones: a few percent of the spheres meet a node). `up`: every direction has z > 0.
inline std::vector<layout::ConeNode> RandomNodes(Rng& rng, std::size_t count, bool up = false) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<layout::Ray> rays;
  std::vector<std::uint32_t> order, first{0};
  while (first.size() <= count) {
    glm::vec3 dir = RandomDir(rng);
    if (up) dir = emu::Normalize(glm::vec3(dir.x, dir.y, std::fabs(dir.z) + 1.0f));
    const glm::vec3 centre(u(rng) * 2.0f, u(rng) * 2.0f, u(rng) * 2.0f);
    for (std::uint32_t j = 0, n = 1 + rng() % 8; j < n; ++j) {
      layout::Ray r{};
      r.origin_tmin = glm::vec4(centre + 0.1f * glm::vec3(u(rng), u(rng), u(rng)), 0.0f);
      r.direction_tmax = glm::vec4(emu::Normalize(dir + 0.2f * glm::vec3(u(rng), u(rng), u(rng))), 100.0f);
      r.info = glm::uvec4(static_cast<std::uint32_t>(rays.size()), layout::kNoPrim, 0u, 0u);
      order.push_back(static_cast<std::uint32_t>(rays.size()));
      rays.push_back(r);
    }
    first.push_back(static_cast<std::uint32_t>(order.size()));
  }
  return emu::PassBuildLeaves({.rays = rays, .order = order, .first = first});
}

// `behind`: every sphere far below z = 0, behind nodes whose rays all go up (no survivors).
inline std::vector<glm::vec4> RandomSpheres(Rng& rng, std::size_t count, bool behind = false) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), r(0.05f, 1.5f);
  std::vector<glm::vec4> s(count);
  for (glm::vec4& x : s) x = glm::vec4(u(rng) * 6.0f, u(rng) * 6.0f, u(rng) * 6.0f - (behind ? 1000.0f : 0.0f), r(rng));
  return s;
}

// A top level: nodes, spheres, a scene whose triangles belong to `objects` objects in runs, and a
// random object mask, which a call uses or not. `far`: no sphere meets a node.
struct TopCase {
  std::vector<layout::ConeNode> top;
  std::vector<glm::vec4> spheres;
  std::vector<std::uint8_t> mask;
  SceneBuffers scene;
  TopCase(std::uint32_t seed, std::size_t nodes, std::size_t tris, std::uint32_t objects, bool far = false) {
    Rng rng(seed);
    top = RandomNodes(rng, nodes, far);
    spheres = RandomSpheres(rng, tris, far);
    scene.triangles.resize(tris);
    scene.info.resize(tris);
    scene.objects.resize(objects);
    for (std::size_t t = 0; t < tris; ++t) scene.info[t].ids.y = static_cast<std::uint32_t>(t * objects / tris);
    for (std::size_t e = 0; e < top.size() * objects; ++e) mask.push_back(rng() % 3 != 0);
  }
  emu::call::TraverseTop Top(std::uint32_t t0, std::uint32_t t1, std::uint32_t b0, std::uint32_t b1, bool masked, float eps = 0.0f) const {
    return {.top = top, .t0 = t0, .t1 = t1, .b0 = b0, .b1 = b1, .tri_spheres = spheres, .scene = &scene,
            .object_mask = masked ? emu::In<std::uint8_t>(mask) : emu::In<std::uint8_t>{}, .eps = eps};
  }
};

// A lower level: `parents` nodes above with 0..children_max children each among `nodes`, and random
// (parent, triangle) pairs of the parents from base_up on.
struct LevelCase {
  std::vector<layout::ConeNode> nodes;
  std::vector<std::uint32_t> first{0}, pairs;
  std::vector<glm::vec4> spheres;
  std::uint32_t base_up = 3, children_max;
  // `run` > 1: the pairs come in runs of 1 .. run pairs with one parent, as a level's survivors do
  // (a node's triangles together); 1: every pair's parent drawn on its own.
  LevelCase(std::uint32_t seed, std::uint32_t parents, std::size_t pair_count, std::uint32_t children_max_, bool far = false,
            std::uint32_t run = 1)
      : children_max(children_max_) {
    Rng rng(seed);
    for (std::uint32_t p = 0; p < parents; ++p) first.push_back(first.back() + (children_max ? rng() % (children_max + 1) : 0));
    nodes = RandomNodes(rng, first.back(), far);
    nodes.resize(first.back());
    spheres = RandomSpheres(rng, 200, far);
    while (pairs.size() < pair_count) {
      const std::uint32_t parent = rng() % (parents - base_up), n = run > 1 ? 1 + rng() % run : 1;
      for (std::uint32_t i = 0; i < n && pairs.size() < pair_count; ++i) pairs.push_back((parent << layout::kPairTriangleBits) | (rng() % 150));
    }
  }
  emu::call::TraverseLevel Level(float eps = 0.0f) const {
    return {.pairs = pairs, .nodes = nodes, .first = first, .base_up = base_up, .base = first[base_up],
            .children_max = children_max, .b0 = 50, .tri_spheres = spheres, .eps = eps};
  }
};

}  // namespace rayspace::test
