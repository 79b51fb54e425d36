#include "data_command.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

#include "rayspace/data_check.h"
#include "rayspace/error.h"
#include "rayspace/scene.h"

namespace rayspace::app {
namespace {

namespace fs = std::filesystem;

// A scene argument: a JSON file, or a bundled scene's name with or without ".json".
fs::path SceneArgument(const std::string& arg, const std::vector<std::string>& bundled) {
  std::error_code ec;
  if (fs::is_regular_file(arg, ec)) return arg;
  const std::string name = arg.size() > 5 && arg.ends_with(".json") ? arg : arg + ".json";
  if (std::find(bundled.begin(), bundled.end(), name) != bundled.end()) return name;
  std::string list;
  for (const std::string& b : bundled) list += (list.empty() ? "" : ", ") + b.substr(0, b.size() - 5);
  ThrowInput("data check: scene '{}' is neither a file nor a bundled scene ({})", arg, list);
}

}  // namespace

ExitCode RunDataCheck(const DataCheckArgs& args) {
  const std::string root = data::DataRoot(args.data);
  if (root.empty()) ThrowInput("data check: no data root: give --data DIR or set RAYSPACE_DATA (docs/data.md)");
  if (std::error_code ec; !fs::is_directory(root, ec)) ThrowInput("data check: --data {}: not a directory", root);
  const std::vector<std::string> bundled = data::ManifestScenes(data::EmbeddedManifest());
  std::vector<fs::path> scenes;
  for (const std::string& s : args.scenes) scenes.push_back(SceneArgument(s, bundled));
  if (args.scenes.empty())
    for (const std::string& b : bundled) scenes.emplace_back(b);
  std::size_t problems = 0;
  for (const fs::path& scene : scenes) {
    std::vector<data::Problem> found = data::CheckSceneData({scene}, root);
    // A scene file of the user's is loaded too, as render would (its fields, its meshes), so that
    // "ok" means the scene renders; the bundled ones are loaded by the tests.
    if (std::error_code ec; found.empty() && fs::is_regular_file(scene, ec)) {
      try {
        LoadScene(scene, LoadOptions{root});
      } catch (const InputError& e) {
        found.push_back({scene.filename().string(), scene.string(), e.what()});
      }
    }
    if (found.empty()) std::printf("%s: ok\n", scene.filename().c_str());
    for (const data::Problem& p : found) std::printf("%s: problem: %s\n", p.scene.c_str(), p.message.c_str());
    problems += found.size();
  }
  if (problems == 0) return ExitCode::kOk;
  std::fprintf(stderr, "rayspace: error: data check: %zu problem%s (files missing or different under %s, or a scene that does not load)\n",
               problems, problems == 1 ? "" : "s", root.c_str());
  return ExitCode::kBadInput;
}

}  // namespace rayspace::app
