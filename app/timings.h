// Per-phase timings in the thesis's phases (tables 4.25-4.27), summed over a frame's batches.
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

// Maps pass names (raygen.*, hash.*, sort.*, traverse.*, ...) to the thesis's phases.
std::vector<Phase> Phases(const std::vector<emu::PassRecord>& passes);
// Traversal + final tests: the time render --timings divides the total tests by for its throughput.
double SearchMs(const std::vector<Phase>& phases);
// The hierarchy traversal alone (0 for a tracer that does not split it off, brute and embree): the
// part Roger et al. claim grows below linearly with the rays; the final tests grow with them.
double TraversalMs(const std::vector<Phase>& phases);
void PrintPhases(std::FILE* out, const std::vector<Phase>& phases, double frame_ms, std::optional<std::uint64_t> total_tests);
void PhasesToJson(nlohmann::json& j, const std::vector<Phase>& phases);

}  // namespace rayspace::app
