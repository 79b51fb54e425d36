#include "rayspace/mutate/mutate_command.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/mutate/clamped_device.h"
#include "rayspace/mutate/kernel_cases.h"
#include "rayspace/mutate/mutants.h"
#include "rayspace/mutate/mutate_runs.h"
#include "rayspace/mutate/mutate_shards.h"
#include "rayspace/mutate/mutate_junit.h"
#include "rayspace/shard.h"
#include "rayspace/input_file.h"
#include "rayspace/install_paths.h"
#include "rayspace/json_text.h"
#include "rayspace/error.h"
#include "rayspace/output_file.h"
#include "rayspace/pass_registry.h"
#include "rayspace/frame/version.h"
#include "rayspace/settings.h"

namespace rayspace::app {
namespace fs = std::filesystem;
using mutate_runs::DiffConfig;
using nlohmann::json;

namespace {

// A kernel file and the passes that run it (sort.comp: compress, sort, decompress).
struct Kernel {
  std::vector<std::string> passes;
  std::set<std::string> includes;  // every file of the shader directory it includes, transitively
};

std::map<std::string, Kernel> Kernels() {
  std::map<std::string, Kernel> out;
  for (const PassSpec& p : kPasses)
    if (!p.graphics) out[std::string(p.kernel) + ".comp"].passes.emplace_back(p.name);
  for (auto& [file, k] : out) {
    std::vector<std::string> todo = mutate::Includes(mutate_runs::ReadFile(mutate_runs::ShaderDir() / file));
    while (!todo.empty()) {
      const std::string inc = todo.back();
      todo.pop_back();
      if (!fs::exists(mutate_runs::ShaderDir() / inc) || !k.includes.insert(inc).second) continue;
      for (const std::string& more : mutate::Includes(mutate_runs::ReadFile(mutate_runs::ShaderDir() / inc))) todo.push_back(more);
    }
  }
  return out;
}

// A file to mutate, the configurations whose diffs run it (in order: a mutant runs in the first,
// and in the next ones only while it survives), and per configuration the kernels to replace.
struct Target {
  std::string file;
  std::vector<std::size_t> configs;
  std::vector<std::vector<std::string>> kernels;  // per entry of configs: kernel files compiled from the mutant's directory
  std::vector<std::string> passes;                // the passes those kernels serve
};

// A kernel case (kernel_cases.h) saved for replay.
struct SavedCase {
  std::string name, pass;
  fs::path dir;
};

struct Baseline {
  std::vector<std::set<std::string>> passes;  // per configuration: the passes its diff ran (none: skipped)
  std::vector<std::string> scenes;            // per configuration: the scene it renders
  std::map<std::string, Kernel> kernels;      // every kernel file, read once
  std::vector<SavedCase> cases;
  std::unique_ptr<mutate_runs::ClampedBaseline> clamped;  // checked lazily, from the mutants' threads
  json configs = json::array(), case_runs = json::array();
};

Baseline RunBaseline(const mutate_runs::Frame& frame, const std::vector<std::string>& only, const fs::path& work) {
  Baseline b;
  const auto& configs = mutate_runs::Configs();
  bool own_checked = false;  // the first wanted configuration on the command's scene has run
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const bool wanted = only.empty() || std::find(only.begin(), only.end(), configs[c].name) != only.end();
    const std::string scene = wanted ? mutate_runs::SceneFor(configs[c], frame.scene, work / "baseline") : "";
    json j = {{"name", configs[c].name}, {"flags", configs[c].flags}, {"scene", scene}};
    std::set<std::string> ran;
    if (!wanted) {
      j["skipped"] = "not asked for (--config)";
    } else if (scene.empty()) {
      j["skipped"] = "the scene has no material to make glass";
    } else {
      const mutate_runs::DiffRun run = mutate_runs::RunDiff(frame, configs[c], {}, work / "baseline" / configs[c].name, scene);
      // The first configuration on the command's own scene must diff equal (else mutants mean
      // nothing); a later one may not fit the scene (limits), a derived scene may not suit it: left out.
      if (run.code != 0 && configs[c].scene.empty() && !own_checked)
        ThrowInput("{}: the unmutated kernels do not diff equal (exit {}: {}); mutants would mean nothing", frame.scene, run.code, run.last_line);
      own_checked = own_checked || configs[c].scene.empty();
      if (run.code != 0) {
        j["skipped"] = fmt::format("the unmutated kernels do not diff equal here (exit {}: {})", run.code, run.last_line);
        std::fprintf(stderr, "rayspace mutate: warning: configuration %s left out: %s\n", configs[c].name.c_str(),
                     j["skipped"].get<std::string>().c_str());
      } else {
        for (const json& p : run.report.value("passes", json::array())) ran.insert(p.value("pass", std::string()));
        j["seconds"] = run.seconds;
      }
    }
    j["passes"] = std::vector<std::string>(ran.begin(), ran.end());
    b.passes.push_back(ran);
    b.scenes.push_back(scene);
    b.configs.push_back(j);
  }
  return b;
}

bool Runs(const Kernel& k, const std::set<std::string>& ran) {
  return std::any_of(k.passes.begin(), k.passes.end(), [&](const std::string& p) { return ran.count(p) > 0; });
}

// The configurations that run `file` (a kernel, or an include file through the kernels that read
// it), with the kernels to replace in each.
Target TargetOf(const std::string& file, const std::map<std::string, Kernel>& kernels, const Baseline& b) {
  Target t{file, {}, {}, {}};
  std::set<std::string> passes;
  for (std::size_t c = 0; c < b.passes.size(); ++c) {
    std::vector<std::string> replaced;
    for (const auto& [k, kernel] : kernels)
      if ((k == file || kernel.includes.count(file)) && Runs(kernel, b.passes[c])) {
        replaced.push_back(k);
        passes.insert(kernel.passes.begin(), kernel.passes.end());
      }
    if (replaced.empty()) continue;
    t.configs.push_back(c);
    t.kernels.push_back(replaced);
  }
  t.passes.assign(passes.begin(), passes.end());
  return t;
}

// Every kernel some configuration runs, and every include file of the shader directory such a kernel
// reads; with --pass, only those passes' kernels.
std::vector<Target> Targets(const MutateArgs& args, const std::map<std::string, Kernel>& kernels, const Baseline& b) {
  std::set<std::string> wanted;
  for (const std::string& p : args.passes) {
    const auto id = FindPass(p);
    if (!id || Pass(*id).graphics) ThrowInput("--pass '{}': not a compute pass (rayspace/pass_registry.h lists them)", p);
    wanted.insert(std::string(Pass(*id).kernel) + ".comp");
  }
  std::set<std::string> files;
  for (const auto& [file, k] : kernels) {
    if (!wanted.empty() && !wanted.count(file)) continue;
    files.insert(file);
    if (wanted.empty()) files.insert(k.includes.begin(), k.includes.end());
  }
  std::vector<Target> out;
  for (const std::string& f : files)
    if (Target t = TargetOf(f, kernels, b); !t.configs.empty()) out.push_back(std::move(t));
  return out;
}

struct Mutant {
  mutate::Mutation m;
  const Target* target = nullptr;
};

// --limit mutants: each file's mutations shuffled by the seed, then taken one file at a time in turn,
// the files too in an order the seed shuffles, so that every kernel gets its share and a limit below
// the number of files samples different files under each seed (in name order, a sample of 20 never
// reached the 19 files after shading_normal.glsl); --only narrows by id first.
std::vector<Mutant> Choose(const MutateArgs& args, const std::vector<Target>& targets, std::uint64_t seed, std::size_t& total) {
  std::regex only;
  try {
    only = std::regex(args.only);
  } catch (const std::regex_error& e) {
    ThrowInput("--only '{}': not a regular expression ({})", args.only, e.what());
  }
  std::vector<std::vector<Mutant>> per_file;
  total = 0;
  for (const Target& t : targets) {
    std::vector<mutate::Mutation> all = mutate::Enumerate(t.file, mutate_runs::ReadFile(mutate_runs::ShaderDir() / t.file));
    if (!args.only.empty())
      all.erase(std::remove_if(all.begin(), all.end(), [&](const mutate::Mutation& m) { return !std::regex_search(m.Id(), only); }),
                all.end());
    total += all.size();
    std::vector<Mutant> v;
    for (const std::size_t i : mutate::Shuffled(all.size(), seed ^ mutate::SeedOf(t.file))) v.push_back({all[i], &t});
    per_file.push_back(std::move(v));
  }
  std::vector<Mutant> out;
  const std::size_t limit = args.limit == 0 ? total : std::min(args.limit, total);
  const std::vector<std::size_t> file_order = mutate::Shuffled(per_file.size(), seed ^ mutate::SeedOf("files"));
  for (std::size_t round = 0; out.size() < limit; ++round)
    for (const std::size_t f : file_order)
      if (round < per_file[f].size() && out.size() < limit) out.push_back(per_file[f][round]);
  return out;
}

// The mutant's directory: the mutated file and the kernels that read it (an include's); the
// overrides of configuration entry `e` of its target, for the passes that configuration runs (`ran`:
// a kernel given for a pass the diff never launches is refused, rayspace diff --kernel).
std::vector<std::pair<std::string, std::string>> Prepare(const Mutant& mu, std::size_t e, const std::map<std::string, Kernel>& all,
                                                        const std::set<std::string>& ran, const fs::path& dir) {
  fs::create_directories(dir);
  const std::string source = mutate_runs::ReadFile(mutate_runs::ShaderDir() / mu.m.file);
  mutate_runs::WriteFile(dir / mu.m.file, mutate::Apply(source, mu.m));
  std::vector<std::pair<std::string, std::string>> kernels;
  for (const std::string& k : mu.target->kernels[e]) {
    if (k != mu.m.file) fs::copy_file(mutate_runs::ShaderDir() / k, dir / k, fs::copy_options::overwrite_existing);
    for (const std::string& p : all.at(k).passes)
      if (ran.count(p)) kernels.emplace_back(p, (dir / k).string());
  }
  return kernels;
}

// Whether `pass`'s kernel is `file` or includes it: a mutant of `file` changes what a call of `pass` computes.
bool KernelRuns(const std::string& pass, const std::string& file, const std::map<std::string, Kernel>& all) {
  const auto id = FindPass(pass);
  RS_CHECK_MSG(id.has_value(), "mutate: kernel case for an unknown pass {}", pass);
  const std::string k = std::string(Pass(*id).kernel) + ".comp";
  const auto it = all.find(k);
  return it != all.end() && (k == file || it->second.includes.count(file));
}

// Saves the kernel cases and replays each with the built-in kernels. With `chosen`, only the cases of
// a pass one of those mutants changes (the others could kill none of them); the rest are listed as
// skipped. Returns the cases whose replay did not exit 0 (their report entries, in order).
std::vector<json> RunBaselineCases(Baseline& b, const fs::path& work, int timeout, const std::string& backends,
                                   const std::vector<Mutant>* chosen) {
  std::vector<json> unequal;
  for (const mutate::KernelCase& k : mutate::KernelCases()) {
    json entry = {{"name", k.name}, {"pass", k.pass}, {"method", k.method}, {"why", k.why}};
    if (chosen && std::none_of(chosen->begin(), chosen->end(), [&](const Mutant& mu) { return KernelRuns(k.pass, mu.m.file, b.kernels); })) {
      entry["skipped"] = fmt::format("no chosen mutant changes {}'s kernel", k.pass);
      b.case_runs.push_back(entry);
      continue;
    }
    const fs::path dir = work / "cases" / k.name;
    k.call.Save(dir.string(), k.method);
    const mutate_runs::DiffRun run = mutate_runs::RunReplay(dir, {}, work / "baseline" / ("case-" + k.name), timeout, backends);
    entry["seconds"] = run.seconds;
    entry["exit"] = run.code;
    if (run.code != 0) {
      entry["last_line"] = run.last_line;
      unequal.push_back(entry);
    }
    b.cases.push_back({k.name, k.pass, dir});
    b.case_runs.push_back(entry);
  }
  return unequal;
}

// Before any mutant: every replayed case must be equal, or the emulator and the driver disagree at a
// boundary, a finding that no mutant's verdict may hide.
void RequireCasesEqual(const std::vector<json>& unequal) {
  if (unequal.empty()) return;
  const json& c = unequal.front();
  ThrowInput("kernel case {} ({}): the built-in kernels do not replay it equal (exit {}: {}); the emulator and the driver "
             "disagree at a boundary", c["name"].get<std::string>(), c["method"].get<std::string>(), c["exit"].get<int>(),
             c["last_line"].get<std::string>());
}

// The override for a kernel case of `pass`: the kernel that runs the pass, from the mutant's
// directory (Prepare wrote the mutated file there); none when the mutation does not reach that kernel.
std::vector<std::pair<std::string, std::string>> PrepareCase(const Mutant& mu, const std::string& pass,
                                                            const std::map<std::string, Kernel>& all, const fs::path& dir) {
  if (!KernelRuns(pass, mu.m.file, all)) return {};
  const std::string k = std::string(Pass(*FindPass(pass)).kernel) + ".comp";
  if (k != mu.m.file) fs::copy_file(mutate_runs::ShaderDir() / k, dir / k, fs::copy_options::overwrite_existing);
  return {{pass, (dir / k).string()}};  // the case replays a call of `pass` alone
}

// A survivor the optimiser proves equal: every kernel it touches compiles, with the specialization
// constants at their defaults (no planted fault), after spirv-opt -O and with ids renumbered, to
// the same SPIR-V as the original, up to the order of global declarations (mutate_runs::Canonical).
bool ProvablyEquivalent(const Mutant& mu, const fs::path& dir) {
  std::set<std::string> touched;
  for (const auto& ks : mu.target->kernels) touched.insert(ks.begin(), ks.end());
  const std::vector<std::string> recipe = {"--freeze-spec-const", "--fold-spec-const-op-composite", "-O", "--compact-ids"};
  for (const std::string& k : touched) {
    std::string err;
    const fs::path a = dir / (k + ".orig.spv"), b = dir / (k + ".mut.spv");
    if (!fs::exists(dir / k)) fs::copy_file(mutate_runs::ShaderDir() / k, dir / k, fs::copy_options::overwrite_existing);
    if (!mutate_runs::Compile(mutate_runs::ShaderDir() / k, a, err) || !mutate_runs::Compile(dir / k, b, err)) return false;
    if (!mutate_runs::Optimize(a, a.string() + ".O", recipe, err) || !mutate_runs::Optimize(b, b.string() + ".O", recipe, err)) return false;
    const std::string ca = mutate_runs::Canonical(a.string() + ".O");
    if (ca.empty() || ca != mutate_runs::Canonical(b.string() + ".O")) return false;
  }
  return true;
}

// --survivors: "none" reads no classifications; unset, the source tree's own list.
json Explanations(const std::string& given) {
  if (given == "none") return json::object();
  const std::string path = given.empty() ? FindDataPaths().survivors.string() : given;
  if (!fs::exists(path)) {
    if (given.empty()) return json::object();
    ThrowInput("--survivors '{}': file not found", given);
  }
  try {
    const json j = ParseJson(ReadInputFile(path, {"survivors file", kMaxTextFileBytes}));
    if (!j.is_object() || !j.contains("mutants") || !j["mutants"].is_object())
      ThrowInput("--survivors '{}': expected an object whose \"mutants\" is an object of explained survivors", path);
    return j["mutants"];
  } catch (const JsonError& e) {
    ThrowInput("--survivors '{}': not JSON ({})", path, e.what());
  }
}

json MutantJson(const Mutant& mu) {
  return {{"id", mu.m.Id()},
          {"file", mu.m.file},
          {"line", mu.m.line},
          {"column", mu.m.column},
          {"operator", mu.m.op},
          {"before", mu.m.before},
          {"after", mu.m.after},
          {"source", mutate::LineText(mutate_runs::ReadFile(mutate_runs::ShaderDir() / mu.m.file), mu.m.line)},
          {"passes", mu.target->passes}};
}

// A run of the mutant (`run(timeout)`: a diff or a replay) classified; a loaded machine slows a run
// too, so a hang counts once it also outlasts four times the limit.
template <typename Run>
mutate_runs::Verdict Judge(int timeout, Run&& run) {
  mutate_runs::DiffRun r = run(timeout);
  if (r.TimedOut()) r = run(4 * timeout);
  return mutate_runs::Classify(r);
}

// A diff of the mutant in one configuration.
mutate_runs::Verdict DiffMutant(const mutate_runs::Frame& frame, const mutate_runs::DiffConfig& config, const mutate_runs::Overrides& kernels,
                                const fs::path& dir, const std::string& scene) {
  return Judge(frame.timeout, [&](int timeout) {
    mutate_runs::Frame f = frame;
    f.timeout = timeout;
    return mutate_runs::RunDiff(f, config, kernels, dir, scene);
  });
}

// Every built-in kernel configuration `c` runs, as overrides from the shader directory.
mutate_runs::Overrides Builtins(const Baseline& base, std::size_t c) {
  mutate_runs::Overrides out;
  for (const auto& [k, kernel] : base.kernels)
    if (Runs(kernel, base.passes[c]))
      for (const std::string& p : kernel.passes)
        if (base.passes[c].count(p)) out.emplace_back(p, (mutate_runs::ShaderDir() / k).string());
  return out;
}

// The mutant on the clamping device (clamped_device.h), in each configuration that runs its code and
// where the clamped built-in kernels diff equal, until one kills it.
mutate_runs::Verdict RunClamped(const Mutant& mu, const mutate_runs::Frame& frame, const Baseline& base, const fs::path& dir, json& tried) {
  mutate_runs::Verdict v{"survived", "", {}};
  if (!base.clamped) return v;  // the simulated GPU: memcheck names what clamping would hide
  for (std::size_t e = 0; e < mu.target->configs.size() && v.status == "survived"; ++e) {
    const std::size_t c = mu.target->configs[e];
    if (!base.clamped->Usable(c, Builtins(base, c), base.scenes[c])) continue;
    const mutate_runs::DiffConfig& config = mutate_runs::Configs()[c];
    mutate_runs::Overrides clamped;
    std::string error;
    if (!mutate_runs::Clamp(Prepare(mu, e, base.kernels, base.passes[c], dir), dir / ("clamped-" + config.name), clamped, error)) continue;
    v = DiffMutant(frame, config, clamped, dir / ("clamped-" + config.name), base.scenes[c]);
    tried.push_back("clamped:" + config.name);
    if (v.status == "killed") {
      v.caught["device"] = "clamped";
      v.reason = "on a device that clamps out-of-bounds indices (spirv-opt --graphics-robust-access): " + v.reason;
    }
  }
  return v;
}

// The mutant through its configurations until one kills it (or it cannot run); a survivor is checked
// for provable equivalence, else run through the kernel cases of its passes and on the clamping
// device, and a survivor of all is looked up among the explained survivors.
json RunMutant(const Mutant& mu, const mutate_runs::Frame& frame, const Baseline& base, const fs::path& dir, const json& explained) {
  json j = MutantJson(mu);
  mutate_runs::Verdict v;
  json tried = json::array();
  for (std::size_t e = 0; e < mu.target->configs.size(); ++e) {
    const std::size_t c = mu.target->configs[e];
    const mutate_runs::DiffConfig& config = mutate_runs::Configs()[c];
    v = DiffMutant(frame, config, Prepare(mu, e, base.kernels, base.passes[c], dir), dir / config.name, base.scenes[c]);
    tried.push_back(config.name);
    if (v.status != "survived") break;
  }
  // The frames left it alive. The optimiser's proof first: a proved-equivalent module computes what
  // the original does on every input and every device, so no case or clamping can kill it.
  const bool proved = v.status == "survived" && ProvablyEquivalent(mu, dir);
  // Then the hand-made calls of its passes, at the boundaries no frame reaches.
  for (const SavedCase& c : base.cases) {
    if (proved || v.status != "survived") break;
    const auto kernels = PrepareCase(mu, c.pass, base.kernels, dir);
    if (kernels.empty()) continue;
    v = Judge(frame.timeout,
              [&](int timeout) { return mutate_runs::RunReplay(c.dir, kernels, dir / ("case-" + c.name), timeout, frame.backends); });
    tried.push_back("case:" + c.name);
    if (v.status == "killed") v.caught["case"] = c.name;
  }
  if (v.status == "survived" && !proved) v = RunClamped(mu, frame, base, dir, tried);
  j["configs"] = tried;
  j["status"] = v.status;
  if (!v.reason.empty()) j["reason"] = v.reason;
  if (!v.caught.empty()) j["caught"] = v.caught;
  if (v.status != "survived") return j;
  if (proved) {
    j["status"] = "equivalent";
    j["why"] = "proved by the optimiser: the same SPIR-V as the original with no fault planted, after spirv-opt -O";
  } else if (explained.contains(mu.m.Id())) {
    const json& e = explained[mu.m.Id()];
    if (mutate::ClassificationApplies(e.value("source", std::string()), j["source"].get<std::string>())) {
      j["class"] = e.value("class", std::string());
      j["why"] = e.value("why", std::string());
      if (j["class"] == "equivalent") j["status"] = "equivalent";
    } else {
      j["stale_classification"] = e;  // made for another text of the line: an unexplained survivor
    }
  }
  return j;
}

std::string Describe(const json& j) {
  std::string s = fmt::format("{}:{} {} '{}' -> '{}': {}", j["file"].get<std::string>(), j["line"].get<int>(), j["operator"].get<std::string>(),
                              j["before"].get<std::string>(), j["after"].get<std::string>(), j["status"].get<std::string>());
  if (j.contains("caught") && j["caught"].contains("pass") && j["caught"]["pass"].is_string())
    s += " by " + j["caught"]["pass"].get<std::string>() + (j["caught"].contains("buffer") ? " (" + j["caught"]["buffer"].value("buffer", std::string()) + ")" : "");
  else if (j.contains("reason") && j["status"] != "survived")
    s += " (" + j["reason"].get<std::string>() + ")";
  return s;
}

// Runs the mutants `jobs` at a time; results in the mutants' order.
std::vector<json> RunAll(const std::vector<Mutant>& mutants, const mutate_runs::Frame& frame, const Baseline& base, const fs::path& work,
                         const json& explained, int jobs) {
  std::vector<json> out(mutants.size());
  std::atomic<std::size_t> next{0};
  std::mutex print;
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < mutants.size();) {
      try {
        out[i] = RunMutant(mutants[i], frame, base, work / "mutants" / fmt::format("{:04}", i), explained);
      } catch (const std::exception& e) {
        // A mutant that breaks the tool, not the kernel: reported, never counted as killed.
        out[i] = {{"id", mutants[i].m.Id()}, {"file", mutants[i].m.file}, {"line", mutants[i].m.line}, {"operator", mutants[i].m.op},
                  {"before", mutants[i].m.before}, {"after", mutants[i].m.after}, {"passes", mutants[i].target->passes},
                  {"status", "error"}, {"reason", e.what()}};
      }
      const std::lock_guard<std::mutex> lock(print);
      std::printf("  [%zu/%zu] %s\n", i + 1, mutants.size(), Describe(out[i]).c_str());
      std::fflush(stdout);
    }
  };
  std::vector<std::thread> threads;
  const Settings& settings = CurrentSettings();  // each job runs with the caller's
  for (int t = 0; t < std::max(1, jobs); ++t)
    threads.emplace_back([&] {
      const SettingsInForce in_force(settings);
      worker();
    });
  for (std::thread& t : threads) t.join();
  return out;
}

}  // namespace

