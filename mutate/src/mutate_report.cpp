// `rayspace mutate`: the equivalent variants (spirv-opt recipes) and the scores.
#include <cstdio>
#include <filesystem>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/mutate/mutants.h"
#include "rayspace/mutate/mutate_command.h"
#include "rayspace/mutate/mutate_runs.h"
#include "rayspace/error.h"
#include "rayspace/shard.h"
#include "rayspace/pass_registry.h"

namespace rayspace::app {
namespace fs = std::filesystem;
using mutate_runs::DiffConfig;
using nlohmann::json;

namespace {

// spirv-opt recipes that keep every float operation as written: the standard optimisation sets and
// single passes that move control flow and code but never reassociate or contract arithmetic.
const std::vector<std::pair<std::string, std::vector<std::string>>>& Recipes() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> recipes = {
      {"O", {"-O"}},
      {"Os", {"-Os"}},
      {"merge-blocks", {"--merge-blocks"}},
      {"inline", {"--inline-entry-points-exhaustive"}},
      {"dead-code", {"--eliminate-dead-code-aggressive"}},
      {"local-ssa", {"--inline-entry-points-exhaustive", "--eliminate-local-multi-store"}},
      {"if-conversion", {"--inline-entry-points-exhaustive", "--eliminate-local-multi-store", "--if-conversion"}},
  };
  return recipes;
}

std::vector<std::string> PassesOf(const std::string& kernel_file) {
  std::vector<std::string> out;
  for (const PassSpec& p : kPasses)
    if (!p.graphics && std::string(p.kernel) + ".comp" == kernel_file) out.emplace_back(p.name);
  return out;
}

json RunVariant(const std::string& kernel, const std::pair<std::string, std::vector<std::string>>& recipe, const DiffConfig& config,
                const std::string& scene, const mutate_runs::Frame& frame, const fs::path& dir) {
  fs::create_directories(dir);
  json j = {{"kernel", kernel}, {"recipe", recipe.first}, {"spirv_opt", recipe.second}, {"config", config.name}};
  std::string err;
  const fs::path base = dir / (kernel + ".spv"), variant = dir / (kernel + "." + recipe.first + ".spv");
  if (!mutate_runs::Compile(mutate_runs::ShaderDir() / kernel, base, err) || !mutate_runs::Optimize(base, variant, recipe.second, err)) {
    j["status"] = "error";
    j["reason"] = err;
    return j;
  }
  std::vector<std::pair<std::string, std::string>> kernels;
  for (const std::string& p : PassesOf(kernel)) kernels.emplace_back(p, variant.string());
  const mutate_runs::DiffRun run = mutate_runs::RunDiff(frame, config, kernels, dir, scene);
  const mutate_runs::Verdict v = mutate_runs::Classify(run);
  j["status"] = v.status == "survived" ? "equal" : v.status == "killed" ? "diverged" : "error";
  j["seconds"] = run.seconds;
  if (!v.reason.empty() && v.status != "survived") j["reason"] = v.reason;
  if (!v.caught.empty()) j["caught"] = v.caught;
  if (j["status"] == "diverged") {
    std::string flags;
    for (const std::string& f : config.flags) flags += " " + f;
    std::string overrides;
    for (const auto& [p, f] : kernels) overrides += " --kernel " + p + "=" + f;
    j["reproducer"] = fmt::format("rayspace diff {} --size {}{}{} --save-inputs calls/ && rayspace export calls/NNNN-PASS --out repro/",
                                  scene, frame.size, flags, overrides);
  }
  return j;
}

}  // namespace

json RunVariants(const MutateArgs& args, const std::vector<std::string>& kernels,
                 const std::map<std::string, std::pair<const DiffConfig*, std::string>>& config_of, const mutate_runs::Frame& frame,
                 const fs::path& work, std::uint64_t seed, const Shard& shard, std::size_t& chosen) {
  std::vector<std::pair<std::string, std::size_t>> pairs;  // kernel, recipe
  for (const std::string& k : kernels)
    for (std::size_t r = 0; r < Recipes().size(); ++r) pairs.emplace_back(k, r);
  std::size_t count = pairs.size();
  if (args.variants != "all") {
    char* end = nullptr;
    const unsigned long n = std::strtoul(args.variants.c_str(), &end, 10);
    if (args.variants.empty() || *end != '\0') ThrowInput("--variants '{}': a count or 'all'", args.variants);
    count = std::min<std::size_t>(n, pairs.size());
  }
  const std::vector<std::size_t> order = mutate::Shuffled(pairs.size(), seed ^ 0x5A17ull);
  chosen = count;
  json out = json::array();
  for (std::size_t i = 0; i < count; ++i) {
    if (!shard.Holds(i)) continue;
    const auto& [kernel, r] = pairs[order[i]];
    const auto& [config, scene] = config_of.at(kernel);
    json j = RunVariant(kernel, Recipes()[r], *config, scene, frame, work / "variants" / fmt::format("{:03}", i));
    j["index"] = i;
    std::printf("  variant %s through spirv-opt %s: %s\n", kernel.c_str(), Recipes()[r].first.c_str(), j["status"].get<std::string>().c_str());
    std::fflush(stdout);
    out.push_back(j);
  }
  return out;
}

void PrintScores(const json& summary, const json& variants) {
  std::printf("  %-24s %7s %7s %9s %10s %9s %7s  %s\n", "file", "killed", "survived", "equivalent", "stillborn", "invalid", "score", "passes");
  for (const auto& [file, c] : summary["per_file"].items()) {
    std::string passes;
    for (const json& p : c["passes"]) passes += (passes.empty() ? "" : ", ") + p.get<std::string>();
    std::printf("  %-24s %7zu %7zu %9zu %10zu %9zu %6.0f%%  %s\n", file.c_str(), c["killed"].get<std::size_t>(), c["survived"].get<std::size_t>(),
                c["equivalent"].get<std::size_t>(), c["stillborn"].get<std::size_t>(), c["invalid"].get<std::size_t>(),
                100.0 * c["score"].get<double>(), passes.c_str());
  }
  std::size_t equal = 0, diverged = 0;
  for (const json& v : variants) equal += v["status"] == "equal", diverged += v["status"] == "diverged";
  std::printf("  mutants: %zu killed, %zu survived (%zu unexplained), %zu equivalent, %zu stillborn, %zu invalid; score %.1f%% "
              "(killed / (killed + survived))\n",
              summary["killed"].get<std::size_t>(), summary["survived"].get<std::size_t>(), summary["unexplained_survivors"].get<std::size_t>(),
              summary["equivalent"].get<std::size_t>(), summary["stillborn"].get<std::size_t>(), summary["invalid"].get<std::size_t>(),
              100.0 * summary["score"].get<double>());
  std::printf("  variants: %zu equal, %zu diverged, %zu errors\n", equal, diverged, variants.size() - equal - diverged);
}

}  // namespace rayspace::app
