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

// The fitted reading of table 5 (docs/reproduce.md, "Fits"): the regular grid sized to hold about as
// many cells as one face of the 200 x 200 x 4 perspective grid, as the paper's 54^3 = 157,464 against
// 160,000; and the target on its perspective/regular ratio (the paper's 12.7 / 52.0, within 25 %).
inline constexpr std::uint64_t kHuntEqualCells = 200ull * 200ull * 4ull;
inline constexpr double kHuntRatioTolerance = 0.25;

inline constexpr const char* kHuntFewerSteps = "a 3D perspective grid needs fewer cells per soft-shadow ray than a regular grid (table 5)";
inline constexpr const char* kHuntRaysFall = "rays per second fall from the smallest bunny to the largest (table 1)";
inline constexpr const char* kHuntHardSlower = "hard-shadow rays are not quite as fast as eye rays, in rays per second (table 1's text)";
inline constexpr const char* kHuntSoftSlower =
    "soft-shadow rays are substantially slower than hard-shadow rays, under half their rays per second (table 1's text)";
inline constexpr const char* kHuntSoftBuild = "the build is a smaller share of the frame for soft shadows than for hard shadows (table 1's text)";
inline constexpr const char* kHuntFasterEye = "faster than a BVH rebuilt each frame, for eye rays (table 2; section 6.2: always, 1.37x to 2.83x)";
inline constexpr const char* kHuntFasterShadow =
    "faster than a BVH rebuilt each frame, for eye and hard-shadow rays (table 2; section 6.2: in most cases, 0.94x to 2.36x)";
inline constexpr const char* kHuntFasterStatic = "faster for eye rays than a static BVH whose build is not counted (table 3)";
inline constexpr const char* kHuntZBuffer =
    "eye rays through the perspective grid are comparable to a software Z-buffer, in triangles per second (table 4; within 2x: "
    "the project's reading of \"comparable\")";
inline constexpr const char* kHuntBuildRises = "the build's share of the frame rises from the smallest bunny to the largest (table 1)";

// Table 5 and the relations on counts into `report`; table 1 (times) into `timings`.
// Tables 2-4 (timings.md): the grids' frame against Embree's (tables 2 and 3) and against the frame's
// raster pass (table 4), as the relations the paper's numbers support.
Table Tables234(const std::vector<const Result*>& results);
void AddHuntReport(Report& report, Report& timings, const std::vector<const Result*>& results);

}  // namespace rayspace::reproduce
