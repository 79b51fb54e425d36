#include "faithful_args.h"

#include <CLI/CLI.hpp>

namespace rayspace::app {

void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args) {
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