json RunVariants(const MutateArgs& args, const std::vector<std::string>& kernels,
                 const std::map<std::string, std::pair<const DiffConfig*, std::string>>& config_of, const mutate_runs::Frame& frame,
                 const fs::path& work, std::uint64_t seed, const Shard& shard, std::size_t& chosen);
void PrintScores(const json& summary, const json& variants);

// The arguments checked before the first diff runs.
void CheckArgs(const MutateArgs& args) {
  if (args.timeout < 1) ThrowInput("--timeout {}: at least 1 second", args.timeout);
  if (!args.junit.empty() && args.junit == args.report) ThrowInput("--junit '{}': the same file as --report", args.junit);
  if (args.variants != "all" && (args.variants.empty() || args.variants.find_first_not_of("0123456789") != std::string::npos))
    ThrowInput("--variants '{}': a count or 'all'", args.variants);
  for (const std::string& p : args.passes) {
    const auto id = FindPass(p);
    if (!id || Pass(*id).graphics) ThrowInput("--pass '{}': not a compute pass (rayspace/pass_registry.h lists them)", p);
  }
  for (const std::string& c : args.configs)
    if (std::none_of(mutate_runs::Configs().begin(), mutate_runs::Configs().end(), [&](const auto& k) { return k.name == c; }))
      ThrowInput("--config '{}': not a configuration (docs/verification.md lists them)", c);
  if (!args.only.empty()) {
    try {
      std::regex check(args.only);
    } catch (const std::regex_error& e) {
      ThrowInput("--only '{}': not a regular expression ({})", args.only, e.what());
    }
  }
  std::error_code ec;
  if (!args.cases_only && !fs::is_regular_file(args.scene, ec)) ThrowInput("'{}': scene file not found", args.scene);  // the cases bring their own inputs
  if (!args.work.empty() && fs::exists(args.work, ec) && !fs::is_directory(args.work, ec))
    ThrowInput("--work {}: not a directory", args.work);
}

