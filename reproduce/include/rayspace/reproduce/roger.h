// Roger, Assarsson and Holzschuch 2007 ("Whitted ray-tracing for dynamic scenes using a ray-space
// hierarchy on the GPU"): its figures 9 and 13 publish plots, not tables, so `reproduce roger` measures
// what they plot on scenes we hold and checks the claims the text makes of them as relations on our
// counts. Times vary run to run: they are judged in timings.md only.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/reproduce/configs.h"
#include "rayspace/reproduce/counts.h"
#include "rayspace/reproduce/relations.h"

namespace rayspace::reproduce {

// One stand-in scene: a reflector in the room of scenes/roger-*.json.
struct RogerScene {
  std::string name;    // BUNNY res4, WAVY n=4: the configuration's scene
  std::string file;    // relative to the scenes directory
  std::string series;  // "bunny" (figure 9(b)), "wavy" (figure 9(c)), "room" (figure 10 only) or "loose" (figure 12)
  double x = 0;        // the figure's abscissa: the bunny's polygons, or n
  bool quick = false;  // measured by --quick too
  // Figure 10: the reflector (empty: not in the figure) and the room's quads along a wall's side, which
  // set the reflected scene's polygons.
  std::string reflector;
  int room = 5;
};
const std::vector<RogerScene>& RogerScenes();

// The paper's scenes are not held: what stands in for them, for the report's rows.
inline constexpr const char* kRogerStandIn =
    "stand-in: the paper's Kitchen is not held; a room (cornell_room, a ball, a block) holds the reflector";

inline constexpr const char* kRogerOtherStandIn =
    "stand-in: the paper's Patio and Museum are not held; the same room, its walls or a sphere changed";

// The configurations of `reproduce roger` at a base frame size: every scene (--quick: those marked
// quick) with Roger's quadtree and the thesis's RAH (subdivision 8, depth 2) at width x height, and the
// first bunny at half and twice each side too (figure 13(c)).
std::vector<Config> RogerConfigs(int width, int height, bool full);

// Our counts in the paper's terms, summed over the ray types.
std::uint64_t ConeSphereTests(const Counts& c);  // every level's intersections: the traversal's tests
std::uint64_t FinalTests(const Counts& c);       // ray-triangle tests
std::uint64_t Rays(const Counts& c);

// The paper's claims as relations, each named as the report names it.
inline constexpr const char* kRogerGrowsLod = "work grows with the bunny's polygons (fig. 9(b))";
inline constexpr const char* kRogerGrowsN = "work grows with n of cos(nx)cos(ny) (fig. 9(c))";
inline constexpr const char* kRogerPerRay = "ray-triangle tests per ray between 2.5 and 4.5 (fig. 13(a))";
inline constexpr const char* kRogerSubLinear = "4x the pixels, less than 4x the cone-sphere tests (fig. 13(c))";

// Figure 10: irregular reflectors make the frame's work grow faster with the scene's polygons than
// smooth ones. Figure 12: loose upper levels (a sphere's top cone spans every direction; every wall a
// mirror spans the room) do not slow the traversal. The Museum: shadow rays inside the reflection are
// what makes Museum8 slow (3,330 ms with them, 1,316 ms without).
inline constexpr const char* kRogerIrregular = "irregular reflectors: work grows faster with the scene's polygons (fig. 10)";
inline constexpr const char* kRogerLoose = "loose upper levels do not slow the traversal (fig. 12)";
inline constexpr const char* kRogerShadows = "shadow rays inside the reflection more than double the frame (Museum8)";
inline constexpr double kRogerMuseumWith = 3330, kRogerMuseumWithout = 1316;  // ms, Museum8, section 6

// Figure 14(b, c) set the frame beside other systems' on their hardware; what carries over is the
// relation to a BVH: about twice as fast as Lauterbach et al.'s on a reflecting bunny (14(c)), and,
// against Wald et al.'s dynamic BVH, "slower for simple scenes, faster for more complex scenes"
// (14(b)). Ours: the same frame traced by Embree 3's BVH (`--algo embree`) on the bunny's LODs.
inline constexpr const char* kRogerBvhFaster = "faster than a BVH on a reflecting bunny (fig. 14(c): about 2x)";
inline constexpr const char* kRogerBvhTrend = "against a BVH, slower on simple scenes, faster on complex ones (fig. 14(b))";

// The configuration's hierarchy shape as the report names it: "rah-quadtree", "rah s8 d2", with its
// switches and faithful preset.
std::string RogerShape(const Config& c);
// The stand-in scene of a configuration; nullptr for a scene not in RogerScenes().
const RogerScene* RogerSceneOf(const Config& c);
// The WALLS frame with shadow rays from the primary hits only (`--shadow-bounces first`), the Museum
// claim's "without" side.
bool ShadowsFirstOnly(const Config& c);

// The report's claims as rows: claim, where, "holds" or "fails", the compared numbers.
using RogerVerdicts = std::vector<std::vector<std::string>>;

struct GrowthPoint {
  double x = 0;
  std::uint64_t work = 0;
};
// Holds when work strictly increases with x (the points in any order; fewer than two: fails, nothing
// was compared). Detail: the works in x order, "1,200 < 3,400 < 9,000".
Outcome GrowsWith(std::vector<GrowthPoint> points);
// Holds when ours takes less time than the BVH's frame; detail: the ratio.
Outcome FasterThanBvh(double ours_ms, double bvh_ms);
// Figure 14(b): holds when ours over the BVH's frame is above 1 on the fewest polygons and below 1
// on the most (slower on the simplest scene, faster on the most complex). Points: (polygons, ratio).
Outcome OvertakesBvh(std::vector<std::pair<double, double>> points);
// Holds when the irregular reflector's growth (work per ray in the larger room over the smaller)
// exceeds the smooth one's; detail "x1.80 > x1.20".
Outcome GrowsFaster(double irregular, double smooth);
// Holds when v <= reference: the loose frame's work per reflection ray is no more than the tight one's.
Outcome NotAbove(double v, double reference);
// Holds when with / without > 2; detail "x2.31 > x2 (published x2.53)".
Outcome MoreThanDouble(double with, double without);
// Holds when lo <= v <= hi; detail "3.21 in [2.5, 4.5]".
Outcome InRange(double v, double lo, double hi);
// Holds when big / small < pixel_ratio; detail "x3.10 < x4 pixels".
Outcome SubLinear(std::uint64_t small, std::uint64_t big, double pixel_ratio);

}  // namespace rayspace::reproduce
