#include "rayspace/mutate/mutate_runs.h"

#include "rayspace/output_file.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/install_paths.h"

namespace rayspace::app::mutate_runs {
namespace fs = std::filesystem;
namespace {

std::string Quote(const std::string& s) {
  std::string q = "'";
  for (const char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

std::string SelfExe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  RS_CHECK_MSG(!ec, "mutate: cannot find its own executable: {}", ec.message());
  return p.string();
}

// The exit status of a shell command (RunShellCommand; 128 + signal when a signal ended it).
int ExitOf(int status) {
  if (status == -1) return 127;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 127;
}

std::string LastLine(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::string FirstLine(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) return line;
  return {};
}

// The first line that reports an error, else the last line.
std::string ErrorLine(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.find("error") != std::string::npos || line.find("stopped:") != std::string::npos) return line;
  return LastLine(text);
}

}  // namespace

const std::vector<DiffConfig>& Configs() {
  static const std::vector<DiffConfig> configs = {
      {"crsh", {"--path", "passes"}, ""},
      {"crsh-fused", {"--path", "fused"}, ""},
      {"tree", {"--objects", "tree", "--path", "passes"}, ""},
      {"tree-fused", {"--objects", "tree", "--path", "fused"}, ""},
      {"tl", {"--algo", "tl"}, ""},
      {"grid", {"--algo", "grid", "--primary", "grid"}, ""},
      // Dispatches split into parts and folded into rows of workgroups, arrays paged over bindings.
      {"limits", {"--path", "passes", "--max-groups", "3", "--split-bytes", "65536"}, ""},
      {"pairwise", {"--path", "passes", "--algo", "rah-quadtree", "--child-merge", "pairwise"}, ""},
      {"scan", {"--path", "passes", "--reduction", "scan"}, ""},
      // The thesis's preset, with the polar-first 8-bit keys it no longer sets (their hash path stays covered).
      {"thesis", {"--path", "passes", "--faithful", "thesis", "--hash-order", "polar-first", "--hash-bits", "8"}, ""},
      {"roger", {"--path", "passes", "--faithful", "roger"}, ""},
      {"tl-cull", {"--algo", "tl", "--backface-cull", "on"}, ""},
      {"tl-heads", {"--algo", "tl", "--polygon-heads", "regular", "--frustum-cull", "on", "--primary", "tl", "--lists", "6"}, ""},
      {"glass", {"--path", "passes"}, "glass"},
      {"area", {"--path", "fused"}, "cornell-soft.json"},
      {"area-grid", {"--algo", "grid", "--grid-area", "8x8x3", "--grid-area-near", "1"}, "cornell-soft.json"},
      // Front-face culling (grid.count keeps the faces turned away, grid.trace shadows them untraced)
      // and reflection rays through the 3D grid about the eye.
      {"grid-closed", {"--algo", "grid", "--closed-models", "--grid-secondary", "perspective", "--grid-area", "12x12x3"}, ""},
      // cornell-soft's rect light tilted, beside a sphere and a disk light.
      {"shapes", {"--path", "passes"}, "shapes"},
      // A scene with sky: eye and reflection rays that hit nothing.
      {"open", {"--path", "passes"}, "toczek-cubes.json"},
      // Per-ray arrays paged over several bindings (a larger frame than the others: paging needs one).
      {"paged", {"--path", "passes", "--split-bytes", "163840"}, "", "96x96"},
      {"tl-8", {"--algo", "tl", "--lists", "8", "--polygon-heads", "regular"}, ""},
      // Workgroups of one invocation, and of 33 (one past a 32-wide subgroup multiple).
      {"local-1", {"--path", "passes", "--local-size", "1"}, ""},
      {"local-33", {"--path", "fused", "--local-size", "33"}, ""},
      // A procedural scene of 9,032 triangles: an object tree with nodes of exactly one child node (the
      // Cornell boxes' have none), and a grid build over more than one scan block (kScanBlock).
      {"tree-one-child", {"--objects", "tree", "--path", "passes"}, "roger-wavy-n32.json"},
      {"grid-blocks", {"--algo", "grid", "--primary", "grid"}, "roger-wavy-n32.json"},
      // Front-face culling with the light exactly in the plane of the ceiling's triangles.
      {"grid-coplanar", {"--algo", "grid", "--closed-models"}, "light-in-ceiling"},
  };
  return configs;
}

std::string ReadFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteFile(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  RS_CHECK_MSG(out.good(), "mutate: cannot write {}", p.string());
}

// cornell-soft with its rect light tilted (its axes have three non-zero components) and a sphere and
// a disk light added: every light shape's sampler runs.
std::string ShapesScene(const fs::path& work) {
  nlohmann::json j = nlohmann::json::parse(ReadFile(FindDataPaths().scenes / "cornell-soft.json"));
  nlohmann::json sphere = j["lights"][0], disk = j["lights"][0];
  for (nlohmann::json* l : {&sphere, &disk}) {
    l->erase("size");
    (*l)["radius"] = 40;
    (*l)["intensity"] = 0.6;
  }
  sphere.erase("normal");
  sphere["shape"] = "sphere";
  sphere["position"] = {150, 400, 200};
  disk["shape"] = "disk";
  disk["position"] = {400, 500, 350};
  j["lights"][0]["normal"] = {0.4, -1, 0.3};
  j["lights"].push_back(sphere);
  j["lights"].push_back(disk);
  fs::create_directories(work);
  WriteFile(work / "shapes-scene.json", j.dump(2));
  return (work / "shapes-scene.json").string();
}

// cornell-mirrors with its light moved up into the ceiling's plane (y = 548.8, the room generator's
// height): the light lies exactly in the plane of every ceiling triangle, where front-face culling's
// side test (grid.glsl, FacesAway) meets a dot product of exactly 0.
std::string LightInCeilingScene(const fs::path& work) {
  nlohmann::json j = nlohmann::json::parse(ReadFile(FindDataPaths().scenes / "cornell-mirrors.json"));
  j["lights"][0]["position"][1] = 548.8;
  fs::create_directories(work);
  WriteFile(work / "light-in-ceiling-scene.json", j.dump(2));
  return (work / "light-in-ceiling-scene.json").string();
}

std::string SceneFor(const DiffConfig& config, const std::string& scene, const fs::path& work) {
  if (config.scene.empty()) return scene;
  if (config.scene == "shapes") return ShapesScene(work);
  if (config.scene == "light-in-ceiling") return LightInCeilingScene(work);
  if (config.scene != "glass") return (FindDataPaths().scenes / config.scene).string();
  // The command's scene with its first material transparent and refractive (mesh paths are
  // resolved against the data root, so the copy may live anywhere).
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ReadFile(scene));
  } catch (const nlohmann::json::exception&) {
    return "";
  }
  if (!j.contains("materials") || !j["materials"].is_object() || j["materials"].empty()) return "";
  nlohmann::json& m = j["materials"].begin().value();
  m["transparency"] = 0.5;
  m["ior"] = 1.5;
  m["reflectivity"] = 0.2;
  fs::create_directories(work);
  const fs::path out = work / "glass-scene.json";
  WriteFile(out, j.dump(2));
  return out.string();
}

