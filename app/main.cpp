// rayspace command-line interface.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "accuracy_command.h"
#include "exit_codes.h"
#include "render_command.h"
#ifdef RAYSPACE_HAVE_VULKAN
#include "diff_command.h"
#endif

int main(int argc, char** argv) {
  using rayspace::app::ExitCode;
  CLI::App app{"rayspace: emulator and verification suite for GPU secondary-ray tracing with ray-space hierarchies"};
  app.require_subcommand(1);
  app.footer(rayspace::app::ExitCodeHelp());  // before the subcommands, which inherit it
  rayspace::app::RenderArgs render;
  CLI::App* rc = app.add_subcommand("render", "Render a scene through the emulated pipeline and check it with an oracle");
  rc->add_option("scene", render.scene, "Scene JSON file")->required();
  rc->add_option("--algo", render.algo,
                 "Tracer for secondary rays: crsh (ray hashing + sorting, object spheres), rah (same hierarchy over "
                 "unsorted rays), rah-quadtree (Roger et al.'s screen quadtree), brute (emulated direct tracer), embree")
      ->check(CLI::IsMember({"crsh", "rah", "rah-quadtree", "brute", "embree"}));
  rc->add_option("--subdivision", render.subdivision, "Children per hierarchy node")->check(CLI::IsMember({4, 8, 16}));
  auto* depth = rc->add_option("--depth", render.depth, "Hierarchy levels (rah-quadtree: log2 of the image size)")->check(CLI::Range(1, 12));
  rc->add_option("--reduction", render.reduction, "Stream reduction: hierarchical (Roger et al.) or scan")
      ->check(CLI::IsMember({"hierarchical", "scan"}));
  rc->add_option("--component-size", render.component_size, "Component size s of the hierarchical reduction")
      ->check(CLI::Range(1, 1 << 20));
  rc->add_option("--pair-capacity", render.pair_capacity, "Pairs one traversal level may hold; more splits the triangle batch")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30));
  rc->add_option("--size", render.size, "Image size WxH (overrides the scene)");
  rc->add_option("--out", render.out, "Output image (PNG); default <scene name>.png in the current directory");
  rc->add_option("--stats", render.stats, "Write statistics as JSON to this file");
  rc->add_option("--data", render.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  rc->add_option("--threads", render.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  rc->add_option("--direct", render.direct, "Direct tracer mode: auto, exhaustive or bvh")
      ->check(CLI::IsMember({"auto", "exhaustive", "bvh"}));
  rc->add_option("--backend", render.backend,
                 "Where the passes run: emu (the CPU emulation) or vulkan (the GLSL kernels; same bits expected)")
      ->check(CLI::IsMember({"emu", "vulkan"}));
  rc->add_option("--device", render.device, "Vulkan device index for --backend vulkan (default: first non-CPU device, else lavapipe)")
      ->check(CLI::Range(0, 64));
  rc->add_option("--split-bytes", render.split_bytes,
                 "Vulkan: bind at most this many bytes per storage buffer when below the device's "
                 "maxStorageBufferRange, so that passes split and page their buffers on small frames (test use)")
      ->check(CLI::Range(std::size_t{4096}, std::size_t{1} << 40));
  rc->add_option("--max-groups", render.max_groups,
                 "Vulkan: launch at most this many workgroups per row when below the device's "
                 "maxComputeWorkGroupCount, so that large launches fold into rows (test use)")
      ->check(CLI::Range(1u, 65535u));
  rc->add_flag("--no-oracle", render.no_oracle, "Skip the oracle re-trace");
  rc->add_flag("--timings", render.timings, "Print time per phase (the thesis's phases) and tests per second");
  rc->add_flag("--progress", render.progress, "Print each pass and its time on stderr (default when stderr is a terminal)");
  rayspace::app::AccuracyArgs accuracy;
  CLI::App* ac = app.add_subcommand("accuracy", "Measure what accuracy costs: each precision mode of the cone-sphere and ray-triangle tests");
  ac->add_option("scene", accuracy.scene, "Scene JSON file")->required();
  ac->add_option("--data", accuracy.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  ac->add_option("--size", accuracy.size, "Image size WxH of the sampled frame (default 128x128)");
  ac->add_option("--samples", accuracy.samples, "Queries sampled per test (default 100000)");
  ac->add_option("--out", accuracy.out, "Directory for <scene>-accuracy.md, .csv and .png (default .)");
  ac->add_flag("!--no-end-to-end", accuracy.end_to_end, "Skip the frames with each cone-sphere mode");
#ifdef RAYSPACE_HAVE_VULKAN
  rayspace::app::DiffArgs diff;
  CLI::App* dc = app.add_subcommand("diff", "Run every pass of a frame on the emulator and the Vulkan kernels with the same inputs and compare bitwise");
  dc->add_option("scene", diff.scene, "Scene JSON file")->required();
  dc->add_option("--size", diff.size, "Image size WxH (overrides the scene)");
  dc->add_option("--data", diff.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  dc->add_option("--report", diff.report, "Write the comparison as JSON to this file");
  dc->add_option("--inject", diff.inject, "Plant a fault in one kernel: PASS[:FAULT] (test use)");
  dc->add_option("--local-size", diff.local_size, "Workgroup size of every compute kernel (results must not change)")
      ->check(CLI::Range(1, 1024));
  dc->add_option("--device", diff.device, "Vulkan device index (default: first non-CPU device, else lavapipe)")
      ->check(CLI::Range(0, 64));
  dc->add_option("--algo", diff.algo, "Tracer: crsh, rah, rah-quadtree (hierarchy passes diffed), brute or embree (host trace)")
      ->check(CLI::IsMember({"crsh", "rah", "rah-quadtree", "brute", "embree"}));
  dc->add_option("--subdivision", diff.subdivision, "Children per hierarchy node")->check(CLI::IsMember({4, 8, 16}));
  dc->add_option("--depth", diff.depth, "Hierarchy levels")->check(CLI::Range(1, 12));
  dc->add_option("--reduction", diff.reduction, "Stream reduction: hierarchical or scan")->check(CLI::IsMember({"hierarchical", "scan"}));
  dc->add_option("--save-inputs", diff.save_inputs, "Write every pass call's inputs to DIR/NNNN-PASS/ (for replay)");
  dc->add_option("--split-bytes", diff.split_bytes, "Vulkan: bind at most this many bytes per storage buffer (test use)")
      ->check(CLI::Range(std::size_t{4096}, std::size_t{1} << 40));
  dc->add_option("--max-groups", diff.max_groups, "Vulkan: launch at most this many workgroups per row (test use)")
      ->check(CLI::Range(1u, 65535u));
  rayspace::app::ReplayArgs replay;
  CLI::App* pc = app.add_subcommand("replay", "Run one pass call saved by diff --save-inputs on both backends and compare");
  pc->add_option("dir", replay.dir, "Directory of the saved call (DIR/NNNN-PASS)")->required();
  pc->add_option("--report", replay.report, "Write the comparison as JSON to this file");
  pc->add_option("--inject", replay.inject, "Plant a fault in one kernel: PASS[:FAULT] (test use)");
  pc->add_option("--local-size", replay.local_size, "Workgroup size of every compute kernel")->check(CLI::Range(1, 1024));
  pc->add_option("--device", replay.device, "Vulkan device index")->check(CLI::Range(0, 64));
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "rayspace: error: %s\n", e.what());
    return ToInt(ExitCode::kBadInput);
  }
  render.depth_given = depth->count() > 0;
  try {
    if (rc->parsed()) return ToInt(rayspace::app::RunRender(render));
    if (ac->parsed()) return ToInt(rayspace::app::RunAccuracy(accuracy));
#ifdef RAYSPACE_HAVE_VULKAN
    if (dc->parsed()) return ToInt(rayspace::app::RunDiff(diff));
    if (pc->parsed()) return ToInt(rayspace::app::RunReplay(replay));
#endif
  } catch (const rayspace::InputError& e) {
    std::fprintf(stderr, "rayspace: error: %s\n", e.what());
    return ToInt(ExitCode::kBadInput);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rayspace: failure: %s\n", e.what());
    return ToInt(ExitCode::kInternal);
  }
  return ToInt(ExitCode::kOk);
}
