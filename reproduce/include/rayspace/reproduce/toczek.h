// Toczek et al. 2010 ("Efficient stackless ray traversal for bounding sphere hierarchies with
// CUDA"): its tables 1 and 2 give frame rates, rays per second and traversed nodes per second on a
// GTX 280; their ratio, traversed nodes per ray, is what an emulator can compare. `reproduce toczek`
// measures the same quantity with `--algo tl` (sphere and triangle elements tested per ray) on the
// scenes we hold, and judges the relations the tables show.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/reproduce/configs.h"
#include "rayspace/reproduce/relations.h"

namespace rayspace::reproduce {

struct Result;
struct Table;
struct Report;

// The paper's frames: 1024x1024, one point light, direct illumination.
inline constexpr int kToczekFullSide = 1024;

// One scene of the tables: our file, the paper's name and triangle count.
struct ToczekScene {
  std::string name;      // the configuration's scene: BUNNY (no ground), CUBES, SUZANNE, BUNNY+GROUND, DRAGON
  std::string file;      // relative to the scenes directory
  int table = 2;         // 1: table 1 (the bunny without ground), 2: table 2
  std::uint64_t paper_triangles = 0;
  std::string note;      // how ours differs
};
const std::vector<ToczekScene>& ToczekScenes();

// Table 1 on the bunny without ground in both node orders, back-face culling off and on; table 2 on
// every scene (6 lists, earliest first), and again with 1 list (section 4's 6 lists against 1), at
// width x height.
std::vector<Config> ToczekConfigs(int width, int height);

// The published rows: table 1 (node order, back-face culling, per-polygon heads, frustum culling,
// rays/s, traversed nodes/s) and table 2 (scene, triangles, rays/s, traversed nodes/s).
struct ToczekTable1Row {
  std::string order;
  bool culling = false, heads = false, frustum = false;
  double rays_per_s = 0, nodes_per_s = 0;
  double fps = 0;  // at 1024x1024, one point light (GTX 280)
  double NodesPerRay() const { return nodes_per_s / rays_per_s; }
};
const std::vector<ToczekTable1Row>& ToczekTable1();
struct ToczekTable2Row {
  std::string scene;  // the paper's
  std::uint64_t triangles = 0;
  double rays_per_s = 0, nodes_per_s = 0;
  double fps = 0;  // at 1024x1024, one point light (GTX 280)
  double NodesPerRay() const { return nodes_per_s / rays_per_s; }
};
const std::vector<ToczekTable2Row>& ToczekTable2();

inline constexpr const char* kToczekOrder = "the node order changes nodes per ray by at most 20% (table 1)";
inline constexpr const char* kToczekCulling = "back-face culling lowers nodes per ray (table 1)";
inline constexpr const char* kToczekFrustum = "frustum culling lowers nodes per ray (table 1)";
inline constexpr const char* kToczekHeads = "regular per-polygon heads lower nodes per ray (table 1)";
// Table 2's frames and rays per second (timings.md): ours (6 lists, earliest first, every switch
// off) beside the published, and the two relations they support; empty with fewer than two scenes.
Table ToczekRatesTable(const std::vector<const Result*>& results);
inline constexpr const char* kToczekRateFalls =
    "rays per second fall from the smallest scene to the largest (table 2's caption: the traversal rate falls with the polygon count)";
inline constexpr const char* kToczekTenTimes =
    "the small scenes' frame rate is about 10 times the big ones' (section 4: \"10 times higher framerates\"; 5x to 20x, the "
    "project's reading of \"about\")";
inline constexpr const char* kToczekFlat = "nodes per ray within 3x from the smallest scene to the largest (table 2)";

// Holds when the two differ by at most `bound` of the larger; detail "1604 vs 1725: 7.0% <= 20%".
Outcome WithinShare(double a, double b, double bound);
// Holds when `with` is below `without`; detail "1604 without, 1540 with: x0.960".
Outcome Lowers(double without, double with);
// Holds when max / min of the values <= bound; detail "x1.08 over 4 scenes".
Outcome SpreadAtMost(const std::vector<double>& values, double bound);

// What the paper's "traversed nodes" counts is not published: the traversal events a `tl` walk
// counts (docs/reproduce.md, "Fits"), in the protocol's order.
enum class NodeDefinition { kTested, kEntries, kWarpSteps };
inline constexpr NodeDefinition kNodeDefinitions[] = {NodeDefinition::kTested, NodeDefinition::kEntries, NodeDefinition::kWarpSteps};
const char* NodeDefinitionName(NodeDefinition d);
// The fit: the definition whose nodes per ray on the fit row (ours) is closest in |ln| to the
// published `target`; `ours` per definition (negative: not counted, never chosen). Ties: the
// earlier definition.
NodeDefinition FitNodeDefinition(const std::vector<double>& ours, double target);

// The sections of `reproduce toczek`: table 1 and table 2, ours beside the published, their relations.
// The times (6 lists against 1) into `timings`.
void AddToczekReport(Report& report, Report& timings, const std::vector<const Result*>& results);

}  // namespace rayspace::reproduce
