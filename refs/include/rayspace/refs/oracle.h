// Compares a frame's traced batches with a second tracer, ray by ray.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/emu/frame.h"

namespace rayspace::refs {

struct Disagreement {
  std::string batch;
  std::size_t ray = 0;
  // Closest-hit batches: primitive (kNoPrim = miss) and t. Shadow batches: occluded flag in prim.
  std::uint32_t frame_prim = 0, oracle_prim = 0;
  float frame_t = 0, oracle_t = 0;
  std::string note;
  layout::Ray ray_data{};
};

class Oracle {
 public:
  // `tracer` re-traces; `scene` lets ties be recognised by re-testing both triangles.
  Oracle(Tracer& tracer, const SceneBuffers& scene) : tracer_(tracer), scene_(scene) {}
  void Check(const emu::Batch& batch);
  std::size_t rays_checked() const { return rays_checked_; }
  // Every disagreement is settled with exact arithmetic (refs/exact.h) and lands in one list:
  // the frame is wrong (a mismatch), the oracle is wrong, or a tie: both hit triangles at exactly the
  // same distance, or the only occluder is met exactly on an edge (both answers are defensible).
  const std::vector<Disagreement>& mismatches() const { return mismatches_; }
  const std::vector<Disagreement>& oracle_wrong() const { return oracle_wrong_; }
  const std::vector<Disagreement>& ties() const { return ties_; }
  // Lists every mismatch and every oracle error; ties up to max_listed.
  void Report(nlohmann::json& out, std::size_t max_listed) const;

 private:
  Tracer& tracer_;
  const SceneBuffers& scene_;
  std::size_t rays_checked_ = 0;
  std::vector<Disagreement> mismatches_, oracle_wrong_, ties_;
};

}  // namespace rayspace::refs