// The run's work directory: --work as given (kept), or a fresh one under $TMPDIR removed on every
// exit from RunMutate, an error's and a signal's included (TempDirectory).
class WorkDir {
 public:
  explicit WorkDir(const std::string& given) {
    if (!given.empty()) {
      MakeOutputDirectory(given, "--work");
      path_ = given;
      return;
    }
    temp_ = std::make_unique<TempDirectory>(fs::temp_directory_path() / fmt::format("rayspace-mutate-{}", ::getpid()));
    path_ = temp_->path();
  }
  const fs::path& path() const { return path_; }

 private:
  std::unique_ptr<TempDirectory> temp_;
  fs::path path_;
};

// --backends: the actual sides, in order ("vulkan", "sim").
std::vector<std::string> Sides(const std::string& backends) {
  if (backends == "emu,vulkan") return {"vulkan"};
  if (backends == "emu,sim") return {"sim"};
  if (backends == "emu,vulkan,sim") return {"vulkan", "sim"};
  ThrowInput("--backends '{}': expected emu,vulkan, emu,sim or emu,vulkan,sim", backends);
}

// The chosen mutants with the targets of another side's baseline (a configuration that does not
// diff equal there is not run there); a file that side runs in no configuration keeps no mutant.
std::vector<Mutant> OnSide(const std::vector<Mutant>& chosen, const std::vector<Target>& targets) {
  std::vector<Mutant> out;
  for (const Mutant& m : chosen)
    for (const Target& t : targets)
      if (t.file == m.m.file) out.push_back({m.m, &t});
  return out;
}