namespace {

// Runs `args` (a rayspace command and its arguments, without --report) under the time limit, its
// report in dir/report.json and its output in dir/diff.log.
DiffRun RunReporting(int timeout, const std::string& args, const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path report = dir / "report.json", log = dir / "diff.log";
  std::error_code ec;
  fs::remove(report, ec);
  const std::string cmd = fmt::format("timeout --foreground -s KILL {} {} {} --report {} > {} 2>&1", timeout, Quote(SelfExe()), args,
                                      Quote(report.string()), Quote(log.string()));
  const auto t0 = std::chrono::steady_clock::now();
  DiffRun r;
  r.code = ExitOf(RunShellCommand(cmd));
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.log = ReadFile(log);
  r.last_line = LastLine(r.log);
  if (fs::exists(report, ec)) {
    try {
      r.report = nlohmann::json::parse(ReadFile(report));
    } catch (const nlohmann::json::exception&) {
      r.report = nullptr;
    }
  }
  return r;
}

std::string KernelFlags(const std::vector<std::pair<std::string, std::string>>& kernels) {
  std::string flags;
  for (const auto& [pass, file] : kernels) flags += fmt::format(" --kernel {}", Quote(fmt::format("{}={}", pass, file)));
  return flags;
}

}  // namespace

DiffRun RunDiff(const Frame& frame, const DiffConfig& config, const std::vector<std::pair<std::string, std::string>>& kernels,
                const fs::path& dir, const std::string& scene) {
  std::string args = fmt::format("diff {} --size {}", Quote(scene.empty() ? frame.scene : scene), config.size.empty() ? frame.size : config.size);
  if (!frame.data.empty()) args += fmt::format(" --data {}", Quote(frame.data));
  for (const std::string& f : config.flags) args += fmt::format(" {}", Quote(f));
  if (!frame.backends.empty()) args += " --backends " + Quote(frame.backends);
  return RunReporting(frame.timeout, args + KernelFlags(kernels), dir);
}

DiffRun RunReplay(const fs::path& call, const std::vector<std::pair<std::string, std::string>>& kernels, const fs::path& dir,
                  int timeout, const std::string& backends) {
  const std::string flags = backends.empty() ? "" : " --backends " + Quote(backends);
  return RunReporting(timeout, "replay " + Quote(call.string()) + flags + KernelFlags(kernels), dir);
}

