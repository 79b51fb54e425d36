// rayspace command-line interface.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "rayspace/workgroup.h"
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
  rayspace::app::AddFrameOptions(*rc, render);
  rc->add_option("--out", render.out, "Output image (PNG); default <scene name>.png in the current directory");
  rc->add_option("--stats", render.stats, "Write statistics as JSON to this file");
  rc->add_option("--threads", render.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  rc->add_option("--direct", render.direct, "Direct tracer mode: auto, exhaustive or bvh")
      ->check(CLI::IsMember({"auto", "exhaustive", "bvh"}));
  rc->add_option("--backend", render.backend,
                 "Where the passes run: emu (the CPU emulation) or vulkan (the GLSL kernels; same bits expected)")
      ->check(CLI::IsMember({"emu", "vulkan"}));
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
  CLI::App* dc = app.add_subcommand("diff",
                                    "Run every pass of a frame on the emulator and the Vulkan kernels with the same "
                                    "inputs and compare bitwise (with --algo brute or embree the traces run on the "
                                    "host)");
  dc->add_option("scene", diff.scene, "Scene JSON file")->required();
  rayspace::app::AddFrameOptions(*dc, diff);
  dc->add_option("--report", diff.report, "Write the comparison as JSON to this file");
  dc->add_option("--inject", diff.inject, "Plant a fault in one kernel: PASS[:FAULT][@emu], FAULT a number or a "
                 "workgroup fault's name; @emu plants it in the emulated kernel (test use)");
  rayspace::app::AddLocalSizeOption(*dc, diff.local_size);
  dc->add_option("--save-inputs", diff.save_inputs, "Write every pass call's inputs to DIR/NNNN-PASS/ (for replay)");
  rayspace::app::ReplayArgs replay;
  CLI::App* pc = app.add_subcommand("replay", "Run one pass call saved by diff --save-inputs on both backends and compare");
  pc->add_option("dir", replay.dir, "Directory of the saved call (DIR/NNNN-PASS)")->required();
  pc->add_option("--report", replay.report, "Write the comparison as JSON to this file");
  pc->add_option("--inject", replay.inject, "Plant a fault in one kernel: PASS[:FAULT][@emu] (test use)");
  rayspace::app::AddKernelModelOptions(*pc, replay.model);
  rayspace::app::AddLocalSizeOption(*pc, replay.local_size);
  rayspace::app::AddKernelOption(*pc, replay.kernels);
  rayspace::app::AddDeviceOption(*pc, replay.device);
  rayspace::app::AddLimitOptions(*pc, replay.split_bytes, replay.max_groups);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "rayspace: error: %s\n", e.what());
    return ToInt(ExitCode::kBadInput);
  }
  rayspace::wg::SetChecking(false);  // unless a command asks: --check-workgroups, an @emu fault
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
  } catch (const rayspace::wg::CheckError& e) {
    std::fprintf(stderr, "rayspace: workgroup checker: %s\n", e.what());
    return ToInt(ExitCode::kWorkgroupFault);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rayspace: failure: %s\n", e.what());
    return ToInt(ExitCode::kInternal);
  }
  return ToInt(ExitCode::kOk);
}
