#include "rayspace/accuracy/sampler.h"

#include <cmath>
#include <random>

#include "rayspace/accuracy/measure.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"

namespace rayspace::accuracy {
namespace {

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
    OfferLevel(c);
    return ForwardingHierarchyPasses::TraverseLevel(c);
  }
  // The fused calls answer the same queries, offered in the same (slot) order.
  emu::Compacted TraverseTopCompacted(const emu::call::TraverseTopCompacted& c) override {
    for (std::uint32_t n = c.t0; n < c.t1; ++n)
      for (std::uint32_t t = c.b0; t < c.b1; ++t)
        if (emu::TopSlotTested(c, n, t)) cones_.Offer({c.top[n], c.tri_spheres[t]});
    return ForwardingHierarchyPasses::TraverseTopCompacted(c);
  }
  emu::Compacted TraverseLevelCompacted(const emu::call::TraverseLevelCompacted& c) override {
    OfferLevel(c);
    return ForwardingHierarchyPasses::TraverseLevelCompacted(c);
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

 private:
  void OfferLevel(const emu::call::TraverseLevel& c) {
    for (std::uint32_t p : c.pairs) {
      const std::uint32_t parent = c.base_up + (p >> emu::kPairTriangleBits), tri = c.b0 + (p & emu::kPairTriangleMask);
      for (std::uint32_t k = c.first[parent]; k < c.first[parent + 1]; ++k) cones_.Offer({c.nodes[k], c.tri_spheres[tri]});
    }
  }
};

// Each sphere moved to touch its bundle: radius set to the distance, within 2^-20 relative.
std::vector<ConeQuery> NearBoundaryCones(const std::vector<ConeQuery>& cones, std::mt19937_64& rng,
                                         std::uniform_real_distribution<double>& jitter) {
  std::vector<ConeQuery> cones_edge;
  for (const ConeQuery& q : cones) {
    // Radius set to the sphere's distance from the bundle, within 2^-20 relative: touching spheres.
    layout::ConeNode n = q.node;
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
  return cones_edge;
}

// Each ray aimed at a point on an edge of its triangle, nudged across it.
std::vector<TriQuery> NearBoundaryTris(const std::vector<TriQuery>& tris, std::mt19937_64& rng,
                                       std::uniform_real_distribution<double>& jitter) {
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
  return tris_edge;
}

}  // namespace

Workload SampleWorkload(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, std::size_t samples) {
  Recorder rec(samples);
  RunFrame(scene, b, fo, rec);
  Workload w;
  w.cones = rec.cones_.items();
  w.tris = rec.tris_.items();
  w.cones_seen = rec.cones_.seen();
  w.tris_seen = rec.tris_.seen();
  // One generator for both sets, cones first: the same scene gives the same variants.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  w.cones_edge = NearBoundaryCones(w.cones, rng, jitter);
  w.tris_edge = NearBoundaryTris(w.tris, rng, jitter);
  return w;
}

}  // namespace rayspace::accuracy