namespace {

// The first divergent call's pass, label and first unequal buffer, from a diff report.
nlohmann::json Caught(const nlohmann::json& report) {
  nlohmann::json c = nlohmann::json::object();
  if (report.is_null()) return c;
  c["pass"] = report.value("first_divergent_pass", nlohmann::json());
  // A replay's report is the one call itself.
  const nlohmann::json calls = report.contains("calls") ? report["calls"] : nlohmann::json::array({report});
  for (const nlohmann::json& call : calls) {
    if (call.value("equal", true)) continue;
    c["pass"] = call.value("pass", std::string());
    c["call"] = call.value("label", std::string());
    if (call.contains("error")) c["error"] = call["error"];
    for (const nlohmann::json& b : call.value("buffers", nlohmann::json::array()))
      if (b.value("mismatches", 0) > 0) {
        c["buffer"] = b;
        break;
      }
    break;
  }
  if (report.contains("stopped") && report["stopped"].is_string() && !report["stopped"].get<std::string>().empty()) c["stopped"] = report["stopped"];
  return c;
}

}  // namespace

Verdict Classify(const DiffRun& run) {
  Verdict v;
  if (run.code == 0) {
    v.status = "survived";
    return v;
  }
  if (run.code == 124 || run.code == 137) {
    v.status = "killed";
    v.reason = "hang: the diff did not finish within the time limit";
    return v;
  }
  // Exit 2 is the kernel refused before it ran (it does not compile, or the contract check fails);
  // any other exit 2 is the host refusing what the mutant wrote (a later pass's input check): a kill.
  const bool compile = run.log.find("does not compile") != std::string::npos;
  if (run.code == 2 && (compile || run.log.find("kernel for pass") != std::string::npos)) {
    v.status = compile ? "stillborn" : "invalid";
    v.reason = run.last_line;
    return v;
  }
  v.status = "killed";
  v.caught = Caught(run.report);
  v.reason = run.code == 4 ? "diff: a pass diverged" : fmt::format("exit {}: {}", run.code, ErrorLine(run.log));
  // Exit 6 on the simulated GPU: a checker's finding on the kernel (the report names the checker).
  if (run.code == 6 && run.report.is_object() && run.report.contains("simulator_checker") && run.report["simulator_checker"].is_object()) {
    v.caught["checker"] = run.report["simulator_checker"].value("checker", std::string());
    v.reason = fmt::format("the simulator's {} found a fault of the kernel", v.caught["checker"].get<std::string>());
  }
  return v;
}

fs::path ShaderDir() { return FindDataPaths().shaders; }

bool Compile(const fs::path& comp, const fs::path& spv, std::string& error) {
  const fs::path log = spv.string() + ".log";
  const std::string cmd = fmt::format("{} -O0 --target-env=vulkan1.2 -fshader-stage=compute -I {} -I {} -I {} {} -o {} > {} 2>&1",
                                      RAYSPACE_MUTATE_GLSLC, Quote(comp.parent_path().string()), Quote(ShaderDir().string()),
                                      Quote(FindDataPaths().includes.string()), Quote(comp.string()), Quote(spv.string()), Quote(log.string()));
  const int code = ExitOf(RunShellCommand(cmd));
  error = code == 0 ? "" : FirstLine(ReadFile(log));
  return code == 0;
}

std::string Canonical(const fs::path& spv) {
  const fs::path txt = spv.string() + ".txt";
  const std::string cmd = fmt::format("{} --no-header {} -o {} > /dev/null 2>&1", RAYSPACE_MUTATE_SPIRV_DIS, Quote(spv.string()), Quote(txt.string()));
  if (ExitOf(RunShellCommand(cmd)) != 0) return {};
  std::istringstream in(ReadFile(txt));
  std::vector<std::string> globals;
  std::string line, body;
  bool in_functions = false;
  while (std::getline(in, line)) {
    in_functions = in_functions || line.find(" OpFunction ") != std::string::npos;
    if (in_functions) body += line + "\n";
    else globals.push_back(line);
  }
  std::sort(globals.begin(), globals.end());
  std::string out;
  for (const std::string& g : globals) out += g + "\n";
  return out + body;
}

bool Optimize(const fs::path& in, const fs::path& out, const std::vector<std::string>& recipe, std::string& error) {
  const fs::path log = out.string() + ".log";
  std::string cmd = std::string(RAYSPACE_MUTATE_SPIRV_OPT);
  for (const std::string& a : recipe) cmd += fmt::format(" {}", Quote(a));
  cmd += fmt::format(" {} -o {} > {} 2>&1", Quote(in.string()), Quote(out.string()), Quote(log.string()));
  const int code = ExitOf(RunShellCommand(cmd));
  error = code == 0 ? "" : FirstLine(ReadFile(log));
  return code == 0;
}

}  // namespace rayspace::app::mutate_runs
