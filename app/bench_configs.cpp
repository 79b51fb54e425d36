#include "bench_configs.h"

#include <sstream>

#include "frame_args.h"
#include "rayspace/error.h"

namespace rayspace::app {
namespace {

// Variants of a tracer: a later way of running one adds one row here; a later tracer needs no row
// (it is in kAlgorithms). Configurations of one --algo must give the same frame digest.
const BenchConfig kVariants[] = {
    {"crsh-passes", "crsh", "passes", "emu", "crsh with the kernels' passes on the emulator (render --path passes)"},
    {"crsh-tree", "crsh", "auto", "emu", "crsh descending each object's bounding-sphere tree with the cone hierarchy (render --objects tree)", "tree"},
    {"crsh-auto", "crsh", "auto", "emu", "crsh with flat or tree chosen per ray batch, render's default (render --objects auto)", "auto"},
    {"crsh-levels-auto", "crsh", "auto", "emu", "crsh with its levels from the image's pixels (render --levels auto)", "flat", "auto"},
    {"vulkan", "crsh", "fused", "vulkan", "crsh with the GLSL kernels, levels fused (render --backend vulkan; skipped without a device)"},
    {"vulkan-passes", "crsh", "passes", "vulkan", "crsh with the GLSL kernels pass by pass (render --backend vulkan --path passes)"},
    {"vulkan-tree", "crsh", "fused", "vulkan", "crsh-tree with the GLSL kernels (render --backend vulkan --objects tree)", "tree"},
    {"vulkan-tl", "tl", "auto", "vulkan", "tl with the GLSL kernels (render --backend vulkan --algo tl)"},
    {"vulkan-grid", "grid", "auto", "vulkan", "grid with the GLSL kernel (render --backend vulkan --algo grid)"},
};

std::vector<BenchConfig> MakeConfigs() {
  std::vector<BenchConfig> out;
  auto add_algo = [&out](std::string_view algo) {
    out.push_back({std::string(algo), std::string(algo), "auto", "emu", "render --algo " + std::string(algo)});
    for (const BenchConfig& v : kVariants)
      if (v.algo == algo) out.push_back(v);
  };
  add_algo(kBaselineConfig);
  for (const Algorithm& a : kAlgorithms)
    if (a.name != kBaselineConfig) add_algo(a.name);
  return out;
}

}  // namespace

const std::vector<BenchConfig>& BenchConfigs() {
  static const std::vector<BenchConfig> configs = MakeConfigs();
  return configs;
}

std::string DefaultBenchConfigs() {
  std::string s;
  for (const BenchConfig& c : BenchConfigs()) s += (s.empty() ? "" : ",") + c.name;
  return s;
}

std::string BenchConfigsHelp() {
  std::string s;
  for (const BenchConfig& c : BenchConfigs()) s += (s.empty() ? "" : "; ") + c.name + ": " + c.what;
  return s;
}

std::vector<const BenchConfig*> ParseBenchConfigs(const std::string& list) {
  std::vector<const BenchConfig*> out;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const BenchConfig* found = nullptr;
    for (const BenchConfig& c : BenchConfigs())
      if (c.name == name) found = &c;
    if (!found) ThrowInput("--configs '{}': no configuration named '{}'; known: {}", list, name, DefaultBenchConfigs());
    for (const BenchConfig* c : out)
      if (c == found) ThrowInput("--configs '{}': '{}' is given twice", list, name);
    out.push_back(found);
  }
  if (out.empty()) ThrowInput("--configs '{}': expected one or more of {}", list, DefaultBenchConfigs());
  return out;
}

void ApplyBenchConfig(const BenchConfig& config, RenderArgs& args) {
  args.algo = config.algo;
  args.path = config.path;
  args.backend = config.backend;
  args.objects = config.objects;
  if (config.levels == "auto") args.depth_auto = args.depth_given = true;
}

}  // namespace rayspace::app
