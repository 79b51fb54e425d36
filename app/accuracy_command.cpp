#include "accuracy_command.h"
#include "cli_util.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <atomic>
#include <mutex>
#include <random>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <fmt/format.h>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/exact_cone.h"
#include "rayspace/scene.h"

namespace rayspace::app {
namespace {

struct ConeQuery {
  gpu::ConeNode node;
  glm::vec4 sphere;
};
struct TriQuery {
  gpu::Ray ray;
  gpu::Triangle tri;
};

// Uniform sample of a stream (Vitter's algorithm R), seeded: the same scene gives the same sample.
template <typename T>
class Reservoir {
 public:
  Reservoir(std::size_t capacity, std::uint64_t seed) : cap_(capacity), rng_(seed) {}
  void Offer(const T& item) {
    ++seen_;
    if (items_.size() < cap_) {
      items_.push_back(item);
      return;
    }
    const std::uint64_t j = std::uniform_int_distribution<std::uint64_t>(0, seen_ - 1)(rng_);
    if (j < cap_) items_[j] = item;
  }
  const std::vector<T>& items() const { return items_; }
  std::uint64_t seen() const { return seen_; }

 private:
  std::size_t cap_;
  std::mt19937_64 rng_;
  std::uint64_t seen_ = 0;
  std::vector<T> items_;
};

// The emulator's hierarchy passes, sampling every cone-sphere and ray-triangle query they answer.
class Recorder final : public emu::ForwardingHierarchyPasses {
 public:
  explicit Recorder(std::size_t n) : cones_(n, 1), tris_(n, 2) {}
  std::string Name() const override { return "emu (sampling)"; }
  std::vector<std::uint8_t> ObjectMask(const emu::call::ObjectMask& c) override {
    const std::size_t objects = c.object_spheres.size();
    for (std::size_t e = 0; e < c.top.size() * objects; ++e) cones_.Offer({c.top[e / objects], c.object_spheres[e % objects]});
    return ForwardingHierarchyPasses::ObjectMask(c);
  }
  emu::PairSlots TraverseTop(const emu::call::TraverseTop& c) override {
    emu::PairSlots s = ForwardingHierarchyPasses::TraverseTop(c);
    const std::uint32_t T = c.b1 - c.b0;
    for (std::size_t e = 0; e < s.tested.size(); ++e)
      if (s.tested[e]) cones_.Offer({c.top[c.t0 + e / T], c.tri_spheres[c.b0 + e % T]});
    return s;
  }
  emu::PairSlots TraverseLevel(const emu::call::TraverseLevel& c) override {
    for (std::uint32_t p : c.pairs) {
      const std::uint32_t parent = c.base_up + (p >> emu::kPairTriangleBits), tri = c.b0 + (p & emu::kPairTriangleMask);
      for (std::uint32_t k = c.first[parent]; k < c.first[parent + 1]; ++k) cones_.Offer({c.nodes[k], c.tri_spheres[tri]});
    }
    return ForwardingHierarchyPasses::TraverseLevel(c);
  }
  std::vector<std::uint32_t> Intersect(const emu::call::Intersect& c) override {
    for (std::uint32_t p : c.pairs) {
      const std::uint32_t node = c.base1 + (p >> emu::kPairTriangleBits), prim = c.b0 + (p & emu::kPairTriangleMask);
      for (std::uint32_t j = c.first1[node]; j < c.first1[node + 1]; ++j)
        if (c.rays[c.order[j]].info.y != prim) tris_.Offer({c.rays[c.order[j]], c.scene->triangles[prim]});
    }
    return ForwardingHierarchyPasses::Intersect(c);
  }
  Reservoir<ConeQuery> cones_;
  Reservoir<TriQuery> tris_;
};

// ---- cone-sphere modes --------------------------------------------------------------------------

// Thesis eq. 3.16 as printed (after Roger et al.): |C - H| tan(alpha) + (d + r) / cos(alpha) >= |P - H|,
// H the projection of the sphere's centre P on the axis; in float, no margins.
bool PaperConeTest(const gpu::ConeNode& n, glm::vec4 sphere) {
  const glm::vec3 v = emu::Xyz(sphere) - emu::Xyz(n.sphere), x = emu::Xyz(n.cone);
  const float a = emu::Dot(v, x);
  const glm::vec3 off = v - x * a;
  const float c = n.cone.w, s = n.extra.x;
  return std::fabs(a) * (s / c) + (n.sphere.w + sphere.w) / c >= emu::Length(off);
}

struct Mode {
  std::string name;
  std::function<bool(std::size_t)> answer;  // decision for sample i
  bool slow = false;                         // exact rationals: timed on a subsample
};

struct Row {
  std::string test, set, mode;
  std::size_t n = 0, fn = 0, fp = 0, in_plane = 0;  // in_plane: disagreements on rays in the triangle's plane
  double ns = 0;
};

double NsPerTest(const std::function<bool(std::size_t)>& f, std::size_t n) {
  // Median of three timed passes; each pass repeats the samples until it has run 0.2 s.
  std::vector<double> runs;
  volatile std::size_t sink = 0;
  for (int r = 0; r < 3; ++r) {
    std::size_t done = 0;
    const auto t0 = std::chrono::steady_clock::now();
    double s = 0;
    do {
      for (std::size_t i = 0; i < n; ++i) sink = sink + f(i);
      done += n;
      s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } while (s < 0.2);
    runs.push_back(s * 1e9 / static_cast<double>(done));
  }
  std::sort(runs.begin(), runs.end());
  return runs[1];
}

void Evaluate(const std::string& test, const std::string& set, std::size_t n, const std::vector<Mode>& modes,
              const std::vector<char>& truth, std::vector<Row>& rows, const std::vector<char>* in_plane = nullptr) {
  for (const Mode& m : modes) {
    Row r{test, set, m.name, n};
    const std::size_t timed = m.slow ? std::min<std::size_t>(n, 2000) : n;
    for (std::size_t i = 0; i < n; ++i) {
      const bool a = m.answer(i);
      r.fn += truth[i] && !a;
      r.fp += !truth[i] && a;
      r.in_plane += (truth[i] != a) && in_plane && (*in_plane)[i];
    }
    r.ns = NsPerTest(m.answer, timed);
    rows.push_back(r);
    std::fprintf(stderr, "[accuracy] %-13s %-13s %-34s %8.1f ns  FN %zu  FP %zu\n", test.c_str(), set.c_str(), m.name.c_str(),
                 r.ns, r.fn, r.fp);
  }
}

// ---- ray-triangle modes -----------------------------------------------------------------------------

// Moller-Trumbore without epsilons in precision T; t rounded to float for the frame.
template <typename T>
bool MollerTrumboreT(const gpu::Ray& ray, const gpu::Triangle& tri, float& t_out) {
  using V = glm::vec<3, T>;
  const V o(emu::Xyz(ray.origin_tmin)), d(emu::Xyz(ray.direction_tmax));
  const V v0(emu::Xyz(tri.v0)), e1 = V(emu::Xyz(tri.v1)) - v0, e2 = V(emu::Xyz(tri.v2)) - v0;
  const V p = glm::cross(d, e2);
  const T det = glm::dot(e1, p);
  if (det == T(0)) return false;
  const T inv = T(1) / det;
  const V s = o - v0;
  const T u = glm::dot(s, p) * inv;
  if (u < T(0) || u > T(1)) return false;
  const V q = glm::cross(s, e1);
  const T v = glm::dot(d, q) * inv;
  if (v < T(0) || u + v > T(1)) return false;
  const T t = glm::dot(e2, q) * inv;
  if (!(t > T(ray.origin_tmin.w) && t < T(ray.direction_tmax.w))) return false;
  t_out = static_cast<float>(t);
  return true;
}

template <typename T>
bool MollerTrumbore(const gpu::Ray& ray, const gpu::Triangle& tri) {
  float t;
  return MollerTrumboreT<T>(ray, tri, t);
}

// ---- end to end: the frame with each cone-sphere mode in the traversal --------------------------------

// A ray-triangle mode inside the final tests: the hit and its float distance (exact: nullptr below).
using TriTest = std::function<bool(const gpu::Ray&, const gpu::Triangle&, float&)>;

class ModeTraversal final : public emu::ForwardingHierarchyPasses {
 public:
  explicit ModeTraversal(std::function<bool(const gpu::ConeNode&, glm::vec4, float)> test) : test_(std::move(test)) {}
  // Final tests with a ray-triangle mode; `exact`: the exact decision and exact distance order.
  ModeTraversal(TriTest tri, bool exact) : tri_(std::move(tri)), exact_(exact) {}
  std::string Name() const override { return "emu (accuracy mode)"; }
  std::vector<std::uint8_t> ObjectMask(const emu::call::ObjectMask& c) override {
    if (!test_) return ForwardingHierarchyPasses::ObjectMask(c);
    return emu::ObjectMaskWith(test_, c);
  }
  emu::PairSlots TraverseTop(const emu::call::TraverseTop& c) override {
    if (!test_) return ForwardingHierarchyPasses::TraverseTop(c);
    return emu::TraverseTopWith(test_, c);
  }
  emu::PairSlots TraverseLevel(const emu::call::TraverseLevel& c) override {
    if (!test_) return ForwardingHierarchyPasses::TraverseLevel(c);
    return emu::TraverseLevelWith(test_, c);
  }
  std::vector<std::uint32_t> Intersect(const emu::call::Intersect& c) override {
    if (!tri_) return ForwardingHierarchyPasses::Intersect(c);
    return emu::IntersectWith(tri_, [&](std::uint32_t ray, const gpu::Ray& r, float t, std::uint32_t prim) {
      std::vector<std::uint64_t>& hits = *c.hits;
      if (!exact_) return emu::RecordClosestHit(hits, ray, emu::PackHit(t, prim));
      // Exact order of distances (ties to the lower id): compare with the current best under a lock.
      std::lock_guard<std::mutex> lock(locks_[ray % kLocks]);
      const std::uint64_t cur = hits[ray];
      const bool better = cur == emu::kMissPacked || [&] {
        const int cmp = refs::ExactCompareHitDistance(r, c.scene->triangles[prim], c.scene->triangles[emu::HitPrim(cur)]);
        return cmp < 0 || (cmp == 0 && prim < emu::HitPrim(cur));
      }();
      if (better) hits[ray] = emu::PackHit(t, prim);
    }, c);
  }

