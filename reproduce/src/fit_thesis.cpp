#include "rayspace/reproduce/fit_thesis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "rayspace/error.h"
#include "rayspace/reproduce/counts.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::reproduce {

const std::array<FitRange, kFitParams>& ThesisFitRanges(int protocol) {
  static const std::array<FitRange, kFitParams> first = {{{"eye_x", -15, 15},
                                                         {"eye_y", -6, 6},
                                                         {"eye_z", 0.5, 10},
                                                         {"yaw_deg", -180, 180},
                                                         {"pitch_deg", -20, 50},
                                                         {"fov_y_deg", 40, 80},
                                                         {"light_x", -15, 15},
                                                         {"light_y", -6, 6},
                                                         {"light_z", 1, 30}}};
  // Protocol 2: the eye in the open court from the floor to the first gallery, the light inside the
  // walls below the roof's top (Sponza spans x -17.4..17.4, y -7.8..7.8, z -0.9..15.65).
  static const std::array<FitRange, kFitParams> plausible = {{{"eye_x", -12, 12},
                                                             {"eye_y", -3, 3},
                                                             {"eye_z", 1, 8},
                                                             {"yaw_deg", -180, 180},
                                                             {"pitch_deg", -15, 30},
                                                             {"fov_y_deg", 40, 80},
                                                             {"light_x", -12, 12},
                                                             {"light_y", -3, 3},
                                                             {"light_z", 2, 15}}};
  if (protocol != 1 && protocol != 2) ThrowInput("--fit-protocol {}: the protocols are 1 and 2 (docs/reproduce.md, \"Fits\")", protocol);
  return protocol == 1 ? first : plausible;
}

std::string FitRecordStem(int protocol) { return protocol == 1 ? "fit-thesis-sponza" : fmt::format("fit-thesis-sponza-{}", protocol); }
std::string FittedSceneStem(int protocol) { return protocol == 1 ? "sponza-thesis-fit" : fmt::format("sponza-thesis-fit-{}", protocol); }

double Halton(std::uint64_t index, unsigned base) {
  double f = 1.0, r = 0.0;
  for (std::uint64_t i = index; i > 0; i /= base) {
    f /= base;
    r += f * static_cast<double>(i % base);
  }
  return r;
}

