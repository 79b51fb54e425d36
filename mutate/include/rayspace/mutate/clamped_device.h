// A device that clamps every out-of-bounds index (docs/verification.md, "A device that clamps"):
// the kernels compiled as the built-in ones are, then through `spirv-opt --graphics-robust-access`,
// which clamps each array index, private and shared arrays included, to the array's last element, as
// a driver with robustness features may. A kernel that only indexes within its arrays computes the
// same on it; a mutant that reads or writes one past a private array (invisible to lavapipe, which
// leaves such an access to LLVM) computes something else, and the diff sees it.
#pragma once
#include <cstddef>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "rayspace/mutate/mutate_runs.h"

namespace rayspace::app::mutate_runs {

using Overrides = std::vector<std::pair<std::string, std::string>>;  // (pass, kernel file)

// `kernels` (each a .comp) compiled and clamped into `dir`: the same passes, .spv files; false with
// the first error line.
bool Clamp(const Overrides& kernels, const std::filesystem::path& dir, Overrides& out, std::string& error);

// Whether the built-in kernels, clamped, diff equal in a configuration: checked once per
// configuration, on first use, from any thread.
class ClampedBaseline {
 public:
  ClampedBaseline(Frame frame, std::filesystem::path work) : frame_(std::move(frame)), work_(std::move(work)) {}
  // `builtins`: every built-in kernel the configuration runs, as overrides from the shader directory.
  bool Usable(std::size_t config_index, const Overrides& builtins, const std::string& scene);
  // Per configuration checked: equal, or why not.
  std::map<std::string, std::string> Results() const;

 private:
  Frame frame_;
  std::filesystem::path work_;
  mutable std::mutex mutex_;
  std::map<std::size_t, std::pair<bool, std::string>> checked_;
};

}  // namespace rayspace::app::mutate_runs
