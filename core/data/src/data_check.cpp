#include <cstdlib>
#include "rayspace/data_check.h"

#include <fstream>
#include <map>
#include <mutex>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "manifest_text.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/json_text.h"

namespace rayspace::data {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json ParseManifest(const std::string& text) {
  try {
    return ParseJson(text);
  } catch (const JsonError& e) {
    ThrowInput("data manifest: not JSON ({})", e.what());
  }
}

// Each file's SHA-256, computed once per process however many scenes need it.
const std::string& CachedSha256(const fs::path& path) {
  static std::mutex mutex;
  static std::map<fs::path, std::string> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(path);
  if (it == cache.end()) it = cache.emplace(path, Sha256File(path)).first;
  return it->second;
}

// Where to get a file, from its manifest entry and its source's SOURCE.txt.
std::string WhereToGet(const json& manifest, const json& entry) {
  const json& src = manifest["sources"][entry["source"].get<std::string>()];
  const std::string url = entry.value("url", "");
  if (entry.value("obtained", "copy") == "converted")
    return fmt::format("converted from {} as {} states", url, src.value("source_file", "the SOURCE.txt"));
  return fmt::format("get it from {}", url);
}

// The problem with one listed file, or an empty string.
std::string CheckFile(const json& manifest, const json& entry, const fs::path& root) {
  const std::string rel = entry["path"].get<std::string>();
  const fs::path full = root / rel;
  std::error_code ec;
  if (!fs::is_regular_file(full, ec))
    return fmt::format("{}: missing under the data root {} ({})", rel, root.string(), WhereToGet(manifest, entry));
  const std::uintmax_t size = fs::file_size(full, ec), want = entry["size"].get<std::uintmax_t>();
  if (ec || size != want)
    return fmt::format("{}: {} bytes, the manifest says {} ({})", rel, size, want, WhereToGet(manifest, entry));
  const std::string& sha = CachedSha256(full);
  if (sha != entry["sha256"].get<std::string>())
    return fmt::format("{}: SHA-256 {}, the manifest says {}: a different file ({})", rel, sha,
                       entry["sha256"].get<std::string>(), WhereToGet(manifest, entry));
  return {};
}

// The data-root files a scene not in the manifest needs: its meshes not found beside it.
std::vector<std::string> MeshesOf(const fs::path& scene) {
  json j;
  try {
    j = ParseJson(ReadInputFile(scene, {"scene file", kMaxTextFileBytes}));
  } catch (const JsonError& e) {
    ThrowInput("{}: not JSON ({})", scene.string(), e.what());
  }
  std::vector<std::string> meshes;
  for (const json& o : j.value("objects", json::array()))
    if (o.is_object() && o.contains("mesh") && o["mesh"].is_string()) {
      const std::string mesh = o["mesh"].get<std::string>();
      std::error_code ec;
      if (!fs::path(mesh).is_absolute() && !fs::exists(scene.parent_path() / mesh, ec)) meshes.push_back(mesh);
    }
  return meshes;
}

// One scene's problems.
void CheckScene(const json& manifest, const fs::path& scene, const fs::path& root, std::vector<Problem>& out) {
  const std::string name = scene.filename().string();
  const json& listed = manifest["scenes"];
  const std::vector<std::string> files =
      listed.contains(name) ? listed[name].get<std::vector<std::string>>() : MeshesOf(scene);
  for (const std::string& rel : files) {
    const json* entry = nullptr;
    for (const json& e : manifest["files"])
      if (e["path"] == rel) entry = &e;
    std::string message;
    if (entry) {
      message = CheckFile(manifest, *entry, root);
    } else if (std::error_code ec; !fs::is_regular_file(root / rel, ec)) {
      message = fmt::format("{}: missing under the data root {} (the data manifest does not list it)", rel, root.string());
    }
    if (!message.empty()) out.push_back({name, rel, message});
  }
}

}  // namespace

std::string DataRoot(const std::string& given) {
  if (!given.empty()) return given;
  const char* env = std::getenv("RAYSPACE_DATA");
  return env ? std::string(env) : std::string();
}

std::vector<Problem> CheckSceneData(const std::vector<fs::path>& scenes, const fs::path& data_root, const std::string& manifest_json) {
  const json manifest = ParseManifest(manifest_json);
  std::vector<Problem> problems;
  for (const fs::path& scene : scenes) CheckScene(manifest, scene, data_root, problems);
  return problems;
}

std::vector<Problem> CheckSceneData(const std::vector<fs::path>& scenes, const fs::path& data_root) {
  return CheckSceneData(scenes, data_root, EmbeddedManifest());
}

const char* EmbeddedManifest() { return kManifestText; }

std::vector<std::string> ManifestScenes(const std::string& manifest_json) {
  const json manifest = ParseManifest(manifest_json);  // held: the loop below reads into it
  std::vector<std::string> names;
  for (const auto& [name, files] : manifest["scenes"].items()) names.push_back(name);
  return names;
}

}  // namespace rayspace::data
