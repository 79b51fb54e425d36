// Where `rayspace reproduce` keeps its results: one file per configuration, DIR/results/<key>.json,
// named by a hash of the scene's content, the configuration's canonical text and the version, and
// DIR/run.json, the run's manifest (every key of the run and which shard this directory holds).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/shard.h"

#include <nlohmann/json.hpp>

#include "rayspace/reproduce/configs.h"
#include "rayspace/reproduce/counts.h"

namespace rayspace::reproduce {

// The version results are keyed by: results of another version are measured again.
std::string Version();

// The hash of every file the scene was read from (its JSON and meshes), in order.
std::string SceneDigest(const std::vector<std::filesystem::path>& files);
std::string ResultKey(const std::string& scene_digest, const std::string& canonical, const std::string& version);

struct Result {
  std::string key, scene_digest;
  Config config;
  Counts counts;
  nlohmann::json statistics;  // the frame's statistics as `render --stats` writes them
  nlohmann::json timings;     // per phase, ms: varies run to run
};
nlohmann::json ToJson(const Result& r);
// Throws InputError naming `what` when a field is missing or malformed.
Result ResultFromJson(const nlohmann::json& j, const std::string& what);
// A result's pass time (its timings' "passes"), summed over the passes whose name starts with
// `prefix` (grid.trace covers grid.trace.primary.b0, ...), or over those named exactly `prefix`.
double PassMs(const Result& r, const std::string& prefix, bool exact = false);

// Writes `text` as the whole file at `path`, atomically; `what` names it in errors.
void WriteText(const std::filesystem::path& path, const std::string& text, const char* what);

std::filesystem::path ResultPath(const std::filesystem::path& dir, const std::string& key);
// Writes the result atomically (temporary file, renamed into place; removed on SIGINT).
void WriteResult(const std::filesystem::path& dir, const Result& r);
// The stored result when its file exists, parses and holds `key`; nothing otherwise.
std::optional<Result> ReadResult(const std::filesystem::path& dir, const std::string& key);


struct Manifest {
  std::string run;                // a hash of every key of the run
  std::vector<std::string> keys;  // every configuration of the run, sorted
  Shard shard;
  std::vector<std::string> Slice() const;  // this shard's keys: every count-th from index
};
Manifest MakeManifest(std::vector<std::string> keys, Shard shard);
void WriteManifest(const std::filesystem::path& dir, const Manifest& m);
std::optional<Manifest> ReadManifest(const std::filesystem::path& dir);  // throws InputError when malformed

// Checks that `shards` (their directories beside them) are shards of one run covering each shard index
// exactly once. Throws InputError naming the directory or the missing or duplicate shard.
void CheckCoverage(const std::vector<std::pair<std::string, Manifest>>& shards);

}  // namespace rayspace::reproduce
