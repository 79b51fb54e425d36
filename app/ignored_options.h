// Options a run was given but does not use (a hierarchy option with a direct tracer, a Vulkan option
// on the emulator): each is named in one warning line on stderr, so that a flag that changes nothing
// is not mistaken for one that changed nothing measurable. The exit code is not changed.
#pragma once
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace rayspace::app {

struct BenchArgs;
struct FrameArgs;
struct RenderArgs;

struct IgnoredOption {
  std::string option, why;
};

// The frame options (AddFrameOptions) given on `command` that `args` makes unused; `fused`: the
// hierarchy runs traverse.compact, without the reduction.
std::vector<IgnoredOption> IgnoredFrameOptions(const CLI::App& command, const FrameArgs& args, bool fused);
// render's: the frame options, and --direct, --path and the Vulkan options where they do nothing.
std::vector<IgnoredOption> IgnoredRenderOptions(const CLI::App& command, const RenderArgs& args);
// bench's: --device when no configuration runs on Vulkan (a bad --configs is left to the run).
std::vector<IgnoredOption> IgnoredBenchOptions(const CLI::App& command, const BenchArgs& args);
// Prints "rayspace <cmd>: warning: <option> is ignored: <why>" for each.
void WarnIgnored(const std::string& cmd, const std::vector<IgnoredOption>& ignored);

}  // namespace rayspace::app
