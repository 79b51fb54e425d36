#include "rayspace/api.h"

#include <nlohmann/json.hpp>

#include "rayspace/diff/diff_command.h"
#include "rayspace/diff/junit_reports.h"
#include "rayspace/frame/render_command.h"
#include "rayspace/json_text.h"
#include "rayspace/frame/version.h"

namespace rayspace::api {
namespace {

// The frame and the user's kernels, as render's and diff's options (app::FrameArgs) hold them.
void ApplyFrame(const FrameConfig& f, const std::vector<KernelOverride>& kernels, const std::string& prefix, app::FrameArgs& a) {
  a.data = f.data;
  a.size = f.size;
  a.algo = f.algo;
  a.bounces = f.bounces;
  for (const KernelOverride& k : kernels) a.kernels.push_back(k.pass + "=" + k.file);
  a.kernels.data_prefix = prefix;
}

app::DiffArgs ToArgs(const DiffRequest& r) {
  app::DiffArgs a;
  ApplyFrame(r.frame, r.kernels, r.prefix, a);
  a.scene = r.frame.scene;
  a.local_size = r.frame.local_size;
  a.backends = r.backends;
  a.backends_given = true;  // the request names its device: no fallback to the simulated GPU
  a.compare = r.compare;
  a.inject = r.inject;
  return a;
}

}  // namespace

const char* ToString(Verdict v) {
  switch (v) {
    case Verdict::kEqual: return "equal";
    case Verdict::kDivergent: return "divergent";
    case Verdict::kCheckerStopped: return "checker stopped";
    case Verdict::kBackendFailed: return "backend failed";
  }
  return "?";
}

DiffReport Diff(const DiffRequest& request) {
  const app::DiffResult r = app::DiffToReport(ToArgs(request));
  DiffReport out;
  out.verdict = r.verdict == ExitCode::kOk             ? Verdict::kEqual
                : r.verdict == ExitCode::kDivergence   ? Verdict::kDivergent
                : r.verdict == ExitCode::kBackendFault ? Verdict::kBackendFailed
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
    if (!p.equal) p.first_mismatch = app::FirstMismatch(c);
    out.calls.push_back(std::move(p));
  }
  out.json = JsonText(j);
  return out;
}

RenderReport Render(const RenderRequest& request) {
  app::RenderArgs a;
  ApplyFrame(request.frame, request.kernels, request.prefix, a);
  a.scene = request.frame.scene;
  a.backend = request.backend;
  a.path = request.path;
  a.no_oracle = !request.oracle;
  app::RenderValue v = app::RenderToValue(a);
  RenderReport out;
  out.width = v.width;
  out.height = v.height;
  out.rgb = std::move(v.rgb);
  out.digest = v.digest;
  out.oracle_mismatches = v.oracle_mismatches;
  out.statistics = JsonText(v.statistics);
  return out;
}

std::string Version() {
  const std::string text = app::VersionText();
  return text.substr(0, text.find('\n'));
}

}  // namespace rayspace::api
