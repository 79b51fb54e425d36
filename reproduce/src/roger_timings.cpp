// `reproduce roger`'s times (timings.md): Roger's four phases per frame (figure 9(a)), time against
// cone-sphere tests (figure 13(b)) and against pixels (figure 13(c)). Times vary run to run and from
// machine to machine: none of this is in the byte-identical report.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "rayspace/reproduce/report.h"
#include "rayspace/reproduce/roger.h"

namespace rayspace::reproduce {
namespace {

enum RogerPhase { kBuild, kConeSphere, kReduction, kRayTriangle, kOther, kPhases };
constexpr std::array<const char*, kPhases> kPhaseNames = {"build", "cone-sphere", "stream reduction", "ray-triangle", "other"};

bool Starts(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

// Roger's phase of one of our passes: build.* builds the hierarchy; traverse.* and tree.test/roots test
// cones against spheres; reduce, traverse.compact.* and tree.expand/step remove the empty pairs (the
// stream reduction); intersect* is the ray-triangle pass. The rest (rasterisation, ray creation, hashing,
// sorting, shading) is "other".
RogerPhase PhaseOf(const std::string& pass) {
  if (Starts(pass, "build")) return kBuild;
  if (Starts(pass, "reduce") || Starts(pass, "traverse.compact") || Starts(pass, "tree.expand") || Starts(pass, "tree.step"))
    return kReduction;
  if (Starts(pass, "traverse.") || Starts(pass, "tree.test") || Starts(pass, "tree.roots")) return kConeSphere;
  if (Starts(pass, "intersect")) return kRayTriangle;
  return kOther;
}

std::array<double, kPhases> PhaseMs(const Result& r) {
  std::array<double, kPhases> ms{};
  if (!r.timings.contains("passes")) return ms;
  for (const nlohmann::json& p : r.timings["passes"]) {
    const std::string name = p.value("pass", std::string());
    if (Starts(name, "trace.")) continue;  // a tracer's total: its passes are listed too
    ms[PhaseOf(name)] += p.value("ms", 0.0);
  }
  return ms;
}

std::string Name(const Result& r) {
  std::string name = fmt::format("{} {} {}x{}", r.config.scene, r.config.quadtree() ? "rah-quadtree" : "rah s8 d2",
                                 r.config.width, r.config.height);
  for (const std::string& w : r.config.switches) name += " " + w;
  return r.config.faithful.empty() ? name : name + " --faithful " + r.config.faithful;
}

Table PhasesTable(const std::vector<const Result*>& results) {
  Table t{"roger-9a-times", "Roger et al. 2007, figure 9(a): share of frame time per phase (ours: this run, this machine)",
          {"configuration", "frame ms", "build %", "cone-sphere %", "stream reduction %", "ray-triangle %", "other %",
           "stream reduction largest of the four", "build < 1 %"},
          {}, {}};
  int largest = 0, small_build = 0;
  for (const Result* r : results) {
    const std::array<double, kPhases> ms = PhaseMs(*r);
    const double frame = r->timings.value("frame_ms", 0.0);
    if (frame <= 0) continue;
    std::vector<std::string> row = {Name(*r), fmt::format("{:.1f}", frame)};
    for (const double m : ms) row.push_back(fmt::format("{:.1f}", 100.0 * m / frame));
    const bool is_largest = ms[kReduction] >= std::max({ms[kBuild], ms[kConeSphere], ms[kRayTriangle]});
    const bool build_small = ms[kBuild] < 0.01 * frame;
    row.push_back(is_largest ? "holds" : "fails");
    row.push_back(build_small ? "holds" : "fails");
    largest += is_largest, small_build += build_small;
    t.rows.push_back(std::move(row));
  }
  t.notes.push_back(fmt::format("The paper: stream reduction ~60 %, cone-sphere ~15 %, build < 1 % (GeForce 8800). Ours: stream "
                                "reduction the largest of the four traced phases in {} of {} frames; build below 1 % in {} of {}.",
                                largest, t.rows.size(), small_build, t.rows.size()));
  t.notes.push_back("Our phases (roger runs `--path passes`: each level's cone-sphere tests, then its stream reduction, "
                    "Roger's hierarchical one with s = 64): build = build.*; cone-sphere = traverse.*; stream reduction = "
                    "reduce.*; ray-triangle = intersect*; other = rasterisation, ray creation, hashing, sorting, shading.");
  return t;
}

// Pearson's correlation of x and y; 0 when either does not vary.
double Correlation(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx), syy += (y[i] - my) * (y[i] - my);
  return sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
}

Table CorrelationTable(const std::vector<const Result*>& results) {
  Table t{"roger-13b-times", "Roger et al. 2007, figure 13(b): traversal time against cone-sphere tests",
          {"configuration", "cone-sphere tests", "cone-sphere + stream reduction ms", "frame ms"}, {}, {}};
  std::vector<double> x, y;
  for (const Result* r : results) {
    const std::array<double, kPhases> ms = PhaseMs(*r);
    const double traversal = ms[kConeSphere] + ms[kReduction];
    t.rows.push_back({Name(*r), Thousands(ConeSphereTests(r->counts)), fmt::format("{:.1f}", traversal),
                      fmt::format("{:.1f}", r->timings.value("frame_ms", 0.0))});
    x.push_back(static_cast<double>(ConeSphereTests(r->counts)));
    y.push_back(traversal);
  }
  t.notes.push_back(fmt::format("The paper: time is closely correlated to the cone-sphere tests. Ours: Pearson's r = {:.3f} "
                                "over {} frames (traversal time against cone-sphere tests).",
                                Correlation(x, y), x.size()));
  return t;
}

// Figure 13(c) in time: the first bunny's frames by size, each against the one with a quarter of its pixels.
Table PixelsTimes(const std::vector<const Result*>& results) {
  Table t{"roger-13c-times", "Roger et al. 2007, figure 13(c): traversal time against the frame's pixels",
          {"configuration", "cone-sphere + stream reduction ms", "x of a quarter of the pixels", "4x the pixels, less than 4x the time"},
          {}, {}};
  std::map<std::pair<bool, int>, double> ms;  // (quadtree, side) -> traversal ms
  for (const Result* r : results) {
    // The sizes are measured with rayspace's defaults only: a faithful frame has no quarter to compare with.
    if (r->config.scene != RogerScenes().front().name || !r->config.faithful.empty()) continue;
    const std::array<double, kPhases> p = PhaseMs(*r);
    const double traversal = p[kConeSphere] + p[kReduction];
    ms[{r->config.quadtree(), r->config.width}] = traversal;
    const auto quarter = ms.find({r->config.quadtree(), r->config.width / 2});
    const bool has = quarter != ms.end() && quarter->second > 0;
    const double ratio = has ? traversal / quarter->second : 0.0;
    t.rows.push_back({Name(*r), fmt::format("{:.1f}", traversal), has ? fmt::format("{:.2f}", ratio) : "n/a",
                      has ? (ratio < 4.0 ? "holds" : "fails") : "n/a"});
  }
  return t;
}

// Figure 10 and the Museum in time: frame growth from the 5x5 room to the 40x40 one, the bunny's
// against the sphere's per hierarchy shape, and the mirror-walled room's frame with and without the
// shadow rays inside the reflection.
Table ReflectorTimes(const std::vector<const Result*>& results) {
  Table t{"roger-10-times", "Roger et al. 2007, figure 10 and Museum8: frame time against the scene's polygons and shadow rays",
          {"claim", "configuration", "frame ms", "against", "frame ms", "x", "verdict"}, {}, {}};
  const auto frame = [](const Result* r) { return r->timings.value("frame_ms", 0.0); };
  // shape -> reflector -> room -> frame
  std::map<std::string, std::map<std::string, std::map<int, const Result*>>> rooms;
  std::map<std::string, const Result*> walls;  // shape -> WALLS frame, shadow rays after every bounce
  std::map<std::string, const Result*> walls_first;
  for (const Result* r : results) {
    const RogerScene* s = RogerSceneOf(r->config);
    if (!s || frame(r) <= 0) continue;
    const std::string shape = RogerShape(r->config);
    if (s->name == "WALLS" && ShadowsFirstOnly(r->config))
      walls_first[shape.substr(0, shape.find(" --shadow-bounces"))] = r;
    else if (s->name == "WALLS")
      walls[shape] = r;
    else if (!s->reflector.empty() && !ShadowsFirstOnly(r->config))
      rooms[shape][s->reflector][s->room] = r;
  }
  for (const auto& [shape, by_reflector] : rooms) {
    const auto growth = [&, &by = by_reflector](const char* reflector) {
      const auto it = by.find(reflector);
      if (it == by.end() || !it->second.contains(5) || !it->second.contains(40)) return 0.0;
      return frame(it->second.at(40)) / frame(it->second.at(5));
    };
    const double irregular = growth("bunny res3"), smooth = growth("sphere");
    if (irregular <= 0 || smooth <= 0) continue;
    const Result* big = by_reflector.at("bunny res3").at(40);
    const Result* small = by_reflector.at("bunny res3").at(5);
    const Outcome o = GrowsFaster(irregular, smooth);
    t.rows.push_back({kRogerIrregular, Name(*big), fmt::format("{:.1f}", frame(big)), Name(*small), fmt::format("{:.1f}", frame(small)),
                      fmt::format("{:.2f}", irregular),
                      fmt::format("{} (the sphere's x{:.2f})", o.holds ? "holds" : "fails", smooth)});
  }
  for (const auto& [shape, without] : walls_first) {
    const auto with = walls.find(shape);
    if (with == walls.end()) continue;
    const Outcome o = MoreThanDouble(frame(with->second), frame(without));
    t.rows.push_back({kRogerShadows, Name(*with->second), fmt::format("{:.1f}", frame(with->second)), Name(*without),
                      fmt::format("{:.1f}", frame(without)), fmt::format("{:.2f}", frame(with->second) / frame(without)),
                      fmt::format("{} ({})", o.holds ? "holds" : "fails", o.detail)});
  }
  return t;
}

// Figure 14(b, c) as the relations they support: the frame beside the same frame through Embree's
// BVH, per hierarchy shape, on the bunny's LODs at the base size.
Table BvhTimes(const std::vector<const Result*>& hierarchy, const std::vector<const Result*>& bvh) {
  Table t{"roger-14-times", "Roger et al. 2007, figure 14(b, c): the frame against a BVH's (ours: Embree 3 on the same frame, this machine)",
          {"configuration", "polygons", "frame ms", "Embree frame ms", "x Embree"}, {}, {}};
  const auto frame = [](const Result* r) { return r->timings.value("frame_ms", 0.0); };
  std::map<std::pair<std::string, int>, const Result*> bvh_of;  // (scene, width) -> Embree's frame
  for (const Result* r : bvh) bvh_of[{r->config.scene, r->config.width}] = r;
  std::map<std::string, std::vector<std::pair<double, double>>> ratios;  // shape -> (polygons, x Embree)
  std::map<std::string, std::pair<double, const Result*>> largest;       // shape -> its largest bunny
  for (const Result* r : hierarchy) {
    const RogerScene* s = RogerSceneOf(r->config);
    const auto b = bvh_of.find({r->config.scene, r->config.width});
    if (!s || s->series != "bunny" || b == bvh_of.end() || frame(r) <= 0 || frame(b->second) <= 0) continue;
    const double x = frame(r) / frame(b->second);
    const std::string shape = RogerShape(r->config);
    t.rows.push_back({Name(*r), Thousands(static_cast<std::uint64_t>(s->x)), fmt::format("{:.1f}", frame(r)),
                      fmt::format("{:.1f}", frame(b->second)), fmt::format("{:.2f}", x)});
    ratios[shape].push_back({s->x, x});
    if (s->x >= largest[shape].first) largest[shape] = {s->x, r};
  }
  for (const auto& [shape, points] : ratios) {
    const Result* big = largest[shape].second;
    const Outcome faster = FasterThanBvh(frame(big), frame(bvh_of.at({big->config.scene, big->config.width})));
    const Outcome overtakes = OvertakesBvh(points);
    t.notes.push_back(fmt::format("- {}, {} on {}: {} ({})", kRogerBvhFaster, shape, big->config.scene, Verdict(faster), faster.detail));
    t.notes.push_back(fmt::format("- {}, {}: {} ({})", kRogerBvhTrend, shape, Verdict(overtakes), overtakes.detail));
  }
  if (!t.rows.empty())
    t.notes.push_back("The paper's BVHs ran on other authors' GPUs; ours is Embree on this machine's CPU cores, and ours is the "
                      "emulated frame, the CPU running what the paper ran on a GPU. Times vary run to run.");
  return t;
}

}  // namespace

std::vector<Table> RogerTimings(const std::vector<const Result*>& results) {
  std::vector<const Result*> hierarchy, bvh;
  for (const Result* r : results) (r->config.embree() ? bvh : hierarchy).push_back(r);
  if (hierarchy.empty()) return {};
  std::vector<Table> tables = {PhasesTable(hierarchy), CorrelationTable(hierarchy), PixelsTimes(hierarchy)};
  if (Table t = ReflectorTimes(hierarchy); !t.rows.empty()) tables.push_back(std::move(t));
  if (Table t = BvhTimes(hierarchy, bvh); !t.rows.empty()) tables.push_back(std::move(t));
  return tables;
}

}  // namespace rayspace::reproduce
