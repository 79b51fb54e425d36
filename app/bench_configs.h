// The configurations `rayspace bench` runs, as the render options that make each: one table. Every
// tracer of kAlgorithms (frame_args.h) is a configuration under its own name with render's defaults;
// the variants table adds the same tracer run another way (the kernels' passes, the Vulkan backend).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "render_command.h"

namespace rayspace::app {

struct BenchConfig {
  std::string name;
  std::string algo;              // render --algo
  std::string path = "auto";     // render --path
  std::string backend = "emu";   // render --backend
  std::string what;              // one line for --help
  std::string objects = "flat";  // render --objects
  std::string levels;            // render --levels (empty: render's default)
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

// Sets args' tracer, path and backend to the configuration's.
void ApplyBenchConfig(const BenchConfig& config, RenderArgs& args);

}  // namespace rayspace::app
