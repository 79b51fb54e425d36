#include "rayspace/reproduce/store.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <mutex>
#include <regex>

#include <fmt/format.h>

#include "rayspace/digest.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/json_text.h"
#include "rayspace/output_file.h"

namespace rayspace::reproduce {
namespace {

std::string ReadText(const std::filesystem::path& path) {
  return ReadInputFile(path, {"reproduce result", kMaxTextFileBytes});  // regular files only, bounded
}

// OutputFile registers its temporary file with the signal handler; jobs write results concurrently.
std::mutex g_output_mutex;

}  // namespace

void WriteText(const std::filesystem::path& path, const std::string& text, const char* what) {
  std::lock_guard<std::mutex> lock(g_output_mutex);
  OutputFile f(path.string(), OutputOptions{what, false, true, {}});
  f.Commit(text);
}

namespace {

nlohmann::json ConfigJson(const Config& c) {
  nlohmann::json j = {{"target", c.target}, {"scene", c.scene},       {"scene_file", c.scene_file}, {"algo", c.algo},
                      {"subdivision", c.subdivision}, {"levels", c.levels}, {"bounces", c.bounces},
                      {"width", c.width},   {"height", c.height},     {"canonical", c.Canonical()}};
  // Only when set: results without them read as before.
  if (!c.path.empty()) j["path"] = c.path;
  if (!c.faithful.empty()) j["faithful"] = c.faithful;
  if (c.one_object) j["one_object"] = true;
  if (!c.switches.empty()) j["switches"] = c.switches;
  if (c.tl()) j["lists"] = c.lists, j["node_order"] = c.node_order;
  if (c.cull) j["cull"] = true;
  if (!c.heads.empty()) j["heads"] = c.heads;
  if (c.primary) j["primary"] = true;
  if (c.frustum) j["frustum"] = true;
  if (!c.grid_area.empty()) j["grid_area"] = c.grid_area;
  if (c.grid_regular_cells) j["grid_regular_cells"] = c.grid_regular_cells;
  if (c.threads > 0) j["threads"] = c.threads;
  return j;
}

Config ConfigFromJson(const nlohmann::json& j) {
  Config c;
  j.at("target").get_to(c.target);
  j.at("scene").get_to(c.scene);
  j.at("scene_file").get_to(c.scene_file);
  j.at("algo").get_to(c.algo);
  j.at("subdivision").get_to(c.subdivision);
  j.at("levels").get_to(c.levels);
  j.at("bounces").get_to(c.bounces);
  j.at("width").get_to(c.width);
  j.at("height").get_to(c.height);
  c.faithful = j.value("faithful", std::string());
  c.one_object = j.value("one_object", false);
  c.switches = j.value("switches", std::vector<std::string>());
  c.path = j.value("path", std::string());
  c.lists = j.value("lists", 0u);
  c.node_order = j.value("node_order", std::string());
  c.cull = j.value("cull", false);
  c.heads = j.value("heads", std::string());
  c.primary = j.value("primary", false);
  c.frustum = j.value("frustum", false);
  c.grid_area = j.value("grid_area", std::string());
  c.grid_regular_cells = j.value("grid_regular_cells", std::uint64_t{0});
  c.threads = j.value("threads", 0);
  return c;
}

}  // namespace

std::string Version() { return RAYSPACE_REPRODUCE_VERSION; }

std::string SceneDigest(const std::vector<std::filesystem::path>& files) {
  std::uint64_t h = 0;
  for (const std::filesystem::path& f : files) {
    const std::string text = ReadText(f);
    h = HashBytes(text.data(), text.size(), h);
  }
  return HexDigest(h);
}

std::string ResultKey(const std::string& scene_digest, const std::string& canonical, const std::string& version) {
  const std::string text = scene_digest + "\n" + canonical + "\n" + version;
  return HexDigest(HashBytes(text.data(), text.size()));
}

nlohmann::json ToJson(const Result& r) {
  return {{"key", r.key},       {"version", Version()},         {"scene_digest", r.scene_digest},
          {"config", ConfigJson(r.config)}, {"counts", r.counts}, {"statistics", r.statistics},
          {"timings", r.timings}};
}

double PassMs(const Result& r, const std::string& prefix, bool exact) {
  double ms = 0;
  for (const nlohmann::json& p : r.timings.value("passes", nlohmann::json::array())) {
    const std::string name = p.value("pass", std::string());
    if (exact ? name == prefix : name.rfind(prefix, 0) == 0) ms += p.value("ms", 0.0);
  }
  return ms;
}

Result ResultFromJson(const nlohmann::json& j, const std::string& what) {
  try {
    Result r;
    j.at("key").get_to(r.key);
    j.at("scene_digest").get_to(r.scene_digest);
    r.config = ConfigFromJson(j.at("config"));
    j.at("counts").get_to(r.counts);
    r.statistics = j.at("statistics");
    r.timings = j.at("timings");
    return r;
  } catch (const nlohmann::json::exception& e) {
    ThrowInput("{}: not a reproduce result: {}", what, e.what());
  }
}

std::filesystem::path ResultPath(const std::filesystem::path& dir, const std::string& key) {
  return dir / "results" / (key + ".json");
}

void WriteResult(const std::filesystem::path& dir, const Result& r) {
  std::filesystem::create_directories(dir / "results");
  WriteText(ResultPath(dir, r.key), JsonText(ToJson(r)), "a reproduce result");
}

std::optional<Result> ReadResult(const std::filesystem::path& dir, const std::string& key) {
  const std::filesystem::path path = ResultPath(dir, key);
  if (!std::filesystem::is_regular_file(path)) return std::nullopt;
  nlohmann::json j;
  try {
    j = ParseJson(ReadText(path));
  } catch (const JsonError&) {
    return std::nullopt;  // a result half-written by a killed run is made again
  }
  try {
    Result r = ResultFromJson(j, path.string());
    if (r.key != key) return std::nullopt;
    return r;
  } catch (const InputError&) {
    return std::nullopt;
  }
}

std::vector<std::string> Manifest::Slice() const {
  std::vector<std::string> slice;
  for (std::size_t i = static_cast<std::size_t>(shard.index); i < keys.size(); i += static_cast<std::size_t>(shard.count))
    slice.push_back(keys[i]);
  return slice;
}

Manifest MakeManifest(std::vector<std::string> keys, Shard shard) {
  std::sort(keys.begin(), keys.end());
  std::string all;
  for (const std::string& k : keys) all += k + "\n";
  return {HexDigest(HashBytes(all.data(), all.size())), std::move(keys), shard};
}

void WriteManifest(const std::filesystem::path& dir, const Manifest& m) {
  const nlohmann::json j = {{"run", m.run}, {"version", Version()}, {"keys", m.keys},
                            {"shard", {{"index", m.shard.index}, {"count", m.shard.count}}}};
  WriteText(dir / "run.json", JsonText(j), "the run manifest");
}

std::optional<Manifest> ReadManifest(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "run.json";
  if (!std::filesystem::exists(path)) return std::nullopt;
  nlohmann::json j;
  try {
    try {
      j = ParseJson(ReadText(path));
    } catch (const JsonError& e) {
      ThrowInput("not JSON ({})", e.what());
    }
    Manifest m;
    j.at("run").get_to(m.run);
    j.at("keys").get_to(m.keys);
    j.at("shard").at("index").get_to(m.shard.index);
    j.at("shard").at("count").get_to(m.shard.count);
    if (m.shard.count < 1 || m.shard.index < 0 || m.shard.index >= m.shard.count) ThrowInput("shard out of range");
    return m;
  } catch (const std::exception& e) {
    ThrowInput("{}: not a reproduce run manifest: {}", path.string(), e.what());
  }
}

void CheckCoverage(const std::vector<std::pair<std::string, Manifest>>& shards) {
  RS_CHECK(!shards.empty());
  const auto& [first_dir, first] = shards.front();
  std::vector<std::string> seen(static_cast<std::size_t>(first.shard.count));
  for (const auto& [dir, m] : shards) {
    if (m.run != first.run || m.keys != first.keys)
      ThrowInput("{}: holds another run than {} (run {} vs {})", dir, first_dir, m.run, first.run);
    if (m.shard.count != first.shard.count)
      ThrowInput("{}: shard {}/{}, but {} is one of {}", dir, m.shard.index, m.shard.count, first_dir, first.shard.count);
    std::string& slot = seen[static_cast<std::size_t>(m.shard.index)];
    if (!slot.empty()) ThrowInput("shard {}/{} given twice: {} and {}", m.shard.index, m.shard.count, slot, dir);
    slot = dir;
  }
  for (std::size_t i = 0; i < seen.size(); ++i)
    if (seen[i].empty()) ThrowInput("shard {}/{} is missing", i, first.shard.count);
}

}  // namespace rayspace::reproduce
