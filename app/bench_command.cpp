#include "bench_command.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <utility>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bench_configs.h"
#include "bench_report.h"
#include "bench_run.h"
#include "rayspace/frame/command_util.h"
#include "rayspace/frame/memory_estimate.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/json_text.h"
#include "rayspace/parallel.h"
#include "rayspace/frame/render_frame.h"

namespace rayspace::app {
namespace {

// --sizes W1xH1[,W2xH2...], each as --size takes it.
std::vector<std::pair<int, int>> ParseSizes(const std::string& list) {
  std::vector<std::pair<int, int>> sizes;
  std::stringstream ss(list);
  std::string one;
  while (std::getline(ss, one, ',')) {
    int w = 0, h = 0;
    ParseSize(one, w, h, "--sizes");
    sizes.emplace_back(w, h);
  }
  if (sizes.empty()) ThrowInput("--sizes '{}': expected WxH[,WxH...], e.g. 256x256,512x512", list);
  return sizes;
}

// Every input and the JSON file are checked before the first frame: a bad path should not wait for the
// runs before it.
OutputFile CheckInputsAndOutput(const BenchArgs& args) {
  OutputOptions o{"the JSON file", true, true, {}};
  for (const std::string& s : args.scenes) {
    if (const std::string why = NotRegularFile(s); !why.empty()) ThrowInput("{}: cannot open scene file: it {}", s, why);
    o.inputs.emplace_back(s);
  }
  return args.json.empty() ? OutputFile() : OutputFile(args.json, std::move(o));
}

// Every size of every scene must fit the machine before the first frame runs, so that a size too large
// for one scene is refused at once rather than after the frames before it. Each scene is loaded here
// only for its counts, then let go. A frame is estimated as the configuration that holds the most
// (a Vulkan or pass-by-pass one holds more: RenderMemoryUse).
void CheckBenchMemory(const BenchArgs& args, const std::vector<std::pair<int, int>>& sizes,
                      const std::vector<const BenchConfig*>& configs) {
  LoadOptions lo;
  lo.data_root = args.data;
  for (const std::string& path : args.scenes) {
    const Scene scene = LoadScene(path, lo);
    for (const auto& [w, h] : sizes) {
      MemoryEstimate most;
      for (const BenchConfig* c : configs) {
        RenderArgs a;
        ApplyBenchConfig(*c, a);
        const MemoryEstimate e = EstimateFrameMemory(scene, w, h, RenderMemoryUse(a));
        if (e.total > most.total) most = e;
      }
      CheckFitsMachine(most, w, h, "--sizes", fmt::format("a frame of {}", path).c_str());
    }
  }
}

// Each configuration at each size of one scene, the scene loaded once.
void RunScene(const BenchArgs& args, const std::string& path, const std::vector<std::pair<int, int>>& sizes,
              const std::vector<const BenchConfig*>& configs, std::vector<BenchRow>& rows) {
  LoadOptions lo;
  lo.data_root = args.data;
  const Scene scene = LoadScene(path, lo);
  const SceneBuffers buffers = FlattenForFrame(scene, args.faithful);
  RenderArgs base;
  base.scene = path;
  base.data = args.data;
  base.device = args.device;
  base.faithful = args.faithful;
  const bool progress = args.progress || isatty(STDERR_FILENO);
  // Repetitions in rounds: each round runs every configuration once, so a machine whose speed drifts
  // (a shared one) shifts every configuration's frames alike and the ratios of one run hold.
  for (const auto& [w, h] : sizes) {
    const std::size_t first = rows.size();
    for (const BenchConfig* c : configs) rows.push_back(StartBenchRow(base, *c, scene, w, h));
    for (int rep = 0; rep < args.repetitions; ++rep)
      for (std::size_t i = first; i < rows.size(); ++i) RunBenchRepetition(rows[i], scene, buffers, args.repetitions, progress);
  }
}

}  // namespace

ExitCode RunBench(const BenchArgs& args) {
  const std::vector<std::pair<int, int>> sizes = ParseSizes(args.sizes);
  std::vector<const BenchConfig*> configs = ParseBenchConfigs(args.configs.empty() ? DefaultBenchConfigs() : args.configs);
  // The object tree has only the conservative test: without --configs its configurations are left out,
  // a named one is refused before the first frame.
  if (args.faithful.cone_test != "conservative") {
    if (args.configs.empty()) std::erase_if(configs, [](const BenchConfig* c) { return c->objects == "tree"; });
    for (const BenchConfig* c : configs)
      if (c->objects == "tree")
        ThrowInput("--cone-test {}: configuration '{}' traces the object tree, which has only the conservative test",
                   args.faithful.cone_test, c->name);
  }
  OutputFile json = CheckInputsAndOutput(args);
  const ScopedSettings threads([&](Settings& s) { s.threads = args.threads > 0 ? args.threads : s.threads; });
  CheckBenchMemory(args, sizes, configs);

  std::vector<BenchRow> rows;
  for (const std::string& path : args.scenes) RunScene(args, path, sizes, configs, rows);
  std::printf("rayspace bench: %zu scene%s, %zu size%s, %zu configuration%s, %d thread%s\n\n", args.scenes.size(),
              args.scenes.size() == 1 ? "" : "s", sizes.size(), sizes.size() == 1 ? "" : "s", configs.size(),
              configs.size() == 1 ? "" : "s", ThreadCount(), ThreadCount() == 1 ? "" : "s");
  PrintBenchTable(stdout, rows, args.repetitions);
  if (sizes.size() > 1) PrintGrowthTable(stdout, rows);
  std::fflush(stdout);
  const bool agree = CheckDigests(stdout, stderr, rows);
  return WriteOutputs(agree ? ExitCode::kOk : ExitCode::kDivergence, [&] {
    json.Commit(JsonText(BenchJson(rows, args.repetitions, ThreadCount())));
    if (!json.empty() && !json.is_stdout()) std::printf("JSON: %s\n", args.json.c_str());
  });
}

}  // namespace rayspace::app
