#include "faithful_args.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/merge_objects.h"

namespace rayspace::app {

int MaxHashBits() { return (layout::kHashKeyBits - emu::HashConfig{}.light_bits) / 2; }

namespace {

std::string PresetHelp() {
  std::string help = "Work as a paper printed it: thesis (the CRSH thesis) or roger (Roger et al. 2007); none keeps "
                     "rayspace's own choices. A preset sets switches the command line does not give:";
  for (const char* name : {"thesis", "roger"}) {
    help += fmt::format(" {} =", name);
    for (const std::string& w : FaithfulPreset(name)) help += " " + w;
    help += ";";
  }
  help.pop_back();
  return help;
}

// Applies the preset's switches that `command` has and the command line did not give, through the
// options themselves, so each value passes the same checks as when typed.
void ResolvePreset(CLI::App& command, const std::string& preset) {
  const std::vector<std::string> words = FaithfulPreset(preset);
  for (std::size_t i = 0; i < words.size(); ++i) {
    const bool has_value = i + 1 < words.size() && words[i + 1].rfind("--", 0) != 0;
    CLI::Option* opt = command.get_option_no_throw(words[i]);
    const std::string value = has_value ? words[i + 1] : "true";
    if (has_value) ++i;
    if (opt == nullptr || opt->count() > 0) continue;
    opt->add_result(value);
    opt->run_callback();
  }
}

}  // namespace

void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args) {
  command.add_option("--faithful", args.preset, PresetHelp())
      ->check(CLI::IsMember({"none", "thesis", "roger"}))
      ->capture_default_str();
  command.parse_complete_callback([&command, &args] { ResolvePreset(command, args.preset); });
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
      .add_option("--cone-test", args.cone_test,
                  "The traversal's cone-sphere test: conservative (never loses a hit) or printed (the thesis's eq. 3.16 "
                  "as printed, no margins; it can lose hits, which the oracle counts); printed traces --objects flat")
      ->check(CLI::IsMember({"conservative", "printed"}))
      ->capture_default_str();
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

FaithfulArgs FaithfulFromPreset(const std::string& name) {
  FaithfulArgs args;
  CLI::App app;
  AddFaithfulOptions(app, args);
  try {
    app.parse(std::vector<std::string>{name, "--faithful"});  // CLI11 reads the vector from its back
  } catch (const CLI::ParseError& e) {
    ThrowInput("--faithful {}: {}", name, e.what());
  }
  return args;
}

void ApplyFaithful(const FaithfulArgs& args, emu::HierarchyConfig& hc) {
  hc.hash.order = args.hash_order == "polar-first" ? layout::kHashOrderPolarFirst : layout::kHashOrderInterleaved;
  hc.hash.polar_bits = hc.hash.azimuth_bits = args.hash_bits;
  hc.leaf_test = args.leaf_test == "ray-sphere" ? layout::kLeafTestRaySphere : layout::kLeafTestNode;
  hc.child_merge = args.child_merge == "pairwise" ? layout::kChildMergePairwise : layout::kChildMergeSequential;
  if (args.cone_test != "printed") return;
  if (hc.object_tree) ThrowInput("--cone-test printed: the object tree (--objects tree) has only the conservative test");
  hc.cone_test = layout::kConeTestPrinted;
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
