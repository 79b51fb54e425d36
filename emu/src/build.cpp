// Hierarchy build: cone-sphere leaves over sorted rays, parents over the level below (docs/hierarchy.md).
// Mirrors gpu/shaders/build.comp, where a subgroup builds a node: its lanes fetch the node's rays or
// children and every lane runs the same in-order fold over them (subgroupShuffle, no shared memory,
// no barrier). The fold is the node's result, so one fold per node here is the kernel's result on
// every lane; there is nothing for the workgroup checker to see.
#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::vector<layout::ConeNode> PassBuildLeaves(const call::BuildLeaves& c) {
  const In<layout::Ray> rays = c.rays;
  const In<std::uint32_t> order = c.order, first = c.first;
  std::vector<layout::ConeNode> nodes(first.size() - 1);
  ParallelFor(nodes.size(), [&](std::size_t i) {
    nodes[i] = cone::LeafNode(first[i + 1] - first[i], [&](std::uint32_t k) -> const layout::Ray& { return rays[order[first[i] + k]]; });
  });
  return nodes;
}

std::vector<layout::ConeNode> PassBuildParents(const call::BuildParents& c) {
  const In<layout::ConeNode> below = c.below;
  const In<std::uint32_t> first = c.first;
  std::vector<layout::ConeNode> nodes(first.size() - 1);
  ParallelFor(nodes.size(), [&](std::size_t i) { nodes[i] = cone::ParentNode(&below[first[i]], first[i + 1] - first[i], c.child_merge); });
  return nodes;
}

}  // namespace rayspace::emu
