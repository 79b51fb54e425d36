#include "render_options.h"

#include <CLI/CLI.hpp>

#include "rayspace/error.h"
#include "frame_options.h"

namespace rayspace::app {

void AddRenderOptions(CLI::App& command, RenderArgs& args) {
  command.add_option("scene", args.scene, "Scene JSON file")->required();
  AddFrameOptions(command, args);
  command.add_option("--out", args.out, "Output image (PNG); default <scene name>.png in the current directory");
  command.add_option("--stats", args.stats, "Write statistics as JSON to this file (-: to standard output, in place "
                     "of the summary)");
  command.add_option("--threads", args.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  command.add_option("--direct", args.direct, "Direct tracer mode: auto, exhaustive or bvh")
      ->check(CLI::IsMember({"auto", "exhaustive", "bvh"}));
  command.add_option("--backend", args.backend,
                     "Where the passes run: emu (the CPU emulation), vulkan (the GLSL kernels on a device) or sim (the "
                     "kernels' SPIR-V on the simulated GPU, the raster from the emulator); the same bits expected")
      ->check(CLI::IsMember({"emu", "sim", "vulkan"}));
  command.add_option("--path", args.path,
                     "Hierarchy traversal: fused (each level tests and compacts in one pass, traverse.compact; the same "
                     "pairs, statistics and digest) or passes (traverse then reduce); auto: fused unless "
                     "--check-workgroups or --schedule asks for the passes' emulated workgroups. --algo grid: passes runs "
                     "grid.trace ray by ray, fused and auto its cells' triangles in SIMD lanes (the same walks)")
      ->check(CLI::IsMember({"auto", "fused", "passes"}));
  command.add_flag("--no-oracle", args.no_oracle, "Skip the oracle re-trace");
  command.add_flag("--timings", args.timings, "Print time per phase (the thesis's phases) and tests per second");
  command.add_flag("--progress", args.progress, "Print each pass and its time on stderr (default when stderr is a terminal)");
}

void ApplyRenderOptions(const std::string& options, RenderArgs& args) {
  CLI::App render("render");
  const std::string scene = args.scene;
  AddRenderOptions(render, args);
  try {
    // The scene is the caller's: a stand-in fills the required argument.
    render.parse("scene " + options, false);
  } catch (const CLI::ParseError& e) {
    ThrowInput("render options '{}': {}", options, e.what());
  }
  args.scene = scene;
}

}  // namespace rayspace::app
