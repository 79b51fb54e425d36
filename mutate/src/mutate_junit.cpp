#include "rayspace/mutate/mutate_junit.h"

#include <fmt/format.h>

namespace rayspace::app {
namespace {

using Outcome = JUnitCase::Outcome;

std::string Str(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

std::string MutantLine(const nlohmann::json& m) {
  return fmt::format("{}:{} {} '{}' -> '{}'", Str(m, "file"), m.value("line", 0), Str(m, "operator"), Str(m, "before"), Str(m, "after"));
}

JUnitSuite MutantSuite(const std::string& side, const nlohmann::json& mutants) {
  JUnitSuite s{"mutate on " + side, {}};
  for (const nlohmann::json& m : mutants) {
    JUnitCase k;
    k.classname = "mutate." + Str(m, "file");
    k.name = Str(m, "id");
    const std::string status = Str(m, "status");
    const std::string why = Str(m, "why"), reason = Str(m, "reason");
    if (status == "killed") {
      k.output = "killed" + (m.contains("caught") ? ": " + m["caught"].dump() : std::string());
    } else if (status == "survived" && !m.contains("class")) {
      k.outcome = Outcome::kFailure;
      k.type = "survived";
      k.message = MutantLine(m) + ": no diff configuration, kernel case or clamped device tells it from the kernel";
      k.details = m.dump(2);
    } else if (status == "survived" || status == "equivalent" || status == "stillborn" || status == "invalid") {
      k.outcome = Outcome::kSkipped;
      k.message = status == "survived" ? "explained survivor (" + Str(m, "class") + "): " + why
                                       : status + (why.empty() ? reason.empty() ? "" : ": " + reason : ": " + why);
    } else {
      k.outcome = Outcome::kError;
      k.type = status.empty() ? "error" : status;
      k.message = MutantLine(m) + ": " + (reason.empty() ? "no verdict" : reason);
      k.details = m.dump(2);
    }
    s.cases.push_back(std::move(k));
  }
  return s;
}

}  // namespace

std::vector<JUnitSuite> MutateJUnit(const nlohmann::json& report) {
  std::vector<JUnitSuite> out;
  const nlohmann::json sides = report.value("backends", nlohmann::json::array());
  const std::string first = sides.empty() ? "vulkan" : sides[0].get<std::string>();
  out.push_back(MutantSuite(first, report.value("mutants", nlohmann::json::array())));
  for (std::size_t k = 1; k < sides.size(); ++k) {
    const std::string side = sides[k].get<std::string>();
    if (report.contains("on_" + side)) out.push_back(MutantSuite(side, report["on_" + side].value("mutants", nlohmann::json::array())));
  }
  JUnitSuite variants{"mutate variants", {}};
  for (const nlohmann::json& v : report.value("variants", nlohmann::json::array())) {
    JUnitCase k;
    k.classname = "mutate.variant." + Str(v, "kernel");
    k.name = Str(v, "recipe");
    k.seconds = v.value("seconds", 0.0);
    const std::string status = Str(v, "status");
    if (status == "diverged") {
      k.outcome = Outcome::kFailure;
      k.type = "divergence";
      k.message = "the spirv-opt variant diffs unequal: " + Str(v, "reason");
      k.details = v.dump(2);
    } else if (status != "equal") {
      k.outcome = Outcome::kError;
      k.type = "error";
      k.message = Str(v, "reason").empty() ? "no verdict" : Str(v, "reason");
    }
    variants.cases.push_back(std::move(k));
  }
  out.push_back(std::move(variants));
  return out;
}

}  // namespace rayspace::app
