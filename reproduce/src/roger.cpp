#include "rayspace/reproduce/roger.h"

#include <algorithm>

#include <fmt/format.h>

namespace rayspace::reproduce {

const std::vector<RogerScene>& RogerScenes() {
  // The bunny's polygons are its PLY files' (bunny/SOURCE.txt); the paper's LODs run 948 to 69,000.
  // n is the wavy generator's frequency on a unit square (n / 2pi periods across the reflector).
  static const std::vector<RogerScene> scenes = {
      {"BUNNY res4", "roger-bunny-res4.json", "bunny", 948, true},
      {"BUNNY res3", "roger-bunny-res3.json", "bunny", 3851, true, "bunny res3"},
      {"BUNNY res2", "roger-bunny-res2.json", "bunny", 16301, false},
      {"BUNNY full", "roger-bunny-full.json", "bunny", 69451, false},
      {"WAVY n=4", "roger-wavy-n4.json", "wavy", 4, true},
      {"WAVY n=8", "roger-wavy-n8.json", "wavy", 8, true},
      {"WAVY n=16", "roger-wavy-n16.json", "wavy", 16, true},
      {"WAVY n=32", "roger-wavy-n32.json", "wavy", 32, true},
      // Figure 10 (the Patio with a smooth and an irregular reflector, its polygons raised by adding
      // objects): our room's walls cut into 40x40 quads in place of 5x5 raise it from 4K to 23K
      // triangles. The sphere has about the bunny's polygons and covers about its pixels.
      {"BUNNY res3 room 40", "roger-bunny-res3-room40.json", "room", 3851, true, "bunny res3", 40},
      {"SPHERE", "roger-sphere.json", "loose", 0, true, "sphere"},
      {"SPHERE room 40", "roger-sphere-room40.json", "room", 0, true, "sphere", 40},
      // Figure 12(b): every wall a mirror.
      {"WALLS", "roger-walls.json", "loose", 0, true},
  };
  return scenes;
}

std::vector<Config> RogerConfigs(int width, int height, bool full) {
  std::vector<Config> configs;
  auto add = [&](const RogerScene& s, int w, int h, bool faithful) {
    Config c;
    c.target = "roger";
    c.scene = s.name;
    c.scene_file = s.file;
    c.bounces = 1;  // the paper's figures 9 and 13: one bounce
    c.path = "passes";  // cone-sphere tests, then the stream reduction: figure 9(a) times them apart
    c.width = w;
    c.height = h;
    c.algo = "rah-quadtree";
    c.subdivision = 4;
    c.levels = 0;
    configs.push_back(c);
    // The leaf rule's fit (docs/reproduce.md, "Fits"): the quadtree with the leaf-level ray-sphere
    // test alone, at every scene and size, so that every figure can be predicted with it.
    c.switches = {"--leaf-test", "ray-sphere"};
    configs.push_back(c);
    c.switches.clear();
    c.algo = "rah";
    c.subdivision = 8;
    c.levels = 2;
    configs.push_back(c);
    if (!faithful) return;
    // Figure 14: the same frame through Embree's BVH, on the bunny's LODs.
    if (s.series == "bunny") {
      Config e = c;
      e.algo = "embree";
      e.path.clear();
      configs.push_back(e);
    }
    // The quadtree as the paper describes it (--faithful roger: its leaf-level ray-sphere test and its
    // printed cone test), beside rayspace's: figure 13(a)'s tests per ray depend on the leaf test.
    c.algo = "rah-quadtree";
    c.subdivision = 4;
    c.levels = 0;
    c.faithful = "roger";
    configs.push_back(c);
    if (s.name != "WALLS") return;
    // The Museum's shadow rays: the frame again without those inside the reflection (the paper's 1,316 ms).
    c.faithful.clear();
    c.switches = {"--shadow-bounces", "first"};
    configs.push_back(c);
  };
  for (const RogerScene& s : RogerScenes())
    if (full || s.quick) add(s, width, height, true);
  // Figure 13(c): the same frame at a quarter (when it has a pixel) and four times the pixels.
  if (width >= 2 && height >= 2) add(RogerScenes().front(), width / 2, height / 2, false);
  add(RogerScenes().front(), width * 2, height * 2, false);
  return configs;
}

std::string RogerShape(const Config& c) {
  std::string shape = c.quadtree() ? "rah-quadtree" : fmt::format("rah s{} d{}", c.subdivision, c.levels);
  for (const std::string& w : c.switches) shape += " " + w;
  return c.faithful.empty() ? shape : shape + " --faithful " + c.faithful;
}

bool ShadowsFirstOnly(const Config& c) { return !c.switches.empty() && c.switches.front() == "--shadow-bounces"; }

const RogerScene* RogerSceneOf(const Config& c) {
  for (const RogerScene& s : RogerScenes())
    if (s.name == c.scene) return &s;
  return nullptr;
}

std::uint64_t ConeSphereTests(const Counts& c) {
  std::uint64_t n = 0;
  for (const auto& [type, t] : c.types)
    for (const LevelCounts& l : t.levels) n += l.intersections;
  return n;
}

std::uint64_t FinalTests(const Counts& c) {
  std::uint64_t n = 0;
  for (const auto& [type, t] : c.types) n += t.final_tests;
  return n;
}

std::uint64_t Rays(const Counts& c) {
  std::uint64_t n = 0;
  for (const auto& [type, t] : c.types) n += t.rays;
  return n;
}

Outcome GrowsWith(std::vector<GrowthPoint> points) {
  std::stable_sort(points.begin(), points.end(), [](const GrowthPoint& a, const GrowthPoint& b) { return a.x < b.x; });
  if (points.size() < 2) return {false, fmt::format("{} point(s): nothing to compare", points.size())};
  bool holds = true;
  std::string detail = Thousands(points[0].work);
  for (std::size_t i = 1; i < points.size(); ++i) {
    const bool up = points[i].work > points[i - 1].work;
    holds = holds && up;
    detail += fmt::format(" {} {}", up ? "<" : ">=", Thousands(points[i].work));
  }
  return {holds, detail};
}

Outcome GrowsFaster(double irregular, double smooth) {
  const bool holds = irregular > smooth;
  return {holds, fmt::format("x{:.2f} {} x{:.2f}", irregular, holds ? ">" : "<=", smooth)};
}

Outcome NotAbove(double v, double reference) {
  const bool holds = v <= reference;
  return {holds, fmt::format("{:.2f} {} {:.2f}", v, holds ? "<=" : ">", reference)};
}

Outcome MoreThanDouble(double with, double without) {
  const double ratio = without > 0 ? with / without : 0.0;
  const bool holds = without > 0 && ratio > 2.0;
  return {holds, fmt::format("x{:.2f} {} x2 (published x{:.2f})", ratio, holds ? ">" : "<=", kRogerMuseumWith / kRogerMuseumWithout)};
}

Outcome FasterThanBvh(double ours_ms, double bvh_ms) {
  const double ratio = bvh_ms > 0 ? ours_ms / bvh_ms : 0.0;
  const bool holds = bvh_ms > 0 && ours_ms > 0 && ratio < 1.0;
  return {holds, fmt::format("x{:.2f} the BVH's frame (published about x0.5)", ratio)};
}

Outcome OvertakesBvh(std::vector<std::pair<double, double>> points) {
  std::stable_sort(points.begin(), points.end());
  if (points.size() < 2) return {false, fmt::format("{} point(s): nothing to compare", points.size())};
  const double first = points.front().second, last = points.back().second;
  const bool holds = first > 1.0 && last < 1.0;
  std::string detail;
  for (const auto& [polygons, ratio] : points) detail += fmt::format("{}x{:.2f}", detail.empty() ? "" : ", ", ratio);
  return {holds, detail + " from the fewest polygons to the most"};
}

Outcome InRange(double v, double lo, double hi) {
  const bool holds = v >= lo && v <= hi;
  return {holds, fmt::format("{:.2f} {} [{}, {}]", v, holds ? "in" : "not in", lo, hi)};
}

Outcome SubLinear(std::uint64_t small, std::uint64_t big, double pixel_ratio) {
  const double ratio = small ? static_cast<double>(big) / static_cast<double>(small) : 0.0;
  const bool holds = small > 0 && ratio < pixel_ratio;
  return {holds, fmt::format("x{:.2f} {} x{:g} pixels ({} -> {})", ratio, holds ? "<" : ">=", pixel_ratio, Thousands(small),
                             Thousands(big))};
}

}  // namespace rayspace::reproduce
