#include "rayspace/accuracy/measure.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <mutex>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/parallel.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/exact_cone.h"

namespace rayspace::accuracy {
namespace {

double NsPerTest(const std::function<bool(std::size_t)>& f, std::size_t n, double min_time) {
  // Median of three timed passes; each pass repeats the samples until it has run min_time seconds.
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
    } while (s < min_time);
    runs.push_back(s * 1e9 / static_cast<double>(done));
  }
  std::sort(runs.begin(), runs.end());
  return runs[1];
}

}  // namespace

void Evaluate(const std::string& test, const std::string& set, std::size_t n, const std::vector<Mode>& modes,
              const std::vector<char>& truth, std::vector<Row>& rows, double min_time, const std::vector<char>* in_plane) {
  for (const Mode& m : modes) {
    Row r{test, set, m.name, n};
    const std::size_t timed = m.slow ? std::min<std::size_t>(n, 2000) : n;
    for (std::size_t i = 0; i < n; ++i) {
      const bool a = m.answer(i);
      r.fn += truth[i] && !a;
      r.fp += !truth[i] && a;
      r.in_plane += (truth[i] != a) && in_plane && (*in_plane)[i];
    }
    r.ns = NsPerTest(m.answer, timed, min_time);
    rows.push_back(r);
    std::fprintf(stderr, "[accuracy] %-13s %-13s %-34s %8.1f ns  FN %zu  FP %zu\n", test.c_str(), set.c_str(), m.name.c_str(),
                 r.ns, r.fn, r.fp);
  }
}

namespace {

// ---- ray-triangle modes -----------------------------------------------------------------------------

// Moller-Trumbore without epsilons in precision T; t rounded to float for the frame.
template <typename T>
bool MollerTrumboreT(const layout::Ray& ray, const layout::Triangle& tri, float& t_out) {
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
bool MollerTrumbore(const layout::Ray& ray, const layout::Triangle& tri) {
  float t;
  return MollerTrumboreT<T>(ray, tri, t);
}

// ---- end to end: the frame with each mode in the traversal or the final tests -------------------------

// A ray-triangle mode inside the final tests: the hit and its float distance (exact: nullptr below).
using TriTest = std::function<bool(const layout::Ray&, const layout::Triangle&, float&)>;

class ModeTraversal final : public emu::ForwardingHierarchyPasses {
 public:
  explicit ModeTraversal(std::function<bool(const layout::ConeNode&, glm::vec4, float)> test) : test_(std::move(test)) {}
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
  emu::Compacted TraverseTopCompacted(const emu::call::TraverseTopCompacted& c) override {
    if (!test_) return ForwardingHierarchyPasses::TraverseTopCompacted(c);
    return emu::TraverseTopCompactedWith(test_, c);
  }
  emu::Compacted TraverseLevelCompacted(const emu::call::TraverseLevelCompacted& c) override {
    if (!test_) return ForwardingHierarchyPasses::TraverseLevelCompacted(c);
    return emu::TraverseLevelCompactedWith(test_, c);
  }
  std::vector<std::uint32_t> Intersect(const emu::call::Intersect& c) override {
    if (!tri_) return ForwardingHierarchyPasses::Intersect(c);
    return emu::IntersectWith(tri_, [&](std::uint32_t ray, const layout::Ray& r, float t, std::uint32_t prim) {
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
  std::function<bool(const layout::ConeNode&, glm::vec4, float)> test_;
  TriTest tri_;
  bool exact_ = false;
  std::mutex locks_[kLocks];
};

}  // namespace

std::size_t RaysChanged(const FrameOutcome& a, const FrameOutcome& b) {
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a.hits.size() && i < b.hits.size(); ++i) {
    for (std::size_t r = 0; r < a.hits[i].size(); ++r) changed += a.hits[i][r] != b.hits[i][r];
    for (std::size_t r = 0; r < a.occluded[i].size(); ++r) changed += a.occluded[i][r] != b.occluded[i][r];
  }
  return changed;
}

namespace {

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

}  // namespace

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

void MeasureConeModes(const Workload& w, std::vector<Row>& rows, double min_time) {
  const std::vector<ConeQuery>& cones = w.cones;
  const std::vector<ConeQuery>& cones_edge = w.cones_edge;
  for (int set = 0; set < 2; ++set) {
    const std::vector<ConeQuery>& qs = set == 0 ? cones : cones_edge;
    std::vector<char> truth(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) truth[i] = refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere);
    const std::vector<Mode> modes = {
        {"float, eq. 3.16 as printed", [&](std::size_t i) { return emu::cone::PrintedTest(qs[i].node, qs[i].sphere); }},
        {"float, conservative (rayspace)", [&](std::size_t i) { return emu::cone::Test(qs[i].node, qs[i].sphere, 0.0f); }},
        {"double, no margins", [&](std::size_t i) { return refs::DoubleNodeMeetsSphere(qs[i].node, qs[i].sphere); }},
        {"CGAL filtered (interval + exact)", [&](std::size_t i) { return refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere); }},
        {"CGAL exact rationals (Gmpq)",
         [&](std::size_t i) { return refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere, refs::ExactArithmetic::kRational); },
         true},
        {"CGAL Epeck lazy exact",
         [&](std::size_t i) { return refs::ExactNodeMeetsSphere(qs[i].node, qs[i].sphere, refs::ExactArithmetic::kLazy); }, true}};
    Evaluate("cone-sphere", set == 0 ? "workload" : "near-boundary", qs.size(), modes, truth, rows, min_time);
  }
}

