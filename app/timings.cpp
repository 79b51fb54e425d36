#include "timings.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "rayspace/pass_registry.h"

namespace rayspace::app {
namespace {

bool Starts(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

// The thesis's phase for a pass label (the registry's, by the pass the label names); "other" for
// passes the thesis does not time (raster, surfaces, shade, resolve) and labels of no pass (prep).
std::string_view PhaseOf(const std::string& label) {
  const std::optional<PassId> id = PassOfLabel(label);
  return id && !Pass(*id).thesis_phase.empty() ? Pass(*id).thesis_phase : std::string_view("other");
}

}  // namespace

std::vector<Phase> Phases(const std::vector<emu::PassRecord>& passes) {
  std::vector<Phase> out = {{"ray_creation"},       {"ray_compression"},    {"ray_sorting"},
                            {"ray_decompression"},  {"hierarchy_creation"}, {"hierarchy_traversal"},
                            {"final_intersection_tests"}, {"other"}};
  double traced_in_subpasses = 0.0, trace_total = 0.0;
  for (const emu::PassRecord& p : passes) {
    if (!p.ran) continue;
    if (Starts(p.name, "trace.")) {  // a tracer's total; its own passes are listed separately
      trace_total += p.ms;
      continue;
    }
    const std::string_view ph = PhaseOf(p.name);
    Phase& dst = *std::find_if(out.begin(), out.end(), [&](const Phase& x) { return x.name == ph; });
    dst.ms += p.ms;
    dst.elements += p.elements;
    if (ph != "other" && ph != "ray_creation") traced_in_subpasses += p.ms;
  }
  // A tracer without sub-passes (brute, embree) shows as one traversal + intersection lump.
  if (traced_in_subpasses == 0.0) out[6].ms += trace_total;
  return out;
}

double SearchMs(const std::vector<Phase>& phases) { return phases[5].ms + phases[6].ms; }
double TraversalMs(const std::vector<Phase>& phases) { return phases[5].ms; }

void PrintPhases(std::FILE* out, const std::vector<Phase>& phases, double frame_ms, std::optional<std::uint64_t> total_tests) {
  std::fprintf(out, "  %-26s %10s %7s\n", "phase", "ms", "share");
  for (const Phase& p : phases)
    std::fprintf(out, "  %-26s %10.1f %6.1f%%\n", p.name.c_str(), p.ms, frame_ms > 0 ? 100.0 * p.ms / frame_ms : 0.0);
  const double trav = SearchMs(phases);
  if (!total_tests)
    std::fprintf(out, "  %-26s %10s (the tracer does not count its tests)\n", "throughput", "n/a");
  else if (trav > 0)
    std::fprintf(out, "  %-26s %10.1f M tests/s (traversal + final tests)\n", "throughput",
                 static_cast<double>(*total_tests) / (trav * 1e3));
}

void PhasesToJson(nlohmann::json& j, const std::vector<Phase>& phases) {
  nlohmann::json a = nlohmann::json::array();
  for (const Phase& p : phases) a.push_back({{"phase", p.name}, {"ms", p.ms}, {"elements", p.elements}});
  j["phases"] = a;
}

}  // namespace rayspace::app
