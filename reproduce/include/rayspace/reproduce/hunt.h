// Hunt and Mark 2008 ("Ray-specialized acceleration structures for ray tracing"): table 5 counts
// the grid cells a soft-shadow ray visits in a regular 54^3 grid and in a 200x200x4 perspective grid;
// table 1 gives rays per second and the per-frame build's share of the time for eye rays and hard
// shadows on the bunny's levels of detail and the conference room. `reproduce hunt-mark` measures
// both with `--algo grid`: table 5's steps per ray (deterministic, in report.md) on the soft-shadow
// Sponza and conference room; table 1's rates and build shares (timings.md, plotted against the
// triangle count).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/reproduce/configs.h"

namespace rayspace::reproduce {

struct Result;
struct Report;
struct Table;

struct HuntScene {
  std::string name;  // the configuration's scene
  std::string file;  // relative to the scenes directory
  int table = 1;     // 1: eye rays and hard shadows; 5: soft shadows, regular against perspective
  std::string paper; // the paper's row it stands beside (empty: none)
  std::string note;
};
const std::vector<HuntScene>& HuntScenes();

std::vector<Config> HuntConfigs(int width, int height);

inline constexpr const char* kHuntFewerSteps = "a 3D perspective grid needs fewer cells per soft-shadow ray than a regular grid (table 5)";
inline constexpr const char* kHuntRaysFall = "rays per second fall from the smallest bunny to the largest (table 1)";
inline constexpr const char* kHuntBuildRises = "the build's share of the frame rises from the smallest bunny to the largest (table 1)";

// Table 5 and the relations on counts into `report`; table 1 (times) into `timings`.
void AddHuntReport(Report& report, Report& timings, const std::vector<const Result*>& results);

}  // namespace rayspace::reproduce