void MeasureTriModes(const Workload& w, std::vector<Row>& rows, double min_time) {
  const std::vector<TriQuery>& tris = w.tris;
  const std::vector<TriQuery>& tris_edge = w.tris_edge;
  for (int set = 0; set < 2; ++set) {
    const std::vector<TriQuery>& qs = set == 0 ? tris : tris_edge;
    std::vector<char> truth(qs.size()), in_plane(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) {
      truth[i] = refs::ExactHitDecision(qs[i].ray, qs[i].tri);
      in_plane[i] = refs::ExactInPlane(qs[i].ray, qs[i].tri);
    }
    auto watertight = [&](std::size_t i) {
      const layout::Ray& r = qs[i].ray;
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
    Evaluate("ray-triangle", set == 0 ? "workload" : "near-boundary", qs.size(), modes, truth, rows, min_time, &in_plane);
  }
}

std::vector<EndToEnd> ConeEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo) {
  ModeTraversal exact_passes([](const layout::ConeNode& n, glm::vec4 s, float) { return refs::ExactNodeMeetsSphere(n, s); });
  const FrameOutcome exact = RunFrame(scene, b, fo, exact_passes);
  ModeTraversal paper([](const layout::ConeNode& n, glm::vec4 s, float eps) { return emu::cone::PrintedTest(n, s, eps); });
  ModeTraversal dbl([](const layout::ConeNode& n, glm::vec4 s, float eps) { return refs::DoubleNodeMeetsSphere(n, glm::vec4(glm::vec3(s), s.w + eps)); });
  const FrameOutcome fp = RunFrame(scene, b, fo, paper);
  const FrameOutcome fc = RunFrame(scene, b, fo, emu::EmuHierarchyPasses());
  const FrameOutcome fd = RunFrame(scene, b, fo, dbl);
  return {{"float, eq. 3.16 as printed", fp.ms, fp.tests, RaysChanged(fp, exact)},
          {"float, conservative (rayspace)", fc.ms, fc.tests, RaysChanged(fc, exact)},
          {"double, no margins", fd.ms, fd.tests, RaysChanged(fd, exact)},
          {"CGAL filtered (interval + exact)", exact.ms, exact.tests, 0}};
}

std::vector<EndToEnd> TriEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo) {
  // The final tests with each ray-triangle mode (traversal conservative), against exact decisions
  // and exact distance order. A changed ray: another primitive (or hit/miss), or another occlusion.
  auto float_mt = [](const layout::Ray& r, const layout::Triangle& t, float& th) {
    return MollerTrumboreT<float>(r, t, th);
  };
  auto double_mt = [](const layout::Ray& r, const layout::Triangle& t, float& th) { return MollerTrumboreT<double>(r, t, th); };
  auto watertight = [](const layout::Ray& r, const layout::Triangle& t, float& th) {
    return emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax)), emu::Xyz(t.v0),
                                    emu::Xyz(t.v1), emu::Xyz(t.v2), r.origin_tmin.w, r.direction_tmax.w, th);
  };
  auto exact_hit = [](const layout::Ray& r, const layout::Triangle& t, float& th) {
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
  return {{"float, Moller-Trumbore", rm.ms, rm.tests, RaysChangedPrim(rm, rx)},
          {"float, watertight (rayspace)", rw.ms, rw.tests, RaysChangedPrim(rw, rx)},
          {"double, Moller-Trumbore", rd.ms, rd.tests, RaysChangedPrim(rd, rx)},
          {"CGAL filtered (interval + exact)", rx.ms, rx.tests, 0}};
}

}  // namespace rayspace::accuracy
