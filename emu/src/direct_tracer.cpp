// The emulator's direct tracer. Exhaustive mode tests every triangle; BVH mode prunes with boxes
// that are tested conservatively in double with a margin, so it visits a superset of the triangles
// that can change the answer and returns exactly what exhaustive mode returns (tests check it).
#include <algorithm>
#include <numeric>

#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

struct Node {
  glm::dvec3 lo, hi;
  std::uint32_t first;  // leaf: first index into order_; inner: left child (right = left + 1)
  std::uint32_t count;  // leaf: triangle count; inner: 0
};

class DirectTracer final : public Tracer {
 public:
  DirectTracer(const SceneBuffers& scene, DirectMode mode) : scene_(scene) {
    bvh_ = mode == DirectMode::kBvh ||
           (mode == DirectMode::kAuto && scene.triangles.size() > kExhaustiveMaxTriangles);
    if (bvh_) Build();
  }

  std::string Name() const override { return "emu-direct"; }
  void Describe(nlohmann::json& out) const override {
    out["name"] = Name();
    out["mode"] = bvh_ ? "bvh" : "exhaustive";
    out["intersection"] = "watertight (Woop et al. 2013), float, two-sided";
  }

  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    hits.assign(rays.size(), kMissPacked);
    ParallelFor(rays.size(), [&](std::size_t i) { hits[i] = Trace(rays[i], false); });
  }

  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) override {
    occluded.assign(rays.size(), 0u);
    ParallelFor(rays.size(), [&](std::size_t i) {
      occluded[i] = Trace(rays[i], true) != kMissPacked ? 1u : 0u;
    });
  }

 private:
  // Returns the packed closest hit (any hit when any_hit).
  std::uint64_t Trace(const layout::Ray& ray, bool any_hit) const {
    const glm::vec3 org = Xyz(ray.origin_tmin), dir = Xyz(ray.direction_tmax);
    const float tmin = ray.origin_tmin.w, tmax = ray.direction_tmax.w;
    const std::uint32_t ignore = ray.info.y;
    const WatertightRay wr = SetupWatertight(org, dir);
    std::uint64_t best = kMissPacked;
    auto test = [&](std::uint32_t prim) {
      if (prim == ignore) return false;
      const layout::Triangle& t = scene_.triangles[prim];
      float th;
      if (!IntersectWatertight(wr, Xyz(t.v0), Xyz(t.v1), Xyz(t.v2), tmin, tmax, th)) return false;
      best = std::min(best, PackHit(th, prim));
      return any_hit;
    };
    if (!bvh_) {
      for (std::uint32_t p = 0; p < scene_.triangles.size(); ++p)
        if (test(p)) return best;
      return best;
    }
    const glm::dvec3 o(org), inv(1.0 / static_cast<double>(dir.x), 1.0 / static_cast<double>(dir.y),
                                  1.0 / static_cast<double>(dir.z));
    std::uint32_t stack[128];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
      const Node& n = nodes_[stack[--sp]];
      const double limit = best == kMissPacked ? static_cast<double>(tmax) : static_cast<double>(HitT(best));
      if (!BoxHit(n, o, inv, static_cast<double>(tmin), limit)) continue;
      if (n.count > 0) {
        for (std::uint32_t k = n.first; k < n.first + n.count; ++k)
          if (test(order_[k])) return best;
      } else {
        RS_CHECK(sp + 2 <= 128);
        stack[sp++] = n.first + 1;
        stack[sp++] = n.first;
      }
    }
    return best;
  }

  // Slab test in double against the padded box, with the t interval widened by a relative margin:
  // it never rejects a box holding a triangle that the float test accepts.
  static bool BoxHit(const Node& n, const glm::dvec3& o, const glm::dvec3& inv, double tmin, double tmax) {
    double t0 = -INFINITY, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
      if (std::isinf(inv[k])) {  // parallel to the slab
        if (o[k] < n.lo[k] || o[k] > n.hi[k]) return false;
        continue;
      }
      double a = (n.lo[k] - o[k]) * inv[k], b = (n.hi[k] - o[k]) * inv[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    constexpr double kRel = 1e-6;
    return t0 <= t1 + std::fabs(t1) * kRel && t1 >= tmin - std::fabs(tmin) * kRel - 1e-30 &&
           t0 <= tmax + std::fabs(tmax) * kRel;
  }

  void Build() {
    const std::size_t n = scene_.triangles.size();
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0u);
    centroids_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& t = scene_.triangles[i];
      centroids_[i] = (glm::dvec3(Xyz(t.v0)) + glm::dvec3(Xyz(t.v1)) + glm::dvec3(Xyz(t.v2))) / 3.0;
    }
    nodes_.reserve(2 * n / kLeaf + 2);
    nodes_.push_back({});
    BuildNode(0, 0, static_cast<std::uint32_t>(n), 0);
  }

  void BuildNode(std::uint32_t index, std::uint32_t first, std::uint32_t count, int depth) {
    glm::dvec3 lo(INFINITY), hi(-INFINITY), clo(INFINITY), chi(-INFINITY);
    for (std::uint32_t k = first; k < first + count; ++k) {
      const auto& t = scene_.triangles[order_[k]];
      for (const glm::vec4* v : {&t.v0, &t.v1, &t.v2}) {
        lo = glm::min(lo, glm::dvec3(Xyz(*v)));
        hi = glm::max(hi, glm::dvec3(Xyz(*v)));
      }
      clo = glm::min(clo, centroids_[order_[k]]);
      chi = glm::max(chi, centroids_[order_[k]]);
    }
    // Pad outward so rounding in the float triangle test cannot place a hit outside the box.
    const glm::dvec3 pad = (hi - lo) * 1e-6 + glm::max(glm::abs(lo), glm::abs(hi)) * 1e-6 + 1e-30;
    nodes_[index].lo = lo - pad;
    nodes_[index].hi = hi + pad;
    if (count <= kLeaf || depth >= 60) {
      nodes_[index].first = first;
      nodes_[index].count = count;
      return;
    }
    const glm::dvec3 ext = chi - clo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const std::uint32_t mid = first + count / 2;
    // Median split with the triangle index as tie-break: a total order, so the build is deterministic.
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const double ca = centroids_[a][axis], cb = centroids_[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    const std::uint32_t left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[index].first = left;
    nodes_[index].count = 0;
    BuildNode(left, first, mid - first, depth + 1);
    BuildNode(left + 1, mid, first + count - mid, depth + 1);
  }

  static constexpr std::uint32_t kLeaf = 4;
  const SceneBuffers& scene_;
  bool bvh_ = false;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;
  std::vector<glm::dvec3> centroids_;
};

}  // namespace

std::unique_ptr<Tracer> MakeDirectTracer(const SceneBuffers& scene, DirectMode mode) {
  return std::make_unique<DirectTracer>(scene, mode);
}

}  // namespace rayspace::emu
