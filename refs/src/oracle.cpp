#include "rayspace/refs/oracle.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/refs/exact.h"

namespace rayspace::refs {
namespace {

// The emulator's test under the scene's rule: two-sided, or with one-sided triangles only a front hit.
bool EmuHits(const emu::WatertightRay& wr, const layout::Ray& ray, const layout::Triangle& t, bool one_sided, float& th) {
  float det = 0.0f;
  if (!emu::IntersectWatertight(wr, emu::Xyz(t.v0), emu::Xyz(t.v1), emu::Xyz(t.v2), ray.origin_tmin.w, ray.direction_tmax.w, th, &det))
    return false;
  return !one_sided || det > 0.0f;
}

// Nearest triangle the emulator's intersection test accepts for this ray (exhaustive; used only to
// describe a disagreement, never on the hot path).
std::uint64_t NearestByEmuTest(const layout::Ray& ray, const SceneBuffers& scene) {
  const emu::WatertightRay wr = emu::SetupWatertight(emu::Xyz(ray.origin_tmin), emu::Xyz(ray.direction_tmax));
  std::uint64_t best = emu::kMissPacked;
  for (std::uint32_t p = 0; p < scene.triangles.size(); ++p) {
    if (p == ray.info.y) continue;
    const layout::Triangle& t = scene.triangles[p];
    float th;
    if (EmuHits(wr, ray, t, scene.one_sided, th)) best = std::min(best, emu::PackHit(th, p));
  }
  return best;
}

// Could a correct float tracer have said the ray is lit? Only if every triangle that occludes it
// exactly does so fragilely (grazing, near an edge or an interval end).
bool LitDefensible(const layout::Ray& ray, const SceneBuffers& scene) {
  for (std::uint32_t p = 0; p < scene.triangles.size(); ++p) {
    if (p == ray.info.y) continue;
    const Judgement j = ExactJudge(ray, scene.triangles[p], kRoundingRel, scene.one_sided);
    if (j.hit && j.robust) return false;
  }
  return true;
}

// Could a correct float tracer have found an occluder? Only if some triangle the emulator's test
// accepts misses exactly but fragilely.
bool OccludedDefensible(const layout::Ray& ray, const SceneBuffers& scene) {
  const emu::WatertightRay wr = emu::SetupWatertight(emu::Xyz(ray.origin_tmin), emu::Xyz(ray.direction_tmax));
  for (std::uint32_t p = 0; p < scene.triangles.size(); ++p) {
    if (p == ray.info.y) continue;
    const layout::Triangle& t = scene.triangles[p];
    float th;
    if (!EmuHits(wr, ray, t, scene.one_sided, th)) continue;
    if (!ExactJudge(ray, t, kRoundingRel, scene.one_sided).robust) return true;
  }
  return false;
}

// Could a correct float tracer have returned `prim` (kNoPrim: a miss) as the closest hit? It must be
// hit or missed only fragilely, and every triangle hit exactly and robustly must be farther, or so
// close in distance that rounding may order the two either way.
bool ClosestDefensible(const layout::Ray& ray, std::uint32_t prim, const SceneBuffers& scene) {
  if (prim != layout::kNoPrim) {
    const Judgement j = ExactJudge(ray, scene.triangles[prim], kRoundingRel, scene.one_sided);
    if (!j.hit && j.robust) return false;
  }
  for (std::uint32_t p = 0; p < scene.triangles.size(); ++p) {
    if (p == ray.info.y || p == prim) continue;
    const layout::Triangle& q = scene.triangles[p];
    const Judgement j = ExactJudge(ray, q, kRoundingRel, scene.one_sided);
    if (!j.hit || !j.robust) continue;
    if (prim == layout::kNoPrim) return false;
    const layout::Triangle& f = scene.triangles[prim];
    if (ExactCompareHitDistance(ray, q, f) < 0 && !ExactDistancesClose(ray, q, f, kRoundingRel)) return false;
  }
  return true;
}

// How far a float tracer's t for this triangle may lie from the true one: the rounding kRoundingRel
// allows on the vertices (scale L, their largest coordinate relative to the origin) and on t |d|,
// moved along the ray by 1 / cos of the angle between the ray and the plane.
double TTolerance(const layout::Ray& ray, const layout::Triangle& tri, double t) {
  const glm::dvec3 o(emu::Xyz(ray.origin_tmin)), d(emu::Xyz(ray.direction_tmax));
  const glm::dvec3 a = glm::dvec3(emu::Xyz(tri.v0)) - o, b = glm::dvec3(emu::Xyz(tri.v1)) - o,
                   c = glm::dvec3(emu::Xyz(tri.v2)) - o;
  double l = 0;
  for (const glm::dvec3& v : {a, b, c}) l = std::max({l, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double dl = glm::length(d), cosine = std::fabs(glm::dot(n, d)) / (glm::length(n) * dl);
  return kRoundingRel * (l + std::fabs(t) * dl) / (dl * std::max(cosine, 1e-30));
}

// The distance to the triangle's plane along the ray, in double: the reference for two t's.
double PlaneT(const layout::Ray& ray, const layout::Triangle& tri) {
  const glm::dvec3 o(emu::Xyz(ray.origin_tmin)), d(emu::Xyz(ray.direction_tmax)), v0(emu::Xyz(tri.v0));
  const glm::dvec3 n = glm::cross(glm::dvec3(emu::Xyz(tri.v1)) - v0, glm::dvec3(emu::Xyz(tri.v2)) - v0);
  return glm::dot(v0 - o, n) / glm::dot(d, n);
}

}  // namespace

Answer JudgeClosest(const layout::Ray& ray, std::uint32_t prim, const SceneBuffers& scene) {
  if (prim != layout::kNoPrim && prim >= scene.triangles.size()) return Answer::kWrong;  // a faulty kernel's garbage
  const std::vector<std::uint32_t> exact = ExactClosest(ray, scene);
  const bool right = prim == layout::kNoPrim ? exact.empty() : std::find(exact.begin(), exact.end(), prim) != exact.end();
  if (right) return Answer::kExact;
  return ClosestDefensible(ray, prim, scene) ? Answer::kWithinRounding : Answer::kWrong;
}

Answer JudgeOccluded(const layout::Ray& ray, bool occluded, const SceneBuffers& scene) {
  const Contact exact = ExactOccluded(ray, scene);
  if (exact == Contact::kBoundary || (exact == Contact::kInterior) == occluded) return Answer::kExact;
  return (occluded ? OccludedDefensible(ray, scene) : LitDefensible(ray, scene)) ? Answer::kWithinRounding : Answer::kWrong;
}

// Both tracers hit the same triangle; their distances must agree within rounding, and when they do
// not, the plane's distance in double says which one is off.
void Oracle::CheckSameTriangle(const std::string& batch, std::size_t i, const layout::Ray& ray, std::uint64_t frame,
                               std::uint64_t oracle) {
  const std::uint32_t p = emu::HitPrim(frame);
  const float tf = emu::HitT(frame), to = emu::HitT(oracle);
  const layout::Triangle& tri = scene_.triangles[p];
  const double tol = TTolerance(ray, tri, tf);
  if (std::fabs(double(tf) - double(to)) <= tol) return;
  const double exact = PlaneT(ray, tri);
  Disagreement d{batch, i, p, p, tf, to, "", ray};
  const bool frame_right = std::fabs(double(tf) - exact) <= tol;
  d.note = fmt::format("same triangle {}, t {} against the oracle's {}: {} (plane distance {}, tolerance {:.3g})", p, tf, to,
                       frame_right ? "oracle wrong" : "frame wrong", exact, tol);
  (frame_right ? oracle_wrong_ : mismatches_).push_back(d);
}

void Oracle::CheckOccluded(const emu::Batch& batch) {
  const std::vector<layout::Ray>& rays = *batch.rays;
  std::vector<std::uint32_t> mine;
  tracer_.Occluded(rays, mine);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (mine[i] == (*batch.occluded)[i]) continue;
    // Describe both sides with the occluder each one would have found.
    std::vector<layout::Ray> one{rays[i]};
    std::vector<std::uint64_t> oh;
    tracer_.Closest(one, oh);
    const std::uint64_t eh = NearestByEmuTest(rays[i], scene_);
    Disagreement d;
    d.batch = batch.name;
    d.ray = i;
    d.ray_data = rays[i];
    d.frame_prim = emu::HitPrim(eh);
    d.frame_t = eh == emu::kMissPacked ? 0.0f : emu::HitT(eh);
    d.oracle_prim = emu::HitPrim(oh[0]);
    d.oracle_t = oh[0] == emu::kMissPacked ? 0.0f : emu::HitT(oh[0]);
    const Contact exact = ExactOccluded(rays[i], scene_);
    const char* verdict = exact == Contact::kInterior ? "occluded" : exact == Contact::kBoundary ? "grazing an edge" : "lit";
    const bool frame_occluded = (*batch.occluded)[i] != 0;
    d.note = fmt::format("frame says {}, oracle says {}, exact says {}", frame_occluded ? "occluded" : "lit",
                         mine[i] ? "occluded" : "lit", verdict);
    if (exact == Contact::kBoundary) {
      ties_.push_back(d);  // the answer depends on the edge convention
    } else if ((exact == Contact::kInterior) == frame_occluded) {
      oracle_wrong_.push_back(d);
    } else if (frame_occluded ? OccludedDefensible(rays[i], scene_) : LitDefensible(rays[i], scene_)) {
      d.note += "; within rounding (every deciding triangle is grazed, or met near an edge or an interval end)";
      rounding_.push_back(d);
    } else if (!shadow_changes_why_.empty()) {
      d.note += "; changed by " + shadow_changes_why_;
      shadow_changes_.push_back(d);
    } else {
      mismatches_.push_back(d);
    }
  }
}

void Oracle::Check(const emu::Batch& batch) {
  const std::vector<layout::Ray>& rays = *batch.rays;
  rays_checked_ += rays.size();
  if (batch.occluded) return CheckOccluded(batch);
  std::vector<std::uint64_t> mine;
  tracer_.Closest(rays, mine);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::uint64_t a = (*batch.hits)[i], b = mine[i];
    const std::uint32_t pa = emu::HitPrim(a), pb = emu::HitPrim(b);
    const bool ha = a != emu::kMissPacked, hb = b != emu::kMissPacked;
    if (ha == hb && (!ha || pa == pb)) {
      if (ha) CheckSameTriangle(batch.name, i, rays[i], a, b);
      continue;
    }
    Disagreement d;
    d.batch = batch.name;
    d.ray = i;
    d.ray_data = rays[i];
    d.frame_prim = ha ? pa : layout::kNoPrim;
    d.oracle_prim = hb ? pb : layout::kNoPrim;
    d.frame_t = ha ? emu::HitT(a) : 0.0f;
    d.oracle_t = hb ? emu::HitT(b) : 0.0f;
    const std::vector<std::uint32_t> exact = ExactClosest(rays[i], scene_);
    auto in_exact = [&](bool hit, std::uint32_t p) {
      return hit ? std::find(exact.begin(), exact.end(), p) != exact.end() : exact.empty();
    };
    const bool frame_right = in_exact(ha, pa), oracle_right = in_exact(hb, pb);
    std::string ex = exact.empty() ? "miss" : fmt::format("{}", fmt::join(exact, ","));
    if (frame_right && oracle_right) {
      d.note = "exact tie: both triangles at the same distance (exact closest " + ex + ")";
      ties_.push_back(d);
    } else if (frame_right) {
      d.note = "oracle wrong (exact closest " + ex + ")";
      oracle_wrong_.push_back(d);
    } else if (ClosestDefensible(rays[i], d.frame_prim, scene_)) {
      d.note = "within rounding (exact closest " + ex + "; the frame's answer is grazed, near an edge, or as near)";
      rounding_.push_back(d);
    } else {
      d.note = "frame wrong (exact closest " + ex + ")";
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
  out["disagreements"] = mismatches_.size() + oracle_wrong_.size() + ties_.size() + rounding_.size();
  out["oracle_wrong"] = oracle_wrong_.size();
  out["ties"] = ties_.size();
  out["within_rounding"] = rounding_.size();
  if (!shadow_changes_why_.empty()) {
    out["shadow_changes"] = shadow_changes_.size();  // shadow answers the frame departs from on purpose
    out["shadow_changes_by"] = shadow_changes_why_;
  }
  out["rounding_rel"] = kRoundingRel;
  out["adjudication"] = "exact rational arithmetic (CGAL Epeck)";
  // The hit rule the oracle and the exact judge applied: the frame's own (SceneBuffers::one_sided).
  out["triangles"] = scene_.one_sided ? "one-sided (back-face culling): a hit only from the front, against (v1 - v0) x (v2 - v0)"
                                      : "two-sided";
  auto list = [&](const std::vector<Disagreement>& v, std::size_t cap) {
    nlohmann::json a = nlohmann::json::array();
    for (std::size_t i = 0; i < v.size() && i < cap; ++i) {
      const Disagreement& d = v[i];
      a.push_back({{"batch", d.batch}, {"ray", d.ray},
                   {"frame", {{"prim", d.frame_prim == layout::kNoPrim ? nlohmann::json(nullptr) : nlohmann::json(d.frame_prim)}, {"t", d.frame_t}}},
                   {"oracle", {{"prim", d.oracle_prim == layout::kNoPrim ? nlohmann::json(nullptr) : nlohmann::json(d.oracle_prim)}, {"t", d.oracle_t}}},
                   {"origin", {d.ray_data.origin_tmin.x, d.ray_data.origin_tmin.y, d.ray_data.origin_tmin.z}},
                   {"direction", {d.ray_data.direction_tmax.x, d.ray_data.direction_tmax.y, d.ray_data.direction_tmax.z}},
                   {"tmin", d.ray_data.origin_tmin.w}, {"tmax", d.ray_data.direction_tmax.w},
                   {"note", d.note}});
    }
    return a;
  };
  // Every mismatch and oracle error is listed; ties and answers within rounding up to max_listed.
  out["mismatch_list"] = list(mismatches_, mismatches_.size());
  out["oracle_wrong_list"] = list(oracle_wrong_, oracle_wrong_.size());
  out["tie_list"] = list(ties_, max_listed);
  out["rounding_list"] = list(rounding_, max_listed);
}

}  // namespace rayspace::refs
