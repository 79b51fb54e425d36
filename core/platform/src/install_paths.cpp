#include "rayspace/install_paths.h"

#include <system_error>

namespace rayspace {
namespace fs = std::filesystem;

namespace {

// The install's layout (cmake/package.cmake installs these).
DataPaths Installed(const fs::path& prefix) {
  const fs::path share = prefix / "share" / "rayspace";
  return {share / "shaders", prefix / "include", share / "scenes", share / "mutation-survivors.json", "install " + prefix.string()};
}

}  // namespace

DataPaths FindDataPaths(const fs::path& prefix) {
  if (!prefix.empty()) return Installed(prefix);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path candidate = exe.parent_path().parent_path();
    if (fs::is_directory(candidate / "share" / "rayspace" / "shaders", ec)) return Installed(candidate);
  }
  const fs::path src = RAYSPACE_SOURCE_TREE;
  return {src / "gpu" / "shaders", src / "core" / "contract" / "include", src / "scenes", src / "docs" / "mutation-survivors.json",
          "source tree " + src.string()};
}

}  // namespace rayspace
