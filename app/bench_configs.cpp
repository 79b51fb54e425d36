#include "bench_configs.h"

#include <sstream>

#include "rayspace/frame/frame_args.h"
#include "render_options.h"
#include "rayspace/error.h"

namespace rayspace::app {
namespace {

// Variants of a tracer: a later way of running one adds one row here; a later tracer needs no row
// (it is in kAlgorithms). Configurations of one --algo must give the same frame digest.
struct Variant {
  const char* name;
  const char* render;
  const char* what;
};
const Variant kVariants[] = {
    {"crsh-passes", "--algo crsh --path passes", "the kernels' passes on the emulator"},
    {"crsh-flat", "--algo crsh --objects flat", "every triangle of each object a top node reaches (the thesis's)"},
    {"crsh-tree", "--algo crsh --objects tree", "each object's bounding-sphere tree descended with the cone hierarchy"},
    {"crsh-levels-auto", "--algo crsh --levels auto", "levels from the image's pixels"},
    {"vulkan", "--algo crsh --backend vulkan", "the GLSL kernels, levels fused; skipped without a device"},
    {"vulkan-passes", "--algo crsh --backend vulkan --path passes", "the GLSL kernels pass by pass"},
    {"vulkan-tree", "--algo crsh --backend vulkan --objects tree", "crsh-tree with the GLSL kernels"},
    {"vulkan-tl", "--algo tl --backend vulkan", "tl with the GLSL kernels"},
    {"vulkan-grid", "--algo grid --backend vulkan", "grid with the GLSL kernel"},
};

BenchConfig Made(std::string name, std::string render, std::string what) {
  BenchConfig c;
  c.name = std::move(name);
  c.render = std::move(render);
  c.what = std::move(what);
  RenderArgs parsed;
  ApplyRenderOptions(c.render, parsed);
  c.algo = parsed.algo;
  c.path = parsed.path;
  c.backend = parsed.backend;
  c.objects = parsed.objects;
  c.levels_auto = parsed.depth_auto;
  return c;
}

std::vector<BenchConfig> MakeConfigs() {
  std::vector<BenchConfig> variants, out;
  for (const Variant& v : kVariants) variants.push_back(Made(v.name, v.render, v.what));
  auto add_algo = [&](std::string_view algo) {
    out.push_back(Made(std::string(algo), "--algo " + std::string(algo), "render's defaults"));
    for (const BenchConfig& v : variants)
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
  for (const BenchConfig& c : BenchConfigs()) s += (s.empty() ? "" : "; ") + c.name + ": render " + c.render + " (" + c.what + ")";
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

void ApplyBenchConfig(const BenchConfig& config, RenderArgs& args) { ApplyRenderOptions(config.render, args); }

}  // namespace rayspace::app
