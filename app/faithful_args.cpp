#include "faithful_args.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace rayspace::app {

int MaxHashBits() { return (layout::kHashKeyBits - emu::HashConfig{}.light_bits) / 2; }

void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args) {
  command
      .add_option("--hash-order", args.hash_order,
                  "Direction part of the CRSH hash keys: interleaved (polar and azimuth bits alternate) or polar-first "
                  "(all polar bits above the azimuth's, as the thesis prints it)")
      ->check(CLI::IsMember({"interleaved", "polar-first"}))
      ->capture_default_str();
  command
      .add_option("--hash-bits", args.hash_bits,
                  fmt::format("Shadow hash keys: cells bits per angle, polar and azimuth (1 to {}: the light index takes "
                              "{} of the key's {} bits)",
                              MaxHashBits(), emu::HashConfig{}.light_bits, layout::kHashKeyBits))
      ->check(CLI::Range(1, MaxHashBits()))
      ->capture_default_str();
  command
      .add_option("--shadow-rule", args.shadow_rule,
                  "Shadow rays: all (one per covered pixel and light) or lit (only where the light is in front of "
                  "the surface, n.l > 0, as the thesis counts them); the image is the same")
      ->check(CLI::IsMember({"all", "lit"}))
      ->capture_default_str();
  command
      .add_option("--shadow-bounces", args.shadow_bounces,
                  "Shadow rays after every bounce (all) or from the primary hits only (first, the thesis's one shadow "
                  "batch; later bounces then shade with every light unoccluded)")
      ->check(CLI::IsMember({"all", "first"}))
      ->capture_default_str();
  command.add_flag("--one-object", args.one_object,
                   "Merge all of the scene's objects into one (one bounding sphere), as the thesis's Sponza; same hits");
  command
      .add_option("--leaf-test", args.leaf_test,
                  "Rays of a surviving leaf node against its triangle: node (each ray's ray-triangle test) or ray-sphere "
                  "(each ray first against the triangle's bounding sphere, as Roger et al.; counted as leaf sphere "
                  "tests); same hits")
      ->check(CLI::IsMember({"node", "ray-sphere"}))
      ->capture_default_str();
  command
      .add_option("--child-merge", args.child_merge,
                  "How a parent node unites its children: sequential (one after another, as the thesis folds them) "
                  "or pairwise (a balanced binary tree: smaller spheres); same hits")
      ->check(CLI::IsMember({"sequential", "pairwise"}))
      ->capture_default_str();
}

void ApplyFaithful(const FaithfulArgs& args, emu::HierarchyConfig& hc) {
  hc.hash.order = args.hash_order == "polar-first" ? layout::kHashOrderPolarFirst : layout::kHashOrderInterleaved;
  hc.hash.polar_bits = hc.hash.azimuth_bits = args.hash_bits;
  hc.leaf_test = args.leaf_test == "ray-sphere" ? layout::kLeafTestRaySphere : layout::kLeafTestNode;
  hc.child_merge = args.child_merge == "pairwise" ? layout::kChildMergePairwise : layout::kChildMergeSequential;
}

SceneBuffers FlattenForFrame(const Scene& scene, const FaithfulArgs& args) {
  SceneBuffers b = FlattenScene(scene);
  if (!args.one_object || b.objects.size() <= 1) return b;
  // Objects' triangles are consecutive from 0, so the merged object is all of them.
  b.objects.assign(1, glm::uvec4(0u, static_cast<std::uint32_t>(b.triangles.size()), 0u, 0u));
  for (layout::TriangleInfo& i : b.info) i.ids.y = 0u;  // ids.x, the material, stays per triangle
  return b;
}

void ApplyFaithful(const FaithfulArgs& args, emu::FrameOptions& fo) {
  fo.shadow_rule = args.shadow_rule == "lit" ? layout::kShadowRuleLit : layout::kShadowRuleAll;
  fo.shadow_first_bounce_only = args.shadow_bounces == "first";
}

}  // namespace rayspace::app
