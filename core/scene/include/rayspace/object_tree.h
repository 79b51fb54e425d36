// A bounding-sphere hierarchy over each object's triangles (docs/object-tree.md): Toczek et al.'s
// top-down, octree-like build. A node's sphere is centred at the centre of its triangles' tight
// bounding box and is the smallest such sphere holding every vertex (rounded outward); triangles big
// against the node stay its own, the others split into the eight octants of their centroid about
// that centre, recursively. Built once on the host, deterministically (the same triangles in the
// same order give the same bits), and read by every consumer of the object hierarchy.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "rayspace/layout.h"

namespace rayspace {

struct ObjectTreeOptions {
  // A triangle whose bounding radius (about its centroid) is at least this fraction of the node's
  // radius is "big enough compared to the node" and becomes one of its own triangles.
  float big_fraction = 0.25f;
  // A set of at most this many triangles becomes a leaf: splitting it costs more tests than it saves.
  std::uint32_t leaf_triangles = 4;
};

struct ObjectTreeNode {
  glm::vec4 sphere;            // xyz centre, w radius: holds every vertex of every triangle below
  std::uint32_t first_child;   // children: nodes [first_child, first_child + children)
  std::uint32_t children;
  std::uint32_t first_tri;     // own triangles: ObjectTree::triangles[first_tri, first_tri + tris)
  std::uint32_t tris;
};

struct ObjectTree {
  std::vector<ObjectTreeNode> nodes;       // breadth-first per object: a node's children are consecutive
  std::vector<std::uint32_t> triangles;    // scene triangle indices, each exactly once
  std::vector<std::uint32_t> roots;        // per object: its root node
  std::vector<std::uint32_t> depth;        // per node: 0 at a root
};

// `objects[o]`: x first triangle, y count (SceneBuffers::objects). Vertices must be finite (the
// scene loaders refuse others); a violation is an invariant failure, not a bad input. With
// `tri_spheres` (one per triangle), every node's sphere also holds the spheres of the triangles below
// it, so that a test that keeps a triangle's sphere keeps every node above it.
ObjectTree BuildObjectTree(std::span<const layout::Triangle> triangles, std::span<const glm::uvec4> objects,
                           const ObjectTreeOptions& options = {}, std::span<const glm::vec4> tri_spheres = {});

}  // namespace rayspace