FitPoint FromUnit(const std::array<double, kFitParams>& unit, int protocol) {
  const std::array<FitRange, kFitParams>& r = ThesisFitRanges(protocol);
  FitPoint p{};
  for (std::size_t k = 0; k < kFitParams; ++k) p[k] = r[k].lo + unit[k] * (r[k].hi - r[k].lo);
  return p;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// The camera of a point in double: eye, target (one unit along the view), field of view. The fitted
// scene file holds these same doubles, so that loading it gives the floats the fit rendered.
struct PoseCamera {
  glm::dvec3 eye, target;
  double fov_y_deg;
};
PoseCamera CameraOf(const FitPoint& p) {
  const double yaw = p[3] * kPi / 180.0, pitch = p[4] * kPi / 180.0;
  const glm::dvec3 eye(p[0], p[1], p[2]);
  const glm::dvec3 dir(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  return {eye, eye + dir, p[5]};
}

nlohmann::json Vec(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

Scene WithPose(Scene scene, const FitPoint& p) {
  const PoseCamera c = CameraOf(p);
  scene.camera.eye = glm::vec3(c.eye);
  scene.camera.target = glm::vec3(c.target);
  scene.camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
  scene.camera.fov_y_deg = static_cast<float>(c.fov_y_deg);
  RS_CHECK_MSG(!scene.lights.empty(), "the fit's scene has no light");
  scene.lights.front().position = glm::vec3(static_cast<float>(p[6]), static_cast<float>(p[7]), static_cast<float>(p[8]));
  return scene;
}

double FitObjective(const FitCounts& ours) {
  const auto term = [](std::uint64_t a, std::uint64_t b) {
    if (a == 0 || b == 0) return std::numeric_limits<double>::infinity();
    const double l = std::log(static_cast<double>(a) / static_cast<double>(b));
    return l * l;
  };
  return term(ours.rays, kThesisFitSet.rays) + term(ours.level2_hits, kThesisFitSet.level2_hits) +
         term(ours.level1_hits, kThesisFitSet.level1_hits);
}

namespace {

struct Evaluated {
  FitPoint point{};
  FitCounts counts;
  double j = 0.0;
  int size = 0;
  double lit_share = 0.0;  // unoccluded shadow rays over shadow rays (0 with none)
};

nlohmann::json ToJson(const Evaluated& e) {
  nlohmann::json p = nlohmann::json::object();
  for (std::size_t k = 0; k < kFitParams; ++k) p[ThesisFitRanges()[k].name] = e.point[k];
  return {{"point", p}, {"size", e.size}, {"rays", e.counts.rays}, {"level2_hits", e.counts.level2_hits},
          {"level1_hits", e.counts.level1_hits}, {"lit_share", e.lit_share},
          {"J", std::isfinite(e.j) ? nlohmann::json(e.j) : nlohmann::json(nullptr)}};
}

// One frame of SPONZA RAH s8 d2 at size x size with the point's camera and light, counted as the
// thesis counts. `min_lit_share`: a frame whose lit share is below it is no candidate (J infinite).
class Evaluator {
 public:
  Evaluator(const LoadedScene& sponza, const FrameFn& frame, bool progress) : sponza_(sponza), frame_(frame), progress_(progress) {}

  Evaluated operator()(const FitPoint& p, int size, double min_lit_share = 0.0) {
    Config c;
    c.scene = "SPONZA";
    c.scene_file = "sponza-thesis.json";
    c.algo = "rah";
    c.subdivision = 8;
    c.levels = 2;
    c.bounces = 1;
    c.width = c.height = size;
    const Scene scene = WithPose(sponza_.scene, p);
    const SceneBuffers buffers = FlattenScene(scene);
    const FrameOutput out = frame_(c, scene, buffers);
    const Counts counts = SlotAccounting(out.counts, c.subdivision);
    Evaluated e{p, {}, 0.0, size};
    if (const auto it = counts.types.find("shadow"); it != counts.types.end() && it->second.levels.size() == 2)
      e.counts = {it->second.rays, it->second.levels[1].hits, it->second.levels[0].hits};
    e.lit_share = out.shadow_rays == 0 ? 0.0 : static_cast<double>(out.unoccluded_shadow_rays) / static_cast<double>(out.shadow_rays);
    e.j = e.lit_share < min_lit_share ? std::numeric_limits<double>::infinity() : FitObjective(e.counts);
    if (++frames_ % 64 == 0 && progress_) std::fprintf(stderr, "rayspace reproduce --fit: %d frames\n", frames_);
    return e;
  }
  int frames() const { return frames_; }

 private:
  const LoadedScene& sponza_;
  const FrameFn& frame_;
  bool progress_;
  int frames_ = 0;
};

// Stage 1: Halton cameras at a quarter of the size, ranked by how close their covered share of
// pixels is to the thesis's (ties by index); the light stays the scene file's.
std::vector<Evaluated> ScreenCameras(Evaluator& eval, const LoadedScene& sponza, const FitOptions& o, nlohmann::json& record) {
  constexpr unsigned kCameraBases[] = {2, 3, 5, 7, 11, 13};
  const int size = 128;
  const double target = static_cast<double>(kThesisFitSet.rays) / (512.0 * 512.0);
  const glm::vec3 light = sponza.scene.lights.front().position;
  std::vector<std::pair<double, Evaluated>> ranked;
  for (int i = 1; i <= o.screen; ++i) {
    std::array<double, kFitParams> unit{};
    for (std::size_t k = 0; k < 6; ++k) unit[k] = Halton(static_cast<std::uint64_t>(i), kCameraBases[k]);
    FitPoint p = FromUnit(unit, o.protocol);
    p[6] = light.x, p[7] = light.y, p[8] = light.z;
    const Evaluated e = eval(p, size);
    const double covered = static_cast<double>(e.counts.rays) / (size * size);
    record["screen"].push_back({{"index", i}, {"covered", covered}, {"frame", ToJson(e)}});
    ranked.emplace_back(std::abs(covered - target), e);
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Evaluated> kept;
  for (int i = 0; i < o.keep && i < static_cast<int>(ranked.size()); ++i) kept.push_back(ranked[i].second);
  return kept;
}

// A parameter moved by `delta`: yaw wraps around the circle, the others stay in their ranges.
FitPoint Moved(FitPoint p, std::size_t k, double delta, int protocol) {
  const FitRange& r = ThesisFitRanges(protocol)[k];
  double v = p[k] + delta;
  if (k == 3) {
    while (v >= r.hi) v -= r.hi - r.lo;
    while (v < r.lo) v += r.hi - r.lo;
  } else {
    v = std::clamp(v, r.lo, r.hi);
  }
  p[k] = v;
  return p;
}

// Protocol 2's plausibility bound on the lit share, from stage 2 on; none under protocol 1.
double MinLitShare(const FitOptions& o) { return o.protocol >= 2 ? kMinLitShare : 0.0; }

// Stage 3: the compass search from one start (docs/reproduce.md).
Evaluated Compass(Evaluator& eval, Evaluated x, const FitOptions& o, nlohmann::json& path) {
  std::array<double, kFitParams> step{};
  const std::array<FitRange, kFitParams>& ranges = ThesisFitRanges(o.protocol);
  for (std::size_t k = 0; k < kFitParams; ++k) step[k] = (ranges[k].hi - ranges[k].lo) / 8.0;
  int frames = 0, halvings = 0;
  while (frames < o.frames_per_start) {
    bool improved = false;
    for (std::size_t k = 0; k < kFitParams && frames < o.frames_per_start; ++k)
      for (const double sign : {1.0, -1.0}) {
        const FitPoint y = Moved(x.point, k, sign * step[k], o.protocol);
        if (y == x.point || frames >= o.frames_per_start) continue;
        const Evaluated e = eval(y, 512, MinLitShare(o));
        ++frames;
        path.push_back(ToJson(e));
        if (e.j < x.j) {
          x = e, improved = true;
          break;
        }
      }
    if (improved) continue;
    if (halvings == o.halvings) break;
    for (double& s : step) s /= 2.0;
    ++halvings;
  }
  return x;
}

}  // namespace

nlohmann::json FitThesisSponza(const LoadedScene& sponza, const FitOptions& o, const FrameFn& frame) {
  if (sponza.scene.lights.size() != 1) ThrowInput("--fit: the Sponza scene has {} lights; the fit moves one point light", sponza.scene.lights.size());
  nlohmann::json record = {{"fit_set", {{"rays", kThesisFitSet.rays}, {"level2_hits", kThesisFitSet.level2_hits},
                                        {"level1_hits", kThesisFitSet.level1_hits}, {"configuration", "SPONZA rah s8 d2"}}},
                           {"search", {{"screen", o.screen}, {"keep", o.keep}, {"lights", o.lights}, {"starts", o.starts},
                                       {"halvings", o.halvings}, {"frames_per_start", o.frames_per_start}}},
                           {"screen", nlohmann::json::array()}, {"grid", nlohmann::json::array()},
                           {"refine", nlohmann::json::array()}, {"sensitivity", nlohmann::json::array()}};
  const std::array<FitRange, kFitParams>& ranges = ThesisFitRanges(o.protocol);
  for (const FitRange& r : ranges) record["ranges"][r.name] = {r.lo, r.hi};
  record["protocol"] = o.protocol;
  if (MinLitShare(o) > 0.0) record["min_lit_share"] = MinLitShare(o);
  Evaluator eval(sponza, frame, o.progress);
  const std::vector<Evaluated> cameras = ScreenCameras(eval, sponza, o, record);
  // Stage 2: each kept camera under each Halton light, at the thesis's size.
  std::vector<Evaluated> grid;
  for (const Evaluated& c : cameras)
    for (int j = 1; j <= o.lights; ++j) {
      FitPoint p = c.point;
      const FitPoint l = FromUnit({0, 0, 0, 0, 0, 0, Halton(j, 2), Halton(j, 3), Halton(j, 5)}, o.protocol);
      p[6] = l[6], p[7] = l[7], p[8] = l[8];
      grid.push_back(eval(p, 512, MinLitShare(o)));
      record["grid"].push_back(ToJson(grid.back()));
    }
  std::vector<std::size_t> order(grid.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return grid[a].j < grid[b].j; });
  // Stage 3: the compass search from the best starts; the best end point is the fit.
  std::optional<Evaluated> best;
  for (int s = 0; s < o.starts && s < static_cast<int>(order.size()); ++s) {
    nlohmann::json path = nlohmann::json::array();
    const Evaluated end = Compass(eval, grid[order[s]], o, path);
    record["refine"].push_back({{"start", ToJson(grid[order[s]])}, {"path", path}, {"end", ToJson(end)}});
    if (!best || end.j < best->j) best = end;
  }
  if (!best) ThrowInput("--fit: the search evaluated no point");
  if (!std::isfinite(best->j))
    ThrowInput("--fit: no pose of protocol {} is a candidate (every frame's J is infinite: a zero count, or a lit share below {})",
               o.protocol, MinLitShare(o));
  // Stage 4: each parameter moved by +-1/16 and +-1/8 of its range from the fit.
  for (std::size_t k = 0; k < kFitParams; ++k)
    for (const double f : {-0.125, -0.0625, 0.0625, 0.125}) {
      const Evaluated e = eval(Moved(best->point, k, f * (ranges[k].hi - ranges[k].lo), o.protocol), 512, MinLitShare(o));
      record["sensitivity"].push_back({{"parameter", ranges[k].name}, {"fraction", f}, {"frame", ToJson(e)}});
    }
  record["best"] = ToJson(*best);
  record["frames"] = eval.frames();
  return record;
}

nlohmann::json FittedSceneJson(const nlohmann::json& scene_file, const nlohmann::json& record) {
  FitPoint p{};
  const nlohmann::json& point = record.at("best").at("point");
  for (std::size_t k = 0; k < kFitParams; ++k) p[k] = point.at(ThesisFitRanges()[k].name).get<double>();
  const PoseCamera c = CameraOf(p);
  nlohmann::json s = scene_file;
  s["name"] = FittedSceneStem(record.value("protocol", 1));
  s["camera"] = {{"eye", Vec(c.eye)}, {"target", Vec(c.target)}, {"up", {0, 0, 1}}, {"fov_y_deg", c.fov_y_deg}};
  s["lights"].at(0)["position"] = {p[6], p[7], p[8]};
  return s;
}

}  // namespace rayspace::reproduce
