// The scene data a run needs, checked before any scene is loaded: every file the manifest
// (scenes/manifest.json, embedded at build time) lists for a scene must be under the data root with
// its size and SHA-256, so the same inputs give the same numbers anywhere.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace rayspace::data {

// The data root a command uses: the given --data, else $RAYSPACE_DATA, else "" (none). Every command
// that reads data resolves it here, so none of them ignores the variable.
std::string DataRoot(const std::string& given);

// One file that is missing or differs; `message` is one line naming the file, what differs and
// where to get it.
struct Problem {
  std::string scene;  // the scene JSON's file name
  std::string file;   // the path under the data root
  std::string message;
};

// The files each scene needs: the manifest's list for a bundled scene (matched by the JSON's file
// name), else the scene's meshes that are not beside it. Each file is hashed once per process.
std::vector<Problem> CheckSceneData(const std::vector<std::filesystem::path>& scenes, const std::filesystem::path& data_root);

// The same with a given manifest (JSON text), for tests.
std::vector<Problem> CheckSceneData(const std::vector<std::filesystem::path>& scenes, const std::filesystem::path& data_root,
                                    const std::string& manifest_json);

// The embedded manifest's text, and the scene JSON names it lists.
const char* EmbeddedManifest();
std::vector<std::string> ManifestScenes(const std::string& manifest_json);

// The SHA-256 of a file in lowercase hex (OpenSSL's EVP); throws InputError when it cannot be read.
std::string Sha256File(const std::filesystem::path& path);

}  // namespace rayspace::data
