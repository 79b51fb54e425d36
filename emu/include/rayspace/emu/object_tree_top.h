// `--objects tree`: the top level of the ray-space hierarchy against each object's bounding-sphere
// tree (rayspace/object_tree.h) instead of against every triangle. A top node descends into the
// object nodes whose spheres its cone may meet; the triangles of the nodes it reaches are tested as
// the flat top level tests them, and the survivors come out as the flat top level's pairs, in its
// order (node-major, triangle ascending). The tree's spheres hold their triangles' spheres, so a
// triangle the flat test keeps is reached unless the test's own rounding keeps it falsely; the
// final ray-triangle tests decide hits either way (docs/object-tree.md).
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/streams.h"
#include "rayspace/object_tree.h"

namespace rayspace::emu {

// The tree with what the descent reads per node: the smallest and largest scene triangle below it,
// so that a triangle batch [b0, b1) skips the subtrees it holds nothing of, and the node spheres as
// lane arrays (a node's children are consecutive: one multi-lane test).
struct ObjectTreeIndex {
  ObjectTreeIndex() = default;
  ObjectTreeIndex(ObjectTreeIndex&&) = default;  // moving keeps `spheres`' buffer, which `lanes` spans
  ObjectTreeIndex& operator=(ObjectTreeIndex&&) = default;
  ObjectTreeIndex(const ObjectTreeIndex&) = delete;  // a copy's `lanes` would span the original's buffer
  ObjectTreeIndex& operator=(const ObjectTreeIndex&) = delete;
  ObjectTree tree;
  std::vector<std::uint32_t> lo, hi;  // per node
  std::vector<glm::vec4> spheres;     // per node
  cone::SphereArrays lanes;           // of `spheres`
};
ObjectTreeIndex IndexObjectTree(ObjectTree tree);

struct TreeTopResult {
  Compacted pairs;                   // tested: the triangles' cone-sphere tests
  std::uint64_t node_tests = 0, node_hits = 0;  // the object nodes' cone-sphere tests and survivors
};

// The top level of block (top nodes [c.t0, c.t1) x triangles [c.b0, c.b1)); c.object_mask is unused
// (the tree's roots take the object spheres' place).
TreeTopResult TraverseTopTree(const call::TraverseTop& c, const ObjectTreeIndex& index);

}  // namespace rayspace::emu
