// The configurations `rayspace bench` runs, as the render options that make each: one table. Every
// tracer of kAlgorithms (frame_args.h) is a configuration under its own name with render's defaults;
// the variants table adds the same tracer run another way (the kernels' passes, the Vulkan backend).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "rayspace/frame/render_command.h"

namespace rayspace::app {

struct BenchConfig {
  std::string name;
  std::string render;  // the render options that make the row: `rayspace render SCENE <render>`, exactly
  std::string what;    // why the row is there, for --help
  // Read from `render` through render's own parser (ApplyRenderOptions), for the report.
  std::string algo, path, backend, objects;
  bool levels_auto = false;
};

// The configuration every ratio is taken against.
inline constexpr std::string_view kBaselineConfig = "embree";

// Every configuration, in the default order: the baseline, then each --algo followed by its variants.
const std::vector<BenchConfig>& BenchConfigs();
// Their names, comma-separated (the default of --configs).
std::string DefaultBenchConfigs();
// "name: what" per configuration, for --help.
std::string BenchConfigsHelp();

// Parses a comma-separated --configs list; an unknown or repeated name is an InputError naming it and
// listing the known ones.
std::vector<const BenchConfig*> ParseBenchConfigs(const std::string& list);

// Applies the configuration's render options to `args`, as `rayspace render` parses them.
void ApplyBenchConfig(const BenchConfig& config, RenderArgs& args);

}  // namespace rayspace::app
