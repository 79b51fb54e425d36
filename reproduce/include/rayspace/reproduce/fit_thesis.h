// `reproduce thesis --fit`: the thesis's Sponza camera and light, which it does not publish, fitted on
// RAH s8 d2's ray count and level hits by the search docs/reproduce.md ("Fits") fixes.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/reproduce/runner.h"

namespace rayspace::reproduce {

// The 9 parameters, in the protocol's order: eye x, y, z; yaw, pitch, vertical field of view (degrees);
// light x, y, z.
inline constexpr std::size_t kFitParams = 9;
using FitPoint = std::array<double, kFitParams>;
struct FitRange {
  const char* name;
  double lo, hi;
};
// The protocols (docs/reproduce.md, "Fits"): 1, the first ranges; 2, plausible poses (narrower ranges,
// and a lit share of at least kMinLitShare from stage 2 on).
inline constexpr int kFitProtocolLatest = 2;
inline constexpr double kMinLitShare = 0.5;
const std::array<FitRange, kFitParams>& ThesisFitRanges(int protocol = kFitProtocolLatest);

// The thesis's fit set: SPONZA RAH s8 d2 (table 4.3) and the caption's ray count.
struct FitCounts {
  std::uint64_t rays = 0, level2_hits = 0, level1_hits = 0;
};
inline constexpr FitCounts kThesisFitSet{256713, 32686844, 13039589};

// The radical inverse of `index` in `base` (index 1 is the sequence's first point, 1/base).
double Halton(std::uint64_t index, unsigned base);
// A unit-cube point mapped onto the protocol's ranges.
FitPoint FromUnit(const std::array<double, kFitParams>& unit, int protocol = kFitProtocolLatest);
// The scene with the point's camera (up +z) and its first light at the point's position.
Scene WithPose(Scene scene, const FitPoint& p);
// J = sum of ln(ours / the thesis's)^2 over the fit set; a zero count is refused (infinite J).
double FitObjective(const FitCounts& ours);

struct FitOptions {
  std::filesystem::path scene_file;  // sponza-thesis.json: what the fitted scene keeps
  int screen = 2048, keep = 24, lights = 16, starts = 3, halvings = 4, frames_per_start = 80;
  int protocol = kFitProtocolLatest;
  bool progress = false;
};

// Runs the search with `frame` on the loaded Sponza scene; returns the record
// (reproduce/fits/thesis-sponza.json's content) whose "best" holds the fitted point.
nlohmann::json FitThesisSponza(const LoadedScene& sponza, const FitOptions& options, const FrameFn& frame);
// The scene file with the record's best camera and light (name sponza-thesis-fit, -2 for protocol 2).
nlohmann::json FittedSceneJson(const nlohmann::json& scene_file, const nlohmann::json& record);
// The names a protocol's fit writes: "fit-thesis-sponza" and "sponza-thesis-fit" with "-2" for protocol 2.
std::string FitRecordStem(int protocol);
std::string FittedSceneStem(int protocol);

}  // namespace rayspace::reproduce