namespace {

// The mutants of `chosen` that `shard` runs, each verdict tagged with its index in `chosen`.
std::vector<json> RunShard(const std::vector<Mutant>& chosen, const Shard& shard, const mutate_runs::Frame& frame, const Baseline& base,
                           const fs::path& work, const json& explained, int jobs) {
  std::vector<Mutant> mine;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < chosen.size(); ++i)
    if (shard.Holds(i)) mine.push_back(chosen[i]), index.push_back(i);
  std::vector<json> out = RunAll(mine, frame, base, work, explained, jobs);
  for (std::size_t k = 0; k < out.size(); ++k) out[k]["index"] = index[k];
  return out;
}

// Another side (--backends emu,vulkan,sim): the same mutants on its own baseline, cases and (on
// Vulkan) clamping device; its report section, with the mutants whose verdicts differ from `first`'s.
json RunSide(const MutateArgs& args, const std::string& side, const mutate_runs::Frame& frame, const std::vector<Mutant>& chosen,
             const std::map<std::string, Kernel>& kernels, const fs::path& work, const json& explained, const Shard& shard,
             const std::vector<json>& first, const std::string& first_side) {
  Baseline other = RunBaseline(frame, args.configs, work);
  other.kernels = kernels;
  const std::vector<Target> targets = Targets(args, kernels, other);
  const std::vector<Mutant> on_side = OnSide(chosen, targets);
  RequireCasesEqual(RunBaselineCases(other, work, args.timeout, frame.backends, &on_side));
  if (side == "vulkan") other.clamped = std::make_unique<mutate_runs::ClampedBaseline>(frame, work);
  std::printf("  on %s:\n", side.c_str());
  const std::vector<json> results = RunShard(on_side, shard, frame, other, work, explained, args.jobs);
  const json summary = mutate_shards::Summaries(results);
  PrintScores(summary, json::array());
  const json differ = mutate_shards::Differences(first, results, first_side, side);
  std::printf("  %zu mutant(s) with another verdict on %s than on %s:\n", differ.size(), side.c_str(), first_side.c_str());
  for (const json& d : differ)
    std::printf("    %s: %s %s, %s %s%s\n", d["id"].get<std::string>().c_str(), first_side.c_str(), d[first_side].get<std::string>().c_str(),
                side.c_str(), d[side].get<std::string>().c_str(), d.contains("reason") ? (" (" + d["reason"].get<std::string>() + ")").c_str() : "");
  return {{"configs", other.configs}, {"mutants_run", on_side.size()}, {"mutants", results}, {"summary", summary}, {"differences", differ}};
}

