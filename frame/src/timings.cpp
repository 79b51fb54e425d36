#include "rayspace/frame/timings.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "rayspace/pass_registry.h"

namespace rayspace::app {
namespace {

bool Starts(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

constexpr const char* kThesisPhases[] = {"ray_creation",       "ray_compression",     "ray_sorting",
                                         "ray_decompression",  "hierarchy_creation",  "hierarchy_traversal",
                                         "final_intersection_tests"};
constexpr std::size_t kThesis = std::size(kThesisPhases);

// A label's pass without its batch: "tree.step.shadow.b0" -> "tree.step", "shade.b1" -> "shade",
// "traverse.L2.shadow.b0" -> "traverse".
std::string Stem(const std::string& label) {
  std::string stem;
  std::size_t at = 0;
  while (at <= label.size()) {
    const std::size_t dot = std::min(label.find('.', at), label.size());
    const std::string part = label.substr(at, dot - at);
    const bool batch = part == "shadow" || part == "reflection" || part == "refraction" || part == "primary" ||
                       (part.size() > 1 && (part[0] == 'b' || part[0] == 'L') && part.find_first_not_of("0123456789", 1) == std::string::npos);
    if (batch) break;
    stem += (stem.empty() ? "" : ".") + part;
    at = dot + 1;
  }
  return stem.empty() ? label : stem;
}

// The thesis's phase for a pass label (the registry's, by the pass the label names), or the pass's
// own name for the passes the thesis does not time (prep, raster, surfaces, shade, resolve, and a
// tracer's passes of no phase).
std::string PhaseOf(const std::string& label) {
  const std::optional<PassId> id = PassOfLabel(label);
  if (id && !Pass(*id).thesis_phase.empty()) return std::string(Pass(*id).thesis_phase);
  return id ? std::string(Pass(*id).name) : Stem(label);
}

Phase& Row(std::vector<Phase>& out, const std::string& name) {
  const auto it = std::find_if(out.begin(), out.end(), [&](const Phase& x) { return x.name == name; });
  if (it != out.end()) return *it;
  out.push_back({name});
  return out.back();
}

}  // namespace

std::vector<Phase> Phases(const std::vector<emu::PassRecord>& passes, double frame_ms, double oracle_ms) {
  std::vector<Phase> out;
  for (const char* p : kThesisPhases) out.push_back({p});
  double in_frame_passes = 0.0, in_trace = 0.0, trace_total = 0.0, outside_trace_passes = 0.0;
  bool tracer_passes = false;
  for (const emu::PassRecord& p : passes) {
    if (!p.ran) continue;
    if (p.in_trace) {
      tracer_passes = true;
      in_trace += p.ms;
      Phase& dst = Row(out, PhaseOf(p.name));
      dst.ms += p.ms;
      dst.elements += p.elements;
      continue;
    }
    in_frame_passes += p.ms;
    if (Starts(p.name, "trace.")) {
      // A tracer's total: its own passes were listed before it; what they leave is the tracer's.
      trace_total += p.ms;
      outside_trace_passes += std::max(p.ms - in_trace, 0.0);
      in_trace = 0.0;
      continue;
    }
    Phase& dst = Row(out, PhaseOf(p.name));
    dst.ms += p.ms;
    dst.elements += p.elements;
  }
  if (!tracer_passes) {
    // A tracer without passes of its own (brute, embree): one traversal + intersection lump.
    out[kThesis - 1].ms += trace_total;
  } else {
    out.push_back({"tracer_outside_its_passes", outside_trace_passes});
  }
  out.push_back({"oracle", oracle_ms});
  out.push_back({"frame_outside_passes", std::max(frame_ms - in_frame_passes - oracle_ms, 0.0)});
  return out;
}

double SearchMs(const std::vector<Phase>& phases) { return phases[5].ms + phases[6].ms; }
double TraversalMs(const std::vector<Phase>& phases) { return phases[5].ms; }

double NamedShare(const std::vector<Phase>& phases, double frame_ms) {
  double unnamed = 0.0;
  for (const Phase& p : phases)
    if (p.name == "tracer_outside_its_passes" || p.name == "frame_outside_passes") unnamed += p.ms;
  return frame_ms > 0 ? 1.0 - unnamed / frame_ms : 1.0;
}

void PrintPhases(std::FILE* out, const std::vector<Phase>& phases, double frame_ms, std::optional<std::uint64_t> total_tests) {
  std::fprintf(out, "  %-26s %10s %7s\n", "phase", "ms", "share");
  for (const Phase& p : phases)
    std::fprintf(out, "  %-26s %10.1f %6.1f%%\n", p.name.c_str(), p.ms, frame_ms > 0 ? 100.0 * p.ms / frame_ms : 0.0);
  std::fprintf(out, "  %-26s %10.1f %6.1f%% in named passes (the rows above but the two *_outside_* ones)\n", "frame", frame_ms,
               100.0 * NamedShare(phases, frame_ms));
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