 private:
  static constexpr std::size_t kLocks = 4096;
  std::function<bool(const gpu::ConeNode&, glm::vec4, float)> test_;
  TriTest tri_;
  bool exact_ = false;
  std::mutex locks_[kLocks];
};

struct FrameOutcome {
  double ms = 0;
  std::vector<std::vector<std::uint64_t>> hits;
  std::vector<std::vector<std::uint32_t>> occluded;
  std::uint64_t tests = 0;
};

FrameOutcome RunFrame(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, emu::HierarchyPasses& passes) {
  FrameOutcome out;
  emu::HierarchyConfig hc;
  hc.passes = &passes;
  auto tracer = emu::MakeHierarchyTracer(b, hc);
  const auto t0 = std::chrono::steady_clock::now();
  emu::RenderFrame(scene, b, *tracer, fo, [&](const emu::Batch& batch) {
    out.hits.push_back(batch.hits ? *batch.hits : std::vector<std::uint64_t>{});
    out.occluded.push_back(batch.occluded ? *batch.occluded : std::vector<std::uint32_t>{});
  });
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  for (const emu::BatchStats& s : tracer->Stats()) out.tests += s.Total();
  return out;
}

std::size_t RaysChanged(const FrameOutcome& a, const FrameOutcome& b) {
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a.hits.size() && i < b.hits.size(); ++i) {
    for (std::size_t r = 0; r < a.hits[i].size(); ++r) changed += a.hits[i][r] != b.hits[i][r];
    for (std::size_t r = 0; r < a.occluded[i].size(); ++r) changed += a.occluded[i][r] != b.occluded[i][r];
  }
  return changed;
}

// Rays whose hit primitive (or miss) or occlusion differs; distances are compared only through order.
std::size_t RaysChangedPrim(const FrameOutcome& a, const FrameOutcome& b) {
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a.hits.size() && i < b.hits.size(); ++i) {
    const std::size_t n = std::min(a.hits[i].size(), b.hits[i].size());
    changed += std::max(a.hits[i].size(), b.hits[i].size()) - n;
    for (std::size_t r = 0; r < n; ++r) {
      const bool ma = a.hits[i][r] == emu::kMissPacked, mb = b.hits[i][r] == emu::kMissPacked;
      changed += ma != mb || (!ma && emu::HitPrim(a.hits[i][r]) != emu::HitPrim(b.hits[i][r]));
    }
    const std::size_t m = std::min(a.occluded[i].size(), b.occluded[i].size());
    changed += std::max(a.occluded[i].size(), b.occluded[i].size()) - m;
    for (std::size_t r = 0; r < m; ++r) changed += a.occluded[i][r] != b.occluded[i][r];
  }
  return changed;
}

