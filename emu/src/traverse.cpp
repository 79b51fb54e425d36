// Traversal of one block: the top level tests every (node, triangle) pair, lower levels test the
// children of surviving pairs; CRSH culls top nodes against object spheres first. Mirrors
// gpu/shaders/traverse.comp. The loops are templates in emu/hierarchy.h so `rayspace accuracy` can
// swap the cone-sphere test.
#include <algorithm>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/parallel.h"
#include "rayspace/settings.h"

namespace rayspace::emu {

float TraversalEpsilon(const SceneBuffers& scene) {
  const glm::vec3 ext = scene.hi - scene.lo;
  return std::max(glm::length(ext), 1e-30f) * 1e-6f;
}

namespace {
constexpr std::string_view kCompactPass = "traverse.compact";

// Chosen once per call, so the default loops keep the conservative test inlined with no branch.
template <typename Loop, typename Call>
auto WithConeTest(Loop&& loop, const Call& c) {
  if (c.cone_test == layout::kConeTestPrintedSigned) return loop(cone::kPrintedSignedTestFn, c);
  return c.cone_test == layout::kConeTestPrinted ? loop(cone::kPrintedTestFn, c) : loop(cone::kTestFn, c);
}
}  // namespace

PairSlots PassTraverseTop(const call::TraverseTop& c) {
  return WithConeTest([](auto test, const call::TraverseTop& k) { return TraverseTopWith(test, k); }, c);
}

std::vector<std::uint8_t> PassObjectMask(const call::ObjectMask& c) {
  return WithConeTest([](auto test, const call::ObjectMask& k) { return ObjectMaskWith(test, k); }, c);
}

PairSlots PassTraverseLevel(const call::TraverseLevel& c) {
  return WithConeTest([](auto test, const call::TraverseLevel& k) { return TraverseLevelWith(test, k); }, c);
}

// traverse.compact has two emulations with the same survivors in slot order and the same test
// counts: the fused path's levels on SIMD lanes (emu/src/traverse_fused.cpp), which renders need for
// speed, and the mirror of traverse_compact.comp's workgroups (emu/src/traverse_compact_wg.cpp),
// which is what --check-workgroups, a --schedule other than forward and an @emu fault act on. The
// mirror runs when one of those asks for the workgroup model (RunsWorkgroupMirror); the lanes else.
Compacted PassTraverseTopCompacted(const call::TraverseTopCompacted& c) {
  if (RunsWorkgroupMirror(kCompactPass)) return TraverseTopCompactedWorkgroups(c);
  return PassTraverseTopCompacted(static_cast<const call::TraverseTop&>(c));
}
Compacted PassTraverseLevelCompacted(const call::TraverseLevelCompacted& c) {
  if (RunsWorkgroupMirror(kCompactPass)) return TraverseLevelCompactedWorkgroups(c);
  return PassTraverseLevelCompacted(static_cast<const call::TraverseLevel&>(c));
}

Compacted ConcatenateBlocks(std::vector<BlockSurvivors>& parts, const std::vector<std::uint64_t>& tested) {
  Compacted r;
  std::vector<std::size_t> at(parts.size() + 1, 0);  // where each block's survivors go
  for (std::size_t b = 0; b < parts.size(); ++b) {
    if (CurrentSettings().fused_fault && !parts[b].empty()) parts[b].pop_back();
    at[b + 1] = at[b] + parts[b].size();
    r.tested += tested[b];
  }
  r.pairs.resize(at.back());
  ParallelForDynamic(parts.size(), 64, [&](std::size_t b) {
    std::copy(parts[b].begin(), parts[b].end(), r.pairs.begin() + static_cast<std::ptrdiff_t>(at[b]));
  });
  return r;
}

}  // namespace rayspace::emu
