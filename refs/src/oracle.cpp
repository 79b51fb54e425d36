#include "rayspace/refs/oracle.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"

namespace rayspace::refs {
namespace {

// Relative distance below which two different triangles count as hit at the same point.
constexpr float kTieRelative = 1e-5f;

// Nearest triangle the emulator's intersection test accepts for this ray (exhaustive; used only to
// describe a disagreement, never on the hot path).
std::uint64_t NearestByEmuTest(const gpu::Ray& ray, const SceneBuffers& scene) {
  const emu::WatertightRay wr = emu::SetupWatertight(emu::Xyz(ray.origin_tmin), emu::Xyz(ray.direction_tmax));
  std::uint64_t best = emu::kMissPacked;
  for (std::uint32_t p = 0; p < scene.triangles.size(); ++p) {
    if (p == ray.info.y) continue;
    const gpu::Triangle& t = scene.triangles[p];
    float th;
    if (emu::IntersectWatertight(wr, emu::Xyz(t.v0), emu::Xyz(t.v1), emu::Xyz(t.v2), ray.origin_tmin.w,
                                 ray.direction_tmax.w, th))
      best = std::min(best, emu::PackHit(th, p));
  }
  return best;
}

}  // namespace

void Oracle::Check(const emu::Batch& batch) {
  const std::vector<gpu::Ray>& rays = *batch.rays;
  rays_checked_ += rays.size();
  if (batch.occluded) {
    std::vector<std::uint32_t> mine;
    tracer_.Occluded(rays, mine);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (mine[i] == (*batch.occluded)[i]) continue;
      // Describe both sides with the occluder each one would have found.
      std::vector<gpu::Ray> one{rays[i]};
      std::vector<std::uint64_t> oh;
      tracer_.Closest(one, oh);
      const std::uint64_t eh = NearestByEmuTest(rays[i], scene_);
      Disagreement d;
      d.batch = batch.name;
      d.ray = i;
      d.frame_prim = emu::HitPrim(eh);
      d.frame_t = eh == emu::kMissPacked ? 0.0f : emu::HitT(eh);
      d.oracle_prim = emu::HitPrim(oh[0]);
      d.oracle_t = oh[0] == emu::kMissPacked ? 0.0f : emu::HitT(oh[0]);
      d.note = fmt::format("frame says {}, oracle says {} (tmax {})", (*batch.occluded)[i] ? "occluded" : "lit",
                           mine[i] ? "occluded" : "lit", rays[i].direction_tmax.w);
      mismatches_.push_back(d);
    }
    return;
  }
  std::vector<std::uint64_t> mine;
  tracer_.Closest(rays, mine);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::uint64_t a = (*batch.hits)[i], b = mine[i];
    const std::uint32_t pa = emu::HitPrim(a), pb = emu::HitPrim(b);
    const bool ha = a != emu::kMissPacked, hb = b != emu::kMissPacked;
    if (ha == hb && (!ha || pa == pb)) continue;
    Disagreement d;
    d.batch = batch.name;
    d.ray = i;
    d.frame_prim = ha ? pa : gpu::kNoPrim;
    d.oracle_prim = hb ? pb : gpu::kNoPrim;
    d.frame_t = ha ? emu::HitT(a) : 0.0f;
    d.oracle_t = hb ? emu::HitT(b) : 0.0f;
    if (ha && hb && std::fabs(d.frame_t - d.oracle_t) <= kTieRelative * std::max(d.frame_t, d.oracle_t)) {
      d.note = "same distance, different triangle (shared edge or vertex)";
      ties_.push_back(d);
    } else {
      d.note = ha && hb ? "different triangle" : (ha ? "oracle misses" : "frame misses");
      mismatches_.push_back(d);
    }
  }
}

void Oracle::Report(nlohmann::json& out, std::size_t max_listed) const {
  nlohmann::json cfg;
  tracer_.Describe(cfg);
  out = cfg;
  out["rays_checked"] = rays_checked_;
  out["mismatches"] = mismatches_.size();
  out["ties"] = ties_.size();
  auto list = [&](const std::vector<Disagreement>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (std::size_t i = 0; i < v.size() && i < max_listed; ++i) {
      const Disagreement& d = v[i];
      a.push_back({{"batch", d.batch}, {"ray", d.ray},
                   {"frame", {{"prim", d.frame_prim == gpu::kNoPrim ? nlohmann::json(nullptr) : nlohmann::json(d.frame_prim)}, {"t", d.frame_t}}},
                   {"oracle", {{"prim", d.oracle_prim == gpu::kNoPrim ? nlohmann::json(nullptr) : nlohmann::json(d.oracle_prim)}, {"t", d.oracle_t}}},
                   {"note", d.note}});
    }
    return a;
  };
  out["mismatch_list"] = list(mismatches_);
  out["tie_list"] = list(ties_);
}

}  // namespace rayspace::refs
