// Checks a run's scenes and their data before any is loaded, so that a missing file stops the run at
// once, naming it, rather than after the configurations before it.
#pragma once
#include <filesystem>
#include <vector>

namespace rayspace::reproduce {

// Throws InputError naming the first scene file that cannot be read. The data a scene names under
// `data_root` is checked when the scene loads (LoadScene names a missing mesh); a data manifest with
// checksums would be checked here.
void CheckSceneData(const std::vector<std::filesystem::path>& scenes, const std::filesystem::path& data_root);

}  // namespace rayspace::reproduce