// --cases-only: every kernel case on the built-in kernels, on each side, each named with its verdict.
// The exit is the first failing replay's: 4 for a divergence, 6 for a checker's finding on the
// simulator, and an error's own code when a replay could not run (never 4 for work not done).
ExitCode RunCasesOnly(const std::vector<std::string>& sides, const std::vector<std::string>& replay_backends, int timeout,
                      const fs::path& work, OutputFile& report) {
  json j = {{"backends", sides}};
  int first_code = 0;
  std::size_t failed = 0;
  for (std::size_t k = 0; k < sides.size(); ++k) {
    std::printf("rayspace mutate: the kernel cases with the built-in kernels, emu against %s\n", sides[k].c_str());
    Baseline b;
    b.kernels = Kernels();
    const std::vector<json> unequal = RunBaselineCases(b, work / sides[k], timeout, replay_backends[k], nullptr);
    failed += unequal.size();
    if (first_code == 0 && !unequal.empty()) first_code = unequal.front()["exit"].get<int>();
    for (const json& c : b.case_runs) {
      const int code = c["exit"].get<int>();
      const std::string verdict = code == 0 ? "equal"
                                  : fmt::format("{} (exit {}: {})", code == 4 ? "not equal" : "failed", code, c.value("last_line", std::string()));
      std::printf("  %s (%s): %s\n", c["name"].get<std::string>().c_str(), c["pass"].get<std::string>().c_str(), verdict.c_str());
    }
    j[k == 0 ? std::string("kernel_cases") : "on_" + sides[k]] = b.case_runs;
  }
  std::printf("  %s\n", failed == 0 ? "every kernel case equal" : fmt::format("{} kernel case(s) not equal or not run", failed).c_str());
  AddVersion(j);
  mutate_shards::MakeDeterministic(j, work.string());
  report.Commit(JsonText(j));
  if (first_code == 0) return ExitCode::kOk;
  return first_code >= 1 && first_code <= 6 ? static_cast<ExitCode>(first_code) : ExitCode::kInternal;
}

}  // namespace

