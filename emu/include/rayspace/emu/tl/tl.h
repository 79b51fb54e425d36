// Stackless traversal lists over a bounding-sphere hierarchy (Toczek, Houzet, Mancini 2010;
// docs/traversal-lists.md): the object tree's build (rayspace/object_tree.h, the paper's section 2.2)
// over the whole scene, flattened depth first into K lists, each with its nodes ordered along one
// direction, and walked without a stack by following escapes. The CPU core only: no kernel yet.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "rayspace/emu/tl/layout.h"
#include "rayspace/layout.h"
#include "rayspace/object_tree.h"

namespace rayspace::emu::tl {

// How a node's children are ordered along a list's direction, by the projection [lo, hi] of each
// child (sphere or triangle) on it: earliest first by ascending lo, latest last by ascending hi.
// Ties keep the tree's order (own triangles in input order, then child nodes in octant order).
enum class Order { kEarliestFirst, kLatestLast };

struct Options {
  // 1: one list along +x; 2: +x and -x; 6: +-x, +-y, +-z (the paper's sextants); 8: the diagonals
  // (+-1, +-1, +-1) (its octants).
  std::uint32_t lists = 6;
  Order order = Order::kEarliestFirst;
  ObjectTreeOptions tree;  // big_fraction, leaf_triangles: the object tree's defaults
};

// K lists over one vertex array. List k holds the elements [first[k], first[k + 1]); escapes are
// relative, so a list is walked the same wherever it lies.
struct Lists {
  std::uint32_t count = 0;                // K
  std::vector<std::uint32_t> first;       // K + 1 offsets
  std::vector<Escape> escapes;            // per element
  std::vector<Word> words;                // per element
  std::vector<Vertex> vertices;           // shared: distinct positions in first-use order
  std::vector<glm::vec3> directions;      // per list: its unit ordering direction
  std::uint64_t Bytes() const;            // escapes, words, vertices and offsets
};

bool ValidListCount(std::uint32_t k);

// Deterministic: the same triangles and options give the same bytes.
Lists Build(std::span<const layout::Triangle> triangles, const Options& options = {});

// The list a ray of direction `dir` walks: the one whose class holds it (sign of x; dominant axis
// and its sign, ties to the lower axis; the signs of x, y, z). Zero components count as positive.
std::uint32_t ListFor(std::uint32_t count, glm::vec3 dir);

struct Stats {
  std::uint64_t spheres = 0;    // sphere elements tested
  std::uint64_t triangles = 0;  // triangle elements tested (the ignored primitive included)
};

// The closest hit as emu::PackHit (kMissPacked for none), the same as testing every triangle with
// IntersectWatertight over (tmin, tmax) and ignoring ray.info.y: nearest t, ties to the lower id.
std::uint64_t Closest(const Lists& lists, const layout::Ray& ray, Stats* stats = nullptr);
// Whether any triangle but ray.info.y is hit in (tmin, tmax); stops at the first.
bool Any(const Lists& lists, const layout::Ray& ray, Stats* stats = nullptr);

// May the ray's part [tmin, tlimit] meet the sphere? Conservative in float: never false when a point
// of that part lies in the sphere (docs/traversal-lists.md, "Sphere test").
bool SphereMayHit(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 sphere);

}  // namespace rayspace::emu::tl
