#include "rayspace/frame/faithful_args.h"

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/merge_objects.h"

namespace rayspace::app {

int MaxHashBits() { return (layout::kHashKeyBits - emu::HashConfig{}.light_bits) / 2; }


void ApplyFaithful(const FaithfulArgs& args, emu::HierarchyConfig& hc) {
  hc.hash.order = args.hash_order == "polar-first" ? layout::kHashOrderPolarFirst : layout::kHashOrderInterleaved;
  hc.hash.polar_bits = hc.hash.azimuth_bits = args.hash_bits;
  hc.leaf_test = args.leaf_test == "ray-sphere" ? layout::kLeafTestRaySphere : layout::kLeafTestNode;
  hc.child_merge = args.child_merge == "pairwise" ? layout::kChildMergePairwise : layout::kChildMergeSequential;
  if (args.cone_test != "printed" && args.cone_test != "printed-signed") return;
  if (hc.object_tree) ThrowInput("--cone-test {}: the object tree (--objects tree) has only the conservative test", args.cone_test);
  hc.cone_test = args.cone_test == "printed" ? layout::kConeTestPrinted : layout::kConeTestPrintedSigned;
  hc.auto_tree_spread = 0.0f;  // --objects auto: flat, the only descent with the printed test
  hc.auto_tree_triangles = 0;
}

SceneBuffers FlattenForFrame(const Scene& scene, const FaithfulArgs& args) {
  SceneBuffers b = FlattenScene(scene);
  if (args.one_object) MergeObjects(b);
  return b;
}

void ApplyFaithful(const FaithfulArgs& args, emu::FrameOptions& fo) {
  fo.shadow_rule = args.shadow_rule == "lit" ? layout::kShadowRuleLit : layout::kShadowRuleAll;
  fo.shadow_first_bounce_only = args.shadow_bounces == "first";
}

}  // namespace rayspace::app
