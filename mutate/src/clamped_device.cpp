#include "rayspace/mutate/clamped_device.h"

#include <fmt/format.h>

namespace rayspace::app::mutate_runs {
namespace fs = std::filesystem;

bool Clamp(const Overrides& kernels, const fs::path& dir, Overrides& out, std::string& error) {
  fs::create_directories(dir);
  out.clear();
  std::map<std::string, std::string> done;  // kernel file -> its clamped module (sort.comp serves three passes)
  for (const auto& [pass, file] : kernels) {
    auto it = done.find(file);
    if (it == done.end()) {
      const fs::path plain = dir / (fs::path(file).filename().string() + ".spv");
      const fs::path clamped = dir / (fs::path(file).filename().string() + ".clamped.spv");
      if (!Compile(file, plain, error) || !Optimize(plain, clamped, {"--graphics-robust-access"}, error)) return false;
      it = done.emplace(file, clamped.string()).first;
    }
    out.emplace_back(pass, it->second);
  }
  return true;
}

bool ClampedBaseline::Usable(std::size_t config_index, const Overrides& builtins, const std::string& scene) {
  const std::lock_guard<std::mutex> lock(mutex_);  // one check per configuration; the others wait for it
  if (const auto it = checked_.find(config_index); it != checked_.end()) return it->second.first;
  const DiffConfig& config = Configs()[config_index];
  const fs::path dir = work_ / "baseline" / ("clamped-" + config.name);
  Overrides clamped;
  std::string error;
  std::pair<bool, std::string> result{false, ""};
  if (!Clamp(builtins, dir, clamped, error)) {
    result.second = "the built-in kernels do not clamp: " + error;
  } else {
    const DiffRun run = RunDiff(frame_, config, clamped, dir, scene);
    result = {run.code == 0, run.code == 0 ? "equal" : fmt::format("the clamped built-in kernels do not diff equal (exit {}: {})", run.code, run.last_line)};
  }
  checked_[config_index] = result;
  return result.first;
}

std::map<std::string, std::string> ClampedBaseline::Results() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::string, std::string> out;
  for (const auto& [c, r] : checked_) out[Configs()[c].name] = r.second;
  return out;
}

}  // namespace rayspace::app::mutate_runs
