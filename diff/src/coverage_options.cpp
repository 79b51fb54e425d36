#include "rayspace/diff/coverage_options.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <unistd.h>

#include <fmt/format.h>

#include "rayspace/mutate/mutate_runs.h"
#include "rayspace/output_file.h"

namespace rayspace::app {
namespace fs = std::filesystem;

std::vector<std::string> ExpandLineRuns(const std::vector<std::string>& runs) {
  std::vector<std::string> out;
  for (const std::string& run : runs) {
    const std::size_t colon = run.rfind(':');
    if (colon == std::string::npos) continue;
    const std::string file = run.substr(0, colon), span = run.substr(colon + 1);
    const std::size_t dash = span.find('-');
    try {
      const int first = std::stoi(span.substr(0, dash));
      const int last = dash == std::string::npos ? first : std::stoi(span.substr(dash + 1));
      for (int l = first; l <= last; ++l) out.push_back(fmt::format("{}:{}", file, l));
    } catch (const std::exception&) {
      out.push_back(run);  // not a line run (a module without OpLine names instructions): kept whole
    }
  }
  return out;
}

std::vector<std::string> JoinLineRuns(const std::vector<std::string>& lines) {
  std::vector<std::string> out;
  std::string file;
  int first = -1, last = -1;
  const auto flush = [&] {
    if (first < 0) return;
    out.push_back(first == last ? fmt::format("{}:{}", file, first) : fmt::format("{}:{}-{}", file, first, last));
    first = last = -1;
  };
  for (const std::string& l : lines) {
    const std::size_t colon = l.rfind(':');
    int n = -1;
    try {
      n = colon == std::string::npos ? -1 : std::stoi(l.substr(colon + 1));
    } catch (const std::exception&) {
      n = -1;
    }
    if (n < 0) {
      flush();
      out.push_back(l);
      continue;
    }
    const std::string f = l.substr(0, colon);
    if (first >= 0 && f == file && n == last + 1) {
      last = n;
      continue;
    }
    flush();
    file = f;
    first = last = n;
  }
  flush();
  return out;
}

namespace {

// The unreached lines of each kernel in a diff report's kernel_coverage, by pass.
std::map<std::string, std::vector<std::string>> Missed(const nlohmann::json& coverage) {
  std::map<std::string, std::vector<std::string>> out;
  if (!coverage.is_array()) return out;
  for (const nlohmann::json& k : coverage)
    if (k.contains("pass") && k.contains("missed")) out[k["pass"].get<std::string>()] = ExpandLineRuns(k["missed"].get<std::vector<std::string>>());
  return out;
}

std::string Flags(const mutate_runs::DiffConfig& c) {
  std::string s;
  for (const std::string& f : c.flags) s += (s.empty() ? "" : " ") + f;
  if (!c.scene.empty()) s += (s.empty() ? "" : " ") + std::string("on ") + c.scene;
  return s.empty() ? "(defaults)" : s;
}

}  // namespace

nlohmann::json ProbeCoverageOptions(const CoverageProbeArgs& args, const nlohmann::json& coverage) {
  std::map<std::string, std::vector<std::string>> left = Missed(coverage);
  for (auto it = left.begin(); it != left.end();) it = it->second.empty() ? left.erase(it) : std::next(it);
  nlohmann::json out = nlohmann::json::array();
  if (left.empty()) return out;
  std::vector<std::pair<std::string, std::string>> kernels;
  for (const std::string& k : args.kernels) {
    const std::size_t eq = k.find('=');
    if (eq != std::string::npos) kernels.emplace_back(k.substr(0, eq), fs::absolute(k.substr(eq + 1)).string());
  }
  const TempDirectory work(fs::temp_directory_path() / fmt::format("rayspace-coverage-{}", ::getpid()));
  const mutate_runs::Frame frame{fs::absolute(args.scene).string(), args.data, args.size, args.timeout, "emu,sim"};
  std::map<std::string, std::map<std::string, std::string>> found;  // pass -> line -> the first probe reaching it
  std::printf("  coverage options: probing %zu configurations on the simulated GPU at %s\n", mutate_runs::Configs().size(), args.size.c_str());
  std::fflush(stdout);
  for (const mutate_runs::DiffConfig& config : mutate_runs::Configs()) {
    const std::string scene = mutate_runs::SceneFor(config, frame.scene, work.path() / config.name);
    if (scene.empty()) continue;
    mutate_runs::DiffConfig small = config;
    small.size = "";  // the probe's own size, not the configuration's
    const mutate_runs::DiffRun run = mutate_runs::RunDiff(frame, small, kernels, work.path() / config.name, scene);
    if (!run.report.is_object()) continue;  // refused (the run never launches the pass) or timed out
    const auto probe = Missed(run.report.value("kernel_coverage", nlohmann::json()));
    for (auto& [pass, lines] : left) {
      const auto p = probe.find(pass);
      if (p == probe.end()) continue;
      const std::set<std::string> still(p->second.begin(), p->second.end());
      for (const std::string& l : lines)
        if (!still.count(l) && !found[pass].count(l)) found[pass][l] = config.name;
    }
  }
  for (const auto& [pass, lines] : left) {
    std::map<std::string, std::vector<std::string>> by_probe;  // in the unreached lines' order
    std::vector<std::string> never;
    for (const std::string& l : lines) {
      const auto f = found[pass].find(l);
      if (f == found[pass].end()) never.push_back(l);
      else by_probe[f->second].push_back(l);
    }
    std::printf("  coverage options for --kernel %s: %zu unreached line(s)\n", pass.c_str(), lines.size());
    nlohmann::json probes = nlohmann::json::array();
    for (const mutate_runs::DiffConfig& config : mutate_runs::Configs()) {
      const auto b = by_probe.find(config.name);
      if (b == by_probe.end()) continue;
      std::string joined;
      for (const std::string& r : JoinLineRuns(b->second)) joined += (joined.empty() ? "" : ", ") + r;
      std::printf("    reached with %s: %s\n", Flags(config).c_str(), joined.c_str());
      probes.push_back({{"config", config.name}, {"flags", config.flags}, {"scene", config.scene}, {"lines", JoinLineRuns(b->second)}});
    }
    std::string joined;
    for (const std::string& r : JoinLineRuns(never)) joined += (joined.empty() ? "" : ", ") + r;
    if (!never.empty()) std::printf("    reached by no probe: %s\n", joined.c_str());
    out.push_back({{"pass", pass}, {"probes", probes}, {"unreached", JoinLineRuns(never)}});
  }
  return out;
}

}  // namespace rayspace::app
