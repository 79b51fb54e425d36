#include "rayspace/diff/junit_reports.h"

#include <fmt/format.h>

namespace rayspace::app {
namespace {

using Outcome = JUnitCase::Outcome;

std::string Str(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

JUnitSuite FrameSuite(const nlohmann::json& r) {
  JUnitSuite s;
  const std::string inject = Str(r, "inject");
  s.name = fmt::format("diff {} {}x{} {}{}", Str(r, "scene"), r.value("width", 0), r.value("height", 0), Str(r, "algorithm"),
                       inject.empty() ? "" : " --inject " + inject);
  bool failed_call = false;
  for (const nlohmann::json& c : r.value("calls", nlohmann::json::array())) {
    JUnitCase k;
    k.classname = "diff." + Str(c, "pass");
    k.name = fmt::format("{:04} {}", c.value("seq", 0), Str(c, "label"));
    k.seconds = (c.value("emu_ms", 0.0) + c.value("vulkan_ms", 0.0)) / 1000;
    if (!c.value("equal", true) && c.value("within_spec", false)) {
      k.output = "differs only as a conformant device may: " + Str(c, "relaxed_model");
    } else if (!c.value("equal", true)) {
      failed_call = true;
      k.outcome = Outcome::kFailure;
      k.type = "divergence";
      const std::string first = FirstMismatch(c);
      k.message = first.empty() ? "differs" : first;
      std::string details;
      for (const char* key : {"pairs", "hits", "raster"})
        if (!Str(c, key).empty()) details += fmt::format("{}: {}\n", key, Str(c, key));
      k.details = details + c.value("buffers", nlohmann::json::array()).dump(2);
    }
    s.cases.push_back(std::move(k));
  }
  // A stop no call's comparison explains: a checker's finding, a device output error, a driver error.
  const std::string stopped = Str(r, "stopped");
  JUnitCase frame;
  frame.classname = "diff";
  frame.name = "frame";
  if (!stopped.empty() && !failed_call) {
    const bool checker = r.contains("simulator_checker") || (r.contains("workgroup_checker") && !r["workgroup_checker"].is_null());
    frame.outcome = Outcome::kFailure;
    frame.type = checker ? "checker" : "stopped";
    frame.message = stopped;
    frame.details = checker ? (r.contains("simulator_checker") ? r["simulator_checker"] : r["workgroup_checker"]).dump(2) : stopped;
  } else if (!stopped.empty()) {
    frame.output = "stopped: " + stopped;
  }
  s.cases.push_back(std::move(frame));
  return s;
}

}  // namespace

std::string FirstMismatch(const nlohmann::json& call) {
  for (const nlohmann::json& b : call.value("buffers", nlohmann::json::array())) {
    if (b.value("equal", true)) continue;
    if (b.contains("first_mismatch")) {
      const nlohmann::json& m = b["first_mismatch"];
      return fmt::format("{}[{}]: expected {}, actual {} ({} of {} elements differ)", Str(b, "buffer"), m.value("index", 0),
                         Str(m, "expected"), Str(m, "actual"), b.value("mismatches", 0), b.value("elements", 0));
    }
    return fmt::format("{}: {} elements expected, {} actual", Str(b, "buffer"), b.value("expected_elements", 0),
                       b.value("actual_elements", 0));
  }
  return {};
}

std::vector<JUnitSuite> DiffJUnit(const nlohmann::json& report) {
  std::vector<JUnitSuite> out;
  if (report.contains("faults") && report["faults"].is_array()) {
    for (const nlohmann::json& r : report["faults"]) out.push_back(FrameSuite(r));
  } else {
    out.push_back(FrameSuite(report));
  }
  return out;
}

}  // namespace rayspace::app