// ---- the plot: error rate against time per test, log-log ---------------------------------------------

void Plot(const std::filesystem::path& path, const std::string& title, const std::vector<Row>& rows) {
  using namespace OIIO;
  const int W = 900, H = 620, L = 90, R = 330, T = 70, B = 70;
  ImageBuf img(ImageSpec(W, H, 3, TypeDesc::UINT8));
  const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, grey[3] = {0.85f, 0.85f, 0.85f};
  ImageBufAlgo::fill(img, white);
  const std::string font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  bool text_ok = true;
  auto text = [&](int x, int y, const std::string& s, int size, const float* c) {
    text_ok = ImageBufAlgo::render_text(img, x, y, s, size, font, c) && text_ok;
  };
  // x: log10(ns) in [0, 6]; y: log10(error rate) in [-7, 0], zero errors drawn on the bottom line.
  auto X = [&](double ns) { return L + static_cast<int>((std::log10(std::max(ns, 1.0)) / 6.0) * (W - L - R)); };
  auto Y = [&](double rate) {
    const double lr = rate > 0 ? std::max(std::log10(rate), -7.0) : -7.0;
    return T + static_cast<int>((-lr / 7.0) * (H - T - B));
  };
  for (int d = 0; d <= 6; ++d) {
    ImageBufAlgo::render_line(img, X(std::pow(10, d)), T, X(std::pow(10, d)), H - B, grey);
    text(X(std::pow(10, d)) - 12, H - B + 22, fmt::format("1e{}", d), 14, black);
  }
  for (int e = 0; e <= 7; ++e) {
    ImageBufAlgo::render_line(img, L, Y(std::pow(10, -e)), W - R, Y(std::pow(10, -e)), grey);
    text(L - 55, Y(std::pow(10, -e)) + 5, e == 7 ? "0 (none)" : fmt::format("1e-{}", e), 14, black);
  }
  ImageBufAlgo::render_box(img, L, T, W - R, H - B, black);
  text(10, 24, title, 18, black);
  text(10, T - 16, "disagreements with the exact answer per test (FN + FP, log)", 14, black);
  text((W - R) / 2 - 40, H - 15, "ns per test (log)", 15, black);
  const float colours[4][3] = {{0.85f, 0.1f, 0.1f}, {0.1f, 0.35f, 0.85f}, {0.1f, 0.6f, 0.2f}, {0.6f, 0.3f, 0.7f}};
  int legend = 0;
  std::vector<std::string> keys;
  for (const Row& r : rows) {
    const std::string key = r.test + " / " + r.set;
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  for (const Row& r : rows) {
    const int k = static_cast<int>(std::find(keys.begin(), keys.end(), r.test + " / " + r.set) - keys.begin()) % 4;
    const int x = X(r.ns), y = Y(static_cast<double>(r.fn + r.fp) / static_cast<double>(std::max<std::size_t>(r.n, 1)));
    ImageBufAlgo::render_box(img, x - 4, y - 4, x + 4, y + 4, colours[k], true);
    ++legend;
  }
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const int y = T + 20 + static_cast<int>(k) * 22;
    ImageBufAlgo::render_box(img, W - R + 15, y - 10, W - R + 25, y, colours[k % 4], true);
    text(W - R + 32, y, keys[k], 14, black);
  }
  // Mode labels beside the legend, numbered as in the table.
  int line = 0;
  std::vector<std::string> seen;
  for (const Row& r : rows)
    if (std::find(seen.begin(), seen.end(), r.mode) == seen.end()) seen.push_back(r.mode);
  for (std::size_t m = 0; m < seen.size(); ++m) text(W - R + 15, T + 130 + 20 * line++, fmt::format("{}", seen[m]), 12, black);
  for (const Row& r : rows) {
    const std::size_t m = std::find(seen.begin(), seen.end(), r.mode) - seen.begin();
    const int x = X(r.ns), y = Y(static_cast<double>(r.fn + r.fp) / static_cast<double>(std::max<std::size_t>(r.n, 1)));
    text(x + 6, y - 6, fmt::format("{}", m + 1), 11, black);
  }
  for (std::size_t m = 0; m < seen.size(); ++m) text(W - R + 2, T + 130 + 20 * static_cast<int>(m), fmt::format("{}", m + 1), 12, black);
  if (!text_ok) std::fprintf(stderr, "rayspace accuracy: warning: no font at %s (install fonts-dejavu-core); the plot has no labels\n", font.c_str());
  if (!img.write(path.string())) ThrowInput("{}: cannot write the plot ({})", path.string(), img.geterror());
}

}  // namespace

