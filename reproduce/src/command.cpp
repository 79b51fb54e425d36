#include "rayspace/reproduce/command.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <regex>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <unistd.h>

#include "rayspace/image_size.h"
#include "rayspace/output_file.h"
#include "rayspace/data_check.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/merge_objects.h"
#include "rayspace/parallel.h"
#include "rayspace/plot.h"
#include "rayspace/reproduce/fit_thesis.h"
#include "rayspace/reproduce/report.h"
#include "rayspace/reproduce/roger.h"
#include "rayspace/reproduce/hunt.h"
#include "rayspace/reproduce/toczek.h"
#include "rayspace/settings.h"

namespace rayspace::reproduce {
namespace {

namespace fs = std::filesystem;

// The thesis's frame is 512x512; --quick's 128x128 keeps every ray type and level (a quarter of each side).
constexpr int kFullSide = 512, kQuickSide = 128;

void FrameSize(const ReproduceArgs& args, int& w, int& h) {
  if (args.quick && args.full) ThrowInput("--quick and --full exclude each other");
  w = h = args.full ? kFullSide : kQuickSide;
  if (!args.size.empty()) ParseSize(args.size, w, h);
}

// One implemented target's configurations at the run's frame size (roger's figure 13(c) adds half and
// twice the side; --full runs every level of detail of the bunny, --quick the two lowest).
std::vector<Config> TargetConfigs(const std::string& target, const ReproduceArgs& args, int w, int h) {
  if (target == "roger") return RogerConfigs(w, h, args.full);
  if (target == "hunt-mark") return HuntConfigs(w, h);
  // The paper's frames are 1024x1024: --full measures at that size unless --size says otherwise.
  if (target == "toczek") {
    const bool paper = args.full && args.size.empty();
    return ToczekConfigs(paper ? kToczekFullSide : w, paper ? kToczekFullSide : h);
  }
  if (target == "thesis-ablation") return AblationConfigs(args.scenes, w, h);
  return ThesisConfigs(args.scenes, w, h);
}

// The configurations of the implemented targets asked for; a skipped target is said on stderr.
std::vector<Config> Configurations(const ReproduceArgs& args) {
  const std::vector<std::string> targets = args.targets.empty() ? std::vector<std::string>{"thesis"} : args.targets;
  for (const std::string& t : targets)
    if (!FindTarget(t)) {
      std::string names;
      for (const Target& k : Targets()) names += (names.empty() ? "" : ", ") + k.name;
      ThrowInput("unknown target '{}' (targets: {})", t, names);
    }
  int w = 0, h = 0;
  FrameSize(args, w, h);
  std::vector<Config> configs;
  for (const std::string& t : targets) {
    const Target* target = FindTarget(t);
    if (!target->skip_reason.empty()) {
      std::fprintf(stderr, "rayspace reproduce: skipping %s: %s\n", t.c_str(), target->skip_reason.c_str());
      continue;
    }
    for (const Config& c : TargetConfigs(t, args, w, h)) configs.push_back(c);
  }
  if (!args.only.empty()) {
    std::regex re;
    try {
      re = std::regex(args.only);
    } catch (const std::regex_error& e) {
      ThrowInput("--only '{}': not a regular expression: {}", args.only, e.what());
    }
    std::erase_if(configs, [&](const Config& c) { return !std::regex_search(c.Name(), re); });
    if (configs.empty()) ThrowInput("--only '{}': matches no configuration (see --list)", args.only);
  }
  return configs;
}

ExitCode List(const ReproduceArgs& args) {
  int w = 0, h = 0;
  FrameSize(args, w, h);
  for (const Target& t : Targets()) {
    if (!t.skip_reason.empty()) {
      std::printf("%-9s skipped: %s (%s)\n", t.name.c_str(), t.skip_reason.c_str(), t.what.c_str());
      continue;
    }
    for (const Config& c : TargetConfigs(t.name, args, w, h))
      std::printf("%-9s %-34s rayspace render %s\n", t.name.c_str(), c.Name().c_str(), c.RenderArgs().c_str());
  }
  return ExitCode::kOk;
}

// Every scene file readable and every data file its scene needs present with the manifest's size and
// SHA-256, before the first frame: a run of hours must not stop at its last scene, nor measure other
// data than the published numbers were compared with.
void CheckScenesAndData(const std::vector<fs::path>& scenes, const std::string& data_root) {
  for (const fs::path& s : scenes)
    if (const std::string why = NotRegularFile(s.string()); !why.empty())
      ThrowInput("{}: cannot open scene file: it {} (--scenes names the directory of the scene files)", s.string(), why);
  const std::vector<data::Problem> problems = data::CheckSceneData(scenes, data_root);
  if (!problems.empty() && data_root.empty())
    ThrowInput("{} (no data root: give --data DIR or set RAYSPACE_DATA)", problems.front().message);
  if (problems.size() == 1) ThrowInput("{}", problems.front().message);
  if (!problems.empty())
    ThrowInput("{} (and {} more: `rayspace data check --data {}` lists them)", problems.front().message, problems.size() - 1,
               data_root);
}

// A scene as the frames read it: its file, and whether its objects are merged into one.
std::string SceneKey(const Config& c) { return c.scene_file + (c.one_object ? " one-object" : ""); }

// Loads each scene file once per object layout, with the bounces its configurations trace.
std::map<std::string, LoadedScene> LoadScenes(const std::vector<Config>& configs, const ReproduceArgs& args) {
  std::vector<fs::path> paths;
  for (const Config& c : configs)
    if (std::find(paths.begin(), paths.end(), fs::path(args.scenes) / c.scene_file) == paths.end())
      paths.push_back(fs::path(args.scenes) / c.scene_file);
  const std::string data_root = data::DataRoot(args.data);
  CheckScenesAndData(paths, data_root);
  std::map<std::string, LoadedScene> scenes;
  LoadOptions lo;
  lo.data_root = data_root;
  for (const Config& c : configs) {
    if (scenes.count(SceneKey(c))) continue;
    LoadedScene& s = scenes[SceneKey(c)];
    s.scene = LoadScene(fs::path(args.scenes) / c.scene_file, lo);
    s.scene.max_depth = c.bounces;
    s.buffers = FlattenScene(s.scene);
    if (c.one_object) MergeObjects(s.buffers);
    s.digest = SceneDigest(s.scene.files);
  }
  return scenes;
}

// Refuses an output directory that holds another run's results (or another shard of this one).
void CheckOutDir(const fs::path& out, const Manifest& run) {
  if (!fs::exists(out)) return;
  if (!fs::is_directory(out)) ThrowInput("--out {}: not a directory", out.string());
  const std::optional<Manifest> old = ReadManifest(out);
  const bool has_results = fs::exists(out / "results") && !fs::is_empty(out / "results");
  if (old ? (old->run != run.run || old->shard != run.shard) : has_results)
    ThrowInput("--out {}: holds results of another run; give another --out (or remove it)", out.string());
}

std::vector<Result> ReadRun(const fs::path& dir, const std::vector<std::string>& keys) {
  std::vector<Result> results;
  for (const std::string& k : keys) {
    std::optional<Result> r = ReadResult(dir, k);
    if (!r) ThrowInput("{}: result {} is missing or unreadable", dir.string(), ResultPath(dir, k).string());
    results.push_back(std::move(*r));
  }
  return results;
}

}  // namespace

namespace {
// --junit FILE, checked before the run ("-": standard output).
OutputFile JUnitOutput(const std::string& path) {
  return path.empty() ? OutputFile() : OutputFile(path, OutputOptions{"the JUnit report", true, true, {}});
}
}  // namespace

// `--fit`: the thesis's Sponza camera and light (docs/reproduce.md, "Fits"). The record and the fitted
// scene go into --out; committing them (reproduce/fits/, scenes/) is the user's step.
ExitCode RunFit(const ReproduceArgs& args, const FrameFn& frame) {
  for (const std::string& t : args.targets)
    if (t != "thesis")
      ThrowInput("--fit {0}: only the thesis's fit (Sponza's camera and light) searches; the other papers' unknowns take few "
                 "values, each measured by `rayspace reproduce {0}` itself, which reports the fit (docs/reproduce.md, \"Fits\")", t);
  if (args.shard != "0/1" || !args.only.empty() || args.resume || !args.junit.empty() || args.quick || args.full || !args.size.empty())
    ThrowInput("--fit takes none of --shard, --only, --resume, --junit, --quick, --full, --size: its frame sizes are the protocol's");
  Config sponza;
  for (const Config& c : ThesisConfigs(args.scenes, 512, 512))
    if (c.scene == "SPONZA" && c.algo == "rah" && c.faithful.empty()) sponza = c;
  sponza.scene_file = "sponza-thesis.json";  // the fit starts from the hand-chosen scene, whatever is fitted already
  const std::map<std::string, LoadedScene> scenes = LoadScenes({sponza}, args);
  FitOptions o;
  o.scene_file = fs::path(args.scenes) / sponza.scene_file;
  o.progress = args.progress || isatty(STDERR_FILENO);
  if (args.fit_small) o.screen = 8, o.keep = 2, o.lights = 2, o.starts = 1, o.halvings = 1, o.frames_per_start = 6;
  o.protocol = args.fit_protocol > 0 ? args.fit_protocol : kFitProtocolLatest;
  nlohmann::json record = FitThesisSponza(scenes.begin()->second, o, frame);
  fs::create_directories(args.out);
  // Every frame of the search apart from the summary the report reads (the binary carries it).
  nlohmann::json frames = nlohmann::json::object();
  for (const nlohmann::json& r : record["refine"]) record["starts"].push_back({{"start", r.at("start")}, {"end", r.at("end")}});
  for (const char* stage : {"screen", "grid", "refine"}) frames[stage] = std::move(record[stage]), record.erase(stage);
  const std::string stem = FitRecordStem(o.protocol), scene_name = FittedSceneStem(o.protocol) + ".json";
  WriteText(fs::path(args.out) / (stem + "-frames.json"), frames.dump() + "\n", "the fit's frames");
  WriteText(fs::path(args.out) / (stem + ".json"), record.dump(1) + "\n", "the fit's record");
  const nlohmann::json scene_file = nlohmann::json::parse(ReadInputFile(o.scene_file, {"scene file", kMaxTextFileBytes}));
  WriteText(fs::path(args.out) / scene_name, FittedSceneJson(scene_file, record).dump(2) + "\n", "the fitted scene");
  std::printf("rayspace reproduce --fit (protocol %d): %d frames, J = %s; %s (%s beside it) and %s\n", o.protocol,
              record.at("frames").get<int>(), record.at("best").at("J").dump().c_str(), (fs::path(args.out) / (stem + ".json")).c_str(),
              (stem + "-frames.json").c_str(), (fs::path(args.out) / scene_name).c_str());
  return ExitCode::kOk;
}

ExitCode RunReproduce(const ReproduceArgs& args, const FrameFn& frame) {
  if (args.list) return List(args);
  if (args.fit) return RunFit(args, frame);
  if (args.fit_small) ThrowInput("--fit-small: only with --fit");
  if (args.fit_protocol > 0) ThrowInput("--fit-protocol: only with --fit");
  const Shard shard = ParseShard(args.shard);
  if (!args.junit.empty() && shard.count > 1)
    ThrowInput("--junit with --shard {}: a shard writes no report; give --junit to reproduce merge", args.shard);
  OutputFile junit = JUnitOutput(args.junit);
  if (shard.count == 1) plot::CheckTool();  // the report's plots: refuse before hours of frames, not after
  const std::vector<Config> configs = Configurations(args);
  if (configs.empty()) return ExitCode::kOk;
  const std::map<std::string, LoadedScene> scenes = LoadScenes(configs, args);
  std::vector<Planned> planned;
  std::vector<std::string> keys;
  for (const Config& c : configs) {
    const LoadedScene& s = scenes.at(SceneKey(c));
    planned.push_back({c, ResultKey(s.digest, c.Canonical(), Version()), &s});
    keys.push_back(planned.back().key);
  }
  const Manifest manifest = MakeManifest(keys, shard);
  const fs::path out = args.out;
  CheckOutDir(out, manifest);
  fs::create_directories(out / "results");
  WriteManifest(out, manifest);
  const std::vector<std::string> slice = manifest.Slice();
  std::vector<Planned> todo;
  for (const Planned& p : planned)
    if (std::find(slice.begin(), slice.end(), p.key) != slice.end() && !(args.resume && ReadResult(out, p.key)))
      todo.push_back(p);
  std::sort(todo.begin(), todo.end(), [](const Planned& a, const Planned& b) { return a.key < b.key; });
  const ScopedSettings threads([&](Settings& s) {
    s.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / std::max(1, args.jobs));
  });
  RunPlanned(todo, {out, args.jobs, args.stop_after, args.progress || isatty(STDERR_FILENO)}, frame);
  if (shard.count > 1) {
    std::fprintf(stderr, "rayspace reproduce: shard %d/%d: %zu results in %s; combine the shards with rayspace reproduce merge\n",
                 shard.index, shard.count, slice.size(), (out / "results").c_str());
    return ExitCode::kOk;
  }
  junit.Commit(ReportJUnit(WriteReport(out, ReadRun(out, manifest.keys))));
  std::printf("rayspace reproduce: %zu configurations (%zu measured now); report: %s\n", keys.size(), todo.size(),
              (out / "report.md").c_str());
  return ExitCode::kOk;
}

