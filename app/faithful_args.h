// The switches that make a frame trace the rays and objects the CRSH thesis traced (docs/hierarchy.md,
// "Faithful to the thesis"): options of render, diff and bench, defaults the frame rayspace traces.
#pragma once
#include <string>

#include "rayspace/emu/frame.h"

namespace CLI {
class App;
}

namespace rayspace::app {

struct FaithfulArgs {
  std::string shadow_rule = "all";     // --shadow-rule all|lit
  std::string shadow_bounces = "all";  // --shadow-bounces all|first
  bool one_object = false;             // --one-object
};

// Registers --shadow-rule, --shadow-bounces and --one-object on `command`, writing into `args`.
void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args);
// The scene's buffers; with --one-object every triangle in one object (one bounding sphere), each
// triangle keeping its material, as the thesis's Sponza was "not divided into submeshes".
SceneBuffers FlattenForFrame(const Scene& scene, const FaithfulArgs& args);
// Sets the frame options the switches name.
void ApplyFaithful(const FaithfulArgs& args, emu::FrameOptions& fo);

}  // namespace rayspace::app
