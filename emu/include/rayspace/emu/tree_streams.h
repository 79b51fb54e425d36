// The buffers of `--objects tree`'s joint descent (emu/object_tree_traverse.h, docs/object-tree.md):
// the two hierarchies as the tree passes read them and the pair streams they write, with their
// fields named (RS_FIELDS) so the diff moves them to and from buffer sets like any pass's.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "rayspace/emu/fields.h"
#include "rayspace/layout.h"

namespace rayspace::emu {

// The ray-space hierarchy, levels 0 (one node per sorted ray) to D in one array: level L's nodes are
// cone_nodes[cone_base[L] .. cone_base[L + 1]). Level L's CSR child offsets (into level L - 1) start
// at cone_first[cone_base[L] + L] and hold the level's nodes + 1 words (level 0's are 0, 1, ..).
struct ConeTreeView {
  std::span<const layout::ConeNode> cone_nodes;
  std::span<const std::uint32_t> cone_base, cone_first;
  RS_FIELDS(cone_nodes, cone_base, cone_first)
  int Depth() const { return static_cast<int>(cone_base.size()) - 2; }
  std::uint32_t Count(std::uint32_t level) const { return cone_base[level + 1] - cone_base[level]; }
  const layout::ConeNode& Node(std::uint32_t level, std::uint32_t n) const { return cone_nodes[cone_base[level] + n]; }
  std::uint32_t First(std::uint32_t level, std::uint32_t n) const { return cone_first[cone_base[level] + level + n]; }
  std::span<const layout::ConeNode> Level(std::uint32_t level) const { return cone_nodes.subspan(cone_base[level], Count(level)); }
  std::span<const std::uint32_t> FirstOf(std::uint32_t level) const {
    return cone_first.subspan(cone_base[level] + level, Count(level) + 1);
  }
};

// The object tree (rayspace/object_tree.h) as arrays: per node its sphere, its links (x first child,
// y children, z first own triangle, w own triangles) and depth; the roots; per entry of the triangle
// list its sphere and scene triangle.
struct ObjectTreeView {
  std::span<const glm::vec4> tree_spheres;
  std::span<const glm::uvec4> tree_links;
  std::span<const std::uint32_t> tree_depth, tree_roots;
  std::span<const glm::vec4> tree_tri_spheres;
  std::span<const std::uint32_t> tree_triangles;
  RS_FIELDS(tree_spheres, tree_links, tree_depth, tree_roots, tree_tri_spheres, tree_triangles)
};

// A pair's two halves (rayspace/contract.h, kTree*): cone = level << kTreeLevelShift | node within
// its level; item = an object-tree node, or kTreeItemTriangle | an index into the triangle list.
struct TreePairs {
  std::vector<std::uint32_t> cone, item;
  std::size_t size() const { return cone.size(); }
  RS_FIELDS(cone, item)
};

// Tests and survivors, by the level of the tested cone (0..D) and by the depth of the tested object
// node (tri: the tests against triangle spheres).
struct TreeCounts {
  std::vector<std::uint64_t> cone_tests, cone_hits;  // index: cone level
  std::vector<std::uint64_t> node_tests, node_hits;  // index: object-node depth
  std::uint64_t tri_tests = 0, tri_hits = 0;
  void Resize(int cone_levels, std::size_t node_depths);
  void Add(const TreeCounts& o);
  bool operator==(const TreeCounts&) const = default;
  RS_FIELDS(cone_tests, cone_hits, node_tests, node_hits, tri_tests, tri_hits)
};

// Per candidate slot: 0 dropped, 1 goes on, 2 final; the slot's pair; the counts.
struct TreeSlots {
  std::vector<std::uint8_t> flags;
  TreePairs pairs;
  TreeCounts counts;
  RS_NAMED_FIELDS("flags, cone, item, counts", flags, pairs.cone, pairs.item, counts)
};

// A round's output: the pairs that go on, the final pairs, and the counts.
struct TreeRound {
  TreePairs next, final;
  TreeCounts counts;
  RS_NAMED_FIELDS("next_cone, next_item, final_cone, final_item, counts", next.cone, next.item, final.cone, final.item, counts)
};

}  // namespace rayspace::emu