ExitCode RunMerge(const ReproduceArgs& args) {
  plot::CheckTool();
  OutputFile junit = JUnitOutput(args.junit);
  std::vector<std::pair<std::string, Manifest>> shards;
  for (const std::string& d : args.merge_dirs) {
    if (!fs::is_directory(d)) ThrowInput("{}: no such directory", d);
    std::optional<Manifest> m = ReadManifest(d);
    if (!m) ThrowInput("{}: no run.json: not a directory of rayspace reproduce", d);
    shards.emplace_back(d, std::move(*m));
  }
  CheckCoverage(shards);
  const Manifest whole = MakeManifest(shards.front().second.keys, {0, 1});
  const fs::path out = args.merge_out;
  CheckOutDir(out, whole);
  std::vector<Result> results;
  for (const auto& [dir, m] : shards)
    for (Result& r : ReadRun(dir, m.Slice())) results.push_back(std::move(r));
  fs::create_directories(out / "results");
  WriteManifest(out, whole);
  for (const Result& r : results) WriteResult(out, r);
  junit.Commit(ReportJUnit(WriteReport(out, ReadRun(out, whole.keys))));
  std::printf("rayspace reproduce merge: %zu shards, %zu configurations; report: %s\n", shards.size(), results.size(),
              (out / "report.md").c_str());
  return ExitCode::kOk;
}

}  // namespace rayspace::reproduce