ExitCode RunAccuracy(const AccuracyArgs& args) {
  emu::FrameOptions fo;
  const Scene scene = LoadSceneForFrame(args.scene, args.data, args.size, fo.width, fo.height);
  if (args.samples < 100 || args.samples > 10000000) ThrowInput("--samples {}: expected 100 to 10000000", args.samples);
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (ec) ThrowInput("{}: cannot create the output directory ({})", args.out, ec.message());
  const SceneBuffers b = FlattenScene(scene);

  // 1. The workload: queries sampled from a CRSH frame, and near-boundary variants of them.
  Recorder rec(args.samples);
  const FrameOutcome conservative = RunFrame(scene, b, fo, rec);
  const std::vector<ConeQuery>& cones = rec.cones_.items();
  const std::vector<TriQuery>& tris = rec.tris_.items();
  std::vector<ConeQuery> cones_edge;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  for (const ConeQuery& q : cones) {
    // Radius set to the sphere's distance from the bundle, within 2^-20 relative: touching spheres.
    gpu::ConeNode n = q.node;
    const glm::dvec3 v = glm::dvec3(emu::Xyz(q.sphere)) - glm::dvec3(emu::Xyz(n.sphere));
    const glm::dvec3 x = glm::normalize(glm::dvec3(emu::Xyz(n.cone)));
    const double a = glm::dot(v, x), bb = glm::length(glm::cross(v, x));
    const double c = n.cone.w, s = n.extra.x, norm = std::sqrt(c * c + s * s);
    if (emu::cone::IsFull(n) || norm == 0) continue;
    const double sn = (bb * c - a * s) / norm, cs = (a * c + bb * s) / norm;
    const double dist = sn <= 0 ? 0.0 : cs > 0 ? sn : glm::length(v);
    const double r = dist - n.sphere.w;
    if (!(r > 0)) continue;
    cones_edge.push_back({n, glm::vec4(q.sphere.x, q.sphere.y, q.sphere.z, static_cast<float>(r * (1.0 + jitter(rng) * 0x1p-20)))});
  }
  std::vector<TriQuery> tris_edge;
  for (const TriQuery& q : tris) {
    // Aim the ray at a point on an edge, nudged across it by 2^-22 of the edge's length.
    const glm::dvec3 o(emu::Xyz(q.ray.origin_tmin));
    const glm::dvec3 v[3] = {glm::dvec3(emu::Xyz(q.tri.v0)), glm::dvec3(emu::Xyz(q.tri.v1)), glm::dvec3(emu::Xyz(q.tri.v2))};
    const int e = static_cast<int>(rng() % 3);
    const double f = 0.5 + 0.4 * jitter(rng);
    const glm::dvec3 p = v[e] + (v[(e + 1) % 3] - v[e]) * f;
    const glm::dvec3 inward = v[(e + 2) % 3] - p;
    const glm::dvec3 target = p + inward * (jitter(rng) * 0x1p-22);
    TriQuery t = q;
    t.ray.direction_tmax = glm::vec4(glm::vec3(target - o), INFINITY);
    t.ray.origin_tmin.w = 0.0f;
    tris_edge.push_back(t);
  }

  std::vector<Row> rows;
  // 2. Cone-sphere modes.
  for (int set = 0; set < 2; ++set) {
    const std::vector<ConeQuery>& qs = set == 0 ? cones : cones_edge;
    std::vector<char> truth(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) truth[i] = refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere);
    const std::vector<Mode> modes = {
        {"float, eq. 3.16 as printed", [&](std::size_t i) { return PaperConeTest(qs[i].node, qs[i].sphere); }},
        {"float, conservative (rayspace)", [&](std::size_t i) { return emu::cone::Test(qs[i].node, qs[i].sphere, 0.0f); }},
        {"double, no margins", [&](std::size_t i) { return refs::DoubleNodeMeetsSphere(qs[i].node, qs[i].sphere); }},
        {"CGAL filtered (interval + exact)", [&](std::size_t i) { return refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere); }},
        {"CGAL exact rationals (Gmpq)",
         [&](std::size_t i) { return refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere, refs::ExactArithmetic::kRational); },
         true},
        {"CGAL Epeck lazy exact",
         [&](std::size_t i) { return refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere, refs::ExactArithmetic::kLazy); }, true}};
    Evaluate("cone-sphere", set == 0 ? "workload" : "near-boundary", qs.size(), modes, truth, rows);
  }
  // 3. Ray-triangle modes.
  for (int set = 0; set < 2; ++set) {
    const std::vector<TriQuery>& qs = set == 0 ? tris : tris_edge;
    std::vector<char> truth(qs.size()), in_plane(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) {
      truth[i] = refs::ExactHitDecision(qs[i].ray, qs[i].tri);
      in_plane[i] = refs::ExactInPlane(qs[i].ray, qs[i].tri);
    }
    auto watertight = [&](std::size_t i) {
      const gpu::Ray& r = qs[i].ray;
      float t;
      return emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax)), emu::Xyz(qs[i].tri.v0),
                                      emu::Xyz(qs[i].tri.v1), emu::Xyz(qs[i].tri.v2), r.origin_tmin.w, r.direction_tmax.w, t);
    };
    const std::vector<Mode> modes = {
        {"float, Moller-Trumbore", [&](std::size_t i) { return MollerTrumbore<float>(qs[i].ray, qs[i].tri); }},
        {"float, watertight (rayspace)", watertight},
        {"double, Moller-Trumbore", [&](std::size_t i) { return MollerTrumbore<double>(qs[i].ray, qs[i].tri); }},
        {"CGAL filtered (interval + exact)", [&](std::size_t i) { return refs::ExactHitDecision(qs[i].ray, qs[i].tri); }},
        {"CGAL exact rationals (Gmpq)", [&](std::size_t i) { return refs::ExactHitDecision(qs[i].ray, qs[i].tri, false); }, true},
        {"CGAL Epeck constructions", [&](std::size_t i) { return refs::ExactContact(qs[i].ray, qs[i].tri) != refs::Contact::kMiss; },
         true}};
    Evaluate("ray-triangle", set == 0 ? "workload" : "near-boundary", qs.size(), modes, truth, rows, &in_plane);
  }

  // 4. End to end: the frame with each cone-sphere mode in the traversal, against the exact one.
  struct EndToEnd {
    std::string mode;
    double ms = 0;
    std::uint64_t tests = 0;
    std::size_t changed = 0;
  };
  std::vector<EndToEnd> e2e, tri_e2e;
  if (args.end_to_end) {
    ModeTraversal exact_passes([](const gpu::ConeNode& n, glm::vec4 s, float) { return refs::ExactNodeMeetsSphere(n, s); });
    const FrameOutcome exact = RunFrame(scene, b, fo, exact_passes);
    ModeTraversal paper([](const gpu::ConeNode& n, glm::vec4 s, float eps) { return PaperConeTest(n, glm::vec4(glm::vec3(s), s.w + eps)); });
    ModeTraversal dbl([](const gpu::ConeNode& n, glm::vec4 s, float eps) { return refs::DoubleNodeMeetsSphere(n, glm::vec4(glm::vec3(s), s.w + eps)); });
    const FrameOutcome fp = RunFrame(scene, b, fo, paper);
    const FrameOutcome fc = RunFrame(scene, b, fo, emu::EmuHierarchyPasses());
    const FrameOutcome fd = RunFrame(scene, b, fo, dbl);
    e2e = {{"float, eq. 3.16 as printed", fp.ms, fp.tests, RaysChanged(fp, exact)},
           {"float, conservative (rayspace)", fc.ms, fc.tests, RaysChanged(fc, exact)},
           {"double, no margins", fd.ms, fd.tests, RaysChanged(fd, exact)},
           {"CGAL filtered (interval + exact)", exact.ms, exact.tests, 0}};
    // The final tests with each ray-triangle mode (traversal conservative), against exact decisions
    // and exact distance order. A changed ray: another primitive (or hit/miss), or another occlusion.
    auto float_mt = [](const gpu::Ray& r, const gpu::Triangle& t, float& th) {
      return MollerTrumboreT<float>(r, t, th);
    };
    auto double_mt = [](const gpu::Ray& r, const gpu::Triangle& t, float& th) { return MollerTrumboreT<double>(r, t, th); };
    auto watertight = [](const gpu::Ray& r, const gpu::Triangle& t, float& th) {
      return emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax)), emu::Xyz(t.v0),
                                      emu::Xyz(t.v1), emu::Xyz(t.v2), r.origin_tmin.w, r.direction_tmax.w, th);
    };
    auto exact_hit = [](const gpu::Ray& r, const gpu::Triangle& t, float& th) {
      if (!refs::ExactHitDecision(r, t)) return false;
      // The distance the frame shades with: the plane equation in double, rounded once.
      const glm::dvec3 o(emu::Xyz(r.origin_tmin)), d(emu::Xyz(r.direction_tmax)), v0(emu::Xyz(t.v0));
      const glm::dvec3 n = glm::cross(glm::dvec3(emu::Xyz(t.v1)) - v0, glm::dvec3(emu::Xyz(t.v2)) - v0);
      th = static_cast<float>(glm::dot(v0 - o, n) / glm::dot(d, n));
      return true;
    };
    ModeTraversal tri_exact(exact_hit, true), tri_mt(float_mt, false), tri_dmt(double_mt, false), tri_wt(watertight, false);
    const FrameOutcome rx = RunFrame(scene, b, fo, tri_exact);
    const FrameOutcome rm = RunFrame(scene, b, fo, tri_mt), rd = RunFrame(scene, b, fo, tri_dmt), rw = RunFrame(scene, b, fo, tri_wt);
    tri_e2e = {{"float, Moller-Trumbore", rm.ms, rm.tests, RaysChangedPrim(rm, rx)},
               {"float, watertight (rayspace)", rw.ms, rw.tests, RaysChangedPrim(rw, rx)},
               {"double, Moller-Trumbore", rd.ms, rd.tests, RaysChangedPrim(rd, rx)},
               {"CGAL filtered (interval + exact)", rx.ms, rx.tests, 0}};
  }

  // 5. Report: markdown, CSV, plot.
  const std::filesystem::path base = std::filesystem::path(args.out) / (scene.name + "-accuracy");
  std::string md = fmt::format("### {} ({}x{}, crsh)\n\nQueries sampled uniformly from the frame's own work: {} cone-sphere tests of {} and {} ray-triangle tests of {}; near-boundary sets move each sphere to touch the bundle (radius within 2^-20 of the distance) and aim each ray at an edge (2^-22 of the edge across it). FN: the mode says miss where the exact answer is hit; FP: the reverse. Time: median of three passes, one thread.\n\n",
                               scene.name, fo.width, fo.height, cones.size(), rec.cones_.seen(), tris.size(), rec.tris_.seen());
  md += "| # | test | set | mode | queries | ns/test | FN | FP | of which in-plane |\n|---|---|---|---|---:|---:|---:|---:|---:|\n";
  std::string csv = "scene,test,set,mode,queries,ns_per_test,false_negatives,false_positives,in_plane\n";
  std::vector<std::string> names;
  for (const Row& r : rows)
    if (std::find(names.begin(), names.end(), r.mode) == names.end()) names.push_back(r.mode);
  for (const Row& r : rows) {
    const std::size_t num = std::find(names.begin(), names.end(), r.mode) - names.begin() + 1;
    md += fmt::format("| {} | {} | {} | {} | {} | {:.1f} | {} | {} | {} |\n", num, r.test, r.set, r.mode, r.n, r.ns, r.fn, r.fp,
                      r.test == "ray-triangle" ? std::to_string(r.in_plane) : "-");
    csv += fmt::format("{},{},{},\"{}\",{},{:.2f},{},{},{}\n", scene.name, r.test, r.set, r.mode, r.n, r.ns, r.fn, r.fp, r.in_plane);
  }
  if (!e2e.empty()) {
    md += "\nEnd to end, the frame with each cone-sphere mode in the traversal (all else equal), against the exact traversal:\n\n";
    md += "| mode | frame ms | hierarchy tests | rays whose result changes |\n|---|---:|---:|---:|\n";
    for (const EndToEnd& e : e2e) {
      md += fmt::format("| {} | {:.0f} | {} | {} |\n", e.mode, e.ms, e.tests, e.changed);
      csv += fmt::format("{},cone-sphere,end-to-end,\"{}\",{},{:.1f},{},,\n", scene.name, e.mode, e.tests, e.ms, e.changed);
    }
  }
  if (!tri_e2e.empty()) {
    md += "\nEnd to end, the frame with each ray-triangle mode in the final tests (traversal conservative), against exact hit decisions and exact distance order; a changed ray hits another primitive, hits where the exact answer misses or the reverse, or changes occlusion (later bounces inherit the differences):\n\n";
    md += "| mode | frame ms | final and hierarchy tests | rays whose result changes |\n|---|---:|---:|---:|\n";
    for (const EndToEnd& e : tri_e2e) {
      md += fmt::format("| {} | {:.0f} | {} | {} |\n", e.mode, e.ms, e.tests, e.changed);
      csv += fmt::format("{},ray-triangle,end-to-end,\"{}\",{},{:.1f},{},,\n", scene.name, e.mode, e.tests, e.ms, e.changed);
    }
  }
  std::ofstream(base.string() + ".md") << md;
  std::ofstream(base.string() + ".csv") << csv;
  Plot(base.string() + ".png", fmt::format("{}: errors against time per test", scene.name), rows);
  std::printf("%s\n  wrote %s.md, .csv, .png\n", md.c_str(), base.string().c_str());
  return ExitCode::kOk;
}

}  // namespace rayspace::app
