// Per-phase timings in the thesis's phases (tables 4.25-4.27), summed over a frame's batches, and the
// rest of the frame by name, so that the rows add up to the frame's time.
#pragma once
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/emu/frame.h"

namespace rayspace::app {

struct Phase {
  std::string name;
  double ms = 0.0;
  std::size_t elements = 0;
};

// The frame's time in rows: the thesis's seven phases first (raygen.*, hash.*, sort.*, traverse.*,
// ... mapped by the pass registry), then each other pass by name (prep, raster, surfaces, shade,
// resolve, a tracer's passes of no phase), then "tracer_outside_its_passes" (a trace.* pass's time
// its own passes do not cover), "oracle" (`oracle_ms`, run inside the frame) and
// "frame_outside_passes" (the frame's time no pass covers). A tracer without passes of its own
// (brute, embree) counts its trace.* time as final intersection tests.
std::vector<Phase> Phases(const std::vector<emu::PassRecord>& passes, double frame_ms, double oracle_ms);
// The share of the frame in named rows: all but the two *_outside_* ones.
double NamedShare(const std::vector<Phase>& phases, double frame_ms);
// Traversal + final tests: the time render --timings divides the total tests by for its throughput.
double SearchMs(const std::vector<Phase>& phases);
// The hierarchy traversal alone (0 for a tracer that does not split it off, brute and embree): the
// part Roger et al. claim grows below linearly with the rays; the final tests grow with them.
double TraversalMs(const std::vector<Phase>& phases);
void PrintPhases(std::FILE* out, const std::vector<Phase>& phases, double frame_ms, std::optional<std::uint64_t> total_tests);
void PhasesToJson(nlohmann::json& j, const std::vector<Phase>& phases);

}  // namespace rayspace::app
