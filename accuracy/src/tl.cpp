#include "rayspace/accuracy/tl.h"

#include <chrono>
#include <cmath>
#include <random>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/tracer.h"
#include "rayspace/refs/exact.h"

namespace rayspace::accuracy {
namespace {

// The test as a kernel without margins would write it: the same operations as tl::SphereMayHit, the
// radius and the part's ends as they are.
bool PlainFloat(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 s) {
  const float len = emu::Length(dir);
  const glm::vec3 v = emu::Xyz(s) - org;
  const glm::vec3 u(dir.x / len, dir.y / len, dir.z / len);
  const float a = emu::Dot(v, u), b = emu::Length(emu::Cross(v, u));
  if (b > s.w) return false;
  if (a + s.w < tmin * len) return false;
  return !(a - s.w > tlimit * len);
}

bool Exact(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 s) {
  return refs::ExactSegmentMeetsSphere(org, dir, tmin, tlimit, s);
}

// Where the walks' sphere tests go while a frame is sampled: the frame's own test decides, the
// query is kept. A plain function (tl::SphereTest), so the sampling frame walks on one thread, the
// one that samples: the sink is that thread's.
thread_local std::vector<SphereQuery>* tls_sink = nullptr;
bool Recording(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 s) {
  tls_sink->push_back({org, dir, tmin, tlimit, s});
  return emu::tl::SphereMayHit(org, dir, tmin, tlimit, s);
}

// The emulator's passes with tl.trace walking with another sphere test (serially when recording).
class ModeWalks final : public emu::ForwardingHierarchyPasses {
 public:
  explicit ModeWalks(emu::tl::SphereTest test) : test_(test) {}
  std::string Name() const override { return "emu (sphere test mode)"; }
  emu::TlWalks TlTrace(const emu::call::TlTrace& c) override {
    if (test_ != Recording) return emu::TlTraceWith(c, test_);
    emu::TlWalks w = ForwardingHierarchyPasses::TlTrace(c);
    const emu::tl::ListsView view{c.first, c.escapes, c.words, c.vertices};
    for (const layout::Ray& r : c.rays) emu::tl::Walk(view, r, c.shadow != 0, nullptr, Recording);
    return w;
  }

 private:
  emu::tl::SphereTest test_;
};

FrameOutcome RunTlFrame(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, emu::HierarchyPasses& passes) {
  FrameOutcome out;
  auto tracer = emu::MakeTlTracer(b, {}, &passes);
  const auto t0 = std::chrono::steady_clock::now();
  emu::RenderFrame(scene, b, *tracer, fo, [&](const emu::Batch& batch) {
    out.hits.push_back(batch.hits ? *batch.hits : std::vector<std::uint64_t>{});
    out.occluded.push_back(batch.occluded ? *batch.occluded : std::vector<std::uint32_t>{});
  });
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  for (const emu::TlBatchStats& s : tracer->Stats()) out.tests += s.spheres + s.triangles;
  return out;
}

// The distance from the centre to the part [tmin, tlimit] of the ray, in double.
double Distance(const SphereQuery& q) {
  const glm::dvec3 o(q.org), d(q.dir), c(glm::vec3(q.sphere));
  double t = glm::dot(c - o, d) / glm::dot(d, d);
  t = std::max(t, static_cast<double>(q.tmin));
  if (std::isfinite(q.tlimit)) t = std::min(t, static_cast<double>(q.tlimit));
  return glm::length(o + t * d - c);
}

}  // namespace

SphereWorkload SampleSpheres(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, std::size_t samples) {
  std::vector<SphereQuery> all;
  tls_sink = &all;
  ModeWalks recorder(Recording);
  RunTlFrame(scene, b, fo, recorder);
  tls_sink = nullptr;
  SphereWorkload w;
  w.seen = all.size();
  // A seeded uniform sample (the same scene gives the same queries), in the walks' order.
  std::mt19937_64 rng(11);
  std::vector<std::size_t> keep(all.size());
  for (std::size_t i = 0; i < keep.size(); ++i) keep[i] = i;
  if (all.size() > samples) {
    std::shuffle(keep.begin(), keep.end(), rng);
    keep.resize(samples);
    std::sort(keep.begin(), keep.end());
  }
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  for (const std::size_t i : keep) {
    const SphereQuery& q = all[i];
    if (!std::isfinite(q.tmin) || glm::dot(q.dir, q.dir) == 0.0f) continue;
    w.spheres.push_back(q);
    const double dist = Distance(q);
    if (!(dist > 0.0) || !std::isfinite(dist)) continue;
    SphereQuery e = q;
    e.sphere.w = static_cast<float>(dist * (1.0 + jitter(rng) * 0x1p-20));
    w.spheres_edge.push_back(e);
  }
  return w;
}

void MeasureSphereModes(const SphereWorkload& w, std::vector<Row>& rows, double min_time) {
  for (int set = 0; set < 2; ++set) {
    const std::vector<SphereQuery>& qs = set == 0 ? w.spheres : w.spheres_edge;
    std::vector<char> truth(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) truth[i] = Exact(qs[i].org, qs[i].dir, qs[i].tmin, qs[i].tlimit, qs[i].sphere);
    auto mode = [&](emu::tl::SphereTest t) {
      return [&qs, t](std::size_t i) { return t(qs[i].org, qs[i].dir, qs[i].tmin, qs[i].tlimit, qs[i].sphere); };
    };
    const std::vector<Mode> modes = {{"float, no margins", mode(PlainFloat)},
                                     {"float, conservative (rayspace)", mode(emu::tl::SphereMayHit)},
                                     {"CGAL filtered (interval + exact)", mode(Exact)}};
    Evaluate("ray-sphere", set == 0 ? "workload" : "near-boundary", qs.size(), modes, truth, rows, min_time);
  }
}

std::vector<EndToEnd> SphereEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo) {
  ModeWalks exact_walks(Exact), plain_walks(PlainFloat);
  const FrameOutcome exact = RunTlFrame(scene, b, fo, exact_walks);
  const FrameOutcome plain = RunTlFrame(scene, b, fo, plain_walks);
  const FrameOutcome cons = RunTlFrame(scene, b, fo, emu::EmuHierarchyPasses());
  return {{"float, no margins", plain.ms, plain.tests, RaysChanged(plain, exact)},
          {"float, conservative (rayspace)", cons.ms, cons.tests, RaysChanged(cons, exact)},
          {"CGAL filtered (interval + exact)", exact.ms, exact.tests, 0}};
}

}  // namespace rayspace::accuracy
