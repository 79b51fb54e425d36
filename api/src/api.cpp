#include "rayspace/api.h"

#include <nlohmann/json.hpp>

#include "diff_command.h"
#include "rayspace/json_text.h"
#include "version.h"

namespace rayspace::api {
namespace {

app::DiffArgs ToArgs(const DiffRequest& r) {
  app::DiffArgs a;
  a.scene = r.frame.scene;
  a.data = r.frame.data;
  a.size = r.frame.size;
  a.algo = r.frame.algo;
  a.bounces = r.frame.bounces;
  a.local_size = r.frame.local_size;
  a.backends = r.backends;
  a.backends_given = true;  // the request names its device: no fallback to the simulated GPU
  a.compare = r.compare;
  a.inject = r.inject;
  for (const KernelOverride& k : r.kernels) a.kernels.push_back(k.pass + "=" + k.file);
  a.kernels.data_prefix = r.prefix;
  return a;
}

std::string FirstMismatch(const nlohmann::json& call) {
  for (const nlohmann::json& b : call.value("buffers", nlohmann::json::array())) {
    if (b.value("equal", true)) continue;
    const std::string name = b.value("buffer", std::string("?"));
    if (b.contains("first_mismatch")) {
      const nlohmann::json& m = b["first_mismatch"];
      return name + "[" + m["index"].dump() + "]: expected " + m["expected"].get<std::string>() + ", actual " +
             m["actual"].get<std::string>();
    }
    return name + ": " + std::to_string(b.value("expected_elements", 0)) + " elements expected, " +
           std::to_string(b.value("actual_elements", 0)) + " actual";
  }
  return {};
}

}  // namespace

const char* ToString(Verdict v) {
  switch (v) {
    case Verdict::kEqual: return "equal";
    case Verdict::kDivergent: return "divergent";
    case Verdict::kCheckerStopped: return "checker stopped";
  }
  return "?";
}

DiffReport Diff(const DiffRequest& request) {
  const app::DiffResult r = app::DiffToReport(ToArgs(request));
  DiffReport out;
  out.verdict = r.verdict == app::ExitCode::kOk           ? Verdict::kEqual
                : r.verdict == app::ExitCode::kDivergence ? Verdict::kDivergent
                                                          : Verdict::kCheckerStopped;
  const nlohmann::json& j = r.report;
  if (j["first_divergent_pass"].is_string()) out.first_divergent_pass = j["first_divergent_pass"];
  if (j["stopped"].is_string()) out.stopped = j["stopped"];
  for (const nlohmann::json& c : j["calls"]) {
    PassCall p;
    p.pass = c.value("pass", std::string());
    p.label = c.value("label", std::string());
    p.equal = c.value("equal", true);
    p.within_spec = c.value("within_spec", false);
    if (!p.equal) p.first_mismatch = FirstMismatch(c);
    out.calls.push_back(std::move(p));
  }
  out.json = JsonText(j);
  return out;
}

std::string Version() {
  const std::string text = app::VersionText();
  return text.substr(0, text.find('\n'));
}

}  // namespace rayspace::api
