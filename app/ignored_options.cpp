#include "ignored_options.h"

#include <cstdio>

#include <CLI/CLI.hpp>

#include "bench_command.h"
#include "bench_configs.h"
#include "rayspace/error.h"
#include "rayspace/frame/render_command.h"
#include "rayspace/frame/render_frame.h"

namespace rayspace::app {
namespace {

bool Given(const CLI::App& command, const std::string& name) {
  const CLI::Option* o = command.get_option_no_throw(name);
  return o && o->count() > 0;
}

// "--name VALUE" as given, for the warning.
std::string Shown(const CLI::App& command, const std::string& name) {
  const CLI::Option* o = command.get_option_no_throw(name);
  const std::vector<std::string> values = o->as<std::vector<std::string>>();
  return values.empty() ? name : name + " " + values.back();
}

void Note(std::vector<IgnoredOption>& out, const CLI::App& command, const std::string& name, const std::string& why) {
  if (Given(command, name)) out.push_back({Shown(command, name), why});
}

void NoteHierarchyOptions(std::vector<IgnoredOption>& out, const CLI::App& command, const FrameArgs& args, bool fused) {
  const std::string flat = "--algo " + args.algo + " traces without the hierarchy";
  if (args.algo != "tl")
    for (const char* name : {"--lists", "--node-order", "--polygon-heads"}) Note(out, command, name, "only --algo tl walks traversal lists");
  if (args.algo != "grid")
    for (const char* name : {"--grid-cells", "--grid-regular", "--grid-regular-cells", "--grid-area", "--grid-area-near", "--grid-secondary", "--closed-models"}) Note(out, command, name, "only --algo grid builds grids");
  if (!args.Hierarchy()) {
    for (const char* name : {"--subdivision", "--levels", "--reduction", "--component-size", "--pair-capacity", "--objects",
                             "--hash-order", "--hash-bits"})
      Note(out, command, name, flat);
    if (args.algo != "tl")
      for (const char* name : {"--tree-leaf", "--tree-big"}) Note(out, command, name, flat);
    // A preset sets them as if given: only the user's own are noted.
    if (args.faithful.preset == "none")
      for (const char* name : {"--cone-test", "--leaf-test", "--child-merge"}) Note(out, command, name, flat);
    return;
  }
  if (args.algo != "crsh")
    for (const char* name : {"--hash-order", "--hash-bits"}) Note(out, command, name, "--algo " + args.algo + " does not hash its rays");
  if (args.algo == "rah-quadtree") Note(out, command, "--subdivision", "rah-quadtree always subdivides by 4 (2x2 tiles)");
  if (args.objects == "flat") {
    Note(out, command, "--tree-leaf", "--objects flat builds no object tree");
    Note(out, command, "--tree-big", "--objects flat builds no object tree");
  }
  // The fused path compacts each level, and each object-tree round, inside its test pass: the
  // reduction runs only with the passes.
  if (fused) {
    Note(out, command, "--reduction", "the fused path (--path) compacts without the reduction, which --path passes runs");
    Note(out, command, "--component-size", "the fused path (--path) compacts without the reduction, which --path passes runs");
  } else if (args.reduction == "scan") {
    Note(out, command, "--component-size", "only --reduction hierarchical has components");
  }
}

}  // namespace

std::vector<IgnoredOption> IgnoredFrameOptions(const CLI::App& command, const FrameArgs& args, bool fused) {
  std::vector<IgnoredOption> out;
  NoteHierarchyOptions(out, command, args, fused);
  return out;
}

std::vector<IgnoredOption> IgnoredRenderOptions(const CLI::App& command, const RenderArgs& args) {
  std::vector<IgnoredOption> out = IgnoredFrameOptions(command, args, args.Hierarchy() && UsesFusedPath(args));
  const bool direct_runs = args.algo == "brute" || (args.algo == "embree" && !args.no_oracle);
  if (!direct_runs)
    Note(out, command, "--direct",
         args.algo == "embree" ? "the direct tracer is embree's oracle, and --no-oracle skips it"
                               : "--algo " + args.algo + " runs no direct tracer (its oracle is embree)");
  // --algo grid: --path passes runs grid.trace's per-ray pass, the others its lanes (grid.h).
  if (!args.Hierarchy() && args.algo != "grid") Note(out, command, "--path", "--algo " + args.algo + " traces without the hierarchy");
  if (args.backend == "emu")
    for (const char* name : {"--device", "--split-bytes", "--max-groups"})
      Note(out, command, name, "--backend emu runs on the host, without a Vulkan device");
  if (args.backend == "sim") Note(out, command, "--device", "--backend sim runs on the simulated GPU, no Vulkan device");
  return out;
}

std::vector<IgnoredOption> IgnoredBenchOptions(const CLI::App& command, const BenchArgs& args) {
  std::vector<IgnoredOption> out;
  try {
    for (const BenchConfig* c : ParseBenchConfigs(args.configs.empty() ? DefaultBenchConfigs() : args.configs))
      if (c->backend == "vulkan") return out;
  } catch (const InputError&) {
    return out;
  }
  Note(out, command, "--device", "no configuration of --configs runs on Vulkan");
  return out;
}

void WarnIgnored(const std::string& cmd, const std::vector<IgnoredOption>& ignored) {
  for (const IgnoredOption& i : ignored)
    std::fprintf(stderr, "rayspace %s: warning: %s is ignored: %s\n", cmd.c_str(), i.option.c_str(), i.why.c_str());
}

}  // namespace rayspace::app