ExitCode RunMutate(const MutateArgs& args) {
  CheckArgs(args);
  const Shard shard = ParseShard(args.shard);
  const std::vector<std::string> sides = Sides(args.backends);
  const json explained = Explanations(args.survivors);
  const std::string seed_text = args.seed == "commit" ? BuildCommit() : args.seed;
  const std::uint64_t seed = mutate::SeedOf(seed_text);
  OutputFile report = args.report.empty() ? OutputFile() : OutputFile(args.report, OutputOptions{"the report", true, true, {}});
  OutputFile junit = args.junit.empty() ? OutputFile() : OutputFile(args.junit, OutputOptions{"the JUnit report", true, true, {}});
  const WorkDir work_dir(args.work);
  const fs::path& work = work_dir.path();
  const auto frame_on = [&](const std::string& side) {
    return mutate_runs::Frame{fs::absolute(args.scene).string(), args.data, args.size, args.timeout, side == "sim" ? "emu,sim" : "emu,vulkan"};
  };
  const mutate_runs::Frame frame = frame_on(sides[0]);
  if (args.cases_only) {
    std::vector<std::string> replay_backends;
    for (const std::string& side : sides) replay_backends.push_back(frame_on(side).backends);
    return RunCasesOnly(sides, replay_backends, args.timeout, work, report);
  }
  std::printf("rayspace mutate: %s at %s, seed %s (%016llx), on %s%s\n", args.scene.c_str(), args.size.c_str(), seed_text.c_str(),
              static_cast<unsigned long long>(seed), args.backends.c_str(),
              shard.count > 1 ? fmt::format(", shard {}/{}", shard.index, shard.count).c_str() : "");
  const std::map<std::string, Kernel> kernels = Kernels();
  Baseline base = RunBaseline(frame, args.configs, work);
  base.kernels = kernels;
  const std::vector<Target> targets = Targets(args, kernels, base);
  std::size_t total = 0;
  const std::vector<Mutant> chosen = Choose(args, targets, seed, total);
  std::printf("  %zu files, %zu mutants in all; running %zu\n", targets.size(), total, chosen.size());
  if (args.list) {  // the choice needs only the configurations' passes, not the cases or the clamped device
    for (std::size_t i = 0; i < chosen.size(); ++i)
      if (shard.Holds(i))
        std::printf("  %s  (%s)\n", chosen[i].m.Id().c_str(), mutate_runs::Configs()[chosen[i].target->configs[0]].name.c_str());
    return ExitCode::kOk;
  }
  RequireCasesEqual(RunBaselineCases(base, work, args.timeout, frame.backends, &chosen));
  // The clamping device is a Vulkan pipeline's robust access; on the simulator memcheck names the access.
  if (sides[0] == "vulkan") base.clamped = std::make_unique<mutate_runs::ClampedBaseline>(frame, work);
  if (sides.size() > 1) std::printf("  on %s:\n", sides[0].c_str());
  const std::vector<json> results = RunShard(chosen, shard, frame, base, work, explained, args.jobs);
  std::vector<std::string> kernel_files;
  std::map<std::string, std::pair<const DiffConfig*, std::string>> config_of;  // the first configuration, its scene
  for (const Target& t : targets)
    if (t.file.size() > 5 && t.file.substr(t.file.size() - 5) == ".comp")
      kernel_files.push_back(t.file), config_of[t.file] = {&mutate_runs::Configs()[t.configs[0]], base.scenes[t.configs[0]]};
  std::size_t variants_run = 0;
  const json variants = RunVariants(args, kernel_files, config_of, frame, work, seed, shard, variants_run);
  const json summary = mutate_shards::Summaries(results);
  PrintScores(summary, variants);
  json j = {{"scene", args.scene}, {"size", args.size}, {"seed", seed_text}, {"limit", args.limit}, {"timeout", args.timeout},
            {"backends", sides}, {"mutants_in_all", total}, {"mutants_run", chosen.size()}, {"configs", base.configs},
            {"kernel_cases", base.case_runs}, {"clamped_baseline", base.clamped ? json(base.clamped->Results()) : json()},
            {"mutants", results}, {"summary", summary}, {"variants_run", variants_run}, {"variants", variants}};
  for (std::size_t k = 1; k < sides.size(); ++k)
    j["on_" + sides[k]] = RunSide(args, sides[k], frame_on(sides[k]), chosen, kernels, work / sides[k], explained, shard, results, sides[0]);
  if (shard.count > 1) j["shard"] = {{"index", shard.index}, {"count", shard.count}};
  // What the run decided alone (times, its scratch paths, its command line) stays out: shards merge
  // into these bytes, and two runs of one binary write the same report.
  AddVersion(j);
  mutate_shards::MakeDeterministic(j, work.string());
  report.Commit(JsonText(j));
  junit.Commit(JUnitXml("rayspace mutate", MutateJUnit(j)));
  return ExitCode::kOk;
}

ExitCode RunMutateMerge(const MutateMergeArgs& args) {
  if (args.out == args.junit) ThrowInput("--junit '{}': the same file as the merged report", args.junit);
  OutputFile out(args.out, OutputOptions{"the merged report", true, true, {}});
  OutputFile junit = args.junit.empty() ? OutputFile() : OutputFile(args.junit, OutputOptions{"the JUnit report", true, true, {}});
  std::vector<std::pair<std::string, json>> shards;
  for (const std::string& f : args.shards) {
    try {
      shards.emplace_back(f, ParseJson(ReadInputFile(f, {"shard report", kMaxTextFileBytes})));
    } catch (const JsonError& e) {
      ThrowInput("{}: not JSON ({})", f, e.what());
    }
  }
  const json merged = mutate_shards::Merge(shards);
  PrintScores(merged["summary"], merged["variants"]);
  std::printf("rayspace mutate merge: %zu shards, %zu mutants, %zu variants\n", shards.size(), merged["mutants"].size(),
              merged["variants"].size());
  out.Commit(JsonText(merged));
  junit.Commit(JUnitXml("rayspace mutate", MutateJUnit(merged)));
  return ExitCode::kOk;
}

}  // namespace rayspace::app
