// The processes `rayspace mutate` runs: the pass-by-pass diff with some kernels replaced, under a
// time limit, and glslc / spirv-opt for equivalence checks and variants; and what their results mean.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace rayspace::app::mutate_runs {

// The diff configurations whose passes, together, run every kernel and its rarer paths (`--algo`,
// `--objects`, `--path`, the limits that split and fold dispatches, an area light, refraction).
struct DiffConfig {
  std::string name;
  std::vector<std::string> flags;
  // The frame's scene: "" the command's; "glass" the command's with its first material made glass;
  // else a bundled scene (scenes/NAME).
  std::string scene;
  std::string size = "";  // "" the command's --size
};
const std::vector<DiffConfig>& Configs();

struct Frame {
  std::string scene, data, size;
  int timeout = 60;
  std::string backends;  // diff's and replay's --backends ("": their default)
};

// A diff run: its exit code (124 or 137 when the time limit killed it), its report (null when it
// wrote none) and the last line of its output.
struct DiffRun {
  int code = 0;
  nlohmann::json report;
  std::string last_line, log;
  bool TimedOut() const { return code == 124 || code == 137; }
  double seconds = 0;
};
// `rayspace diff` of the frame under `config`, each (pass, file) replacing the pass's kernel; files
// and logs in `dir`.
// `scene` replaces the frame's when not empty.
DiffRun RunDiff(const Frame& frame, const DiffConfig& config, const std::vector<std::pair<std::string, std::string>>& kernels,
                const std::filesystem::path& dir, const std::string& scene = "");
// `rayspace replay` of a saved call (a kernel case) with the same kernel overrides, under the time
// limit; files and logs in `dir`.
DiffRun RunReplay(const std::filesystem::path& call, const std::vector<std::pair<std::string, std::string>>& kernels,
                  const std::filesystem::path& dir, int timeout, const std::string& backends = "");
// The scene a configuration renders, written into `work` when it is derived ("glass"); "" when the
// command's scene has no material to make glass.
std::string SceneFor(const DiffConfig& config, const std::string& scene, const std::filesystem::path& work);

// What a mutant's diff says: "killed", "survived", "stillborn" (does not compile) or "invalid" (the
// contract check refused it); for a kill, what caught it.
struct Verdict {
  std::string status, reason;
  nlohmann::json caught;  // pass, call label, buffer comparison (first mismatching element)
};
Verdict Classify(const DiffRun& run);

// The kernels' GLSL: the install's or the source tree's (rayspace/install_paths.h).
std::filesystem::path ShaderDir();
// Compiles a kernel as the built-in kernels are compiled (glslc -O0, Vulkan 1.2, the file's folder
// first on the include path); false with the first error line in `error`.
bool Compile(const std::filesystem::path& comp, const std::filesystem::path& spv, std::string& error);
// spirv-opt with `recipe` (its arguments); false with the first error line.
bool Optimize(const std::filesystem::path& in, const std::filesystem::path& out, const std::vector<std::string>& recipe, std::string& error);
// The module's disassembly with its global declarations (types, constants, decorations) sorted:
// two modules that differ only in the order of those compare equal; "" when it cannot be read.
std::string Canonical(const std::filesystem::path& spv);
std::string ReadFile(const std::filesystem::path& p);
void WriteFile(const std::filesystem::path& p, const std::string& text);

}  // namespace rayspace::app::mutate_runs
